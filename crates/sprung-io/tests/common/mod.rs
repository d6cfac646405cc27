//! Helpers shared by the io test files.
#![allow(dead_code)] // each test file uses only some of them

pub mod mutate;
pub mod scene_errors;

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

/// Run `f`, giving its panic's message as an error (a fuzz test's way to
/// name what panicked and carry on to report the input).
pub fn without_panic<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(f)).map_err(|panic| {
        panic
            .downcast_ref::<String>()
            .cloned()
            .or_else(|| panic.downcast_ref::<&str>().map(|s| (*s).to_owned()))
            .unwrap_or_default()
    })
}

/// Four particles on a line 1 m apart at height `y` (m), whose springs
/// are listed `[2, 3], [1, 2], [0, 1], [3, 0]`: an order the world does
/// not store them in (it puts runs first), to check that outputs keep the
/// scene's.
pub fn springs_out_of_order(y: f64) -> sprung::BodyData {
    let xs = [0.0, 1.0, 2.0, 3.0];
    let mut body =
        sprung::BodyData::from_positions(xs.map(|x| sprung::Vec3::new(x, y, 0.0)).to_vec());
    body.springs = [[2, 3], [1, 2], [0, 1], [3, 0]]
        .map(|[a, b]| sprung::SpringData::between(a, b))
        .to_vec();
    body
}
