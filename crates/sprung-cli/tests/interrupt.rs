//! SIGINT and SIGTERM stop a run at the end of a step: every row recorded
//! before the signal is in `diagnostics.csv`, every frame written is
//! complete, nothing `.partial` is left, and the exit status is 130 / 143.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Start the flag demo with VTK frames into `out` (and `extra` options),
/// wait until it has recorded some rows, send `signal`, and return the
/// exit status and what it printed on stderr.
fn interrupted_run(out: &Path, signal: &str, extra: &[&str]) -> (Option<i32>, String) {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/flag.toml");
    let child = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args([
            "run",
            scene.to_str().unwrap(),
            "--format",
            "vtk",
            "--quiet",
            "--out",
        ])
        .arg(out)
        .args(extra)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sprung starts");
    // Wait for a few frames (the run takes far longer than this).
    let start = Instant::now();
    let frames = out.join("frames");
    while std::fs::read_dir(&frames).map_or(0, |d| d.count()) < 5 {
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "no frames written"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let status = Command::new("kill")
        .args(["-s", signal, &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    let output = child.wait_with_output().expect("sprung ends");
    (output.status.code(), common::text(&output.stderr))
}

fn check(signal: &str, code: i32, extra: &[&str]) {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("flag");
    let (status, stderr) = interrupted_run(&out, signal, extra);
    assert_eq!(status, Some(code), "{stderr}");
    assert!(stderr.contains(&format!("SIG{signal}")), "{stderr}");
    common::assert_no_partial_files(&out);
    // Every row recorded went with a frame (one record per row): the
    // diagnostics are complete up to the last frame, and every frame reads.
    let csv =
        std::fs::read_to_string(out.join("diagnostics.csv")).expect("diagnostics.csv in place");
    let rows = csv.lines().count() - 1;
    let mut frames: Vec<_> = std::fs::read_dir(out.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with("frame_"))
        })
        .collect();
    frames.sort();
    assert_eq!(frames.len(), rows, "one frame per row");
    // The series file lists them all, written as the run stopped.
    let series = std::fs::read_to_string(out.join("frames/frames.vtk.series")).expect("series");
    assert_eq!(series.matches("\"name\"").count(), rows, "{series}");
    assert!(rows >= 5);
    for frame in &frames {
        let text = std::fs::read_to_string(frame).unwrap();
        sprung_io::export::read_vtk_frame(&text, frame).unwrap_or_else(|e| panic!("{e}"));
    }
    // The message says where the results are.
    assert!(stderr.contains(&format!("{rows} rows")), "{stderr}");
}

#[test]
fn ctrl_c_stops_at_the_end_of_a_step_keeping_everything() {
    check("INT", 130, &[]);
}

#[test]
fn sigterm_stops_at_the_end_of_a_step_keeping_everything() {
    check("TERM", 143, &[]);
}

/// On the GPU the run reads its state back every quarter of a second at
/// most (or at each row), so a signal stops it as soon and keeps as much
/// (skipped where this machine has no adapter and `SPRUNG_GPU_TESTS` is
/// not `require`).
#[test]
fn ctrl_c_stops_a_run_on_the_gpu_keeping_everything() {
    let dir = tempfile::tempdir().unwrap();
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/flag.toml");
    let probe = [
        "run",
        scene.to_str().unwrap(),
        "--device",
        "gpu",
        "--steps",
        "1",
    ];
    let probed = common::sprung(&probe, dir.path());
    let stderr = common::text(&probed.stderr);
    if stderr.contains("no GPU adapter found")
        && std::env::var("SPRUNG_GPU_TESTS").as_deref() != Ok("require")
    {
        eprintln!("skipped: {stderr}");
        return;
    }
    assert!(probed.status.success(), "{stderr}");
    check("INT", 130, &["--device", "gpu"]);
}
