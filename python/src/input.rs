//! The one gate of scene inputs, from Python: every scene file the package
//! reads (`load`, `run`, `sweep` and its workers) goes through
//! `sprung_io::input::read_scene_file`, as `sprung run FILE` does; scene
//! text given in memory (`loads`, a sweep's runs) is checked by the scene
//! reader itself (its size and nesting, before any TOML is parsed): the
//! same limits, refused with the same words, as `sprung.SceneError`.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;

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
