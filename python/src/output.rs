//! The one gate of the package's own output files written from Python
//! (`run(out=...)`'s `scene.toml`, a sweep's `sweep.csv`): written whole
//! or not at all, through `sprung_io::export::AtomicFile` as every file
//! the command line writes, so a symbolic link, a FIFO, a device or a
//! folder at the path is refused, never replaced.

use std::path::PathBuf;

use pyo3::exceptions::PyOSError;
use pyo3::prelude::*;
use sprung_io::export::AtomicFile;

/// Write `text` to the file at `path` whole or not at all (under
/// `PATH.partial`, renamed into place); `OSError` where it cannot be
/// written, or where `path` is not a regular file (a link, FIFO, device
/// or folder: never replaced).
#[pyfunction]
pub fn write_output(py: Python<'_>, path: PathBuf, text: &str) -> PyResult<()> {
    py.detach(|| AtomicFile::write(&path, text.as_bytes()))
        .map_err(|e| PyOSError::new_err(format!("cannot write {}: {e}", path.display())))
}
