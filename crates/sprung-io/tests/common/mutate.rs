//! Damage for the fuzz tests: the mutations that happen to files (lines
//! deleted, duplicated, swapped or moved, bytes flipped or inserted, the
//! file cut short, numbers replaced by `nan`, huge, negative or malformed
//! values), driven by a tiny seeded generator so every run is the same.

/// Marsaglia's xorshift64: enough to scatter mutations, fully reproducible.
pub struct XorShift(pub u64);

impl XorShift {
    pub fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    /// A number in `0..n` (0 when `n` is 0).
    pub fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Byte ranges of the lines of `bytes`, each with its line feed.
pub fn line_ranges(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut ranges = Vec::new();
    let mut start = 0;
    for (i, &b) in bytes.iter().enumerate() {
        if b == b'\n' {
            ranges.push((start, i + 1));
            start = i + 1;
        }
    }
    if start < bytes.len() {
        ranges.push((start, bytes.len()));
    }
    ranges
}

pub const NUMBERS: [&str; 10] = [
    "nan",
    "-inf",
    "1e999",
    "-1e308",
    "-7",
    "99999999999999999999",
    "-0",
    "0x10",
    "1..2",
    "",
];

/// Applies one random mutation to `bytes` and says what it was.
pub fn mutate(bytes: &mut Vec<u8>, rng: &mut XorShift) -> String {
    let lines = line_ranges(bytes);
    let pick = |rng: &mut XorShift| lines.get(rng.below(lines.len())).copied().unwrap_or((0, 0));
    match rng.below(8) {
        0 => {
            let (a, b) = pick(rng);
            bytes.drain(a..b);
            format!("delete bytes {a}..{b} (a line)")
        }
        1 => {
            let (a, b) = pick(rng);
            let line = bytes[a..b].to_vec();
            bytes.splice(a..a, line);
            format!("duplicate the line at {a}..{b}")
        }
        2 => {
            let (a1, b1) = pick(rng);
            let (a2, b2) = pick(rng);
            let (first, second) = if a1 <= a2 {
                ((a1, b1), (a2, b2))
            } else {
                ((a2, b2), (a1, b1))
            };
            if first.1 <= second.0 {
                let mut out = bytes[..first.0].to_vec();
                out.extend_from_slice(&bytes[second.0..second.1]);
                out.extend_from_slice(&bytes[first.1..second.0]);
                out.extend_from_slice(&bytes[first.0..first.1]);
                out.extend_from_slice(&bytes[second.1..]);
                *bytes = out;
            }
            format!(
                "swap the lines at {}..{} and {}..{}",
                first.0, first.1, second.0, second.1
            )
        }
        3 => {
            let at = rng.below(bytes.len());
            let mask = 1 + rng.below(255) as u8;
            if let Some(b) = bytes.get_mut(at) {
                *b ^= mask;
            }
            format!("xor byte {at} with {mask:#04x}")
        }
        4 => {
            let at = rng.below(bytes.len() + 1);
            bytes.truncate(at);
            format!("truncate to {at} bytes")
        }
        5 => {
            let at = rng.below(bytes.len() + 1);
            let byte = [0xFF, 0x00, b':', b'\r', b'\n', b'/', b'-', b'"'][rng.below(8)];
            bytes.insert(at, byte);
            format!("insert byte {byte:#04x} at {at}")
        }
        6 => {
            // Replace a number-looking word of a random line.
            let (a, b) = pick(rng);
            let words: Vec<(usize, usize)> = word_ranges(&bytes[a..b])
                .into_iter()
                .filter(|&(s, _)| {
                    bytes
                        .get(a + s)
                        .is_some_and(|c| c.is_ascii_digit() || *c == b'-' || *c == b'.')
                })
                .collect();
            let Some(&(s, e)) = words.get(rng.below(words.len())) else {
                return "no number to replace".to_owned();
            };
            let value = NUMBERS[rng.below(NUMBERS.len())];
            bytes.splice(a + s..a + e, value.bytes());
            format!("replace the number at {} with {value:?}", a + s)
        }
        _ => {
            // Move a line elsewhere.
            let (a, b) = pick(rng);
            let line: Vec<u8> = bytes.drain(a..b).collect();
            let at = rng.below(bytes.len() + 1);
            bytes.splice(at..at, line);
            format!("move the line at {a}..{b} to {at}")
        }
    }
}

/// Ranges of the words of a line, relative to its start.
pub fn word_ranges(line: &[u8]) -> Vec<(usize, usize)> {
    let mut words = Vec::new();
    let mut start = None;
    for (i, &b) in line.iter().enumerate() {
        let space = b.is_ascii_whitespace() || b == b':';
        match (start, space) {
            (None, false) => start = Some(i),
            (Some(s), true) => {
                words.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        words.push((s, line.len()));
    }
    words
}
