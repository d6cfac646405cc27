//! Outputs of a run: `diagnostics.csv` ([`Diagnostics`]) and frame
//! sequences in legacy VTK (ParaView) and OBJ (Blender) ([`write_frame`]),
//! and VTK frames read back ([`read_vtk_frame`]).
//!
//! Every file is written completely or not at all: it is written under a
//! temporary name beside its final place and renamed into place only once
//! complete ([`AtomicFile`]).
//!
//! To add a frame format: a file here rendering a [`sprung::World`] to
//! bytes, and a variant of [`FrameFormat`].

mod atomic;
mod diagnostics;
mod obj;
mod vtk;
mod vtk_read;

pub use atomic::AtomicFile;
pub use diagnostics::{Diagnostics, Real};
pub use vtk_read::{read_vtk_frame, DataArray, VtkFrame, VtkReadError};

use std::io;
use std::path::{Path, PathBuf};

use sprung::World;

/// A frame file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FrameFormat {
    /// Legacy VTK polydata (`.vtk`): ParaView opens the numbered sequence.
    Vtk,
    /// Wavefront OBJ (`.obj`): Blender imports the numbered sequence.
    Obj,
}

impl FrameFormat {
    /// The file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            FrameFormat::Vtk => "vtk",
            FrameFormat::Obj => "obj",
        }
    }
}

impl std::str::FromStr for FrameFormat {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, String> {
        match name {
            "vtk" => Ok(FrameFormat::Vtk),
            "obj" => Ok(FrameFormat::Obj),
            other => Err(format!(
                "unknown frame format \"{other}\" (known: vtk, obj)"
            )),
        }
    }
}

/// The path of frame number `index` in `dir`: `frame_000042.vtk`, numbered
/// with six digits so the files sort and load as a sequence.
pub fn frame_path(dir: &Path, index: usize, format: FrameFormat) -> PathBuf {
    dir.join(format!("frame_{index:06}.{}", format.extension()))
}

/// Write the world's current state as frame `index` in `dir`, atomically.
pub fn write_frame(
    dir: &Path,
    index: usize,
    world: &World,
    format: FrameFormat,
) -> io::Result<PathBuf> {
    let path = frame_path(dir, index, format);
    let bytes = match format {
        FrameFormat::Vtk => vtk::render(world),
        FrameFormat::Obj => obj::render(world),
    };
    AtomicFile::write(&path, bytes.as_bytes())?;
    Ok(path)
}
