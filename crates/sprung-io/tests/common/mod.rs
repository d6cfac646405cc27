//! Helpers shared by the io test files.
#![allow(dead_code)] // each test file uses only some of them

pub mod mutate;

use std::path::{Path, PathBuf};

/// `shared/meshes`, the repository's sibling folder. A missing folder fails
/// the test: these checks must not be skipped silently.
pub fn meshes_dir() -> PathBuf {
    let beside = Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../../shared/meshes"
    ));
    if beside.is_dir() {
        return beside.to_path_buf();
    }
    match std::env::var_os("SPRUNG_SHARED_DIR") {
        Some(dir) => {
            let meshes = PathBuf::from(dir).join("meshes");
            assert!(
                meshes.is_dir(),
                "SPRUNG_SHARED_DIR/meshes ({}) is not a directory",
                meshes.display()
            );
            meshes
        }
        None => panic!(
            "shared meshes not found at {} and SPRUNG_SHARED_DIR is not set",
            beside.display()
        ),
    }
}
