//! The readers never panic: every real mesh file, damaged in thousands of
//! deterministic random ways, gives `Ok` or `Err`, and whatever is accepted
//! goes through the topology functions without a panic either.
//!
//! The damage imitates what happens to files: lines deleted, duplicated,
//! swapped or moved, bytes flipped or inserted, the file cut short, numbers
//! replaced by `nan`, huge, negative or malformed values. A tiny xorshift
//! generator with fixed seeds makes every run the same; a panic is reported
//! with the file, the case number and the mutations that caused it.

mod common;

use common::meshes_dir;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use sprung_io::mesh::{
    bending_pairs, closed_surface, edge_report, parse_mesh, select_object, signed_volume,
    unique_edges, MeshFormat,
};

/// Marsaglia's xorshift64: enough to scatter mutations, fully reproducible.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x
    }

    /// A number in `0..n` (0 when `n` is 0).
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
}

/// Byte ranges of the lines of `bytes`, each with its line feed.
fn line_ranges(bytes: &[u8]) -> Vec<(usize, usize)> {
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

const NUMBERS: [&str; 10] = [
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
fn mutate(bytes: &mut Vec<u8>, rng: &mut XorShift) -> String {
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
fn word_ranges(line: &[u8]) -> Vec<(usize, usize)> {
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

/// Runs the readers and the topology functions on `bytes`; `Err` carries
/// the panic message if anything panicked.
fn exercise(bytes: &[u8], format: MeshFormat, path: &Path) -> Result<bool, String> {
    catch_unwind(AssertUnwindSafe(|| {
        let Ok(meshes) = parse_mesh(bytes, format, path) else {
            return false;
        };
        for mesh in &meshes {
            let _ = closed_surface(mesh, path);
            let _ = signed_volume(&mesh.positions, &mesh.triangles);
            let _ = edge_report(&mesh.triangles);
            let _ = unique_edges(&mesh.triangles);
            let _ = bending_pairs(&mesh.triangles);
        }
        let first = meshes.first().map(|m| m.name.clone());
        let _ = select_object(meshes.clone(), first.as_deref(), path);
        let _ = select_object(meshes, None, path);
        true
    }))
    .map_err(|panic| {
        panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
            .unwrap_or_default()
    })
}

/// Damages `original` `cases` times (1 to 3 mutations each) and checks that
/// nothing panics. Returns how many damaged files were still accepted.
fn fuzz(name: &str, original: &[u8], format: MeshFormat, cases: usize, seed: u64) -> usize {
    let path = Path::new(name);
    assert_eq!(
        exercise(original, format, path),
        Ok(true),
        "{name}: the undamaged file must be accepted"
    );
    let mut rng = XorShift(seed);
    let mut accepted = 0;
    for case in 0..cases {
        let mut bytes = original.to_vec();
        let steps: Vec<String> = (0..1 + rng.below(3))
            .map(|_| mutate(&mut bytes, &mut rng))
            .collect();
        match exercise(&bytes, format, path) {
            Ok(true) => accepted += 1,
            Ok(false) => {}
            Err(message) => panic!("{name}: case {case} panicked ({message}) after: {steps:?}"),
        }
    }
    accepted
}

fn fuzz_file(name: &str, cases: usize, seed: u64) {
    let path = meshes_dir().join(name);
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let format = MeshFormat::from_path(&path).unwrap_or_else(|e| panic!("{e}"));
    let accepted = fuzz(name, &bytes, format, cases, seed);
    // Some damage is harmless (a swapped comment line, a changed digit), most
    // is not: both outcomes must occur, or the mutations are not reaching
    // the parser.
    assert!(
        accepted > 0 && accepted < cases,
        "{name}: {accepted} of {cases} accepted"
    );
}

// Case counts: a few thousand for the small files. A case costs about
// 0.7 ms for the 40 kB files and 5 to 25 ms for the large OBJ files (bunny,
// horse) in the dev profile on a loaded 2-core machine, so those get a few
// hundred at most, keeping this file within a few seconds.

#[test]
fn damaged_cube_asc_never_panics() {
    fuzz_file("cube.asc", 4000, 0x9E37_79B9_7F4A_7C15);
}

#[test]
fn damaged_uusalku_asc_never_panics() {
    fuzz_file("UUSALKU.ASC", 2000, 0xD1B5_4A32_D192_ED03);
}

#[test]
fn damaged_icosahedron_stl_never_panics() {
    fuzz_file("icosahedron_ascii.stl", 3000, 0x2545_F491_4F6C_DD1D);
}

#[test]
fn damaged_binary_stl_never_panics() {
    // The icosahedron's facets as binary STL, written here.
    let path = meshes_dir().join("icosahedron_ascii.stl");
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{e}"));
    let corners: Vec<f32> = text
        .lines()
        .filter_map(|l| l.trim().strip_prefix("vertex"))
        .flat_map(|l| l.split_whitespace().map(|w| w.parse::<f32>().unwrap()))
        .collect();
    let mut bytes = b"solid binary".to_vec();
    bytes.resize(80, 0);
    let triangles = corners.len() / 9;
    bytes.extend(u32::try_from(triangles).unwrap().to_le_bytes());
    for t in corners.chunks(9) {
        bytes.extend([0u8; 12]);
        for c in t {
            bytes.extend(c.to_le_bytes());
        }
        bytes.extend([0u8; 2]);
    }
    let accepted = fuzz(
        "binary.stl",
        &bytes,
        MeshFormat::Stl,
        3000,
        0x5851_F42D_4C95_7F2D,
    );
    assert!(accepted > 0 && accepted < 3000, "{accepted} accepted");
}

#[test]
fn damaged_sphere_low_off_never_panics() {
    fuzz_file("sphere_low.off", 1500, 0x1405_7B7E_F767_814F);
}

#[test]
fn damaged_sphere_obj_never_panics() {
    fuzz_file("sphere.obj", 1200, 0x6C07_8965_2F1B_3A5D);
}

#[test]
fn damaged_spot_obj_never_panics() {
    fuzz_file("spot_low_resolution.obj", 400, 0x94D0_49BB_1331_11EB);
}

#[test]
fn damaged_horse_obj_never_panics() {
    fuzz_file("horse.obj", 150, 0xBF58_476D_1CE4_E5B9);
}

#[test]
fn damaged_bunny_obj_never_panics() {
    fuzz_file("bunny.obj", 120, 0x3C6E_F372_FE94_F82B);
}
