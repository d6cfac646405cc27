//! STL (stereolithography), ASCII and binary.
//!
//! STL stores every triangle with its own three corners, so a closed surface
//! arrives as a soup of unconnected triangles. The reader welds corners whose
//! coordinates are exactly equal (`-0.0` and `0.0` count as equal), which
//! restores the connectivity of files written from an indexed mesh. It does
//! not merge corners that are merely close. A facet two of whose corners
//! weld into one vertex has no area (a sliver collapsed to a line or a
//! point, common in exported STL files) and is left out: its edges are an
//! edge of its neighbours' taken there and back, so leaving it out keeps a
//! closed surface closed. Facet normals are ignored: the
//! orientation comes from the corner order (counter-clockwise seen from
//! outside, as the format requires).
//!
//! * Binary: an 80-byte header, a little-endian `u32` triangle count `n`,
//!   then `n` records of 50 bytes (normal and three corners as 12 `f32`, and
//!   a 2-byte attribute). A file is taken as binary when its size is exactly
//!   `84 + 50 n`, whatever its first bytes: some binary writers start the
//!   header with `solid`, and an ASCII file cannot match that size by chance
//!   (its bytes 80..84 are text, which makes `n` hundreds of millions).
//! * ASCII: `solid name`, then `facet normal nx ny nz` / `outer loop` /
//!   three `vertex x y z` / `endloop` / `endfacet`, and `endsolid name`.
//!   Several solids in one file give several objects.
//!
//! The reader is written by hand rather than taken from a crate: it is
//! short, and it lets every error name the line (ASCII) or the triangle
//! (binary) and refuse non-finite coordinates, which a general STL crate
//! does not report that way.

use std::collections::HashMap;
use std::path::Path;

use super::error::{MeshError, MeshErrorKind};
use super::text::{coordinate, decode, lines, shown, stem_name, syntax};
use super::topology::is_degenerate;
use super::TriangleMesh;

/// Reads an STL file, ASCII or binary, welding exactly equal corners.
///
/// Positions are in the file's units. `file` is used in error messages; its
/// stem names a binary file's single object, and an ASCII solid without a
/// name.
pub fn parse_stl(bytes: &[u8], file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    if bytes.iter().all(u8::is_ascii_whitespace) {
        return Err(MeshError::new(file, MeshErrorKind::Empty));
    }
    if let Some(count) = binary_count(bytes) {
        return parse_binary(bytes, count, file);
    }
    let starts_solid = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .and_then(|start| bytes.get(start..start + 5))
        .is_some_and(|word| word.eq_ignore_ascii_case(b"solid"));
    if starts_solid {
        return parse_ascii(decode(bytes, file)?, file);
    }
    let detail = match read_u32(bytes, 80) {
        Some(n) => {
            let needs = 84 + 50 * u64::from(n);
            let has = bytes.len() as u64;
            let why = if has < needs {
                "truncated?"
            } else {
                "bytes after the last triangle, or a wrong count?"
            };
            format!(
                "as binary STL its header declares {n} triangles, which needs {needs} bytes, \
                 but the file has {has} ({why})"
            )
        }
        None => format!(
            "the file has {} bytes, less than the 84 of a binary STL header",
            bytes.len()
        ),
    };
    Err(MeshError::new(
        file,
        syntax(format!(
            "not an ASCII STL (it does not start with `solid`), and {detail}"
        )),
    ))
}

/// The triangle count if `bytes` has exactly the size of a binary STL.
fn binary_count(bytes: &[u8]) -> Option<usize> {
    let n = read_u32(bytes, 80)?;
    let expected = 84 + 50 * u64::from(n);
    (u64::try_from(bytes.len()).ok()? == expected)
        .then(|| usize::try_from(n).ok())
        .flatten()
}

fn read_u32(bytes: &[u8], at: usize) -> Option<u32> {
    let word: [u8; 4] = bytes.get(at..at.checked_add(4)?)?.try_into().ok()?;
    Some(u32::from_le_bytes(word))
}

fn read_f32(bytes: &[u8], at: usize) -> Option<f32> {
    let word: [u8; 4] = bytes.get(at..at.checked_add(4)?)?.try_into().ok()?;
    Some(f32::from_le_bytes(word))
}

fn parse_binary(bytes: &[u8], count: usize, file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    let records = bytes.get(84..).unwrap_or_default();
    let mut welder = Welder::default();
    let mut triangles = Vec::with_capacity(count);
    for (t, record) in records.chunks_exact(50).enumerate() {
        let mut triangle = [0usize; 3];
        for (corner, slot) in triangle.iter_mut().enumerate() {
            let mut p = [0.0f64; 3];
            for (axis, value) in p.iter_mut().enumerate() {
                let at = 12 + 12 * corner + 4 * axis;
                let v = read_f32(record, at).ok_or_else(|| {
                    MeshError::new(file, MeshErrorKind::Truncated(format!("triangle {t}")))
                })?;
                if !v.is_finite() {
                    return Err(MeshError::new(
                        file,
                        syntax(format!(
                            "triangle {t}, corner {corner}: coordinate {v} is not a finite number"
                        )),
                    ));
                }
                *value = f64::from(v);
            }
            *slot = welder.index(p);
        }
        if !is_degenerate(&triangle) {
            triangles.push(triangle);
        }
    }
    if triangles.is_empty() {
        return Err(MeshError::new(file, MeshErrorKind::NoMesh));
    }
    let (positions, triangles) = used_only(welder.positions, triangles);
    Ok(vec![TriangleMesh {
        name: stem_name(file),
        positions,
        triangles,
    }])
}

/// The vertices some triangle uses, in their order, and the triangles
/// numbered among them: a corner only a left-out sliver had would be a
/// particle of no triangle.
fn used_only(
    positions: Vec<[f64; 3]>,
    mut triangles: Vec<[usize; 3]>,
) -> (Vec<[f64; 3]>, Vec<[usize; 3]>) {
    let mut used = vec![false; positions.len()];
    for &v in triangles.iter().flatten() {
        used[v] = true;
    }
    if used.iter().all(|&u| u) {
        return (positions, triangles);
    }
    let mut number = vec![0; positions.len()];
    let mut kept = Vec::with_capacity(positions.len());
    for (v, p) in positions.into_iter().enumerate() {
        if used[v] {
            number[v] = kept.len();
            kept.push(p);
        }
    }
    for v in triangles.iter_mut().flatten() {
        *v = number[*v];
    }
    (kept, triangles)
}

/// Maps exactly equal coordinates to one vertex index.
#[derive(Default)]
struct Welder {
    positions: Vec<[f64; 3]>,
    index_of: HashMap<[u64; 3], usize>,
}

impl Welder {
    fn index(&mut self, p: [f64; 3]) -> usize {
        // `+ 0.0` turns -0.0 into 0.0, so both weld together.
        let key = p.map(|c| (c + 0.0).to_bits());
        *self.index_of.entry(key).or_insert_with(|| {
            self.positions.push(p);
            self.positions.len() - 1
        })
    }
}

/// Where the ASCII reader is.
enum Expect {
    Solid,
    FacetOrEnd,
    OuterLoop,
    VertexOrEndLoop,
    EndFacet,
}

struct Solid {
    name: String,
    welder: Welder,
    triangles: Vec<[usize; 3]>,
}

fn parse_ascii(text: &str, file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    let err = |kind: MeshErrorKind, line: usize| MeshError::new(file, kind).at_line(line);
    let mut meshes = Vec::new();
    let mut state = Expect::Solid;
    let mut solid: Option<Solid> = None;
    let mut corners: Vec<usize> = Vec::with_capacity(3);
    let mut last_line = 0;
    for (line, raw) in lines(text) {
        last_line = line;
        let mut words = raw.split_whitespace();
        let Some(keyword) = words.next() else {
            continue;
        };
        let keyword = keyword.to_ascii_lowercase();
        let unexpected = |wanted: &str| {
            err(
                syntax(format!("expected {wanted}, found {}", shown(raw.trim()))),
                line,
            )
        };
        match (&state, keyword.as_str()) {
            (Expect::Solid, "solid") => {
                let name = words.collect::<Vec<_>>().join(" ");
                solid = Some(Solid {
                    name: if name.is_empty() {
                        stem_name(file)
                    } else {
                        name
                    },
                    welder: Welder::default(),
                    triangles: Vec::new(),
                });
                state = Expect::FacetOrEnd;
            }
            (Expect::Solid, _) => return Err(unexpected("`solid`")),
            (Expect::FacetOrEnd, "facet") => state = Expect::OuterLoop,
            (Expect::FacetOrEnd, "endsolid") => {
                if let Some(s) = solid.take() {
                    let (positions, triangles) = used_only(s.welder.positions, s.triangles);
                    meshes.push(TriangleMesh {
                        name: s.name,
                        positions,
                        triangles,
                    });
                }
                state = Expect::Solid;
            }
            (Expect::FacetOrEnd, _) => return Err(unexpected("`facet` or `endsolid`")),
            (Expect::OuterLoop, "outer") if words.next() == Some("loop") => {
                corners.clear();
                state = Expect::VertexOrEndLoop;
            }
            (Expect::OuterLoop, _) => return Err(unexpected("`outer loop`")),
            (Expect::VertexOrEndLoop, "vertex") => {
                let coords: Vec<&str> = words.collect();
                let [x, y, z] = coords.as_slice() else {
                    return Err(err(
                        syntax(format!(
                            "a vertex needs 3 coordinates, found {}",
                            coords.len()
                        )),
                        line,
                    ));
                };
                let mut p = [0.0; 3];
                for (slot, word) in p.iter_mut().zip([x, y, z]) {
                    *slot = coordinate(word).map_err(|k| err(k, line))?;
                }
                if corners.len() == 3 {
                    return Err(err(
                        syntax("a facet with more than 3 vertices; STL facets are triangles"),
                        line,
                    ));
                }
                if let Some(s) = solid.as_mut() {
                    corners.push(s.welder.index(p));
                }
            }
            (Expect::VertexOrEndLoop, "endloop") => {
                let [a, b, c] = corners.as_slice() else {
                    return Err(err(
                        syntax(format!(
                            "a facet with {} vertices; STL facets are triangles",
                            corners.len()
                        )),
                        line,
                    ));
                };
                if let Some(s) = solid.as_mut() {
                    if !is_degenerate(&[*a, *b, *c]) {
                        s.triangles.push([*a, *b, *c]);
                    }
                }
                state = Expect::EndFacet;
            }
            (Expect::VertexOrEndLoop, _) => return Err(unexpected("`vertex` or `endloop`")),
            (Expect::EndFacet, "endfacet") => state = Expect::FacetOrEnd,
            (Expect::EndFacet, _) => return Err(unexpected("`endfacet`")),
        }
    }
    if !matches!(state, Expect::Solid) {
        return Err(err(
            MeshErrorKind::Truncated("inside a solid, before its `endsolid`".into()),
            last_line,
        ));
    }
    if meshes.iter().all(|m| m.triangles.is_empty()) {
        return Err(MeshError::new(file, MeshErrorKind::NoMesh));
    }
    Ok(meshes)
}
