//! The error of a scene file: the file, the line where known, and what is
//! wrong, in the user's own words (the keys of the file).

use std::fmt;
use std::path::{Path, PathBuf};

/// A scene file that cannot be read or built.
///
/// It names the file, the line and the key, in the words of the file:
///
/// ```
/// use std::path::Path;
///
/// let text = r#"
/// [sim]
/// dt = 1e-3
/// steps = 10
///
/// [[body]]
/// name = "rope"
/// rope = { particles = 1, length = 1.0 }
/// "#;
/// let error = sprung_io::parse_scene(text, Path::new("rope.toml")).unwrap_err();
/// assert_eq!(error.file, Path::new("rope.toml"));
/// assert_eq!(error.line, Some(8));
/// assert_eq!(
///     error.to_string(),
///     "rope.toml:8: body \"rope\": `rope.particles` = 1: a rope needs at least 2 particles"
/// );
///
/// // An unknown key is refused with its name, at its line.
/// let typo = text.replace("steps = 10", "steps = 10\ntimestep = 3");
/// let error = sprung_io::parse_scene(&typo, Path::new("rope.toml")).unwrap_err();
/// assert_eq!(error.line, Some(5));
/// assert!(error.message.starts_with("unknown field `timestep`, expected one of `dt`, "));
/// assert_eq!(error.key.as_deref(), Some("timestep"));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The scene file.
    pub file: PathBuf,
    /// 1-based line of the offending key or table, where known.
    pub line: Option<usize>,
    /// What is wrong, naming the key.
    pub message: String,
    /// The key the error is about, where known: as written in its table
    /// (`dt`, `stiffness`, `timestep` for a misspelt key, `rope` for a
    /// builder's table), or the dotted key of an override
    /// (`body.ball.stiffness`, [`Override`](super::Override)). Not part of
    /// the [`Display`](fmt::Display) text, whose message names it already.
    pub key: Option<String>,
    /// The mesh file's own error (its file and line), where the scene
    /// failed on one of its meshes; the message already quotes it.
    pub mesh: Option<Box<crate::mesh::MeshError>>,
}

impl SceneError {
    /// An error in `file` at `line` (1-based, if known).
    pub fn new(file: &Path, line: Option<usize>, message: impl Into<String>) -> Self {
        SceneError {
            file: file.to_path_buf(),
            line,
            message: message.into(),
            key: None,
            mesh: None,
        }
    }

    /// The same error, caused by the mesh file's `error` (see
    /// [`SceneError::mesh`]).
    pub fn with_mesh(mut self, error: Option<crate::mesh::MeshError>) -> Self {
        self.mesh = error.map(Box::new);
        self
    }

    /// The same error, about `key` (see [`SceneError::key`]).
    pub fn with_key(mut self, key: impl Into<String>) -> Self {
        self.key = Some(key.into());
        self
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
    keys.iter()
        .find_map(|key| offset_of_key(text, start, key))
        .map(|offset| line_of(text, offset))
}

/// The byte offset in `text` of the line of the first `key = ...` in the
/// table that starts at byte `start`, as [`line_of_key`] finds it.
fn offset_of_key(text: &str, start: usize, key: &str) -> Option<usize> {
    let start = text
        .get(..start.min(text.len()))?
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let section = text.get(start..)?;
    let key = key.split(['.', '[']).next().unwrap_or(key);
    let mut offset = start;
    for (number, line) in section.split_inclusive('\n').enumerate() {
        let trimmed = line.trim();
        if number > 0 && is_table_header(trimmed) {
            break;
        }
        if let Some(rest) = trimmed.strip_prefix(key) {
            if rest.trim_start().starts_with('=') {
                return Some(offset);
            }
        }
        offset += line.len();
    }
    None
}

/// The 1-based line of the entry a `message` names as `` `key`[i] ``, for
/// the key of `keys` that [`line_of_key`] finds, in the array that is its
/// value in the table that starts at byte `start` of `text`: an array
/// written over several lines is pointed at the entry, not at its first
/// line. `None` when the message names no entry of that key or the entry
/// is not found.
pub(crate) fn line_of_entry(
    text: &str,
    start: usize,
    keys: &[&str],
    message: &str,
) -> Option<usize> {
    let (key, line) = keys
        .iter()
        .find_map(|key| Some((key, offset_of_key(text, start, key)?)))?;
    let named = format!("`{key}`[");
    let at = message.find(&named)? + named.len();
    let digits = &message[at..];
    let index: usize = digits[..digits.find(']')?].parse().ok()?;
    let value = line + text[line..].find('=')? + 1;
    let entry = offset_of_array_entry(&text[value..], index)?;
    Some(line_of(text, value + entry))
}

/// The byte offset in `value` (a TOML value, from just after its `=`) of
/// entry `index` of the array it starts with: strings, comments and nested
/// arrays and tables passed over. `None` if it is no array or is shorter.
fn offset_of_array_entry(value: &str, index: usize) -> Option<usize> {
    let open = value.find(|c: char| !c.is_whitespace())?;
    if !value[open..].starts_with('[') {
        return None;
    }
    let (mut depth, mut entry, mut expecting) = (0_usize, 0_usize, true);
    let mut chars = value[open..].char_indices().map(|(i, c)| (open + i, c));
    while let Some((i, c)) = chars.next() {
        match c {
            '#' => {
                // A comment, to the end of its line.
                for (_, c) in chars.by_ref() {
                    if c == '\n' {
                        break;
                    }
                }
                continue;
            }
            c if c.is_whitespace() => continue,
            _ => {}
        }
        if depth == 1 && expecting && c != ']' && c != ',' {
            if entry == index {
                return Some(i);
            }
            expecting = false;
        }
        match c {
            '[' | '{' => depth += 1,
            ']' | '}' => {
                depth = depth.checked_sub(1)?;
                if depth == 0 {
                    return None;
                }
            }
            ',' if depth == 1 => {
                entry += 1;
                expecting = true;
            }
            '"' | '\'' => {
                // A string, to its closing quote (a basic string's `\"`
                // escaped).
                let mut escaped = false;
                for (_, d) in chars.by_ref() {
                    if d == c && !escaped {
                        break;
                    }
                    escaped = c == '"' && d == '\\' && !escaped;
                }
            }
            _ => {}
        }
    }
    None
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_entry_of_an_array_over_several_lines_is_found_on_its_line() {
        // Entries after comments, strings holding brackets and commas, and
        // nested arrays and tables; past the end, none.
        let text = "[[body]]\nname = \"a\"\npinned = [ # the corners\n  0, \"x,]\",\n  [1, 2],\n  { a = [3, 4] },\n  99,\n]\n";
        let line = |index| line_of_entry(text, 0, &["pinned"], &format!("`pinned`[{index}] = 99"));
        assert_eq!(line(0), Some(4));
        assert_eq!(line(1), Some(4));
        assert_eq!(line(2), Some(5));
        assert_eq!(line(3), Some(6));
        assert_eq!(line(4), Some(7));
        assert_eq!(line(5), None);
        assert_eq!(
            line_of_entry(text, 0, &["pinned"], "`pinned` is empty"),
            None
        );
        assert_eq!(line_of_entry(text, 0, &["name"], "`name`[0]"), None);
    }
}
