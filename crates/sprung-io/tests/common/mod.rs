//! Helpers shared by the io test files.
#![allow(dead_code)] // each test file uses only some of them

pub mod mutate;

use std::path::PathBuf;

/// The test mesh `name`: from `tests/meshes` (the readers' test files),
/// else from the repository's `scenes/meshes` (the demos' `cube.asc` and
/// `horse.obj`). A missing file fails the test: these checks must not be
/// skipped silently.
pub fn mesh_path(name: &str) -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let candidates = [
        root.join("tests/meshes").join(name),
        root.join("../../scenes/meshes").join(name),
    ];
    candidates
        .iter()
        .find(|p| p.is_file())
        .cloned()
        .unwrap_or_else(|| candidates[0].clone())
}
