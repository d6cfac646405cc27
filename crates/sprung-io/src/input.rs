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
