//! The `[[body]]` sections of a scene's text, so that a scene is parsed one
//! body at a time: the TOML parser holds some fifty times the text it
//! reads (its tree of tables and spans), and a scene's bodies are nearly
//! all of it. Each section runs from its `[[body]]` header to the next
//! top-level header that is not one of the body's own sub-tables
//! (`[body.gas]`, `[[body.rods]]`); the rest of the file is parsed with
//! the body sections blanked out (spaces, newlines kept), so every byte
//! keeps its offset and every error its line.

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
