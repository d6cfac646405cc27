//! Shared helpers of the text readers: decoding, numbers, error text.

use std::path::Path;

use super::error::{MeshError, MeshErrorKind};

/// Decodes a text mesh file: refuses empty (or blank) files and bytes that
/// are not UTF-8, naming the line of the first invalid byte; drops a UTF-8
/// byte order mark.
pub(crate) fn decode<'a>(bytes: &'a [u8], file: &Path) -> Result<&'a str, MeshError> {
    let bytes = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    match std::str::from_utf8(bytes) {
        Ok(text) => {
            if text.trim().is_empty() {
                Err(MeshError::new(file, MeshErrorKind::Empty))
            } else {
                Ok(text)
            }
        }
        Err(e) => {
            let offset = e.valid_up_to();
            let line = 1 + bytes
                .get(..offset)
                .map_or(0, |b| b.iter().filter(|&&c| c == b'\n').count());
            Err(MeshError::new(file, MeshErrorKind::NotUtf8 { offset }).at_line(line))
        }
    }
}

/// The lines of `text` with their 1-based numbers. A line ends at `\n`,
/// `\r\n` or a lone `\r` (old Macintosh files), so line numbers match what
/// an editor shows for any of the three conventions.
pub(crate) fn lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    let mut rest = text;
    let mut number = 0;
    std::iter::from_fn(move || {
        if rest.is_empty() {
            return None;
        }
        number += 1;
        let end = rest.find(['\n', '\r']).unwrap_or(rest.len());
        let (line, tail) = rest.split_at_checked(end)?;
        rest = tail
            .strip_prefix("\r\n")
            .or_else(|| tail.strip_prefix(['\n', '\r']))
            .unwrap_or(tail);
        Some((number, line))
    })
}

/// Refuses a text that is empty or blank.
pub(crate) fn require_content(text: &str, file: &Path) -> Result<(), MeshError> {
    if text.trim().is_empty() {
        Err(MeshError::new(file, MeshErrorKind::Empty))
    } else {
        Ok(())
    }
}

/// A token cut short if long, for error messages (a damaged file can hold a
/// very long "word").
pub(crate) fn clip(token: &str) -> String {
    const MAX: usize = 40;
    if token.chars().count() <= MAX {
        token.to_owned()
    } else {
        let head: String = token.chars().take(MAX).collect();
        format!("{head}...")
    }
}

/// A token as shown in an error message: clipped and quoted.
pub(crate) fn shown(token: &str) -> String {
    format!("{:?}", clip(token))
}

/// Parses a finite coordinate.
pub(crate) fn coordinate(token: &str) -> Result<f64, MeshErrorKind> {
    match token.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        Ok(_) => Err(MeshErrorKind::NonFinite { value: clip(token) }),
        Err(_) => Err(MeshErrorKind::Syntax(format!(
            "expected a number, found {}",
            shown(token)
        ))),
    }
}

/// Parses a non-negative integer (a count or a 0-based index).
pub(crate) fn unsigned(token: &str, what: &str) -> Result<usize, MeshErrorKind> {
    token.parse::<usize>().map_err(|_| {
        MeshErrorKind::Syntax(format!(
            "expected {what} (a non-negative integer), found {}",
            shown(token)
        ))
    })
}

/// A syntax error kind from a message.
pub(crate) fn syntax(message: impl Into<String>) -> MeshErrorKind {
    MeshErrorKind::Syntax(message.into())
}

/// The file stem, used as the object name for formats without names.
pub(crate) fn stem_name(file: &Path) -> String {
    file.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .unwrap_or_else(|| "mesh".to_owned())
}
