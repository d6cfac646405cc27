//! The mesh readers against the real files in `tests/meshes`, whose counts
//! and volumes are stated (and were measured independently, by a separate
//! Python script) in `tests/meshes/README.md`, and against small meshes
//! written here whose geometry is known exactly.

mod common;

use common::mesh_path;

use std::f64::consts::PI;
use std::path::Path;

use sprung_io::mesh::{
    closed_surface, edge_report, load_mesh_file, parse_mesh, parse_obj, parse_off, parse_stl,
    select_object, signed_volume, unique_edges, MeshErrorKind, MeshFormat, TriangleMesh,
};

fn load(name: &str) -> Vec<TriangleMesh> {
    let path = mesh_path(name);
    load_mesh_file(&path).unwrap_or_else(|e| panic!("{e}"))
}

fn load_one(name: &str, object: Option<&str>) -> TriangleMesh {
    let path = mesh_path(name);
    select_object(load(name), object, &path).unwrap_or_else(|e| panic!("{e}"))
}

fn volume(mesh: &TriangleMesh) -> f64 {
    signed_volume(&mesh.positions, &mesh.triangles)
}

fn norm(p: [f64; 3]) -> f64 {
    p.iter().map(|c| c * c).sum::<f64>().sqrt()
}

#[test]
fn cube_asc_is_the_side_two_cube_of_volume_eight() {
    let cube = load_one("cube.asc", None);
    assert_eq!(cube.name, "Cube");
    assert_eq!(cube.positions.len(), 8);
    assert_eq!(cube.triangles.len(), 12);
    for p in &cube.positions {
        assert!(
            p.iter().all(|c| c.abs() == 1.0),
            "vertex {p:?} is not at (±1, ±1, ±1)"
        );
    }
    // docs/physics.md section 4: a closed cube of side 2 has V = 8. Every
    // coordinate is ±1, so every triple product is a small integer computed
    // exactly; 1e-12 only guards against a change of summation order.
    assert!(
        (volume(&cube) - 8.0).abs() < 1e-12,
        "volume {}",
        volume(&cube)
    );
}

/// A closed mesh of `tests/meshes` with the numbers the meshes README states.
struct Expected {
    file: &'static str,
    object: Option<&'static str>,
    vertices: usize,
    triangles: usize,
    edges: usize,
    volume: f64,
    /// One unit in the last digit the meshes README prints: the measured volume
    /// was rounded to that digit, so the true value is within half of it.
    volume_tolerance: f64,
}

const CLOSED: [Expected; 7] = [
    Expected {
        file: "horse.obj",
        object: None,
        vertices: 4002,
        triangles: 8000,
        edges: 12000,
        volume: 2.6304e-4,
        volume_tolerance: 1e-8,
    },
    Expected {
        file: "spot_low_resolution.obj",
        object: None,
        vertices: 829,
        triangles: 1654,
        edges: 2481,
        volume: 0.67973,
        volume_tolerance: 1e-5,
    },
    Expected {
        file: "sphere.obj",
        object: None,
        vertices: 642,
        triangles: 1280,
        edges: 1920,
        volume: 4.15268,
        volume_tolerance: 1e-5,
    },
    Expected {
        file: "sphere_low.off",
        object: None,
        vertices: 589,
        triangles: 1174,
        edges: 1761,
        volume: 0.099471,
        volume_tolerance: 1e-6,
    },
    Expected {
        file: "icosahedron_ascii.stl",
        object: None,
        vertices: 12,
        triangles: 20,
        edges: 30,
        volume: 2.53615,
        volume_tolerance: 1e-5,
    },
    Expected {
        file: "UUSALKU.ASC",
        object: Some("Object"),
        vertices: 28,
        triangles: 52,
        edges: 78,
        volume: 1.46988e7,
        volume_tolerance: 1e2,
    },
    Expected {
        file: "cube.asc",
        object: None,
        vertices: 8,
        triangles: 12,
        edges: 18,
        volume: 8.0,
        volume_tolerance: 1e-12,
    },
];

#[test]
fn closed_meshes_have_the_counts_and_volumes_sources_states() {
    for e in &CLOSED {
        let path = mesh_path(e.file);
        let mesh = load_one(e.file, e.object);
        assert_eq!(mesh.positions.len(), e.vertices, "{}: vertices", e.file);
        assert_eq!(mesh.triangles.len(), e.triangles, "{}: triangles", e.file);
        // A closed triangle surface has E = 3T/2 (each edge in two
        // triangles); the meshes README states E, and χ = V - E + T = 2 (genus 0).
        let edges = unique_edges(&mesh.triangles).len();
        assert_eq!(edges, e.edges, "{}: edges", e.file);
        assert_eq!(
            e.vertices + e.triangles,
            edges + 2,
            "{}: Euler characteristic",
            e.file
        );

        let report = edge_report(&mesh.triangles);
        assert!(report.is_closed(), "{}: {report:?}", e.file);
        // The meshes README: every one is consistently oriented.
        assert!(
            report.misoriented.is_empty(),
            "{}: misoriented edges",
            e.file
        );

        let v = volume(&mesh);
        assert!(
            (v - e.volume).abs() <= e.volume_tolerance,
            "{}: volume {v}, the meshes README states {}",
            e.file,
            e.volume
        );
        // The meshes README: all are oriented outward already, so the check keeps
        // every triangle as it is.
        let checked = closed_surface(&mesh, &path).unwrap_or_else(|err| panic!("{err}"));
        assert_eq!(checked.triangles, mesh.triangles, "{}: reoriented", e.file);
    }
}

#[test]
fn stl_icosahedron_welds_into_a_regular_icosahedron_of_circumradius_one() {
    let ico = load_one("icosahedron_ascii.stl", None);
    assert_eq!(ico.name, "vcg");
    // 20 facets × 3 corners = 60 corners, welded on equal coordinates.
    assert_eq!(ico.positions.len(), 12);
    assert_eq!(ico.triangles.len(), 20);
    // Coordinates are printed with 7 significant digits (error ≤ 5e-7 each),
    // so |p| is 1 to within about 1e-6.
    for p in &ico.positions {
        assert!(
            (norm(*p) - 1.0).abs() < 2e-6,
            "vertex {p:?} not on the unit sphere"
        );
    }
    // Regular icosahedron of circumradius R = 1: edge a = 4R / sqrt(10 + 2√5),
    // volume (5/12)(3 + √5) a³. The coordinates' relative error of 1e-6 gives
    // a relative volume error of about 3e-6.
    let s5 = 5f64.sqrt();
    let a = 4.0 / (10.0 + 2.0 * s5).sqrt();
    let exact = 5.0 / 12.0 * (3.0 + s5) * a.powi(3);
    let v = volume(&ico);
    assert!(
        (v - exact).abs() / exact < 1e-5,
        "volume {v}, exact {exact}"
    );
}

#[test]
fn sphere_obj_is_inscribed_in_the_unit_ball() {
    let ball = load_one("sphere.obj", None);
    // The meshes README: the vertices lie on the unit sphere; written with 6 decimals
    // (error ≤ 5e-7 per coordinate, under 1e-6 on the radius).
    for p in &ball.positions {
        assert!(
            (norm(*p) - 1.0).abs() < 1e-6,
            "vertex {p:?} not on the unit sphere"
        );
    }
    // A convex polyhedron inscribed in the unit ball holds less than 4π/3.
    let v = volume(&ball);
    assert!(v > 0.0 && v < 4.0 * PI / 3.0, "volume {v}");
}

#[test]
fn uusalku_holds_two_meshes_and_skips_the_light_and_camera() {
    let meshes = load("UUSALKU.ASC");
    let summary: Vec<(&str, usize, usize)> = meshes
        .iter()
        .map(|m| (m.name.as_str(), m.positions.len(), m.triangles.len()))
        .collect();
    assert_eq!(summary, [("s01", 152, 272), ("Object", 28, 52)]);
    let s01 = &meshes[0];
    // Lines 17 and 1063 of the file, read digit for digit.
    assert_eq!(s01.positions[0], [7.463437, 678.775696, -67.417412]);
    assert_eq!(s01.triangles[271], [151, 146, 145]);
    // "Face 9" and "Smoothing" of "Object" straddle the "Page 17" break.
    assert_eq!(meshes[1].triangles[9], [12, 7, 6]);
    assert_eq!(meshes[1].triangles[10], [12, 6, 5]);
}

#[test]
fn uusalku_object_is_closed_with_the_stated_volume() {
    let path = mesh_path("UUSALKU.ASC");
    let object = load_one("UUSALKU.ASC", Some("Object"));
    let closed = closed_surface(&object, &path).unwrap_or_else(|e| panic!("{e}"));
    // The meshes README: +1.46988e7, six significant digits: tolerance one unit in
    // the last digit (100 cubic units).
    let v = volume(&closed);
    assert!((v - 1.46988e7).abs() <= 1e2, "volume {v}");
}

#[test]
fn uusalku_spaceship_is_refused_as_a_gas_body() {
    let path = mesh_path("UUSALKU.ASC");
    let s01 = load_one("UUSALKU.ASC", Some("s01"));
    let err = closed_surface(&s01, &path).expect_err("s01 is open");
    let MeshErrorKind::NotClosed { count, first } = err.kind else {
        panic!("expected NotClosed, got {err}");
    };
    // The meshes README: 20 boundary edges.
    assert_eq!(count, 20);
    // The edge named really is a boundary edge: one triangle uses it
    // (counted here by brute force, independently of the edge map).
    let [a, b] = first;
    let users = s01
        .triangles
        .iter()
        .filter(|t| t.contains(&a) && t.contains(&b))
        .count();
    assert_eq!(users, 1, "edge {a}-{b} is used by {users} triangles");
    let message = err.to_string();
    for needle in [
        "UUSALKU.ASC",
        "object \"s01\"",
        "20 boundary edges",
        &format!("between vertices {a} and {b}"),
        "cloth",
    ] {
        assert!(
            message.contains(needle),
            "{needle:?} missing from: {message}"
        );
    }
    // The meshes README: χ = V - E + T = 6 (5 components, with holes), so E = 418.
    let report = edge_report(&s01.triangles);
    assert_eq!(report.boundary.len(), 20);
    assert!(report.non_manifold.is_empty());
    assert_eq!(152 + 272 - report.edges.len(), 6);
}

#[test]
fn obj_objects_polygons_and_index_forms() {
    let text = "\
# two objects; vertices are global, each object numbers its own
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vn 0 0 1
o square
f 1//1 2//1 3//1 4//1
l 1 3
o pentagon
v 2 0 0
v 3 0 0
v 3.5 1 0
v 2.5 2 0
v 1.5 1 0
f -5 -4/ -3 -2 -1
";
    let meshes = parse_obj(text, Path::new("two.obj")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(meshes.len(), 2);
    let [square, pentagon] = meshes.as_slice() else {
        unreachable!()
    };
    assert_eq!(square.name, "square");
    // A quad splits into 2 triangles, fanned around its first corner.
    assert_eq!(square.triangles, [[0, 1, 2], [0, 2, 3]]);
    assert_eq!(square.positions[2], [1.0, 1.0, 0.0]);
    assert_eq!(pentagon.name, "pentagon");
    assert_eq!(pentagon.triangles.len(), 3);
    assert_eq!(pentagon.positions.len(), 5);
    assert_eq!(pentagon.positions[0], [2.0, 0.0, 0.0]);

    // Faces before any `o` line: the object takes the file's stem.
    let plain = parse_obj(
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
        Path::new("dir/tri.obj"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(plain[0].name, "tri");
    // A vertex weight w divides the coordinates.
    let weighted = parse_obj("v 2 4 6 2\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", Path::new("w.obj"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(weighted[0].positions[0], [1.0, 2.0, 3.0]);
    // A comment may follow a statement on its line.
    let commented = parse_obj(
        "v 0 0 0 # origin\nv 1 0 0\nv 0 1 0#tip\no tri # name\nf 1 2 3 # the face\n",
        Path::new("c.obj"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(commented[0].name, "tri");
    assert_eq!(commented[0].positions[2], [0.0, 1.0, 0.0]);
    assert_eq!(commented[0].triangles, [[0, 1, 2]]);
    // The vertices keep the file's order, whatever order the faces use
    // them in (as OFF and `.asc` keep theirs): `pinned` and `--probe`
    // name the file's vertices. A tetrahedron whose first face starts at
    // its last vertex.
    let tetra = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 4 3 2\nf 1 2 3\nf 1 4 2\nf 1 3 4\n";
    let mesh = &parse_obj(tetra, Path::new("t.obj")).unwrap_or_else(|e| panic!("{e}"))[0];
    assert_eq!(
        mesh.positions,
        [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0]
        ]
    );
    assert_eq!(mesh.triangles, [[3, 2, 1], [0, 1, 2], [0, 3, 1], [0, 2, 3]]);
    // A second object numbers its own vertices in the file's order too.
    let two = format!("{tetra}o second\nv 5 5 5\nf 5 2 1\n");
    let meshes = parse_obj(&two, Path::new("t.obj")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        meshes[1].positions,
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [5.0, 5.0, 5.0]]
    );
    assert_eq!(meshes[1].triangles, [[2, 1, 0]]);
}

#[test]
fn off_counts_on_the_header_line_comments_and_polygons() {
    let text = "OFF 5 2 0  # counts on the header line\n\
                # a unit square and an apex\n\
                0 0 0\n1 0 0\n1 1 0\n0 1 0\n\n0.5 0.5 1\n\
                4 0 1 2 3\n\
                3 0 1 4 255 0 0  # a face colour is ignored\n";
    let meshes = parse_off(text, Path::new("pyramid.off")).unwrap_or_else(|e| panic!("{e}"));
    let [mesh] = meshes.as_slice() else {
        panic!("one object expected")
    };
    assert_eq!(mesh.name, "pyramid");
    assert_eq!(mesh.positions.len(), 5);
    assert_eq!(mesh.triangles, [[0, 1, 2], [0, 2, 3], [0, 1, 4]]);
}

/// The 50-byte binary STL record of one triangle.
fn binary_record(corners: [[f64; 3]; 3]) -> Vec<u8> {
    let mut record = Vec::with_capacity(50);
    record.extend([0u8; 12]); // normal: the reader ignores it
    for p in corners {
        for c in p {
            record.extend((c as f32).to_le_bytes());
        }
    }
    record.extend([0u8; 2]);
    record
}

#[test]
fn binary_stl_reads_back_the_same_welded_icosahedron() {
    let ico = load_one("icosahedron_ascii.stl", None);
    // A header starting with "solid", as some binary writers do: the size
    // must decide, not the first word.
    let mut bytes = b"solid written by the sprung test".to_vec();
    bytes.resize(80, b' ');
    bytes.extend(u32::try_from(ico.triangles.len()).unwrap().to_le_bytes());
    for t in &ico.triangles {
        bytes.extend(binary_record(t.map(|v| ico.positions[v])));
    }
    let back = parse_stl(&bytes, Path::new("ico.stl")).unwrap_or_else(|e| panic!("{e}"));
    let [mesh] = back.as_slice() else {
        panic!("one object expected")
    };
    assert_eq!(mesh.name, "ico");
    assert_eq!(mesh.triangles, ico.triangles);
    assert_eq!(mesh.positions.len(), 12);
    // Stored as f32: relative rounding at most 2^-24 ≈ 6e-8 of |c| ≤ 1.
    for (p, q) in mesh.positions.iter().zip(&ico.positions) {
        for (a, b) in p.iter().zip(q) {
            assert!((a - b).abs() <= 6e-8, "{p:?} vs {q:?}");
        }
    }
}

#[test]
fn stl_welds_minus_zero_with_zero_and_keeps_near_misses_apart() {
    let text = "solid t\n\
        facet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\n endfacet\n\
        facet normal 0 0 1\n outer loop\n  vertex -0.0 0 0\n  vertex 0 -1 0\n  vertex 1.0000001 0 0\n endloop\n endfacet\n\
        endsolid t\n";
    let meshes = parse_stl(text.as_bytes(), Path::new("t.stl")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(meshes[0].triangles, [[0, 1, 2], [0, 3, 4]]);
    assert_eq!(meshes[0].positions.len(), 5);
}

#[test]
fn stl_facets_welded_into_a_line_or_a_point_are_left_out() {
    // The icosahedron with a sliver facet collapsed onto one of its edges
    // and one collapsed to a point, in ASCII and in binary: the same
    // closed, welded surface as without them.
    let ico = load_one("icosahedron_ascii.stl", None);
    // Corners of the first facet: welded to the vertices it numbered, the
    // slivers number nothing new wherever they come.
    let first = ico.triangles[0];
    let [a, b] = [ico.positions[first[0]], ico.positions[first[1]]];
    let mut facets: Vec<[[f64; 3]; 3]> = ico
        .triangles
        .iter()
        .map(|t| t.map(|v| ico.positions[v]))
        .collect();
    facets.insert(3, [a, b, a]);
    facets.push([b, b, b]);
    // A sliver whose third corner is nowhere else: that corner is no
    // vertex either (it would be a particle of no triangle).
    facets.push([a, a, [9.0, 9.0, 9.0]]);
    let ascii: String = std::iter::once("solid s\n".to_owned())
        .chain(facets.iter().map(|corners| {
            let vertices: String = corners
                .iter()
                .map(|p| format!("vertex {:?} {:?} {:?}\n", p[0], p[1], p[2]))
                .collect();
            format!("facet normal 0 0 0\nouter loop\n{vertices}endloop\nendfacet\n")
        }))
        .chain(std::iter::once("endsolid s\n".to_owned()))
        .collect();
    let mut binary = vec![b' '; 80];
    binary.extend(u32::try_from(facets.len()).unwrap().to_le_bytes());
    for corners in &facets {
        binary.extend(binary_record(*corners));
    }
    for bytes in [ascii.as_bytes(), &binary] {
        let meshes = parse_stl(bytes, Path::new("s.stl")).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(meshes[0].triangles, ico.triangles);
        assert_eq!(meshes[0].positions.len(), 12);
        assert!(closed_surface(&meshes[0], Path::new("s.stl")).is_ok());
    }
    // Nothing but slivers: no mesh.
    let sliver = "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 0\nendloop\nendfacet\nendsolid s\n";
    let err = parse_stl(sliver.as_bytes(), Path::new("s.stl")).expect_err("no area");
    assert!(err.to_string().contains("no triangle mesh"), "{err}");
}

#[test]
fn select_object_by_name_or_the_only_one() {
    let path = mesh_path("UUSALKU.ASC");
    let meshes = load("UUSALKU.ASC");
    let object =
        select_object(meshes.clone(), Some("Object"), &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(object.triangles.len(), 52);

    let missing = select_object(meshes.clone(), Some("Camera01"), &path).expect_err("not a mesh");
    let message = missing.to_string();
    assert!(message.contains("UUSALKU.ASC"), "{message}");
    assert!(message.contains("\"Camera01\""), "{message}");
    assert!(message.contains("\"s01\", \"Object\""), "{message}");

    let ambiguous = select_object(meshes, None, &path).expect_err("two objects");
    assert!(
        ambiguous.to_string().contains("\"s01\", \"Object\""),
        "{ambiguous}"
    );

    let cube = select_object(load("cube.asc"), None, &path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(cube.name, "Cube");
}

#[test]
fn format_follows_the_extension_in_any_case() {
    assert_eq!(
        MeshFormat::from_path(Path::new("a/B.ASC")).ok(),
        Some(MeshFormat::Asc)
    );
    assert_eq!(
        MeshFormat::from_path(Path::new("b.Obj")).ok(),
        Some(MeshFormat::Obj)
    );
    assert_eq!(
        MeshFormat::from_path(Path::new("c.OFF")).ok(),
        Some(MeshFormat::Off)
    );
    assert_eq!(
        MeshFormat::from_path(Path::new("d.stl")).ok(),
        Some(MeshFormat::Stl)
    );

    let unknown = load_mesh_file(Path::new("model.ply")).expect_err("not supported");
    assert!(
        unknown
            .to_string()
            .starts_with("model.ply: unsupported mesh format \"ply\""),
        "{unknown}"
    );

    let missing = mesh_path("no_such_mesh.obj");
    let err = load_mesh_file(&missing).expect_err("missing file");
    assert!(matches!(err.kind, MeshErrorKind::Io(_)), "{err}");
    assert!(
        err.to_string()
            .contains("no_such_mesh.obj: cannot read the file"),
        "{err}"
    );

    // The same bytes through `parse_mesh` as through the file.
    let path = mesh_path("cube.asc");
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(
        parse_mesh(&bytes, MeshFormat::Asc, &path).ok(),
        load_mesh_file(&path).ok()
    );
}

#[test]
fn lf_crlf_and_cr_line_ends_read_alike() {
    let path = mesh_path("cube.asc");
    let lf = std::fs::read_to_string(&path).unwrap();
    let reference =
        parse_mesh(lf.as_bytes(), MeshFormat::Asc, &path).unwrap_or_else(|e| panic!("{e}"));
    for ending in ["\r\n", "\r"] {
        let text = lf.replace('\n', ending);
        let meshes =
            parse_mesh(text.as_bytes(), MeshFormat::Asc, &path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(meshes, reference, "{ending:?}");
        // Line numbers count the same lines: face 0 is on line 13.
        let broken = text.replace("A:0 B:1 C:2", "A:0 B:1 C:8");
        let err = parse_mesh(broken.as_bytes(), MeshFormat::Asc, &path).expect_err("index 8");
        assert_eq!(err.line, Some(13), "{ending:?}: {err}");
    }
}
