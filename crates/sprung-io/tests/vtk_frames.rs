//! VTK frames: what `write_frame` puts in them (rest lengths, strain and
//! 2D outlines as cell data) and `read_vtk_frame` reading them back
//! exactly; malformed files are errors naming the file and line, never
//! panics.

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

fn frame_text(world: &World) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = write_frame(dir.path(), 7, world, FrameFormat::Vtk).expect("frame");
    std::fs::read_to_string(path).expect("read")
}

fn read(text: &str) -> VtkFrame {
    read_vtk_frame(text, Path::new("f.vtk")).expect("reads")
}

#[test]
fn frames_carry_rest_length_strain_and_outline_per_cell() {
    let world = world();
    let text = frame_text(&world);
    let springs = world.springs.len();
    let faces: usize = world.bodies.iter().map(|b| b.faces.len()).sum();
    assert!(text.contains(&format!("POINTS {} double", world.particles.len())));
    assert!(text.contains(&format!("LINES {springs} {}", 3 * springs)));
    assert!(text.contains(&format!("CELL_DATA {}", springs + faces)));
    let frame = read(&text);
    assert_eq!(
        frame.line_scalars("rest_length"),
        Some(&world.springs.rest_length[..])
    );
    let all = &frame.cell_data["rest_length"].values;
    assert!(all[springs..].iter().all(|&v| v == 0.0), "0 for polygons");
    let strain = frame.line_scalars("strain").expect("strain");
    for s in 0..springs {
        let p = &world.particles.position;
        let d =
            p[world.springs.first()[s] as usize].distance(p[world.springs.second()[s] as usize]);
        let expected = (d - world.springs.rest_length[s]) / world.springs.rest_length[s];
        assert_eq!(strain[s], expected);
    }
    // The ring's 5 springs are its outline; no other spring is.
    let outline = frame.line_scalars("outline").expect("outline");
    let ring = world.body("ring").expect("ring").springs.clone();
    for (s, &flag) in outline.iter().enumerate() {
        assert_eq!(flag == 1.0, ring.contains(&s), "spring {s}");
    }
}

#[test]
fn a_frame_reads_back_exactly() {
    let world = world();
    let frame = read(&frame_text(&world));
    assert_eq!(
        frame.points, world.particles.position,
        "shortest round-trip numbers"
    );
    assert_eq!(frame.step, Some(world.steps()));
    assert_eq!(frame.time, Some(world.time()));
    let lines: Vec<Vec<u32>> = (0..world.springs.len())
        .map(|s| vec![world.springs.first()[s], world.springs.second()[s]])
        .collect();
    assert_eq!(frame.lines, lines);
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
    assert_eq!(frame.point_data["velocity"].components, 3);
    assert_eq!(
        frame.point_data["velocity"].values.len(),
        3 * world.particles.len()
    );
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
    broken(&text, "POLYDATA", "UNSTRUCTURED_GRID", "only POLYDATA");
    broken(&text, "POINTS 17", "POINTS x7", "not a count");
    broken(&text, "\nLINES", "\nLINEZ", "unknown section \"LINEZ\"");
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
    let first_point = lines[5];
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
