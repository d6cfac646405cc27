//! Software rendering of sprung worlds and runs to PNG pictures and an
//! animated GIF, in 2D and 3D, with no GPU.
//!
//! A picture shows springs coloured by strain `ε = (d - L0) / L0` (green
//! at rest, red stretched, blue compressed: [`strain`]), faces shaded by a
//! directional light (Lambert plus ambient, two-sided) drawn back to front
//! with the springs over them (the painter's algorithm), pinned particles
//! as small dark squares, optional face normals, and the colliders: planes
//! as a faint floor, spheres as grey balls.
//!
//! The camera ([`Camera`]) is framed once over all frames of a run so it
//! does not jump: 2D scenes (all z = 0) are seen straight on,
//! orthographic; 3D ones in perspective from an elevated angle; or from a
//! given eye and target.
//!
//! Snapshots come from a world run in memory ([`record`]) or from a
//! finished run's VTK frames ([`read_run`]); [`render_to_dir`] writes
//! `frame_000000.png` ... and `animation.gif`. The output is deterministic:
//! the same snapshots and settings give the same bytes (one thread, no
//! time stamps, no hash-ordered iteration).
//!
//! ```no_run
//! use sprung_view::render::{record, render_to_dir, RenderSettings};
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let mut scene = sprung_io::load_scene("scenes/ball2d.toml".as_ref())?;
//! let recording = record(&mut scene.world, scene.dt, 2000, 40);
//! let mut settings = RenderSettings::new(800, 600);
//! settings.gif = true;
//! render_to_dir(&recording.snapshots, "out/ball2d/render".as_ref(), &settings)?;
//! # Ok(())
//! # }
//! ```

mod camera;
mod canvas;
mod clip;
mod draw;
mod fit;
mod gif;
mod image;
mod output;
mod scenery;
mod snapshot;
mod source;
pub mod strain;
pub mod style;

use std::path::{Path, PathBuf};

pub use camera::{Bounds, Camera, CameraSetting, Projection, ViewPoint, DEFAULT_FOV_DEGREES};
pub use draw::draw;
pub use gif::{delay_centiseconds, GifWriter, MIN_DELAY_CENTISECONDS};
pub use image::Image;
pub use output::{
    check_size, frame_run, render_in_memory, render_to_dir, RenderSettings, Rendered, GIF_NAME,
    MAX_SIZE, MIN_SIZE,
};
pub use snapshot::{chain_loops, Model, Snapshot};
pub use source::{
    frame_files, read_run, record, record_by, steps_between_pictures, Recording,
    DEFAULT_PICTURE_RATE,
};
pub use strain::StrainColours;
pub use style::Style;

use sprung_io::export::VtkReadError;

/// Why pictures could not be made.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// A run folder without VTK frames (the path of its `frames/`).
    #[error("no VTK frames in {} (expected frame_000000.vtu or .vtk ..., written by `sprung run SCENE --format vtu` or `vtk`)", .0.display())]
    NoFrames(PathBuf),
    /// A VTK frame that cannot be read (file and line inside).
    #[error("{0}")]
    Vtk(#[from] VtkReadError),
    /// A file or folder that cannot be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// What went wrong.
        source: std::io::Error,
    },
    /// A picture size that cannot be used.
    #[error("bad picture size: {0}")]
    BadSize(String),
    /// Another option that cannot be used.
    #[error("{0}")]
    BadOption(String),
    /// Nothing to draw.
    #[error("no snapshots to draw")]
    Empty,
    /// The PNG or GIF encoder failed.
    #[error("cannot encode {0}")]
    Encode(String),
}

impl RenderError {
    /// An I/O error on `path`.
    pub fn io(path: &Path, source: std::io::Error) -> Self {
        RenderError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
