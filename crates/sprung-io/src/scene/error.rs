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

/// The key whose value starts at byte `offset` of `text` (`max_iterations`
/// in `max_iterations = -3`, `nx` in `cloth = { nx = -1 }`), if there is one
/// on that line.
pub(crate) fn key_before(text: &str, offset: usize) -> Option<&str> {
    let before = text.get(..offset.min(text.len()))?;
    let line = &before[before.rfind('\n').map_or(0, |i| i + 1)..];
    let assignment = &line[..line.rfind('=')?];
    let key = assignment
        .trim_end()
        .rsplit(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == '.'))
        .next()?;
    (!key.is_empty()).then_some(key)
}

/// The 1-based line of the first `key = ...` (or `key=`) in the table that
/// starts at byte `start` of `text`, looking up to the next table header;
/// for a dotted key `table.key` the line of `table`. Tries each of `keys`
/// in turn (a mass may have been given as `mass`, `masses` or `total_mass`).
pub(crate) fn line_of_key(text: &str, start: usize, keys: &[&str]) -> Option<usize> {
    let start = text
        .get(..start.min(text.len()))?
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let section = text.get(start..)?;
    keys.iter().find_map(|key| {
        let key = key.split(['.', '[']).next().unwrap_or(key);
        let mut offset = start;
        for (number, line) in section.split_inclusive('\n').enumerate() {
            let trimmed = line.trim();
            if number > 0 && is_table_header(trimmed) {
                break;
            }
            if let Some(rest) = trimmed.strip_prefix(key) {
                if rest.trim_start().starts_with('=') {
                    return Some(line_of(text, offset));
                }
            }
            offset += line.len();
        }
        None
    })
}

/// `[name]` or `[[name]]`: a table header, not the line of an array.
fn is_table_header(line: &str) -> bool {
    let inner = line.trim_start_matches('[').trim_end_matches(']');
    line.starts_with('[')
        && line.ends_with(']')
        && !inner.is_empty()
        && inner
            .chars()
            .all(|c| c.is_alphanumeric() || c == '_' || c == '.' || c == '-')
}
