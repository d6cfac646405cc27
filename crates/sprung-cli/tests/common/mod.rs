//! Helpers shared by the command-line tests: run the binary, write
//! scenes, read what it wrote.
#![allow(dead_code)] // each test file uses only some of them

use std::path::{Path, PathBuf};

/// Explicit Euler on a 1000 N/m, 0.01 kg chain: ω_max = 2√(k/m) ≈ 632 /s,
/// so the stable estimate is 1/√(k/m) ≈ 3.2e-3 s; dt = 0.02 s is far above
/// and the run blows up within a few steps.
pub const BLOW_UP_SCENE: &str = r#"[sim]
dt = 0.02
integrator = "euler"
steps = 100000

[[body]]
name = "chain"
rope = { particles = 6, length = 1.0 }
mass = 0.01
stiffness = 1000.0
"#;
use std::process::{Command, Output};

/// Run the `sprung` binary with `args` in `dir`.
pub fn sprung(args: &[&str], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the sprung binary runs")
}

/// Write `text` to `dir/name` (a scene) and return the path.
pub fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, text).expect("write scene");
    path
}

/// Bytes (a process's output) as text.
pub fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// Width and height from a PNG's IHDR chunk.
pub fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).expect("png");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{}", path.display());
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

/// Nothing left half-written anywhere under `dir`.
pub fn assert_no_partial_files(dir: &Path) {
    for entry in std::fs::read_dir(dir).expect("dir").flatten() {
        let path = entry.path();
        assert!(
            !path.to_string_lossy().ends_with(".partial"),
            "left behind: {}",
            path.display()
        );
        if path.is_dir() {
            assert_no_partial_files(&path);
        }
    }
}

/// Rows of a CSV file: header, then the records, as numbers (an empty
/// cell as 0, a cell of the text column `solver_preconditioner` as NaN:
/// [`csv_text`] reads it).
pub fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let content = std::fs::read_to_string(path).expect("csv exists");
    let mut lines = content.lines();
    let header: Vec<String> = lines
        .next()
        .expect("header")
        .split(',')
        .map(String::from)
        .collect();
    let rows = lines
        .map(|l| {
            l.split(',')
                .zip(&header)
                .map(|(v, name)| match (v.is_empty(), name.as_str()) {
                    (true, _) => 0.0,
                    (false, "solver_preconditioner") => f64::NAN,
                    (false, _) => v.parse().expect("number"),
                })
                .collect()
        })
        .collect();
    (header, rows)
}

/// The cells of the CSV file's column `name`, as text, one per record.
pub fn csv_text(path: &Path, name: &str) -> Vec<String> {
    let content = std::fs::read_to_string(path).expect("csv exists");
    let mut lines = content.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let column = header.iter().position(|c| *c == name).expect("the column");
    lines
        .map(|l| l.split(',').nth(column).unwrap_or("").to_string())
        .collect()
}
