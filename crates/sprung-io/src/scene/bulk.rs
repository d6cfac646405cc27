//! The long arrays of a body given particle by particle (`particles`,
//! `springs`, `faces`, ...), read straight into vectors instead of through
//! the TOML parser's tree of values and spans, which holds some fifty times
//! their text.
//!
//! Only arrays whose every element is a plain number in the forms scenes
//! use (`12`, `-0.5`, `1.5e-3`, `inf`, `nan`) are read here; anything
//! else (underscores, hexadecimal, a string, an element of the wrong
//! shape, a key given twice) is left to the TOML parser, so that every
//! scene means exactly what TOML says and every error keeps its message.
//! An array read here is replaced by `[]` in the text the parser sees,
//! padded with spaces so that every other byte keeps its offset.

use std::ops::Range;

use toml_parser::lexer::{Token, TokenKind};
use toml_parser::Source;

use super::tables::BodyTable;

/// What one array holds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shape {
    /// Numbers (`masses`, `rest_lengths`, `rod_lengths`).
    Reals,
    /// Indices (`pinned`).
    Indices,
    /// Arrays of numbers of any length (`particles`, `velocities`).
    Points,
    /// Arrays of `n` indices (`springs`, `segments`, `rods`: 2; `faces`: 3).
    Tuples(usize),
}

/// The keys read here and their shapes.
const KEYS: [(&str, Shape); 10] = [
    ("particles", Shape::Points),
    ("velocities", Shape::Points),
    ("springs", Shape::Tuples(2)),
    ("segments", Shape::Tuples(2)),
    ("rods", Shape::Tuples(2)),
    ("faces", Shape::Tuples(3)),
    ("masses", Shape::Reals),
    ("rest_lengths", Shape::Reals),
    ("rod_lengths", Shape::Reals),
    ("pinned", Shape::Indices),
];

/// One array read: its key, where its text was, and its values.
#[derive(Debug)]
struct Array {
    key: &'static str,
    range: Range<usize>,
    values: Values,
}

#[derive(Debug, PartialEq)]
enum Values {
    Reals(Vec<f64>),
    Indices(Vec<usize>),
    Points(Vec<Vec<f64>>),
    Tuples(Vec<Vec<usize>>),
}

/// The arrays of one `[[body]]` section read in bulk.
#[derive(Debug, Default)]
pub(crate) struct BulkArrays {
    arrays: Vec<Array>,
}

impl BulkArrays {
    /// Read the bulk arrays of the body section `text` (which starts with
    /// its `[[body]]` header); returns them with the text the TOML parser
    /// is to read instead.
    pub fn read(text: &str) -> (Self, Option<String>) {
        let mut arrays: Vec<Array> = Vec::new();
        let mut seen: Vec<&str> = Vec::new();
        let mut tokens = Source::new(text).lex().peekable();
        // Past the section's own header line.
        for token in tokens.by_ref() {
            if token.kind() == TokenKind::Newline {
                break;
            }
        }
        let mut line_start = true;
        let mut depth = 0usize;
        while let Some(token) = tokens.next() {
            let kind = token.kind();
            match kind {
                TokenKind::Whitespace | TokenKind::Comment => continue,
                TokenKind::Newline => {
                    line_start = true;
                    continue;
                }
                // The body's sub-tables: no bulk keys there.
                TokenKind::LeftSquareBracket if depth == 0 && line_start => break,
                TokenKind::Atom if depth == 0 && line_start => {
                    let key = &text[token.span().start()..token.span().end()];
                    line_start = false;
                    if let Some(&(key, shape)) = KEYS.iter().find(|(k, _)| *k == key) {
                        seen.push(key);
                        skip_blanks(&mut tokens);
                        if tokens.peek().map(Token::kind) != Some(TokenKind::Equals) {
                            continue;
                        }
                        tokens.next();
                        skip_blanks(&mut tokens);
                        match tokens.peek() {
                            Some(open) if open.kind() == TokenKind::LeftSquareBracket => {
                                let start = open.span().start();
                                tokens.next();
                                if let Some((values, end)) = read_array(text, &mut tokens, shape) {
                                    arrays.push(Array {
                                        key,
                                        range: start..end,
                                        values,
                                    });
                                }
                            }
                            _ => continue,
                        }
                    }
                    continue;
                }
                TokenKind::LeftSquareBracket | TokenKind::LeftCurlyBracket => depth += 1,
                TokenKind::RightSquareBracket | TokenKind::RightCurlyBracket => {
                    depth = depth.saturating_sub(1)
                }
                _ => {}
            }
            line_start = false;
        }
        // A key given twice is left to the parser, which refuses it.
        arrays.retain(|a| seen.iter().filter(|&&k| k == a.key).count() == 1);
        if arrays.is_empty() {
            return (BulkArrays::default(), None);
        }
        let mut bytes = text.as_bytes().to_vec();
        for array in &arrays {
            // Newlines too: what follows the array stays on its line, as
            // TOML reads it (errors are placed by their offsets in the
            // original text, so no line number moves).
            let range = &mut bytes[array.range.clone()];
            range.fill(b' ');
            range[0] = b'[';
            range[1] = b']';
        }
        // Whole UTF-8 sequences (in comments) were replaced by spaces.
        let blanked = String::from_utf8(bytes).ok();
        (BulkArrays { arrays }, blanked)
    }

    /// Put the arrays read into `body`, whose keys the parser read as `[]`.
    pub fn fill(self, body: &mut BodyTable) {
        for array in self.arrays {
            let tuples = |t: Vec<Vec<usize>>| -> Vec<[usize; 2]> {
                t.into_iter().map(|p| [p[0], p[1]]).collect()
            };
            match (array.key, array.values) {
                ("particles", Values::Points(p)) => body.particles = Some(p),
                ("velocities", Values::Points(p)) => body.velocities = Some(p),
                ("springs", Values::Tuples(t)) => body.springs = Some(tuples(t)),
                ("segments", Values::Tuples(t)) => body.segments = Some(tuples(t)),
                ("rods", Values::Tuples(t)) => body.rods = Some(tuples(t)),
                ("faces", Values::Tuples(t)) => {
                    body.faces = Some(t.into_iter().map(|f| [f[0], f[1], f[2]]).collect())
                }
                ("masses", Values::Reals(r)) => body.masses = Some(r),
                ("rest_lengths", Values::Reals(r)) => body.rest_lengths = Some(r),
                ("rod_lengths", Values::Reals(r)) => body.rod_lengths = Some(r),
                ("pinned", Values::Indices(i)) => body.pinned = Some(i),
                _ => {}
            }
        }
    }
}

fn skip_blanks<I: Iterator<Item = Token>>(tokens: &mut std::iter::Peekable<I>) {
    while tokens
        .peek()
        .is_some_and(|t| t.kind() == TokenKind::Whitespace)
    {
        tokens.next();
    }
}

/// Read an array whose `[` was just taken, of `shape`; returns its values
/// and the end of its `]`, or `None` (the array skipped to its end) when
/// it is not all plain numbers of that shape.
fn read_array<I: Iterator<Item = Token>>(
    text: &str,
    tokens: &mut std::iter::Peekable<I>,
    shape: Shape,
) -> Option<(Values, usize)> {
    let mut reader = ArrayReader::new(shape);
    let mut depth = 1usize;
    // The text of the number being read (tokens `1`, `.`, `5e-3`).
    let mut number: Option<Range<usize>> = None;
    for token in tokens.by_ref() {
        let span = token.span();
        let kind = token.kind();
        if matches!(kind, TokenKind::Atom | TokenKind::Dot) {
            number = Some(match number {
                Some(r) if r.end == span.start() => r.start..span.end(),
                _ => {
                    reader.start_value();
                    span.start()..span.end()
                }
            });
            continue;
        }
        if let Some(range) = number.take() {
            reader.number(&text[range], depth);
        }
        let raw = &text[span.start()..span.end()];
        match kind {
            // What TOML allows between values (anything else, a bare CR or
            // a control character in a comment, is left to the parser,
            // which refuses it).
            TokenKind::Whitespace if raw.bytes().all(|b| b == b' ' || b == b'\t') => {}
            TokenKind::Newline if raw == "\n" || raw == "\r\n" => {}
            TokenKind::Comment
                if raw
                    .chars()
                    .all(|c| c == '\t' || !(c.is_control() || c == '\u{7f}')) => {}
            TokenKind::Comma => reader.comma(),
            TokenKind::LeftSquareBracket => {
                reader.start_value();
                depth += 1;
                reader.open(depth);
            }
            TokenKind::RightSquareBracket => {
                depth -= 1;
                reader.close(depth);
                if depth == 0 {
                    return reader.finish().map(|values| (values, span.end()));
                }
            }
            TokenKind::LeftCurlyBracket => {
                reader.ok = false;
                depth += 1;
            }
            TokenKind::RightCurlyBracket => {
                reader.ok = false;
                depth = depth.saturating_sub(1);
                if depth == 0 {
                    return None;
                }
            }
            _ => reader.ok = false,
        }
    }
    None
}

/// The values of one array as its tokens come, and whether they are all
/// plain numbers of its shape, each pair separated by one comma.
struct ArrayReader {
    shape: Shape,
    ok: bool,
    /// A value ended and no comma came since.
    needs_comma: bool,
    reals: Vec<f64>,
    indices: Vec<usize>,
    points: Vec<Vec<f64>>,
    tuples: Vec<Vec<usize>>,
    /// The inner array being read (nested shapes).
    inner: Option<(Vec<f64>, Vec<usize>)>,
}

impl ArrayReader {
    fn new(shape: Shape) -> Self {
        ArrayReader {
            shape,
            ok: true,
            needs_comma: false,
            reals: Vec::new(),
            indices: Vec::new(),
            points: Vec::new(),
            tuples: Vec::new(),
            inner: None,
        }
    }

    fn nested(&self) -> bool {
        matches!(self.shape, Shape::Points | Shape::Tuples(_))
    }

    /// A value (number or array) starts: there must have been a comma.
    fn start_value(&mut self) {
        if self.needs_comma {
            self.ok = false;
        }
    }

    fn comma(&mut self) {
        if !self.needs_comma {
            self.ok = false; // `[,1]` or `[1,,2]`
        }
        self.needs_comma = false;
    }

    /// The number `literal` at `depth` (1: the outer array).
    fn number(&mut self, literal: &str, depth: usize) {
        self.needs_comma = true;
        let element_depth = if self.nested() { 2 } else { 1 };
        if !self.ok || depth != element_depth {
            self.ok = false;
            return;
        }
        if matches!(self.shape, Shape::Indices | Shape::Tuples(_)) {
            match (index(literal), self.inner.as_mut()) {
                (Some(i), Some((_, list))) => list.push(i),
                (Some(i), None) => self.indices.push(i),
                (None, _) => self.ok = false,
            }
        } else {
            match (real(literal), self.inner.as_mut()) {
                (Some(x), Some((list, _))) => list.push(x),
                (Some(x), None) => self.reals.push(x),
                (None, _) => self.ok = false,
            }
        }
    }

    /// An array opened, now at `depth`.
    fn open(&mut self, depth: usize) {
        if depth == 2 && self.nested() {
            self.inner = Some((Vec::new(), Vec::new()));
        } else {
            self.ok = false;
        }
    }

    /// An array closed, now at `depth`.
    fn close(&mut self, depth: usize) {
        self.needs_comma = true;
        if depth != 1 {
            return;
        }
        match (self.inner.take(), self.shape) {
            (Some((reals, _)), Shape::Points) => self.points.push(reals),
            (Some((_, indices)), Shape::Tuples(n)) if indices.len() == n => {
                self.tuples.push(indices)
            }
            _ => self.ok = false,
        }
    }

    fn finish(self) -> Option<Values> {
        self.ok.then_some(match self.shape {
            Shape::Reals => Values::Reals(self.reals),
            Shape::Indices => Values::Indices(self.indices),
            Shape::Points => Values::Points(self.points),
            Shape::Tuples(_) => Values::Tuples(self.tuples),
        })
    }
}

/// A TOML decimal integer without sign or underscores, as an index.
fn index(literal: &str) -> Option<usize> {
    let digits = literal.as_bytes();
    let plain = !digits.is_empty()
        && digits.iter().all(u8::is_ascii_digit)
        && (digits[0] != b'0' || digits.len() == 1);
    // Parsed as TOML does (a 64-bit signed integer), then as an index.
    let value: i64 = if plain { literal.parse().ok()? } else { None? };
    usize::try_from(value).ok()
}

/// A TOML number in the plain forms (`-12`, `0.5`, `1.5e-3`, `+inf`,
/// `nan`), as a float: integers as TOML reads them (64-bit) and then
/// converted, as serde does.
fn real(literal: &str) -> Option<f64> {
    let unsigned = literal.trim_start_matches(['+', '-']);
    if literal.len() - unsigned.len() > 1 {
        return None;
    }
    match unsigned {
        "inf" | "nan" => return literal.parse().ok(),
        _ => {}
    }
    let bytes = unsigned.as_bytes();
    let digits_end = bytes
        .iter()
        .position(|b| !b.is_ascii_digit())
        .unwrap_or(bytes.len());
    let (int_part, rest) = unsigned.split_at(digits_end);
    if int_part.is_empty() || (int_part.len() > 1 && int_part.starts_with('0')) {
        return None;
    }
    if rest.is_empty() {
        return literal.parse::<i64>().ok().map(|i| i as f64);
    }
    let rest = match rest.strip_prefix('.') {
        Some(fraction) => {
            let end = fraction
                .bytes()
                .position(|b| !b.is_ascii_digit())
                .unwrap_or(fraction.len());
            if end == 0 {
                return None;
            }
            &fraction[end..]
        }
        None => rest,
    };
    if !rest.is_empty() {
        let exponent = rest.strip_prefix(['e', 'E'])?;
        let digits = exponent.strip_prefix(['+', '-']).unwrap_or(exponent);
        if digits.is_empty() || !digits.bytes().all(|b| b.is_ascii_digit()) {
            return None;
        }
    }
    // Out of range (TOML refuses `1e400`; `1e-400` is left to it too).
    let value: f64 = literal.parse().ok()?;
    let nonzero = unsigned
        .split(['e', 'E'])
        .next()
        .is_some_and(|m| m.bytes().any(|b| (b'1'..=b'9').contains(&b)));
    (value.is_finite() && (value != 0.0 || !nonzero)).then_some(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The values the TOML parser gives for `value` of `shape`.
    fn by_toml(value: &str, shape: Shape) -> Option<Values> {
        #[derive(serde::Deserialize)]
        struct Reals {
            a: Vec<f64>,
        }
        #[derive(serde::Deserialize)]
        struct Indices {
            a: Vec<usize>,
        }
        #[derive(serde::Deserialize)]
        struct Points {
            a: Vec<Vec<f64>>,
        }
        #[derive(serde::Deserialize)]
        struct Pairs {
            a: Vec<[usize; 2]>,
        }
        let text = format!("a = {value}\n");
        match shape {
            Shape::Reals => toml::from_str::<Reals>(&text)
                .ok()
                .map(|t| Values::Reals(t.a)),
            Shape::Indices => toml::from_str::<Indices>(&text)
                .ok()
                .map(|t| Values::Indices(t.a)),
            Shape::Points => toml::from_str::<Points>(&text)
                .ok()
                .map(|t| Values::Points(t.a)),
            Shape::Tuples(_) => toml::from_str::<Pairs>(&text)
                .ok()
                .map(|t| Values::Tuples(t.a.into_iter().map(|p| p.to_vec()).collect())),
        }
    }

    /// What this module reads from `value`, `None` where it leaves it to
    /// the parser.
    fn by_bulk(value: &str, shape: Shape) -> Option<Values> {
        let mut tokens = Source::new(value).lex().peekable();
        tokens.next(); // the `[`
        read_array(value, &mut tokens, shape).map(|(v, _)| v)
    }

    /// Bit-exact equality, NaN included.
    fn same(a: &Values, b: &Values) -> bool {
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        match (a, b) {
            (Values::Reals(a), Values::Reals(b)) => bits(a) == bits(b),
            (Values::Points(a), Values::Points(b)) => {
                a.len() == b.len() && a.iter().zip(b).all(|(a, b)| bits(a) == bits(b))
            }
            _ => a == b,
        }
    }

    #[test]
    fn what_is_read_here_is_what_toml_reads() {
        let cases = [
            (
                "[1.5, -2e3, +inf, -nan, 0, -0, -0.0, 1E+02, 12345678901234567, 0.1e-5]",
                Shape::Reals,
            ),
            (
                "[1e400, -0.4e0466, 1e-400, 0e999, 0.0e-999, 1e02]",
                Shape::Reals,
            ),
            ("[ 1.0 , 2 ,\n 3 # comment\n ]", Shape::Reals),
            ("[1_000.0]", Shape::Reals),
            ("[0x1F]", Shape::Reals),
            ("[01.5]", Shape::Reals),
            ("[1.]", Shape::Reals),
            ("[.5]", Shape::Reals),
            ("[1e]", Shape::Reals),
            ("[1 2]", Shape::Reals),
            ("[1,,2]", Shape::Reals),
            ("[,1]", Shape::Reals),
            ("[1,]", Shape::Reals),
            ("[[0, 1] [1, 2]]", Shape::Tuples(2)),
            ("[[0, 1,], [1, 2],]", Shape::Tuples(2)),
            ("[[0 1]]", Shape::Tuples(2)),
            ("[99999999999999999999]", Shape::Reals),
            ("[\"1\"]", Shape::Reals),
            ("[[1.0, 2.0, 3.0], [4, 5, 6],\n [7.5, 8.5]]", Shape::Points),
            ("[[1.0, [2.0]]]", Shape::Points),
            ("[1.0, [2.0]]", Shape::Points),
            ("[[0, 1], [1, 2], [2, 0],]", Shape::Tuples(2)),
            ("[[0, 1, 2]]", Shape::Tuples(2)),
            ("[[0, -1]]", Shape::Tuples(2)),
            ("[[0, 1.0]]", Shape::Tuples(2)),
            ("[[0, 01]]", Shape::Tuples(2)),
            ("[[0, +1]]", Shape::Tuples(2)),
            ("[{ a = 1 }]", Shape::Tuples(2)),
            ("[0, 5, 9223372036854775807]", Shape::Indices),
            ("[9223372036854775808]", Shape::Indices),
            ("[]", Shape::Indices),
        ];
        for (value, shape) in cases {
            let toml = by_toml(value, shape);
            // What is left to the parser (`None`) is fine whatever it says.
            if let Some(bulk) = by_bulk(value, shape) {
                let toml = toml.unwrap_or_else(|| panic!("{value}: TOML refuses it"));
                assert!(same(&bulk, &toml), "{value}: {bulk:?} against {toml:?}");
            }
        }
        // The plain forms are all read here.
        assert!(by_bulk("[[0, 1], [1, 2]]", Shape::Tuples(2)).is_some());
        assert!(by_bulk("[[1.0, 2.0, 3.0], [4, 5, 6]]", Shape::Points).is_some());
        assert!(by_bulk("[1.5, -2e3, +inf, -nan]", Shape::Reals).is_some());
    }
}
