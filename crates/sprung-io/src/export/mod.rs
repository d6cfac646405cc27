//! Outputs of a run: `diagnostics.csv` ([`Diagnostics`]); frame sequences
//! ([`write_frame`]) in VTK XML `.vtu` (the default) and legacy `.vtk`
//! (ParaView, VTK, pyvista, meshio; both described in `frame.rs`) with
//! their time-series file ([`write_series`]), and in OBJ (Blender); and
//! VTK frames read back ([`read_vtk_frame`]).
//!
//! Every file is written completely or not at all: it is written under a
//! temporary name beside its final place and renamed into place only once
//! complete ([`AtomicFile`]).
//!
//! To add a frame format: a file here rendering a [`sprung::World`] to
//! bytes, and a variant of [`FrameFormat`].

mod animation;
mod atomic;
mod diagnostics;
mod frame;
mod glb;
mod meshes;
mod obj;
mod series;
mod tearing;
mod vtk;
mod vtk_read;
mod vtu;
mod vtu_read;

pub use animation::{Animation, FRAMES_PER_MESH};
pub use atomic::{partial_path, replaceable, AtomicFile};
pub use diagnostics::{energy_columns, Diagnostics, NotFiniteValue, Real};
pub use frame::CellKind;
pub use series::{series_path, write_series};
pub use vtk_read::{read_vtk_frame, DataArray, VtkFrame, VtkReadError};

use std::io;
use std::path::{Path, PathBuf};

use sprung::World;

/// A frame file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameFormat {
    /// VTK XML unstructured grid (`.vtu`), binary and compressed: the
    /// default; ParaView plays the sequence through `frames.pvd`.
    Vtu,
    /// Legacy VTK unstructured grid, ASCII (`.vtk`); ParaView plays the
    /// sequence through `frames.vtk.series`.
    Vtk,
    /// Wavefront OBJ (`.obj`): Blender imports the numbered sequence.
    Obj,
}

impl FrameFormat {
    /// Every format, the default first.
    pub const ALL: [FrameFormat; 3] = [FrameFormat::Vtu, FrameFormat::Vtk, FrameFormat::Obj];

    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            FrameFormat::Vtu => "vtu",
            FrameFormat::Vtk => "vtk",
            FrameFormat::Obj => "obj",
        }
    }
}

impl std::str::FromStr for FrameFormat {
    type Err = sprung::UnknownName;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        FrameFormat::ALL
            .into_iter()
            .find(|f| f.extension() == name)
            .ok_or_else(|| {
                sprung::UnknownName::new(
                    "frame format",
                    name,
                    FrameFormat::ALL.map(|f| f.extension()),
                )
            })
    }
}

/// What `--format` asks a run to write: a frame file per record, or one
/// glTF animation of the whole run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputFormat {
    /// Frame files in this format (with their series file).
    Frames(FrameFormat),
    /// One binary glTF file, `animation.glb` ([`Animation`]).
    Gltf,
}

impl std::str::FromStr for OutputFormat {
    type Err = sprung::UnknownName;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        match name {
            "gltf" | "glb" => Ok(OutputFormat::Gltf),
            _ => name.parse().map(OutputFormat::Frames).map_err(|_| {
                let frames = FrameFormat::ALL.map(|f| f.extension());
                sprung::UnknownName::new("frame format", name, frames.into_iter().chain(["gltf"]))
            }),
        }
    }
}

/// Every body's triangles (world particle indices), in body order.
pub(crate) fn all_faces(world: &World) -> Vec<[u32; 3]> {
    world
        .bodies
        .iter()
        .flat_map(|b| b.faces.iter().copied())
        .collect()
}

/// The path of frame number `index` in `dir`: `frame_000042.vtk`, numbered
/// with six digits so the files sort and load as a sequence.
pub fn frame_path(dir: &Path, index: usize, format: FrameFormat) -> PathBuf {
    dir.join(format!("frame_{index:06}.{}", format.extension()))
}

/// Write the world's current state as frame `index` in `dir`, atomically.
/// The folder must exist.
///
/// A cloth's frames, the last read back:
///
/// ```
/// use sprung::{build, IntegratorKind, World};
/// use sprung_io::export::{read_vtk_frame, series_path, write_frame, write_series, FrameFormat};
///
/// let dir = std::env::temp_dir().join(format!("sprung-doc-frames-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let cloth = build::cloth(4, 3, 1.0, 1.0, Default::default()).unwrap().with_stiffness(100.0);
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// world.add_body("cloth", cloth).unwrap();
///
/// let mut times = Vec::new();
/// for index in 0..3 {
///     let path = write_frame(&dir, index, &world, FrameFormat::Vtu).unwrap();
///     assert_eq!(path, dir.join(format!("frame_00000{index}.vtu")));
///     times.push(world.time());
///     world.step(1e-3).unwrap();
/// }
/// write_series(&dir, FrameFormat::Vtu, &world, &times).unwrap();
/// assert!(series_path(&dir, FrameFormat::Vtu).unwrap().is_file()); // frames.pvd
///
/// let text = std::fs::read_to_string(dir.join("frame_000002.vtu")).unwrap();
/// let frame = read_vtk_frame(&text, "frame_000002.vtu".as_ref()).unwrap();
/// assert_eq!(frame.step, Some(2));
/// assert_eq!(frame.points.len(), 12);
/// assert_eq!(frame.polygons.len(), 12); // two triangles a cell
///
/// // OBJ, for Blender: a vertex line per particle.
/// let obj = write_frame(&dir, 3, &world, FrameFormat::Obj).unwrap();
/// let text = std::fs::read_to_string(obj).unwrap();
/// assert_eq!(text.lines().filter(|l| l.starts_with("v ")).count(), 12);
/// std::fs::remove_dir_all(&dir).unwrap();
/// ```
pub fn write_frame(
    dir: &Path,
    index: usize,
    world: &World,
    format: FrameFormat,
) -> io::Result<PathBuf> {
    let path = frame_path(dir, index, format);
    let bytes = match format {
        FrameFormat::Vtu => vtu::render(world),
        FrameFormat::Vtk => vtk::render(world).into_bytes(),
        FrameFormat::Obj => obj::render(world).into_bytes(),
    };
    AtomicFile::write(&path, &bytes)?;
    Ok(path)
}
