//! The one gate of scene inputs, from Python: every scene file the package
//! reads (`load`, `run`, `sweep` and its workers) goes through
//! `sprung_io::input::read_scene_file`, as `sprung run FILE` does, and
//! every scene text given in memory (`loads`, a sweep's runs) through
//! [`check_text`]: the same limits, refused with the same words, as
//! `sprung.SceneError`.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use sprung_io::scene::check_text_depth;
use sprung_io::{Disk, SceneError};

use crate::errors::scene_error;

/// The text of the scene file at `path`, read through the command line's
/// gate with the GIL released: a regular file (not a device such as
/// `/dev/zero`, a FIFO or a folder, also behind a link), at most 16 MiB
/// (`SPRUNG_MAX_INPUT_BYTES` bytes when set), UTF-8; else
/// `sprung.SceneError` with the words `sprung run` prints.
#[pyfunction]
pub fn read_scene(py: Python<'_>, path: PathBuf) -> PyResult<String> {
    read_scene_text(py, &path)
}

/// [`read_scene`] from Rust.
pub fn read_scene_text(py: Python<'_>, path: &Path) -> PyResult<String> {
    py.detach(|| sprung_io::input::read_scene_file(path))
        .map_err(|e| scene_error(py, &e))
}

/// Refuse scene `text` (named `path` in errors) that is longer than a
/// scene file may be, or whose arrays and tables nest deeper than
/// `sprung_io::scene::MAX_VALUE_DEPTH` (the TOML reader recurses), with
/// the words the scene reader gives (the line where it nests too deep),
/// before anything parses it.
pub fn check_text(text: &str, path: &Path) -> Result<(), SceneError> {
    sprung_io::input::check_scene_text(text, path)?;
    match check_text_depth(text) {
        Ok(()) => Ok(()),
        // The scene reader counts the nesting before it parses, and names
        // the line: its error, not a second wording of it.
        Err(message) => Err(sprung_io::parse_scene_with(text, path, &Disk)
            .err()
            .unwrap_or_else(|| SceneError::new(path, None, message))),
    }
}
