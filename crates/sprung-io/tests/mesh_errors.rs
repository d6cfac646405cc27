//! Broken mesh files: each is refused with an error that names the file,
//! the line where there is one, the object where there is one, and the
//! problem.

mod common;

use common::mesh_path;

use std::path::Path;

use sprung_io::mesh::{parse_mesh, MeshError, MeshErrorKind, MeshFormat, TriangleMesh};

fn mesh_text(name: &str) -> String {
    let path = mesh_path(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Parses `text` as the format of `file` and returns the error.
fn error_of(text: &str, file: &str) -> MeshError {
    error_of_bytes(text.as_bytes(), file)
}

fn error_of_bytes(bytes: &[u8], file: &str) -> MeshError {
    let path = Path::new(file);
    let format = MeshFormat::from_path(path).unwrap_or_else(|e| panic!("{e}"));
    match parse_mesh(bytes, format, path) {
        Ok(meshes) => panic!("{file}: accepted: {:?}", summary(&meshes)),
        Err(e) => e,
    }
}

fn summary(meshes: &[TriangleMesh]) -> Vec<(String, usize, usize)> {
    meshes
        .iter()
        .map(|m| (m.name.clone(), m.positions.len(), m.triangles.len()))
        .collect()
}

/// `text` with its 1-based line `number` replaced.
fn with_line(text: &str, number: usize, line: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[number - 1] = line;
    lines.join("\n") + "\n"
}

/// The first `count` lines of `text`.
fn first_lines(text: &str, count: usize) -> String {
    text.lines().take(count).collect::<Vec<_>>().join("\n") + "\n"
}

// cube.asc: line 2 is the `Tri-mesh` header, lines 4-11 vertices 0-7,
// line 12 `Face list:`, line 13 face 0, then `Smoothing` and faces in turn.

#[test]
fn asc_face_index_out_of_range() {
    let text = with_line(
        &mesh_text("cube.asc"),
        13,
        "Face 0: A:9 B:1 C:2 AB:1 BC:1 CA:1",
    );
    assert_eq!(
        error_of(&text, "cube.asc").to_string(),
        "cube.asc:13: object \"Cube\": face 0 vertex index 9 out of range (8 vertices)"
    );
}

#[test]
fn asc_face_with_a_vertex_twice() {
    let text = with_line(
        &mesh_text("cube.asc"),
        13,
        "Face 0: A:2 B:1 C:2 AB:1 BC:1 CA:1",
    );
    assert_eq!(
        error_of(&text, "cube.asc").to_string(),
        "cube.asc:13: object \"Cube\": face 0: vertex 2 is listed twice; a face needs distinct vertices"
    );
}

#[test]
fn asc_counts_that_disagree_with_the_header() {
    let cube = mesh_text("cube.asc");
    let text = with_line(&cube, 2, "Tri-mesh, Vertices: 9 Faces: 12");
    assert_eq!(
        error_of(&text, "cube.asc").to_string(),
        "cube.asc:2: object \"Cube\": the header declares 9 vertices, the file has 8"
    );
    let text = with_line(&cube, 2, "Tri-mesh, Vertices: 8 Faces: 11");
    assert_eq!(
        error_of(&text, "cube.asc").to_string(),
        "cube.asc:35: object \"Cube\": face 11 is beyond the 11 faces the header declares"
    );
    // A vertex listed twice (a duplicated line).
    let text = with_line(&cube, 6, "Vertex 1: X:-1.0 Y:-1.0 Z:1.0");
    assert_eq!(
        error_of(&text, "cube.asc").to_string(),
        "cube.asc:6: object \"Cube\": vertex 1 is listed twice"
    );
}

#[test]
fn asc_truncated_file() {
    let cube = mesh_text("cube.asc");
    // Cut after line 8 (vertex 4).
    let err = error_of(&first_lines(&cube, 8), "cube.asc");
    assert!(matches!(err.kind, MeshErrorKind::Truncated(_)), "{err}");
    assert_eq!(
        err.to_string(),
        "cube.asc:8: object \"Cube\": the file ends early (truncated?): after 5 of the 8 \
         vertices the `Tri-mesh` header on line 2 declares"
    );
    // Cut in the middle of line 8.
    let cut = &cube[..cube.find("Vertex 4").unwrap() + 20];
    let err = error_of(cut, "cube.asc");
    assert_eq!(err.line, Some(8), "{err}");
    assert!(err.to_string().contains("field Z: missing"), "{err}");
    // Cut in the face list.
    let err = error_of(&first_lines(&cube, 20), "cube.asc");
    assert!(
        err.to_string()
            .contains("truncated?): after 4 of the 12 faces"),
        "{err}"
    );
}

#[test]
fn asc_coordinates_that_are_not_finite() {
    let cube = mesh_text("cube.asc");
    for (value, line) in [("nan", 4), ("inf", 5), ("1e999", 11)] {
        let text = with_line(
            &cube,
            line,
            &format!("Vertex {}: X:{value} Y:1.0 Z:1.0", line - 4),
        );
        assert_eq!(
            error_of(&text, "cube.asc").to_string(),
            format!(
                "cube.asc:{line}: object \"Cube\": coordinate \"{value}\" is not a finite number"
            )
        );
    }
}

#[test]
fn asc_structure_errors() {
    let err = error_of("Vertex 0: X:1 Y:2 Z:3\n", "loose.asc");
    assert_eq!(
        err.to_string(),
        "loose.asc:1: vertex or face data outside a `Tri-mesh` object"
    );
    let lights_only = "Ambient light color: Red=0.3 Green=0.3 Blue=0.3\r\n\r\n\
                       Named object: \"Light01\"\r\nDirect light\r\n\
                       Position:  X:426.159027 Y:1339.46167 Z:-934.576965\r\n";
    assert_eq!(
        error_of(lights_only, "lights.asc").kind,
        MeshErrorKind::NoMesh
    );
    let text = "Named object: \"T\"\nTri-mesh, Vertices: 3 Faces: 1\nVertex list:\n\
                Vertex 0: X:0 Y:0 Z:0\nVertex 1: X:1 Y:0 Z:0 W:4\n";
    assert_eq!(
        error_of(text, "w.asc").to_string(),
        "w.asc:5: object \"T\": vertex: unexpected field \"W:\""
    );
}

#[test]
fn text_that_is_not_utf8() {
    let mut bytes = mesh_text("cube.asc").into_bytes();
    // Offset of line 3: just after the second line feed.
    let third_line = 1 + bytes
        .iter()
        .enumerate()
        .filter(|(_, &b)| b == b'\n')
        .nth(1)
        .unwrap()
        .0;
    bytes.insert(third_line + 3, 0xFF);
    let err = error_of_bytes(&bytes, "cube.asc");
    assert_eq!(
        err.kind,
        MeshErrorKind::NotUtf8 {
            offset: third_line + 3
        }
    );
    assert!(
        err.to_string().starts_with("cube.asc:3: not UTF-8 text"),
        "{err}"
    );

    for file in ["latin1.obj", "latin1.off", "latin1.stl"] {
        let err = error_of_bytes(b"solid \xE9t\xE9\nv 1 2 3\n", file);
        assert!(
            matches!(err.kind, MeshErrorKind::NotUtf8 { .. }),
            "{file}: {err}"
        );
        assert_eq!(err.line, Some(1), "{file}");
    }
}

#[test]
fn empty_files() {
    for file in ["e.asc", "e.obj", "e.off", "e.stl"] {
        for content in ["", " \r\n\n\t\n"] {
            let err = error_of(content, file);
            assert_eq!(err.to_string(), format!("{file}: the file is empty"));
        }
    }
}

#[test]
fn obj_errors_name_the_line() {
    let good = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let cases = [
        (
            with_line(good, 3, "v 0 1"),
            "t.obj:3: a vertex needs 3 coordinates, found 2",
        ),
        (
            with_line(good, 1, "v nan 0 0"),
            "t.obj:1: coordinate \"nan\" is not a finite number",
        ),
        (
            with_line(good, 2, "v 1 x 0"),
            "t.obj:2: expected a number, found \"x\"",
        ),
        (
            with_line(good, 4, "f 1 2 4"),
            "t.obj:4: face 0 vertex index 4 out of range (3 vertices)",
        ),
        (
            with_line(good, 4, "f 1 2 -4"),
            "t.obj:4: face 0 vertex index -4 out of range (3 vertices)",
        ),
        (
            with_line(good, 4, "f 0 1 2"),
            "t.obj:4: face 0: vertex index 0 (OBJ indices start at 1)",
        ),
        (
            with_line(good, 4, "f 1/1 2/1 3/1"),
            "t.obj:4: face 0: texture coordinate index 1 out of range (0 texture coordinates)",
        ),
        (
            with_line(good, 4, "f 1 2"),
            "t.obj:4: face 0 has 2 corners; a face needs at least 3",
        ),
        // A vertex twice in a face, also when counted back from the last.
        (
            with_line(good, 4, "f 1 1 2"),
            "t.obj:4: face 0: vertex 1 is listed twice (as \"1\"); a face needs distinct vertices",
        ),
        (
            with_line(good, 4, "f 1 2 -1 3"),
            "t.obj:4: face 0: vertex 3 is listed twice (as \"3\"); a face needs distinct vertices",
        ),
        (
            with_line(good, 4, "f 1 2 99999999999999999999"),
            "t.obj:4: face 0: expected a vertex index, found \"99999999999999999999\"",
        ),
        (
            "v 0 0 0\n# no faces\n".to_owned(),
            "t.obj: no triangle mesh in the file",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(error_of(&text, "t.obj").to_string(), expected);
    }
}

#[test]
fn off_errors_name_the_line() {
    let sphere = mesh_text("sphere_low.off");
    let lines = sphere.lines().count();
    // Line 1 `OFF`, line 2 the counts, then 589 vertex and 1174 face lines.
    assert_eq!(lines, 2 + 589 + 1174);

    let err = error_of(&first_lines(&sphere, lines - 10), "s.off");
    assert_eq!(
        err.to_string(),
        "s.off:2: the file ends early (truncated?): the header declares 589 vertices and 1174 faces, a line each, but 1753 lines of data follow"
    );
    let err = error_of(&(sphere.clone() + "3 0 1 2\n"), "s.off");
    assert_eq!(err.line, Some(lines + 1), "{err}");
    assert!(
        err.to_string()
            .contains("data after the 589 vertices and 1174 faces"),
        "{err}"
    );
    let err = error_of(&with_line(&sphere, 2, "589 1175 0"), "s.off");
    assert!(matches!(err.kind, MeshErrorKind::Truncated(_)), "{err}");

    let small = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    let cases = [
        // More vertices than the file has lines: the count is named at the
        // header, not the face line read as a vertex.
        (
            with_line(small, 2, "1000000000000 1 0"),
            "t.off:2: the file ends early (truncated?): the header declares 1000000000000 \
             vertices and 1 faces, a line each, but 4 lines of data follow",
        ),
        (
            with_line(small, 6, "3 0 1 3"),
            "t.off:6: face 0 vertex index 3 out of range (3 vertices)",
        ),
        (
            with_line(small, 4, "1 NaN 0"),
            "t.off:4: coordinate \"NaN\" is not a finite number",
        ),
        (
            with_line(small, 4, "1 0"),
            "t.off:4: vertex 1: expected 3 coordinates, found 2 words",
        ),
        (
            with_line(small, 6, "3 0 1"),
            "t.off:6: face 0 declares 3 vertices but lists 2",
        ),
        (
            with_line(small, 6, "2 0 1"),
            "t.off:6: face 0 has 2 vertices; a face needs at least 3",
        ),
        (
            with_line(small, 6, "3 0 1 1"),
            "t.off:6: face 0: vertex 1 is listed twice; a face needs distinct vertices",
        ),
        (
            with_line(small, 1, "PLY"),
            "t.off:1: expected the header `OFF`, found \"PLY\"",
        ),
        (
            with_line(small, 2, "3 -1 0"),
            "t.off:2: expected a face count (a non-negative integer), found \"-1\"",
        ),
    ];
    for (text, expected) in cases {
        assert_eq!(error_of(&text, "t.off").to_string(), expected);
    }
}

#[test]
fn stl_errors() {
    let ico = mesh_text("icosahedron_ascii.stl");
    // Cut after line 10, inside the second facet.
    let err = error_of(&first_lines(&ico, 10), "i.stl");
    assert_eq!(
        err.to_string(),
        "i.stl:10: the file ends early (truncated?): inside a solid, before its `endsolid`"
    );
    // Line 4 is the first `vertex` line.
    let err = error_of(&with_line(&ico, 4, "vertex 0 nan 0"), "i.stl");
    assert_eq!(
        err.to_string(),
        "i.stl:4: coordinate \"nan\" is not a finite number"
    );
    let err = error_of(&with_line(&ico, 4, "vertex 0 0"), "i.stl");
    assert_eq!(
        err.to_string(),
        "i.stl:4: a vertex needs 3 coordinates, found 2"
    );
    let err = error_of(&with_line(&ico, 6, "vertex 1 2 3\nvertex 1 2 4"), "i.stl");
    assert_eq!(err.line, Some(7), "{err}");
    assert!(err.to_string().contains("more than 3 vertices"), "{err}");

    // Binary: one triangle, then damaged.
    let mut binary = vec![0u8; 80];
    binary.extend(1u32.to_le_bytes());
    binary.extend([0u8; 12]);
    for c in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        binary.extend(c.to_le_bytes());
    }
    binary.extend([0u8; 2]);
    assert!(parse_mesh(&binary, MeshFormat::Stl, Path::new("b.stl")).is_ok());

    let err = error_of_bytes(&binary[..binary.len() - 7], "b.stl");
    assert_eq!(
        err.to_string(),
        "b.stl: not an ASCII STL (it does not start with `solid`), and as binary STL its \
         header declares 1 triangles, which needs 134 bytes, but the file has 127 (truncated?)"
    );
    // Longer than the count needs: not called truncated.
    let mut padded = binary.clone();
    padded.extend([0u8; 4]);
    let err = error_of_bytes(&padded, "b.stl");
    assert!(
        err.to_string().ends_with(
            "which needs 134 bytes, but the file has 138 (bytes after the last triangle, or a wrong count?)"
        ),
        "{err}"
    );
    let mut nan = binary.clone();
    nan[84 + 12 + 16..84 + 12 + 20].copy_from_slice(&f32::NAN.to_le_bytes());
    let err = error_of_bytes(&nan, "b.stl");
    assert_eq!(
        err.to_string(),
        "b.stl: triangle 0, corner 1: coordinate NaN is not a finite number"
    );
    let err = error_of_bytes(&binary[..84], "b.stl");
    assert_eq!(err.to_string(), "b.stl: not an ASCII STL (it does not start with `solid`), and as binary STL its header declares 1 triangles, which needs 134 bytes, but the file has 84 (truncated?)");
    let err = error_of_bytes(b"hello", "b.stl");
    assert!(
        err.to_string()
            .contains("less than the 84 of a binary STL header"),
        "{err}"
    );
}
