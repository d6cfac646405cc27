//! The error of a scene file: the file, the line where known, and what is
//! wrong, in the user's own words (the keys of the file).

use std::fmt;
use std::path::{Path, PathBuf};

/// A scene file that cannot be read or built.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The scene file.
    pub file: PathBuf,
    /// 1-based line of the offending key or table, where known.
    pub line: Option<usize>,
    /// What is wrong, naming the key.
    pub message: String,
}

impl SceneError {
    /// An error in `file` at `line` (1-based, if known).
    pub fn new(file: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        SceneError {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.line {
            Some(line) => write!(f, "{}:{}: {}", self.file.display(), line, self.message),
            None => write!(f, "{}: {}", self.file.display(), self.message),
        }
    }
}

impl std::error::Error for SceneError {}

/// The 1-based line of byte `offset` in `text`.
pub(crate) fn line_of(text: &str, offset: usize) -> usize {
    let end = offset.min(text.len());
    text.as_bytes()[..end]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The 1-based line of the first `key = ...` (or `key=`) inside the byte
/// range `span` of `text`; for a dotted key `table.key` the table's line.
pub(crate) fn line_of_key(text: &str, span: std::ops::Range<usize>, key: &str) -> Option<usize> {
    let key = key.split(['.', '[']).next().unwrap_or(key);
    let start = span.start.min(text.len());
    let end = span.end.min(text.len());
    let mut offset = start;
    for line in text.get(start..end)?.split_inclusive('\n') {
        let trimmed = line.trim_start();
        if let Some(rest) = trimmed.strip_prefix(key) {
            if rest.trim_start().starts_with('=') {
                return Some(line_of(text, offset));
            }
        }
        offset += line.len();
    }
    None
}
