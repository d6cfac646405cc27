//! Triangle meshes from files: 3D Studio ASCII (`.asc`), Wavefront OBJ,
//! OFF and STL, and the topology checks a body built from a mesh needs.
//!
//! Every reader returns the objects of a file as [`TriangleMesh`]es with
//! `f64` positions in the file's own units and 0-based vertex indices. The
//! readers never panic: malformed input gives a [`MeshError`] that names the
//! file, the line where known, the object where relevant, and the problem.
//! [`closed_surface`] then checks that a mesh can hold a gas (closed,
//! edge-manifold, orientable) and orients it outward; [`unique_edges`] and
//! [`bending_pairs`] give the springs of a mesh body.
//!
//! Only the edge and bending-pair functions come from the `sprung` engine,
//! which builds surface bodies with them.

mod asc;
mod error;
mod obj;
mod off;
mod stl;
mod text;
pub mod topology;

use std::path::Path;

pub use asc::parse_asc;
pub use error::{MeshError, MeshErrorKind};
pub use obj::parse_obj;
pub use off::parse_off;
pub use stl::parse_stl;
pub use topology::{
    bending_pairs, closed_surface, edge_report, signed_volume, unique_edges, EdgeReport,
};

/// A triangle mesh as read from a file: one named object.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    /// The object's name in the file (the file stem for formats without
    /// names).
    pub name: String,
    /// Vertex positions, in the file's units.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as three 0-based indices into `positions`, in the file's
    /// winding order.
    pub triangles: Vec<[usize; 3]>,
}

/// The mesh file formats that can be read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MeshFormat {
    /// 3D Studio ASCII export (`.asc`).
    Asc,
    /// Wavefront OBJ (`.obj`).
    Obj,
    /// Object File Format (`.off`).
    Off,
    /// STL, ASCII or binary (`.stl`).
    Stl,
}

impl MeshFormat {
    /// The format named by the file's extension, ignoring case.
    pub fn from_path(path: &Path) -> Result<Self, MeshError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match extension.as_str() {
            "asc" => Ok(MeshFormat::Asc),
            "obj" => Ok(MeshFormat::Obj),
            "off" => Ok(MeshFormat::Off),
            "stl" => Ok(MeshFormat::Stl),
            _ => Err(MeshError::new(
                path,
                MeshErrorKind::UnsupportedFormat { extension },
            )),
        }
    }
}

/// Reads every object of a mesh file; the format is chosen by the file's
/// extension (`asc`, `obj`, `off`, `stl`, any case).
pub fn load_mesh_file(path: &Path) -> Result<Vec<TriangleMesh>, MeshError> {
    let format = MeshFormat::from_path(path)?;
    let bytes = crate::input::read_input(path, crate::input::DEFAULT_MAX_INPUT_BYTES)
        .map_err(|e| MeshError::new(path, MeshErrorKind::Io(e.to_string())))?;
    parse_mesh(&bytes, format, path)
}

/// Reads every object of a mesh file's contents in the given format; `file`
/// is used only in error messages (and to name unnamed objects). Text
/// formats must be UTF-8 (ASCII is); a leading byte order mark is skipped.
pub fn parse_mesh(
    bytes: &[u8],
    format: MeshFormat,
    file: &Path,
) -> Result<Vec<TriangleMesh>, MeshError> {
    match format {
        MeshFormat::Stl => parse_stl(bytes, file),
        MeshFormat::Asc => parse_asc(text::decode(bytes, file)?, file),
        MeshFormat::Obj => parse_obj(text::decode(bytes, file)?, file),
        MeshFormat::Off => parse_off(text::decode(bytes, file)?, file),
    }
}

/// Picks one object out of a file's objects.
///
/// With a `name`, the first object of that name; without one, the file's
/// only object. Otherwise an error naming `file` and listing the objects
/// available.
pub fn select_object(
    meshes: Vec<TriangleMesh>,
    name: Option<&str>,
    file: &Path,
) -> Result<TriangleMesh, MeshError> {
    let available = || meshes.iter().map(|m| m.name.clone()).collect();
    let not_found = |available| {
        MeshError::new(
            file,
            MeshErrorKind::ObjectNotFound {
                requested: name.map(str::to_owned),
                available,
            },
        )
    };
    match name {
        Some(wanted) => match meshes.iter().position(|m| m.name == wanted) {
            Some(k) => meshes
                .into_iter()
                .nth(k)
                .ok_or_else(|| not_found(Vec::new())),
            None => Err(not_found(available())),
        },
        None if meshes.len() == 1 => meshes
            .into_iter()
            .next()
            .ok_or_else(|| not_found(Vec::new())),
        None => Err(not_found(available())),
    }
}
