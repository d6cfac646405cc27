//! Why a plot could not be made.

use std::io;
use std::path::PathBuf;

/// Why reading a run's diagnostics or writing its plots failed. Every error
/// about a file's content names the file and the line (and the column where
/// there is one).
#[derive(Debug, thiserror::Error)]
pub enum PlotError {
    /// A file could not be read (missing, unreadable).
    #[error("cannot read {}: {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: io::Error,
    },
    /// A folder without `diagnostics.csv`.
    #[error(
        "{} has no diagnostics.csv (is it the output folder of `sprung run` or `sprung demo`?)",
        dir.display()
    )]
    NoDiagnostics {
        /// The folder.
        dir: PathBuf,
    },
    /// A diagnostics file that does not follow the contract (README.md, "Usage").
    #[error("{}, line {line}: {message}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// The line, counted from 1.
        line: usize,
        /// What is wrong, naming the column where there is one.
        message: String,
    },
    /// A plot file that could not be written.
    #[error("cannot write {}: {source}", path.display())]
    Write {
        /// The file or folder.
        path: PathBuf,
        /// The underlying error.
        source: io::Error,
    },
    /// Options that cannot be used (a size out of range, nothing to compare).
    #[error("{0}")]
    Options(String),
    /// The drawing library failed (not expected with valid options).
    #[error("cannot draw the plot: {0}")]
    Draw(String),
}
