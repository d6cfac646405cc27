//! `sprung view`: the interactive viewer. It is its own program,
//! `sprung-viewer` (crates/sprung-viewer, macroquad), kept out of this
//! binary so that the command line needs no windowing or GPU libraries; this
//! command runs the one next to the `sprung` binary and passes the
//! arguments on.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

use clap::Args;

use crate::error::CliError;

/// The viewer's program name.
const VIEWER: &str = "sprung-viewer";

/// Arguments of `sprung view`.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// The scene file (TOML); without one, the viewer opens on the demo ball2d.
    scene: Option<PathBuf>,
    /// Start on a built-in demo instead (see `sprung demo --list`).
    #[arg(long, conflicts_with = "scene")]
    demo: Option<String>,
    /// Draw N frames, then exit (for scripts and tests).
    #[arg(long)]
    frames: Option<u64>,
    /// With --frames or --exit-after: save the last frame as a PNG.
    #[arg(long)]
    screenshot: Option<PathBuf>,
    /// Exit after this many seconds.
    #[arg(long, value_name = "SECONDS")]
    exit_after: Option<f64>,
    /// Window size in pixels, WIDTHxHEIGHT (default 1280x800).
    #[arg(long, value_name = "WxH")]
    size: Option<String>,
    /// Where the steps run: cpu, gpu or gpu_f64 (the GPU step in f32 or
    /// f64 while it can run the world; docs/gpu.md), instead of the
    /// scene's `device`.
    #[arg(long)]
    device: Option<sprung_io::Device>,
}

impl ViewArgs {
    /// The viewer's command line.
    fn to_args(&self) -> Vec<OsString> {
        let mut args: Vec<OsString> = Vec::new();
        let mut flag = |name: &str, value: Option<OsString>| {
            if let Some(value) = value {
                args.push(name.into());
                args.push(value);
            }
        };
        flag("--demo", self.demo.clone().map(Into::into));
        flag("--frames", self.frames.map(|n| n.to_string().into()));
        flag("--screenshot", self.screenshot.clone().map(Into::into));
        flag(
            "--exit-after",
            self.exit_after.map(|s| s.to_string().into()),
        );
        flag("--size", self.size.clone().map(Into::into));
        flag("--device", self.device.map(|d| d.name().into()));
        if let Some(scene) = &self.scene {
            args.push(scene.clone().into());
        }
        args
    }
}

/// Run `sprung view`: start the viewer and wait for it to close.
pub fn run(args: &ViewArgs) -> Result<(), CliError> {
    let viewer = viewer()?;
    let status = Command::new(&viewer)
        .args(args.to_args())
        .status()
        .map_err(|e| CliError::Input(format!("cannot start {}: {e}", viewer.display())))?;
    match status.code() {
        Some(0) => Ok(()),
        Some(code) => Err(CliError::Child(
            code,
            format!(
                "the viewer ({}) exited with status {code}",
                viewer.display()
            ),
        )),
        None => Err(CliError::Input(format!(
            "the viewer ({}) was stopped by a signal",
            viewer.display()
        ))),
    }
}

/// The viewer program: `$SPRUNG_VIEWER`, else `sprung-viewer` in the folder
/// of the running `sprung`.
fn viewer() -> Result<PathBuf, CliError> {
    if let Some(path) = std::env::var_os("SPRUNG_VIEWER") {
        return Ok(PathBuf::from(path));
    }
    let exe = std::env::current_exe()
        .map_err(|e| CliError::Input(format!("cannot find where `sprung` runs from: {e}")))?;
    let folder = exe.parent().unwrap_or(Path::new("."));
    viewer_in(folder).map_err(CliError::Input)
}

/// `sprung-viewer` in `folder`, or an error saying how to build it.
fn viewer_in(folder: &Path) -> Result<PathBuf, String> {
    let path = folder.join(format!("{VIEWER}{}", std::env::consts::EXE_SUFFIX));
    if path.is_file() {
        return Ok(path);
    }
    let release = if folder.ends_with("debug") {
        ""
    } else {
        "--release "
    };
    Err(format!(
        "the viewer is not built: {} is missing. Build it with \
         `cargo build {release}-p {VIEWER}` (it goes next to this `sprung`), \
         or set SPRUNG_VIEWER to its path",
        path.display()
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_viewer_says_how_to_build_it() {
        let folder = Path::new("no/such/target/release");
        let message = viewer_in(folder).err().unwrap_or_default();
        assert!(
            message.contains("cargo build --release -p sprung-viewer"),
            "{message}"
        );
        assert!(message.contains("no/such/target/release"), "{message}");
        let debug = viewer_in(Path::new("no/such/target/debug"))
            .err()
            .unwrap_or_default();
        assert!(debug.contains("cargo build -p sprung-viewer"), "{debug}");
    }

    #[test]
    fn arguments_pass_through() {
        let args = ViewArgs {
            scene: Some(PathBuf::from("a.toml")),
            demo: None,
            frames: Some(5),
            screenshot: Some(PathBuf::from("s.png")),
            exit_after: None,
            size: None,
            device: Some(sprung_io::Device::Gpu),
        };
        let line: Vec<String> = args
            .to_args()
            .into_iter()
            .map(|a| a.to_string_lossy().into_owned())
            .collect();
        let expected = [
            "--frames",
            "5",
            "--screenshot",
            "s.png",
            "--device",
            "gpu",
            "a.toml",
        ];
        assert_eq!(line, expected);
    }
}
