//! Reading input files within a budget: only regular files (not a device
//! such as `/dev/zero`, a pipe or a folder, also behind a link), and at
//! most a size limit, so that no input can exhaust memory before it is
//! refused: [`DEFAULT_MAX_INPUT_BYTES`] for mesh files, and
//! [`DEFAULT_MAX_SCENE_BYTES`] for scene files (loading one takes about
//! twelve times the file at most, nearly all of it the world it describes:
//! bodies are parsed one at a time and long arrays read straight into
//! vectors, see `scene::sections`).

use std::io::Read;
use std::path::Path;

use crate::scene::{scene_text, SceneError};

/// The largest input file read by default (bytes): 256 MiB, far above
/// any scene or mesh the demos use (the 4002-vertex horse is 0.3 MB).
pub const DEFAULT_MAX_INPUT_BYTES: u64 = 256 << 20;

/// The largest scene file read by default (bytes): 16 MiB, some 200 MB
/// while it loads; a scene's large data belongs in mesh files.
pub const DEFAULT_MAX_SCENE_BYTES: u64 = 16 << 20;

/// The environment variable that overrides both limits (a number of
/// bytes).
pub const MAX_INPUT_VARIABLE: &str = "SPRUNG_MAX_INPUT_BYTES";

/// The size limit (bytes): `SPRUNG_MAX_INPUT_BYTES` when it is set,
/// else `default`; refused when it is set but not a whole number of bytes
/// (a limit the user meant to set is not silently replaced).
pub fn max_input_bytes(default: u64) -> std::io::Result<u64> {
    match std::env::var(MAX_INPUT_VARIABLE) {
        Err(_) => Ok(default),
        Ok(text) => text.trim().parse().map_err(|_| {
            std::io::Error::other(format!(
                "{MAX_INPUT_VARIABLE}={text:?}: expected a whole number of bytes"
            ))
        }),
    }
}

/// The bytes of the regular file at `path`, refused (with a sentence that
/// says why and the figures) when it is not a regular file or is larger
/// than [`max_input_bytes`] of `default` (bytes).
pub fn read_input(path: &Path, default: u64) -> std::io::Result<Vec<u8>> {
    let limit = max_input_bytes(default)?;
    let metadata = std::fs::metadata(path)?;
    if !metadata.is_file() {
        return Err(std::io::Error::other(
            "not a regular file (a device, pipe or folder is not read)",
        ));
    }
    let too_large = |size: u64| {
        std::io::Error::other(format!(
            "{size} bytes is more than the {limit} bytes an input file may have \
             (set {MAX_INPUT_VARIABLE} to raise the limit)"
        ))
    };
    if metadata.len() > limit {
        return Err(too_large(metadata.len()));
    }
    // Read at most one byte more than the limit: a file that grew since is
    // refused too.
    let mut bytes = Vec::with_capacity(metadata.len() as usize);
    std::fs::File::open(path)?
        .take(limit + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(too_large(bytes.len() as u64));
    }
    Ok(bytes)
}

/// The one gate every door reads a scene file through (the command line,
/// Python's `load`, `run` and `sweep`, the sweep's workers): the text of
/// the regular file at `path`, at most [`max_input_bytes`] of
/// [`DEFAULT_MAX_SCENE_BYTES`], UTF-8; refused with the same words
/// whichever door asked (a device such as `/dev/zero`, a FIFO, a folder, a
/// file too large, bytes that are not UTF-8).
pub fn read_scene_file(path: &Path) -> Result<String, SceneError> {
    let bytes = read_input(path, DEFAULT_MAX_SCENE_BYTES)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    Ok(scene_text(&bytes, path)?.to_string())
}

/// A scene read from a stream (standard input), named `name` in errors:
/// at most [`max_input_bytes`] of [`DEFAULT_MAX_SCENE_BYTES`], UTF-8.
pub fn read_scene_stream(stream: impl Read, name: &Path) -> Result<String, SceneError> {
    let unreadable =
        |e: std::io::Error| SceneError::new(name, None, format!("cannot read the scene: {e}"));
    let limit = max_input_bytes(DEFAULT_MAX_SCENE_BYTES).map_err(unreadable)?;
    let mut bytes = Vec::new();
    stream
        .take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(unreadable)?;
    if bytes.len() as u64 > limit {
        return Err(unreadable(too_large_scene(limit)));
    }
    Ok(scene_text(&bytes, name)?.to_string())
}

/// Refuse a scene given as text in memory (Python's `loads`, a sweep's
/// scene) that is longer than a scene file may be, with the words a file
/// gets; `name` names it in errors.
pub fn check_scene_text(text: &str, name: &Path) -> Result<(), SceneError> {
    let refuse =
        |e: std::io::Error| SceneError::new(name, None, format!("cannot read the scene: {e}"));
    let limit = max_input_bytes(DEFAULT_MAX_SCENE_BYTES).map_err(refuse)?;
    if text.len() as u64 > limit {
        return Err(refuse(too_large_scene(limit)));
    }
    Ok(())
}

/// The error of a scene over `limit` bytes.
fn too_large_scene(limit: u64) -> std::io::Error {
    std::io::Error::other(format!(
        "more than the {limit} bytes a scene may have (set {MAX_INPUT_VARIABLE} to raise the limit)"
    ))
}
