//! The good base scene of the scene-error tests (`scene_errors_*.rs`), its
//! variants, and the error a bad one is refused with.

use std::path::Path;

use sprung_io::{parse_scene, SceneError};

pub const GOOD: &str = r#"[sim]
dt = 1e-3
steps = 10

[[body]]
name = "b"
particles = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
springs = [[0, 1], [1, 2]]
mass = 1.0
"#;

/// The scene `GOOD` with `from` replaced by `to`; panics if `from` is absent
/// so that a typo in a test cannot make it pass vacuously.
pub fn variant(from: &str, to: &str) -> String {
    assert!(
        GOOD.contains(from),
        "test setup: {from:?} not in the base scene"
    );
    GOOD.replacen(from, to, 1)
}

pub fn error_of(text: &str) -> SceneError {
    match parse_scene(text, Path::new("bad.toml")) {
        Ok(_) => panic!("scene was accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Assert the error names the file, the expected line and every fragment.
pub fn assert_error(text: &str, line: usize, fragments: &[&str]) {
    let error = error_of(text);
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("bad.toml:{line}: ")),
        "wrong place: {message}"
    );
    for fragment in fragments {
        assert!(message.contains(fragment), "{message:?} lacks {fragment:?}");
    }
}
