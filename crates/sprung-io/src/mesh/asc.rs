//! 3D Studio ASCII export (`.asc`), as written by 3D Studio (DOS) R1-R4.
//!
//! The format is line based. A file is a sequence of `Named object: "name"`
//! blocks; a block is a light, a camera or a triangle mesh:
//!
//! ```text
//! Named object: "Cube"
//! Tri-mesh, Vertices: 8     Faces: 12
//! Vertex list:
//! Vertex 0:  X: -1.0     Y: 1.0     Z: 1.0
//! Face list:
//! Face 0:    A:0 B:1 C:2 AB:1 BC:1 CA:1
//! Material:"LIGHT_BLUE"
//! Smoothing:  1, 2
//! ```
//!
//! Variants handled: `Vertex List:` or `Vertex list:`, LF, CRLF or CR line
//! ends, any spacing around the `label:` fields, optional `U:`/`V:` texture
//! coordinates on vertex lines, an `Ambient light color` line, lights and
//! cameras (skipped), printer page breaks (`Page 7`) and blank lines
//! anywhere, `Material:` and `Smoothing:` lines after faces (ignored).
//! Vertices and faces must be listed in order (`Vertex 0`, `Vertex 1`...),
//! as 3D Studio writes them; a count that disagrees with the `Tri-mesh`
//! header, a face index out of range, a coordinate that is not a finite
//! number and a file that ends inside a mesh are errors. Lines of other
//! kinds are ignored.
//! Face vertex indices are 0-based. Every `Tri-mesh` object is returned,
//! even one with no faces.

use std::path::Path;

use super::error::{MeshError, MeshErrorKind};
use super::text::{coordinate, lines, require_content, shown, syntax, unsigned};
use super::TriangleMesh;

/// Reads every triangle mesh object of a 3D Studio ASCII file.
///
/// Positions are in the file's units. `file` is used only in error messages.
pub fn parse_asc(text: &str, file: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    require_content(text, file)?;
    let mut reader = Reader {
        file,
        state: State::Top,
        meshes: Vec::new(),
    };
    let mut last_line = 0;
    for (line, raw) in lines(text) {
        last_line = line;
        reader.line(raw.trim(), line)?;
    }
    reader.finish(true, last_line)?;
    if reader.meshes.is_empty() {
        return Err(MeshError::new(file, MeshErrorKind::NoMesh));
    }
    Ok(reader.meshes)
}

/// Where the reader is in the file.
enum State {
    /// Before the first `Named object`.
    Top,
    /// Inside a named object that is not (yet) a mesh: a light, a camera.
    Named(String),
    /// Inside a `Tri-mesh` object.
    Mesh(MeshBuilder),
}

#[derive(PartialEq)]
enum Section {
    Header,
    Vertices,
    Faces,
}

struct MeshBuilder {
    name: String,
    header_line: usize,
    declared_vertices: usize,
    declared_faces: usize,
    positions: Vec<[f64; 3]>,
    triangles: Vec<[usize; 3]>,
    section: Section,
}

struct Reader<'a> {
    file: &'a Path,
    state: State,
    meshes: Vec<TriangleMesh>,
}

/// What kind of line this is, from its first word.
enum LineKind<'l> {
    Blank,
    NamedObject(&'l str),
    TriMesh(&'l str),
    VertexList,
    FaceList,
    Vertex(&'l str),
    Face(&'l str),
    Other,
}

fn strip_prefix_ci<'l>(line: &'l str, prefix: &str) -> Option<&'l str> {
    let head = line.get(..prefix.len())?;
    if head.eq_ignore_ascii_case(prefix) {
        line.get(prefix.len()..)
    } else {
        None
    }
}

fn classify(line: &str) -> LineKind<'_> {
    if line.is_empty() || is_page_break(line) {
        return LineKind::Blank;
    }
    if let Some(rest) = strip_prefix_ci(line, "Named object:") {
        return LineKind::NamedObject(rest.trim());
    }
    if let Some(rest) = strip_prefix_ci(line, "Tri-mesh,") {
        return LineKind::TriMesh(rest);
    }
    if let Some(rest) = strip_prefix_ci(line, "Vertex") {
        let rest = rest.trim_start();
        if strip_prefix_ci(rest, "list").is_some() {
            return LineKind::VertexList;
        }
        if rest.starts_with(|c: char| c.is_ascii_digit()) {
            return LineKind::Vertex(rest);
        }
    }
    if let Some(rest) = strip_prefix_ci(line, "Face") {
        let rest = rest.trim_start();
        if strip_prefix_ci(rest, "list").is_some() {
            return LineKind::FaceList;
        }
        if rest.starts_with(|c: char| c.is_ascii_digit()) {
            return LineKind::Face(rest);
        }
    }
    LineKind::Other
}

/// A printer page break such as `Page 17`.
fn is_page_break(line: &str) -> bool {
    strip_prefix_ci(line, "Page").is_some_and(|rest| {
        let rest = rest.trim();
        !rest.is_empty() && rest.bytes().all(|b| b.is_ascii_digit())
    })
}

/// The object name of a `Named object:` line, without its quotes.
fn object_name(rest: &str) -> String {
    let unquoted = rest
        .strip_prefix('"')
        .and_then(|r| r.strip_suffix('"'))
        .unwrap_or(rest);
    unquoted.to_owned()
}

/// Splits `X: 1.0 Y:2 Z: 3` into labelled values: a label is a word ending
/// in `:`, its value is glued to it or the next word.
fn fields(text: &str) -> Result<Vec<(&str, &str)>, MeshErrorKind> {
    let mut out = Vec::new();
    let mut words = text.split_whitespace();
    while let Some(word) = words.next() {
        let Some((label, glued)) = word.split_once(':') else {
            return Err(syntax(format!(
                "expected a `label:` field, found {}",
                shown(word)
            )));
        };
        let value = if glued.is_empty() {
            words
                .next()
                .ok_or_else(|| syntax(format!("field {}: has no value", shown(label))))?
        } else {
            glued
        };
        out.push((label, value));
    }
    Ok(out)
}

/// Picks the fields `wanted` out of `fields` (labels compared ignoring
/// case); labels in `optional` may appear and are ignored; any other label,
/// a repeated label or a missing one is an error.
fn pick<'t, const N: usize>(
    fields: &[(&str, &'t str)],
    wanted: [&str; N],
    optional: &[&str],
    what: &str,
) -> Result<[&'t str; N], MeshErrorKind> {
    let mut found: [Option<&str>; N] = [None; N];
    for &(label, value) in fields {
        if let Some(slot) = wanted
            .iter()
            .position(|w| w.eq_ignore_ascii_case(label))
            .and_then(|k| found.get_mut(k))
        {
            if slot.is_some() {
                return Err(syntax(format!("{what}: field {label}: given twice")));
            }
            *slot = Some(value);
        } else if !optional.iter().any(|o| o.eq_ignore_ascii_case(label)) {
            return Err(syntax(format!(
                "{what}: unexpected field {}",
                shown(&format!("{label}:"))
            )));
        }
    }
    let mut out = [""; N];
    for ((slot, value), label) in out.iter_mut().zip(found).zip(wanted) {
        *slot = value.ok_or_else(|| syntax(format!("{what}: field {label}: missing")))?;
    }
    Ok(out)
}

/// Splits `12:  X: ...` into the item number and the rest.
fn numbered<'l>(rest: &'l str, what: &str) -> Result<(usize, &'l str), MeshErrorKind> {
    let (number, tail) = rest
        .split_once(':')
        .ok_or_else(|| syntax(format!("{what} line without `:` after its number")))?;
    let number_what = if what == "vertex" {
        "a vertex number"
    } else {
        "a face number"
    };
    Ok((unsigned(number.trim(), number_what)?, tail))
}

impl Reader<'_> {
    fn error(&self, kind: MeshErrorKind, line: usize) -> MeshError {
        let error = MeshError::new(self.file, kind).at_line(line);
        match &self.state {
            State::Top => error,
            State::Named(name) => error.in_object(name),
            State::Mesh(mesh) => error.in_object(&mesh.name),
        }
    }

    fn line(&mut self, text: &str, line: usize) -> Result<(), MeshError> {
        match classify(text) {
            LineKind::Blank | LineKind::Other => Ok(()),
            LineKind::NamedObject(rest) => {
                self.finish(false, line)?;
                self.state = State::Named(object_name(rest));
                Ok(())
            }
            LineKind::TriMesh(rest) => self.header(rest, line),
            data => {
                let result = match &mut self.state {
                    State::Mesh(mesh) => mesh.data_line(data),
                    State::Top | State::Named(_) => {
                        Err(syntax("vertex or face data outside a `Tri-mesh` object"))
                    }
                };
                result.map_err(|kind| self.error(kind, line))
            }
        }
    }

    fn header(&mut self, rest: &str, line: usize) -> Result<(), MeshError> {
        let name = match &self.state {
            State::Named(name) => name.clone(),
            State::Top => {
                return Err(self.error(syntax("`Tri-mesh` header before any `Named object`"), line))
            }
            State::Mesh(_) => {
                return Err(self.error(syntax("a second `Tri-mesh` header in one object"), line))
            }
        };
        let parsed = fields(rest)
            .and_then(|f| pick(&f, ["Vertices", "Faces"], &[], "Tri-mesh header"))
            .and_then(|[v, f]| Ok((unsigned(v, "a vertex count")?, unsigned(f, "a face count")?)));
        let (declared_vertices, declared_faces) = parsed.map_err(|kind| self.error(kind, line))?;
        self.state = State::Mesh(MeshBuilder {
            name,
            header_line: line,
            declared_vertices,
            declared_faces,
            positions: Vec::new(),
            triangles: Vec::new(),
            section: Section::Header,
        });
        Ok(())
    }

    /// Closes the current object; `at_end` when the file has ended.
    fn finish(&mut self, at_end: bool, line: usize) -> Result<(), MeshError> {
        let State::Mesh(mesh) = std::mem::replace(&mut self.state, State::Top) else {
            return Ok(());
        };
        // At the end of the file, a list still being read when the file
        // ends is reported as truncated; any other shortfall is a mismatch.
        let in_faces = mesh.section == Section::Faces;
        let counts = [
            (
                "vertices",
                mesh.declared_vertices,
                mesh.positions.len(),
                !in_faces,
            ),
            ("faces", mesh.declared_faces, mesh.triangles.len(), true),
        ];
        for (what, declared, found, still_reading) in counts {
            if declared != found {
                let kind = if at_end && still_reading && found < declared {
                    MeshErrorKind::Truncated(format!(
                        "after {found} of the {declared} {what} the `Tri-mesh` header \
                         on line {} declares",
                        mesh.header_line
                    ))
                } else {
                    MeshErrorKind::CountMismatch {
                        what,
                        declared,
                        found,
                    }
                };
                let at = match kind {
                    MeshErrorKind::Truncated(_) => line,
                    _ => mesh.header_line,
                };
                return Err(MeshError::new(self.file, kind)
                    .at_line(at)
                    .in_object(&mesh.name));
            }
        }
        self.meshes.push(TriangleMesh {
            name: mesh.name,
            positions: mesh.positions,
            triangles: mesh.triangles,
        });
        Ok(())
    }
}

impl MeshBuilder {
    fn data_line(&mut self, kind: LineKind<'_>) -> Result<(), MeshErrorKind> {
        match kind {
            LineKind::VertexList => {
                if self.section == Section::Faces {
                    return Err(syntax("`Vertex list:` after the face list"));
                }
                self.section = Section::Vertices;
                Ok(())
            }
            LineKind::FaceList => {
                self.section = Section::Faces;
                Ok(())
            }
            LineKind::Vertex(rest) => self.vertex(rest),
            LineKind::Face(rest) => self.face(rest),
            LineKind::Blank | LineKind::Other | LineKind::NamedObject(_) | LineKind::TriMesh(_) => {
                Ok(())
            }
        }
    }

    fn vertex(&mut self, rest: &str) -> Result<(), MeshErrorKind> {
        if self.section == Section::Faces {
            return Err(syntax("vertex line inside the face list"));
        }
        let (index, tail) = numbered(rest, "vertex")?;
        if index >= self.declared_vertices {
            return Err(syntax(format!(
                "vertex {index} is beyond the {} vertices the header declares",
                self.declared_vertices
            )));
        }
        expect_next(index, self.positions.len(), "vertex")?;
        let [x, y, z] = pick(&fields(tail)?, ["X", "Y", "Z"], &["U", "V"], "vertex")?;
        self.positions
            .push([coordinate(x)?, coordinate(y)?, coordinate(z)?]);
        Ok(())
    }

    fn face(&mut self, rest: &str) -> Result<(), MeshErrorKind> {
        let (index, tail) = numbered(rest, "face")?;
        if index >= self.declared_faces {
            return Err(syntax(format!(
                "face {index} is beyond the {} faces the header declares",
                self.declared_faces
            )));
        }
        expect_next(index, self.triangles.len(), "face")?;
        let corners = pick(&fields(tail)?, ["A", "B", "C"], &["AB", "BC", "CA"], "face")?;
        let mut triangle = [0usize; 3];
        for (slot, text) in triangle.iter_mut().zip(corners) {
            let vertex = unsigned(text, "a vertex index")?;
            if vertex >= self.declared_vertices {
                return Err(MeshErrorKind::IndexOutOfRange {
                    face: index,
                    index: i64::try_from(vertex).unwrap_or(i64::MAX),
                    vertices: self.declared_vertices,
                });
            }
            *slot = vertex;
        }
        if let Some(&twice) = triangle
            .iter()
            .enumerate()
            .find_map(|(k, v)| triangle[..k].contains(v).then_some(v))
            .as_ref()
        {
            return Err(syntax(format!(
                "face {index}: vertex {twice} is listed twice; a face needs distinct vertices"
            )));
        }
        self.section = Section::Faces;
        self.triangles.push(triangle);
        Ok(())
    }
}

/// Vertices and faces come in order: `found` must be the `expected` next one.
fn expect_next(found: usize, expected: usize, what: &str) -> Result<(), MeshErrorKind> {
    if found == expected {
        Ok(())
    } else if found < expected {
        Err(syntax(format!("{what} {found} is listed twice")))
    } else {
        Err(syntax(format!(
            "{what} {found} out of order: expected {what} {expected}"
        )))
    }
}
