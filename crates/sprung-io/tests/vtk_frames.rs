//! VTK frames, `.vtu` and legacy `.vtk`: what `write_frame` puts in them
//! (each cell's kind, body, rest length and strain, each point's body) and
//! `read_vtk_frame` reading them back exactly; other tools' files read;
//! malformed files are errors naming the file and line, never panics.

mod common;

use std::path::Path;

use sprung::{build, IntegratorKind, Vec3, World};
use sprung_io::export::{read_vtk_frame, write_frame, FrameFormat, VtkFrame};

/// A gas-free ring (a closed 2D outline), a rope and a small cloth.
fn world() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    let ring = build::ring(5, 0.5).expect("ring").with_stiffness(100.0);
    world.add_body("ring", ring).expect("ring");
    let rope = build::rope(3, 1.0).expect("rope").with_stiffness(100.0);
    world.add_body("rope", rope).expect("rope");
    let cloth = build::cloth(3, 3, 1.0, 1.0, build::ClothSprings::default())
        .expect("cloth")
        .with_stiffness(100.0)
        .with_pinned(vec![6]);
    world.add_body("cloth", cloth).expect("cloth");
    for _ in 0..20 {
        world.step(1e-3).expect("stable");
    }
    world
}

fn frame_in(world: &World, format: FrameFormat) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = write_frame(dir.path(), 7, world, format).expect("frame");
    std::fs::read_to_string(path).expect("read")
}

fn frame_text(world: &World) -> String {
    frame_in(world, FrameFormat::Vtk)
}

fn read(text: &str) -> VtkFrame {
    read_vtk_frame(text, Path::new("f.vtk")).expect("reads")
}

/// The world's cells in the order of the frames: springs, rods, segments
/// (lines), then triangles.
fn expected_lines(world: &World) -> Vec<Vec<u32>> {
    let mut lines: Vec<Vec<u32>> = world
        .springs_in_scene_order()
        .into_iter()
        .map(|s| world.springs.endpoints(s).to_vec())
        .collect();
    for body in &world.bodies {
        lines.extend(body.segments.iter().map(|s| s.to_vec()));
    }
    lines
}

#[test]
fn frames_carry_kind_body_rest_length_and_strain_per_cell() {
    let world = world();
    let springs = world.springs.len();
    let segments: usize = world.bodies.iter().map(|b| b.segments.len()).sum();
    let faces: usize = world.bodies.iter().map(|b| b.faces.len()).sum();
    assert_eq!(segments, 5, "the ring's outline");
    for format in [FrameFormat::Vtu, FrameFormat::Vtk] {
        let frame = read(&frame_in(&world, format));
        assert_eq!(frame.lines.len(), springs + segments, "{format:?}");
        assert_eq!(frame.polygons.len(), faces);
        let kind = &frame.cell_data["kind"].values;
        let expected_kind: Vec<f64> = std::iter::repeat_n(0.0, springs)
            .chain(std::iter::repeat_n(2.0, segments))
            .chain(std::iter::repeat_n(3.0, faces))
            .collect();
        assert_eq!(kind, &expected_kind);
        let rest = &frame.cell_data["rest_length"].values;
        let in_scene_order = world.springs_in_scene_order();
        let scene_rest: Vec<f64> = in_scene_order
            .iter()
            .map(|&s| world.springs.rest_length[s])
            .collect();
        assert_eq!(&rest[..springs], &scene_rest[..]);
        assert!(
            rest[springs..].iter().all(|&v| v == 0.0),
            "0 off the springs"
        );
        let strain = &frame.cell_data["strain"].values;
        let p = &world.particles.position;
        let spring_strain = |s: usize| {
            let [a, b] = world.springs.endpoints(s);
            let d = p[a as usize].distance(p[b as usize]);
            (d - world.springs.rest_length[s]) / world.springs.rest_length[s]
        };
        for (&s, &value) in in_scene_order.iter().zip(&strain[..springs]) {
            assert_eq!(value, spring_strain(s), "spring {s}");
        }
        // A triangle's strain is the mean of its edges' springs' (each
        // edge of the cloth's triangles has a structural or shear spring).
        let cloth = world.body("cloth").expect("cloth");
        let face = cloth.faces[0];
        let edge = |a: u32, b: u32| {
            (0..springs)
                .find(|&s| {
                    let [x, y] = world.springs.endpoints(s);
                    (x, y) == (a, b) || (x, y) == (b, a)
                })
                .map(spring_strain)
                .expect("a spring on every edge")
        };
        let mean = (edge(face[0], face[1]) + edge(face[1], face[2]) + edge(face[2], face[0])) / 3.0;
        let first_face = springs + segments + world.body("ring").expect("ring").faces.len();
        assert!(
            (strain[first_face] - mean).abs() <= 1e-15,
            "{} vs {mean}",
            strain[first_face]
        );
        assert!(mean != 0.0, "the cloth is stretched under gravity");
        // Each point's and cell's body.
        let body = &frame.point_data["body"].values;
        for (index, b) in world.bodies.iter().enumerate() {
            assert!(body[b.particles.clone()].iter().all(|&v| v == index as f64));
        }
        assert_eq!(frame.field_data["TIME"].values, vec![world.time()]);
    }
}

#[test]
fn spring_cells_come_in_the_scenes_order() {
    // The world stores a body's springs in an order of its own (runs
    // first, for the spring force), which the frames followed: a user
    // reading the `rest_length` or `strain` of spring cell k, or driving
    // spring k by a muscle, counts in the scene's order. Claim: the
    // springs listed [2, 3], [1, 2], [0, 1], [3, 0] come out as cells in
    // that order with their own rest lengths (1 m apart each but the last,
    // 3 m), for a body added after another.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world
        .add_body("before", build::rope(3, 1.0).expect("rope"))
        .expect("rope");
    world
        .add_body("x", common::springs_out_of_order(5.0))
        .expect("valid body");
    let frame = read(&frame_text(&world));
    let rope_springs = world.body("before").expect("rope").springs.len();
    let offset = world.body("x").expect("x").particles.start as u32;
    let cells: Vec<Vec<u32>> = frame.lines[rope_springs..rope_springs + 4]
        .iter()
        .map(|line| line.iter().map(|p| p - offset).collect())
        .collect();
    assert_eq!(cells, vec![vec![2, 3], vec![1, 2], vec![0, 1], vec![3, 0]]);
    let rest = &frame.cell_data["rest_length"].values[rope_springs..rope_springs + 4];
    assert_eq!(rest, &[1.0, 1.0, 1.0, 3.0]);
}

#[test]
fn a_frame_reads_back_exactly() {
    let world = world();
    for format in [FrameFormat::Vtu, FrameFormat::Vtk] {
        let frame = read(&frame_in(&world, format));
        assert_eq!(
            frame.points, world.particles.position,
            "{format:?}: shortest round-trip numbers, or the bits"
        );
        assert_eq!(frame.step, Some(world.steps()));
        assert_eq!(frame.time, Some(world.time()));
        assert_eq!(frame.lines, expected_lines(&world));
        let faces: Vec<Vec<u32>> = world
            .bodies
            .iter()
            .flat_map(|b| b.faces.iter().map(|f| f.to_vec()))
            .collect();
        assert_eq!(frame.polygons, faces);
        let pinned: Vec<f64> = (0..world.particles.len())
            .map(|i| f64::from(u8::from(world.particles.is_pinned(i))))
            .collect();
        assert_eq!(frame.point_scalars("pinned"), Some(&pinned[..]));
        let velocity: Vec<f64> = world
            .particles
            .velocity
            .iter()
            .flat_map(|v| v.to_array())
            .collect();
        assert_eq!(frame.point_data["velocity"].components, 3);
        assert_eq!(frame.point_data["velocity"].values, velocity);
    }
}

/// A `.vtu` frame is a third the size of the legacy one or less (the
/// issue's figure for compressed binary against ASCII), on a cloth.
#[test]
fn vtu_frames_are_compact() {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let cloth = build::cloth(30, 20, 3.0, 2.0, build::ClothSprings::default())
        .expect("cloth")
        .with_stiffness(100.0);
    world.add_body("flag", cloth).expect("cloth");
    for _ in 0..50 {
        world.step(1e-3).expect("stable");
    }
    let (vtu, vtk) = (
        frame_in(&world, FrameFormat::Vtu),
        frame_in(&world, FrameFormat::Vtk),
    );
    assert!(
        3 * vtu.len() <= vtk.len(),
        "{} against {} bytes",
        vtu.len(),
        vtk.len()
    );
}

#[test]
fn other_tools_unstructured_grids_sort_their_cells() {
    // A triangle, a line and a quad, in that order, with their data.
    let text = "# vtk DataFile Version 4.2\nanother tool\nASCII\nDATASET UNSTRUCTURED_GRID\n\
        POINTS 4 float\n0 0 0 1 0 0 1 1 0 0 1 0\n\
        CELLS 3 12\n3 0 1 2\n2 0 2\n4 0 1 2 3\n\
        CELL_TYPES 3\n5\n3\n9\n\
        CELL_DATA 3\nSCALARS id int 1\nLOOKUP_TABLE default\n10 20 30\n";
    let frame = read(text);
    assert_eq!(frame.lines, vec![vec![0, 2]]);
    assert_eq!(frame.polygons, vec![vec![0, 1, 2], vec![0, 1, 2, 3]]);
    assert_eq!(frame.cell_data["id"].values, vec![20.0, 10.0, 30.0]);
    let tetra = text.replace("CELL_TYPES 3\n5\n3\n9", "CELL_TYPES 3\n5\n3\n10");
    let error = read_vtk_frame(&tetra, Path::new("t.vtk")).expect_err("a tetrahedron");
    assert!(error.to_string().contains("cell type 10"), "{error}");
}

#[test]
fn other_tools_polydata_with_field_data_and_quads_reads() {
    let text = "# vtk DataFile Version 2.0\nfrom another tool\nascii\nDATASET POLYDATA\n\
        POINTS 4 float\n0 0 0 1 0 0\n1 1 0 0 1 0\n\
        POLYGONS 1 5\n4 0 1 2 3\n\
        CELL_DATA 1\nSCALARS id int 1\nLOOKUP_TABLE default\n7\n\
        POINT_DATA 4\nNORMALS n float\n0 0 1 0 0 1 0 0 1 0 0 1\n\
        FIELD extra 1\nweight 1 4 double\n1 2 3 4\n\
        SCALARS colour float 3\nLOOKUP_TABLE default\n0 0 0 1 1 1 0 0 0 1 1 1\n";
    let frame = read(text);
    assert_eq!(frame.points.len(), 4);
    assert_eq!(frame.polygons, vec![vec![0, 1, 2, 3]]);
    assert_eq!(frame.cell_data["id"].values, vec![7.0]);
    assert_eq!(frame.point_data["weight"].values, vec![1.0, 2.0, 3.0, 4.0]);
    assert_eq!(frame.point_data["colour"].components, 3);
    assert_eq!(frame.time, None);
}

/// Replace the first occurrence of `from` by `to` in a valid frame, read
/// it, and expect an error at `line` containing `needle`.
fn broken(text: &str, from: &str, to: &str, needle: &str) {
    assert!(text.contains(from), "{from:?} not in the frame");
    let bad = text.replacen(from, to, 1);
    let line = bad[..bad.find(to).expect("replaced")].matches('\n').count() + 1;
    let error = read_vtk_frame(&bad, Path::new("dir/frame_000003.vtk")).expect_err(to);
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("dir/frame_000003.vtk:{}:", error.line)),
        "{message}"
    );
    assert!(message.contains(needle), "{to:?}: {message}");
    assert!(
        error.line == line || error.line == line + 1,
        "{to:?}: line {} for a change on line {line}: {message}",
        error.line
    );
}

#[test]
fn malformed_frames_are_errors_naming_file_and_line() {
    let text = frame_text(&world());
    broken(
        &text,
        "# vtk DataFile",
        "# not vtk",
        "not a legacy VTK file",
    );
    broken(&text, "ASCII", "BINARY", "only ASCII");
    broken(
        &text,
        "UNSTRUCTURED_GRID",
        "STRUCTURED_POINTS",
        "only POLYDATA and UNSTRUCTURED_GRID",
    );
    broken(&text, "POINTS 17", "POINTS x7", "not a count");
    broken(&text, "\nCELLS", "\nCELLZ", "unknown section \"CELLZ\"");
    broken(&text, "CELL_TYPES", "CELL_TYPEZ", "unknown section");
    broken(
        &text,
        "\n2 0 1\n",
        "\n2 0 999\n",
        "point index 999 out of range",
    );
    broken(&text, "\n2 0 1\n", "\n2 0 -1\n", "not a point index");
    broken(
        &text,
        "POINT_DATA 17",
        "POINT_DATA 16",
        "data for 16 points, but the file has 17",
    );
    broken(
        &text,
        "LOOKUP_TABLE default\n0",
        "LOOKUP_TABLE default\nzero",
        "not a number",
    );
    broken(
        &text,
        "SCALARS pinned int 1\nLOOKUP_TABLE",
        "SCALARS pinned int 1\nTABLE",
        "expected LOOKUP_TABLE",
    );
    // A non-finite point.
    let lines: Vec<&str> = text.lines().collect();
    let first_point = lines[lines
        .iter()
        .position(|l| l.starts_with("POINTS"))
        .expect("points")
        + 1];
    broken(&text, first_point, "nan 0 0", "not finite");
}

#[test]
fn truncated_or_scrambled_frames_never_panic() {
    let text = frame_text(&world());
    let mut cuts = 0;
    for end in (0..text.len()).filter(|&i| text.is_char_boundary(i)) {
        let cut = &text[..end];
        // A cut inside the last values can still be a valid, shorter
        // number; anything else must be an error, never a panic.
        if read_vtk_frame(cut, Path::new("cut.vtk")).is_err() {
            cuts += 1;
        }
    }
    assert!(cuts > text.len() / 2, "most cuts are errors");
    // Every seventh token after the title replaced in turn by a huge
    // count or garbage.
    let mut lines = text.lines();
    let header = format!(
        "{}\n{}\n",
        lines.next().expect("header"),
        lines.next().expect("title")
    );
    let tokens: Vec<&str> = lines.flat_map(str::split_whitespace).collect();
    for k in (0..tokens.len()).step_by(7) {
        for junk in ["18446744073709551615", "-", "1e999", "4294967296", "nan"] {
            let mut scrambled = tokens.clone();
            scrambled[k] = junk;
            let joined = format!("{header}{}", scrambled.join("\n"));
            let _ = read_vtk_frame(&joined, Path::new("junk.vtk"));
        }
    }
}

/// A `.vtu` frame damaged in its structure or its data is an error naming
/// the file and line; cut anywhere, it never panics.
#[test]
fn damaged_vtu_frames_are_errors() {
    let text = frame_in(&world(), FrameFormat::Vtu);
    let fail = |bad: &str, needle: &str| {
        let error = read_vtk_frame(bad, Path::new("f.vtu")).expect_err(needle);
        assert!(error.to_string().contains(needle), "{needle}: {error}");
    };
    fail(
        &text.replace("UnstructuredGrid\"", "PolyData\""),
        "only UnstructuredGrid",
    );
    fail(
        &text.replace("vtkZLibDataCompressor", "vtkLZ4DataCompressor"),
        "zlib only",
    );
    fail(
        &text.replace("NumberOfPoints=\"17\"", "NumberOfPoints=\"18\""),
        "tuples",
    );
    fail(
        &text.replace("format=\"binary\">\n", "format=\"binary\">\n!!"),
        "base64",
    );
    fail(
        &text.replace("Name=\"offsets\"", "Name=\"offsetz\""),
        "connectivity, offsets and types",
    );
    for end in (0..text.len()).step_by(97) {
        let _ = read_vtk_frame(&text[..end], Path::new("cut.vtu"));
    }
    // Flipped characters in the base64 text: an error or different
    // numbers, never a panic.
    let bytes = text.as_bytes();
    for at in (0..bytes.len()).step_by(31) {
        let mut damaged = bytes.to_vec();
        damaged[at] = if damaged[at] == b'A' { b'B' } else { b'A' };
        if let Ok(damaged) = String::from_utf8(damaged) {
            let _ = read_vtk_frame(&damaged, Path::new("flip.vtu"));
        }
    }
}

/// Hostile `.vtu` arrays found by review: a short block header, a last
/// block larger than the blocks, counts whose product overflows, no points.
#[test]
fn hostile_vtu_headers_are_errors_not_panics() {
    let text = frame_in(&world(), FrameFormat::Vtu);
    let start = text.find("format=\"binary\">\n").expect("an array") + "format=\"binary\">\n".len();
    let end = start + text[start..].find('\n').expect("its line");
    let replace = |with: &str| format!("{}{with}{}", &text[..start], &text[end..]);
    use base64::Engine as _;
    let encode = |numbers: &[u64]| {
        let bytes: Vec<u8> = numbers.iter().flat_map(|n| n.to_le_bytes()).collect();
        base64::engine::general_purpose::STANDARD.encode(bytes)
    };
    for bad in [
        "AAAAAAAAAAAAAA==".to_string(),
        encode(&[1, 1, 1 << 62]),
        encode(&[u64::MAX, 1, 0]),
        format!("{}{}", encode(&[1, 8, 0]), "AAAA"),
    ] {
        let result = read_vtk_frame(&replace(&bad), Path::new("h.vtu"));
        assert!(result.is_err(), "{bad}");
    }
    let overflow = text.replacen(
        "NumberOfPoints=\"17\"",
        "NumberOfPoints=\"9223372036854775809\"",
        1,
    );
    assert!(read_vtk_frame(&overflow, Path::new("o.vtu")).is_err());
    let points_start = text.find("<Points>").expect("points");
    let points_end = text.find("</Points>").expect("points") + "</Points>".len();
    let no_points = format!("{}{}", &text[..points_start], &text[points_end..]);
    let error = read_vtk_frame(&no_points, Path::new("n.vtu")).expect_err("no points");
    assert!(error.to_string().contains("declares 17 points"), "{error}");
}
