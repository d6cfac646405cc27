//! Object File Format (`.off`), as used by Geomview, CGAL and PMP.
//!
//! ```text
//! OFF                 # header; the counts may follow on the same line
//! 589 1174 0          # vertices, faces, edges (the edge count is ignored)
//! 0.17 -0.03 -0.22    # one vertex per line: x y z
//! 3 0 1 2             # one face per line: n, then n 0-based vertex indices
//! ```
//!
//! `#` starts a comment; blank lines are skipped. Polygons are split into a
//! fan of triangles around their first vertex, which is exact for convex
//! planar polygons. Words after a face's indices (a colour) are ignored.
//! Counts that disagree with the data, indices out of range, coordinates
//! that are not finite numbers and a file that ends early are errors. The
//! variants with colours or normals on vertex lines (`COFF`, `NOFF`...)
//! are not read. The object is named after the file stem.

use std::path::Path;

use super::error::{MeshError, MeshErrorKind};
use super::text::{coordinate, lines, require_content, shown, stem_name, syntax, unsigned};
use super::TriangleMesh;

/// Reads the single mesh of an OFF file.
///
/// Positions are in the file's units. `file` is used in error messages and
/// its stem names the object.
pub fn parse_off(text: &str, file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    require_content(text, file)?;
    let err = |kind: MeshErrorKind, line: usize| MeshError::new(file, kind).at_line(line);

    // Data lines: comments removed, blank lines skipped, 1-based numbers kept.
    let data: Vec<(usize, &str)> = lines(text)
        .filter_map(|(line, raw)| {
            let data = raw.split('#').next().unwrap_or("").trim();
            (!data.is_empty()).then_some((line, data))
        })
        .collect();
    let mut data_lines = data.iter().copied();

    let (header_line, header) = data_lines
        .next()
        .ok_or_else(|| MeshError::new(file, MeshErrorKind::Empty))?;
    let mut header_words = header.split_whitespace();
    if header_words.next() != Some("OFF") {
        return Err(err(
            syntax(format!(
                "expected the header `OFF`, found {}",
                shown(header)
            )),
            header_line,
        ));
    }
    let header_rest: Vec<&str> = header_words.collect();
    let (counts_line, counts): (usize, Vec<&str>) = if header_rest.is_empty() {
        let (n, text) = data_lines.next().ok_or_else(|| {
            err(
                MeshErrorKind::Truncated("no counts after the `OFF` header".into()),
                header_line,
            )
        })?;
        (n, text.split_whitespace().collect())
    } else {
        (header_line, header_rest)
    };
    let (vertex_count, face_count) = match counts.as_slice() {
        [v, f] | [v, f, _] => (
            unsigned(v, "a vertex count").map_err(|k| err(k, counts_line))?,
            unsigned(f, "a face count").map_err(|k| err(k, counts_line))?,
        ),
        _ => {
            return Err(err(
                syntax(format!(
                    "expected the counts `vertices faces edges`, found {} words",
                    counts.len()
                )),
                counts_line,
            ))
        }
    };
    if let [_, _, edges] = counts.as_slice() {
        unsigned(edges, "an edge count").map_err(|k| err(k, counts_line))?;
    }

    // Each vertex and each face takes a data line of its own: counts
    // beyond the lines that follow are refused here, at the header, rather
    // than by reading faces as vertices.
    let data_left = data_lines.len();
    if vertex_count.saturating_add(face_count) > data_left {
        return Err(err(
            MeshErrorKind::Truncated(format!(
                "the header declares {vertex_count} vertices and {face_count} faces, \
                 a line each, but {data_left} lines of data follow"
            )),
            counts_line,
        ));
    }

    let truncated = |found: usize, declared: usize, what: &str| {
        err(
            MeshErrorKind::Truncated(format!(
                "after {found} of the {declared} {what} declared on line {counts_line}"
            )),
            counts_line,
        )
    };

    let mut positions = Vec::new();
    while positions.len() < vertex_count {
        let (line, data) = data_lines
            .next()
            .ok_or_else(|| truncated(positions.len(), vertex_count, "vertices"))?;
        let words: Vec<&str> = data.split_whitespace().collect();
        let [x, y, z] = words.as_slice() else {
            return Err(err(
                syntax(format!(
                    "vertex {}: expected 3 coordinates, found {} words",
                    positions.len(),
                    words.len()
                )),
                line,
            ));
        };
        let point = [coordinate(x), coordinate(y), coordinate(z)];
        let mut p = [0.0; 3];
        for (slot, value) in p.iter_mut().zip(point) {
            *slot = value.map_err(|k| err(k, line))?;
        }
        positions.push(p);
    }

    let mut triangles = Vec::new();
    let mut faces_read = 0;
    while faces_read < face_count {
        let (line, data) = data_lines
            .next()
            .ok_or_else(|| truncated(faces_read, face_count, "faces"))?;
        face(data, faces_read, vertex_count, &mut triangles).map_err(|k| err(k, line))?;
        faces_read += 1;
    }

    if let Some((line, _)) = data_lines.next() {
        return Err(err(
            syntax(format!(
                "data after the {vertex_count} vertices and {face_count} faces \
                 the header declares on line {counts_line}"
            )),
            line,
        ));
    }
    Ok(vec![TriangleMesh {
        name: stem_name(file),
        positions,
        triangles,
    }])
}

/// Reads face number `face` (`n i0 i1 ...`) and appends its fan triangles.
fn face(
    data: &str,
    face: usize,
    vertex_count: usize,
    triangles: &mut Vec<[usize; 3]>,
) -> Result<(), MeshErrorKind> {
    let mut words = data.split_whitespace();
    let n = unsigned(words.next().unwrap_or(""), "the face's vertex count")?;
    if n < 3 {
        return Err(syntax(format!(
            "face {face} has {n} vertices; a face needs at least 3"
        )));
    }
    let mut corners = Vec::with_capacity(n.min(64));
    for k in 0..n {
        let word = words
            .next()
            .ok_or_else(|| syntax(format!("face {face} declares {n} vertices but lists {k}")))?;
        let index = unsigned(word, "a vertex index")?;
        if index >= vertex_count {
            return Err(MeshErrorKind::IndexOutOfRange {
                face,
                index: i64::try_from(index).unwrap_or(i64::MAX),
                vertices: vertex_count,
            });
        }
        if corners.contains(&index) {
            return Err(syntax(format!(
                "face {face}: vertex {index} is listed twice; a face needs distinct vertices"
            )));
        }
        corners.push(index);
    }
    if let Some((&first, rest)) = corners.split_first() {
        for pair in rest.windows(2) {
            if let [b, c] = *pair {
                triangles.push([first, b, c]);
            }
        }
    }
    Ok(())
}
