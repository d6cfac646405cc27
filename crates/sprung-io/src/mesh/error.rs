//! Errors of the mesh readers and of the topology checks.
//!
//! Every error names the file, the line (1-based) where one is known, the
//! object where one is relevant, and what is wrong, for example
//! `cube.asc:13: object "Cube": face 0 vertex index 9 out of range (8 vertices)`.

use std::fmt;
use std::path::{Path, PathBuf};

/// A mesh file that could not be read, or a mesh that failed a topology check.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshError {
    /// The file the mesh came from, as the caller named it.
    pub file: PathBuf,
    /// The 1-based line where the problem is, when it is tied to one line.
    pub line: Option<usize>,
    /// The object (named mesh in the file) concerned, when there is one.
    pub object: Option<String>,
    /// What is wrong.
    pub kind: MeshErrorKind,
}

impl MeshError {
    /// An error about `file` with no line and no object yet.
    pub fn new(file: &Path, kind: MeshErrorKind) -> Self {
        MeshError {
            file: file.to_path_buf(),
            line: None,
            object: None,
            kind,
        }
    }

    /// The same error tied to the 1-based `line`.
    pub fn at_line(mut self, line: usize) -> Self {
        self.line = Some(line);
        self
    }

    /// The same error tied to the object `name`.
    pub fn in_object(mut self, name: &str) -> Self {
        self.object = Some(name.to_owned());
        self
    }
}

impl fmt::Display for MeshError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
        }
        f.write_str(": ")?;
        if let Some(object) = &self.object {
            write!(f, "object {object:?}: ")?;
        }
        write!(f, "{}", self.kind)
    }
}

impl std::error::Error for MeshError {}

/// The ways a mesh file or a mesh can be wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum MeshErrorKind {
    /// The file could not be read (missing, a directory, no permission...).
    #[error("cannot read the file: {0}")]
    Io(String),
    /// The file has no content, or only white space.
    #[error("the file is empty")]
    Empty,
    /// A text format holds bytes that are not UTF-8 (or ASCII) text.
    #[error("not UTF-8 text (invalid byte at offset {offset})")]
    NotUtf8 {
        /// Byte offset of the first invalid byte from the start of the file.
        offset: usize,
    },
    /// The file name's extension names no supported format.
    #[error("unsupported mesh format {extension:?}: expected .asc, .obj, .off or .stl")]
    UnsupportedFormat {
        /// The extension found (empty if none).
        extension: String,
    },
    /// A line that does not have the expected form.
    #[error("{0}")]
    Syntax(String),
    /// A coordinate that is NaN or infinite (or overflows `f64`).
    #[error("coordinate {value:?} is not a finite number")]
    NonFinite {
        /// The text of the offending value.
        value: String,
    },
    /// A count declared in a header disagrees with the data that follows.
    #[error("the header declares {declared} {what}, the file has {found}")]
    CountMismatch {
        /// What is counted ("vertices", "faces"...).
        what: &'static str,
        /// The count the header declares.
        declared: usize,
        /// The count found in the data.
        found: usize,
    },
    /// The file ends before the data its header or structure announces.
    #[error("the file ends early (truncated?): {0}")]
    Truncated(String),
    /// A face refers to a vertex that does not exist.
    #[error("face {face} vertex index {index} out of range ({vertices} vertices)")]
    IndexOutOfRange {
        /// The 0-based face (or triangle) number.
        face: usize,
        /// The offending index as written (0-based for ASC, OFF and
        /// topology checks; as in the file for OBJ).
        index: i64,
        /// The number of vertices available.
        vertices: usize,
    },
    /// The file holds no triangle mesh (only lights, cameras, points...).
    #[error("no triangle mesh in the file")]
    NoMesh,
    /// [`select_object`](super::select_object) found no object to return.
    #[error("{}", object_not_found(.requested.as_deref(), .available))]
    ObjectNotFound {
        /// The requested name, or `None` when no name was given and the
        /// file holds several objects.
        requested: Option<String>,
        /// The names of the objects in the file, in file order.
        available: Vec<String>,
    },
    /// The surface has boundary edges (edges used by only one triangle).
    #[error(
        "not closed: {count} boundary edges, the first between vertices {} and {}; \
         a gas body needs a closed surface (it can still be used as cloth)",
        .first[0], .first[1]
    )]
    NotClosed {
        /// Number of boundary edges.
        count: usize,
        /// The first boundary edge in face order, as (lower, higher) vertex index.
        first: [usize; 2],
    },
    /// Some edges are shared by more than two triangles.
    #[error(
        "not edge-manifold: {count} edges shared by more than two triangles, \
         the first between vertices {} and {} ({triangles} triangles)",
        .first[0], .first[1]
    )]
    NonManifold {
        /// Number of non-manifold edges.
        count: usize,
        /// The first one in face order, as (lower, higher) vertex index.
        first: [usize; 2],
        /// How many triangles share that first edge.
        triangles: usize,
    },
    /// A triangle uses the same vertex twice.
    #[error("triangle {triangle} is degenerate: vertex {vertex} appears twice")]
    Degenerate {
        /// The 0-based triangle number.
        triangle: usize,
        /// The repeated vertex index.
        vertex: usize,
    },
    /// The triangles cannot be given one consistent orientation (the surface
    /// is one-sided, like a Möbius strip or a Klein bottle).
    #[error(
        "not orientable: the triangles cannot all be oriented consistently \
         (found while crossing the edge between vertices {} and {})",
        .edge[0], .edge[1]
    )]
    NotOrientable {
        /// The edge where the contradiction was found.
        edge: [usize; 2],
    },
    /// A closed component encloses (almost) no volume: it is flat.
    #[error(
        "the closed surface of triangle {triangle} encloses no volume \
         ({volume:e}, cubed file units); it is flat and cannot hold a gas"
    )]
    FlatComponent {
        /// A triangle of the flat component.
        triangle: usize,
        /// Its signed volume, in the file's units cubed.
        volume: f64,
    },
    /// The OBJ reader (`tobj`) refused the file for a reason the line
    /// pre-scan did not find.
    #[error("OBJ reader: {0}")]
    Obj(String),
}

fn object_not_found(requested: Option<&str>, available: &[String]) -> String {
    let names = if available.is_empty() {
        "the file holds no objects".to_owned()
    } else {
        let quoted: Vec<String> = available.iter().map(|n| format!("{n:?}")).collect();
        format!("available: {}", quoted.join(", "))
    };
    match requested {
        Some(name) => format!("no object named {name:?}; {names}"),
        None => format!(
            "the file holds {} objects, name the one to use; {names}",
            available.len()
        ),
    }
}
