//! What a run refuses before it writes anything: an output over one of
//! its inputs, a `--save-state` path that cannot be written or is one of
//! the run's own outputs, and any output that would replace what is not a
//! regular file of the run's own (a link, a device, a FIFO, a folder).

use std::path::{Path, PathBuf};

use sprung_io::export;

use super::ANIMATION;
use crate::error::CliError;

/// The tables of a run's diagnostics that a resumed run can go on from
/// (`Diagnostics::resume` reads the first that exists).
pub(super) const DIAGNOSTICS_TABLES: [&str; 3] = [
    "diagnostics.csv",
    "diagnostics.csv.partial",
    "diagnostics.csv.previous",
];

/// `path` made absolute, with its longest existing part resolved (links
/// followed, `..` taken away), so two names of one file compare equal.
pub(crate) fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut base = absolute.clone();
    let mut rest = Vec::new();
    while !base.exists() {
        let Some(last) = base.components().next_back() else {
            return absolute;
        };
        rest.push(last.as_os_str().to_owned());
        if !base.pop() {
            return absolute;
        }
    }
    let mut resolved = base.canonicalize().unwrap_or(base);
    // The part that does not exist yet has no links: its `..` go back a
    // name.
    for name in rest.iter().rev() {
        match name.to_str() {
            Some("..") => {
                resolved.pop();
            }
            Some(".") => {}
            _ => resolved.push(name),
        }
    }
    resolved
}

/// Refuse a `--save-state` path that cannot be written, or would be written
/// over one of the run's own outputs in `out` (or over `out` itself),
/// before anything is made.
pub(super) fn check_state_path(state: &Path, out: &Path) -> Result<(), CliError> {
    let shown = state.display().to_string();
    let refuse = |why: String| Err(CliError::Input(format!("--save-state {shown}: {why}")));
    if state.as_os_str().is_empty() {
        return refuse("is empty (give a file name)".into());
    }
    let (state, out) = (resolved(state), resolved(out));
    if state.is_dir() {
        return refuse("is a folder (give a file name)".into());
    }
    if out.starts_with(&state) {
        return refuse(format!("is the run's folder {} or holds it", out.display()));
    }
    let own = DIAGNOSTICS_TABLES.iter().chain(&[ANIMATION]);
    if own.clone().any(|name| state == out.join(name)) || state.starts_with(out.join("frames")) {
        return refuse(format!(
            "is one of the run's own outputs in {} (give another file)",
            out.display()
        ));
    }
    let folder = state.parent().unwrap_or(Path::new("."));
    if !folder.is_dir() && folder != out {
        return refuse(format!(
            "there is no folder {} to write it in",
            folder.display()
        ));
    }
    Ok(())
}

/// Refuse a run whose outputs (`--save-state`, or a table, animation or
/// frame in `out`) would be written over one of the files it reads,
/// `inputs` (the scene, its meshes, the state it resumes from).
pub(super) fn check_inputs_kept(
    inputs: &[&Path],
    out: &Path,
    state: Option<&Path>,
) -> Result<(), CliError> {
    let out_resolved = resolved(out);
    let frames = out_resolved.join("frames");
    let state_resolved = state.map(resolved);
    for input in inputs {
        let input_resolved = resolved(input);
        let over = if state_resolved.as_ref() == Some(&input_resolved) {
            Some(format!("--save-state {}", state.unwrap_or(input).display()))
        } else if DIAGNOSTICS_TABLES
            .iter()
            .chain(&[ANIMATION])
            .any(|name| input_resolved == out_resolved.join(name))
            || (input_resolved.starts_with(&frames)
                && input_resolved
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("frame_")))
        {
            Some(format!("the run's outputs in --out {}", out.display()))
        } else {
            None
        };
        if let Some(output) = over {
            return Err(CliError::Input(format!(
                "{output} would be written over {}, which this run reads: give another path (nothing was written)",
                input.display()
            )));
        }
    }
    Ok(())
}

/// Refuse, before anything is written, a run whose outputs would replace
/// what is not a regular file of its own: a link, device, FIFO or folder
/// where `out` would have a table, an animation, a series file or a
/// frame, a `frames` folder that is a link (the frames would go outside
/// `out`), or such a node at `--save-state` (or their temporary names).
pub fn check_own_files(out: &Path, frames: &Path, state: Option<&Path>) -> Result<(), CliError> {
    let refuse = |e: std::io::Error| CliError::Input(format!("{e} (nothing was written)"));
    if out.exists() && !out.is_dir() {
        // Refused as it is by `prepare_output`.
        return Ok(());
    }
    let tables = DIAGNOSTICS_TABLES.iter().chain(&[ANIMATION, "scene.toml"]);
    for path in tables.map(|name| out.join(name)) {
        export::replaceable(&path).map_err(refuse)?;
        export::replaceable(&export::partial_path(&path)).map_err(refuse)?;
    }
    if let Some(state) = state {
        for path in [state.to_path_buf(), export::partial_path(state)] {
            export::replaceable(&path).map_err(|e| {
                CliError::Input(format!(
                    "--save-state {}: {e} (nothing was written)",
                    state.display()
                ))
            })?;
        }
    }
    if frames.is_symlink() {
        return Err(CliError::Input(format!(
            "--out {}: its `frames` is a symbolic link, and the frames would be written where it points: remove it or give another --out (nothing was written)",
            out.display()
        )));
    }
    for format in export::FrameFormat::ALL {
        if let Some(series) = export::series_path(frames, format) {
            export::replaceable(&series).map_err(refuse)?;
        }
    }
    let Ok(entries) = std::fs::read_dir(frames) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        if entry.file_name().to_string_lossy().starts_with("frame_") {
            export::replaceable(&entry.path()).map_err(refuse)?;
        }
    }
    Ok(())
}

/// The folder a `--save-state` file goes in.
pub(super) fn state_folder(state: &Path) -> &Path {
    match state.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    }
}

/// Refuse a `--save-state` file whose folder does not take a new file,
/// by making (and removing) an empty one beside it: found before the
/// run, not after it.
pub(super) fn check_writable(state: &Path) -> Result<(), CliError> {
    let folder = state_folder(state);
    let probe = folder.join(format!(".sprung-probe-{}", std::process::id()));
    let made = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe);
    match made {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::Input(format!(
            "--save-state {}: cannot write a file in {}: {e} (nothing was run)",
            state.display(),
            folder.display()
        ))),
    }
}
