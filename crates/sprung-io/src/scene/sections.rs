//! The `[[body]]` sections of a scene's text, so that a scene is parsed one
//! body at a time: the TOML parser holds some fifty times the text it
//! reads (its tree of tables and spans), and a scene's bodies are nearly
//! all of it. Each section runs from its `[[body]]` header to the next
//! top-level header that is not one of the body's own sub-tables
//! (`[body.gas]`, `[[body.rods]]`); the rest of the file is parsed with
//! the body sections blanked out (spaces, newlines kept), so every byte
//! keeps its offset and every error its line. `Lines` counts the lines
//! those errors and the bodies' warnings are placed at, once in all.

use std::cell::Cell;
use std::ops::Range;

use toml_parser::lexer::TokenKind;
use toml_parser::Source;

/// A scene's text split into its body sections and the rest.
#[derive(Debug)]
pub(crate) struct Sections {
    /// Byte ranges of the `[[body]]` sections, in the order of the file.
    pub bodies: Vec<Range<usize>>,
}

/// What a table header names, by its key with quotes and spaces removed.
enum Header {
    /// `[[body]]`: a new body.
    Body,
    /// `[body.…]` or `[[body.…]]`: a sub-table of the last body.
    BodyPart,
    /// Any other table.
    Other,
}

fn classify(key: &str, array: bool) -> Header {
    let key: String = key
        .chars()
        .filter(|c| !matches!(c, ' ' | '\t' | '"' | '\''))
        .collect();
    if key == "body" && array {
        Header::Body
    } else if key.starts_with("body.") {
        Header::BodyPart
    } else {
        Header::Other
    }
}

impl Sections {
    /// Find the body sections of `text`. Malformed TOML is not judged here:
    /// the sections found are parsed, and the parser reports it with its
    /// line.
    pub fn find(text: &str) -> Self {
        let mut bodies: Vec<Range<usize>> = Vec::new();
        // The section being read: a body's start, or none.
        let mut open: Option<usize> = None;
        let mut close = |open: &mut Option<usize>, end: usize| {
            if let Some(start) = open.take() {
                bodies.push(start..end);
            }
        };
        let source = Source::new(text);
        let tokens = source.lex();
        // Depth of value brackets and braces; a `[` at depth 0 at the start
        // of a line opens a table header.
        let mut depth = 0usize;
        let mut line_start = true;
        let mut header: Option<(usize, bool, usize)> = None; // (start, array, key start)
        let mut previous_bracket: Option<usize> = None;
        let mut seen_body = false;
        for token in tokens {
            let span = token.span();
            match token.kind() {
                TokenKind::Whitespace | TokenKind::Comment => continue,
                TokenKind::Newline => {
                    line_start = true;
                    previous_bracket = None;
                    continue;
                }
                TokenKind::LeftSquareBracket if depth == 0 && header.is_none() => {
                    if line_start {
                        header = Some((span.start(), false, span.end()));
                        previous_bracket = Some(span.end());
                    } else if previous_bracket == Some(span.start()) {
                        // `[[`: an array of tables.
                        if let Some(h) = header.as_mut() {
                            h.1 = true;
                            h.2 = span.end();
                        }
                    } else {
                        depth += 1;
                    }
                }
                TokenKind::LeftSquareBracket
                    if header.is_some() && previous_bracket == Some(span.start()) =>
                {
                    if let Some(h) = header.as_mut() {
                        h.1 = true;
                        h.2 = span.end();
                    }
                }
                TokenKind::RightSquareBracket if depth == 0 => {
                    if let Some((start, array, key_start)) = header.take() {
                        let key = text.get(key_start..span.start()).unwrap_or_default();
                        // An escape in a quoted key (`"bod\u0079"`) is
                        // beyond this splitting: the file is parsed whole.
                        if key.contains('\\') {
                            return Sections { bodies: Vec::new() };
                        }
                        match classify(key, array) {
                            Header::Body => {
                                close(&mut open, start);
                                open = Some(start);
                                seen_body = true;
                            }
                            // A sub-table of the last body after another
                            // table: valid TOML, but the body is no longer
                            // one piece of text; the file is parsed whole.
                            Header::BodyPart if open.is_none() && seen_body => {
                                return Sections { bodies: Vec::new() };
                            }
                            Header::BodyPart => {}
                            Header::Other => close(&mut open, start),
                        }
                    }
                }
                TokenKind::LeftSquareBracket | TokenKind::LeftCurlyBracket => depth += 1,
                TokenKind::RightSquareBracket | TokenKind::RightCurlyBracket => {
                    depth = depth.saturating_sub(1)
                }
                _ => {}
            }
            line_start = false;
            if token.kind() != TokenKind::LeftSquareBracket {
                previous_bracket = None;
            }
        }
        close(&mut open, text.len());
        Sections { bodies }
    }

    /// `text` with the body sections blanked: every byte but newlines
    /// becomes a space, so the rest parses at its own offsets.
    pub fn without_bodies(&self, text: &str) -> String {
        let mut bytes = text.as_bytes().to_vec();
        for range in &self.bodies {
            for b in &mut bytes[range.clone()] {
                if *b != b'\n' && *b != b'\r' {
                    *b = b' ';
                }
            }
        }
        // Whole UTF-8 sequences were replaced by ASCII spaces.
        String::from_utf8(bytes).unwrap_or_default()
    }
}

/// The lines of a scene's text, counted on from the last place asked
/// about, so that placing the errors and warnings of the bodies, asked for
/// in the order of the text (a warning per body), counts each line once in
/// all rather than all the lines before each.
#[derive(Debug)]
pub(crate) struct Lines<'a> {
    text: &'a str,
    /// The byte counted up to, the lines before the line that holds it,
    /// and where that line starts.
    counted: Cell<(usize, usize, usize)>,
}

impl<'a> Lines<'a> {
    pub fn new(text: &'a str) -> Self {
        Lines {
            text,
            counted: Cell::new((0, 0, 0)),
        }
    }

    /// Where the line that holds byte `offset` starts, and how many lines
    /// come before it; a place before the last one asked about is counted
    /// from the top again.
    pub fn line_start(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let (mut from, mut lines, mut start) = self.counted.get();
        if offset < from {
            (from, lines, start) = (0, 0, 0);
        }
        let stretch = &self.text.as_bytes()[from..offset];
        lines += stretch.iter().filter(|&&b| b == b'\n').count();
        if let Some(last) = stretch.iter().rposition(|&b| b == b'\n') {
            start = from + last + 1;
        }
        self.counted.set((offset, lines, start));
        (start, lines)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every place's line start and lines before, asked in order, out of
    /// order and past the end, are what counting from the top gives; asked
    /// in order, each call counts on from the last place, so the text is
    /// read once in all.
    #[test]
    fn lines_are_counted_once_on_from_the_last_place() {
        let text = "[sim]\ndt = 1\n\n[[body]]\r\nname = \"é\"\n\n\nx = 1";
        let top = |offset: usize| {
            let before = &text.as_bytes()[..offset.min(text.len())];
            let start = before
                .iter()
                .rposition(|&b| b == b'\n')
                .map_or(0, |i| i + 1);
            (start, before.iter().filter(|&&b| b == b'\n').count())
        };
        let lines = Lines::new(text);
        for offset in 0..=text.len() {
            assert_eq!(lines.line_start(offset), top(offset), "{offset}");
            assert_eq!(lines.counted.get().0, offset);
        }
        for offset in [7, 3, 30, 0, text.len() + 5, 12, 12] {
            assert_eq!(lines.line_start(offset), top(offset), "{offset}");
        }
    }
}
