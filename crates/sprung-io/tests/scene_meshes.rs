//! Bodies from mesh files in scenes: every file of `tests/meshes` loads
//! into a world, the engine's divergence-theorem volume of each closed
//! mesh is the one `the meshes README` states, and an open object is refused as a
//! gas body (naming the file, the object and the first boundary edge) but
//! accepted as cloth.

mod common;

use std::path::Path;

use common::mesh_path;
use sprung_io::parse_scene;

/// A scene with one mesh body; `extra` lines are added to the body table.
fn scene(mesh: &Path, extra: &str) -> String {
    format!(
        "[sim]\ndt = 1e-4\nsteps = 1\n\n[[body]]\nname = \"m\"\nmesh = \"{}\"\n{extra}\n",
        mesh.display()
    )
}

fn world_volume(file: &str, extra: &str) -> f64 {
    let path = mesh_path(file);
    let text = scene(&path, extra);
    let scene = parse_scene(&text, Path::new("mesh.toml")).unwrap_or_else(|e| panic!("{e}"));
    scene.world.volume(0).expect("a closed body has a volume")
}

#[test]
fn cube_asc_encloses_exactly_8() {
    // Vertices at ±1 are exact in binary and the divergence sum of a cube's
    // faces involves only sums of ±1 products: the only error is rounding.
    let volume = world_volume("cube.asc", "gas = { nrt = 1.0 }");
    assert!((volume - 8.0).abs() < 1e-12, "{volume}");
}

#[test]
fn closed_meshes_have_the_volumes_of_sources_md() {
    // the meshes README prints 5 or 6 significant digits: compare to half a unit
    // of the last printed digit.
    let cases: [(&str, &str, f64, f64); 6] = [
        ("horse.obj", "", 2.6304e-4, 0.00005e-4),
        ("spot_low_resolution.obj", "", 0.67973, 0.000005),
        ("sphere.obj", "", 4.15268, 0.000005),
        ("sphere_low.off", "", 0.099471, 0.0000005),
        ("icosahedron_ascii.stl", "", 2.53615, 0.000005),
        (
            "UUSALKU.ASC",
            "object = \"Object\"\n",
            1.46988e7,
            0.000005e7,
        ),
    ];
    for (file, extra, expected, tolerance) in cases {
        let volume = world_volume(file, &format!("{extra}gas = {{ nrt = 1.0 }}"));
        assert!(
            (volume - expected).abs() <= tolerance,
            "{file}: {volume} vs {expected}"
        );
    }
}

#[test]
fn mesh_bodies_get_edge_and_bending_springs() {
    // The icosahedron has 30 edges. The two triangles of an edge u-v have
    // opposite vertices p, q whose only common neighbours are u and v, so
    // each edge gives a distinct bending pair: 30 more springs.
    let path = mesh_path("icosahedron_ascii.stl");
    let count = |extra: &str| {
        let scene = parse_scene(&scene(&path, extra), Path::new("m.toml"))
            .unwrap_or_else(|e| panic!("{e}"));
        (scene.world.particles.len(), scene.world.springs.len())
    };
    assert_eq!(count("bending = false"), (12, 30));
    assert_eq!(count(""), (12, 60));
    // A centre particle joined to all 12 vertices.
    assert_eq!(count("bending = false\ninternal = \"centre\""), (13, 42));
    // refine = 1 splits 20 triangles into 80: 12 + 30 vertices, 120 edges.
    assert_eq!(count("bending = false\nrefine = 1"), (42, 120));
}

#[test]
fn the_open_object_of_uusalku_is_refused_as_a_gas_body_and_accepted_as_cloth() {
    let path = mesh_path("UUSALKU.ASC");
    let text = scene(&path, "object = \"s01\"\ngas = { nrt = 1.0 }");
    let message = parse_scene(&text, Path::new("ship.toml"))
        .expect_err("open")
        .to_string();
    for fragment in [
        "ship.toml:7:",
        "body \"m\"",
        "UUSALKU.ASC",
        "object \"s01\"",
        "20 boundary edges",
        "67",
        "75",
    ] {
        assert!(message.contains(fragment), "{message:?} lacks {fragment:?}");
    }
    let cloth = parse_scene(&scene(&path, "object = \"s01\""), Path::new("ship.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cloth.world.particles.len(), 152);
    assert_eq!(
        cloth.world.volume(0),
        None,
        "an open surface encloses no volume"
    );
}

#[test]
fn a_multi_object_file_needs_an_object_name() {
    let path = mesh_path("UUSALKU.ASC");
    let message = parse_scene(&scene(&path, ""), Path::new("m.toml"))
        .expect_err("ambiguous")
        .to_string();
    assert!(
        message.contains("s01") && message.contains("Object"),
        "{message}"
    );
    let message = parse_scene(&scene(&path, "object = \"nope\""), Path::new("m.toml"))
        .expect_err("absent")
        .to_string();
    assert!(message.contains("nope"), "{message}");
}

#[test]
fn gas_and_surface_keys_are_checked() {
    let path = mesh_path("cube.asc");
    let cases = [
        ("gas = { nrt = -1.0 }", "`gas.nrt` = -1"),
        (
            "gas = { nrt = 1.0, volume = \"guess\" }",
            "known volume models",
        ),
        (
            "gas = { nrt = 1.0, ramp_time = 1.0, schedule = [[0.5, 2.0]] }",
            "after the ramp",
        ),
        (
            "gas = { nrt = 1.0, pressure = 3.0 }",
            "unknown field `pressure`",
        ),
        (
            "internal = \"jelly\"",
            "\"none\", \"centre\" and \"lattice\"",
        ),
        ("internal = \"lattice\"", "needs `lattice_spacing`"),
        (
            "lattice_spacing = 0.5",
            "goes with `internal = \"lattice\"`",
        ),
        (
            "internal = \"lattice\"\nlattice_spacing = -1.0",
            "spacing must be positive",
        ),
        ("refine = 9", "`refine` = 9"),
    ];
    for (extra, fragment) in cases {
        let message = parse_scene(&scene(&path, extra), Path::new("m.toml"))
            .expect_err(extra)
            .to_string();
        assert!(
            message.contains(fragment),
            "{extra}: {message:?} lacks {fragment:?}"
        );
    }
    let missing = parse_scene(&scene(Path::new("/no/such.obj"), ""), Path::new("m.toml"))
        .expect_err("missing");
    assert!(missing.to_string().contains("/no/such.obj"), "{missing}");
}

#[test]
fn gas_on_a_cloth_is_refused() {
    let text = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"c\"\ncloth = { nx = 3, ny = 3, width = 1.0, height = 1.0 }\ngas = { nrt = 1.0 }\n";
    let message = parse_scene(text, Path::new("c.toml"))
        .expect_err("open")
        .to_string();
    assert!(
        message.starts_with("c.toml:7:") && message.contains("closed surface"),
        "{message}"
    );
}

#[test]
fn rings_and_spheres_from_scene_keys() {
    let text = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"r\"\nring = { particles = 17, radius = 0.5 }\ngas = { nrt = 10.0 }\n\n[[body]]\nname = \"s\"\nsphere = { radius = 1.0, subdivisions = 3 }\n";
    let scene = parse_scene(text, Path::new("r.toml")).unwrap_or_else(|e| panic!("{e}"));
    let n = 17.0_f64;
    let area = 0.5 * n * 0.25 * (std::f64::consts::TAU / n).sin();
    assert!((scene.world.volume(0).expect("closed") - area).abs() < 1e-12);
    // the meshes README: sphere.obj is the same 3-level unit icosphere, +4.15268.
    assert!((scene.world.volume(1).expect("closed") - 4.15268).abs() < 5e-6);
    assert_eq!(scene.world.bodies[1].particles.len(), 642);
}

#[test]
fn a_lattice_fills_the_textbook_cube_and_holds_its_shape_without_gas() {
    // cube.asc has side 2: at spacing 0.5, floor(2 / 0.5) = 4 points fit
    // along each axis, centred: at ±0.25 and ±0.75, all strictly inside, so
    // 4³ = 64 lattice particles join the surface.
    let path = mesh_path("cube.asc");
    let text = format!(
        "[sim]\ndt = 2e-4\nsteps = 1\n\n[[body]]\nname = \"m\"\nmesh = \"{}\"\nrefine = 1\nbending = false\ntotal_mass = 1.0\nstiffness = 500.0\ndamping = 0.5\ntranslate = [0.0, 1.2, 0.0]\ninternal = \"lattice\"\nlattice_spacing = 0.5\n\n[[collider]]\nplane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}\nfriction = 0.5\n",
        path.display()
    );
    let mut scene = parse_scene(&text, Path::new("m.toml")).unwrap_or_else(|e| panic!("{e}"));
    // refine = 1: 8 corners + 12 edge midpoints + 6 face centres = 26
    // surface points on 48 triangles, so 26 + 48 - 2 = 72 edges (Euler).
    assert_eq!(scene.world.particles.len(), 26 + 64);
    // Lattice springs over the 13 forward directions of a 4×4×4 block:
    // 3 axes · 4²·3 + 6 face diagonals · 4·3² + 4 body diagonals · 3³
    // = 144 + 216 + 108 = 468; plus one tie per surface point: 26.
    assert_eq!(scene.world.springs.len(), 72 + 468 + 26);
    let inside = scene.world.particles.position[26..].iter().all(|p| {
        let local = *p - sprung::Vec3::new(0.0, 1.2, 0.0);
        local.abs().max_element() < 1.0
    });
    assert!(
        inside,
        "every lattice particle lies strictly inside the cube"
    );
    // Dropped on a floor without gas it holds its shape: the weight per
    // lattice column (~1 kg g / 16 ≈ 0.6 N) against 500 N/m springs
    // shortens a 0.5 m link by ~0.1 %; 0.9 × 2 m leaves room for settling.
    for _ in 0..15_000 {
        scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
    }
    let ys = scene.world.particles.position.iter().map(|p| p.y);
    let (low, high) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), y| {
        (l.min(y), h.max(y))
    });
    assert!(high - low > 1.8, "lattice cube height {}", high - low);
}

#[test]
fn lattice_spacing_is_in_scene_metres_after_scaling() {
    // cube.asc scaled ×2 has side 4: at spacing 1 m, 4 points fit along each
    // axis, as at spacing 0.5 m on the unscaled cube: 64 lattice particles.
    let path = mesh_path("cube.asc");
    let text = scene(
        &path,
        "scale = 2.0\ninternal = \"lattice\"\nlattice_spacing = 1.0\nbending = false",
    );
    let scene = parse_scene(&text, Path::new("m.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.world.particles.len(), 8 + 64);
}
