//! Nothing the user brought is overwritten and nothing a run wrote is
//! lost: an output path that is one of the run's inputs (the scene, a
//! mesh, the state it resumes from) is refused before the run, and so is a
//! `--save-state` path that cannot be written (found before the first
//! step, not after the last).

mod common;

use std::path::Path;

use common::{sprung, text, write};

const ROPE: &str = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"rope\"\nrope = { particles = 5, length = 1.0 }\nmass = 0.1\nstiffness = 200.0\npinned = [0]\n";

/// Run `args` in `dir`, expecting status 1 with `needle` in the error.
fn refused(dir: &Path, args: &[&str], needle: &str) {
    let output = sprung(args, dir);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
}

#[test]
fn a_state_saved_over_the_scene_is_refused_and_the_scene_kept() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "r.toml", ROPE);
    let args = ["run", "r.toml", "--out", "o", "--steps", "10"];
    refused(
        d,
        &[&args[..], &["--save-state", "r.toml"]].concat(),
        "--save-state r.toml would be written over r.toml, which this run reads",
    );
    // The same file by another name.
    refused(
        d,
        &[&args[..], &["--save-state", "./o/../r.toml"]].concat(),
        "which this run reads",
    );
    assert_eq!(std::fs::read_to_string(d.join("r.toml")).unwrap(), ROPE);
    assert!(!d.join("o").exists(), "nothing written");
}

#[test]
fn a_mesh_or_the_resumed_state_is_never_written_over() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let mesh = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    write(d, "t.obj", mesh);
    let scene = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"t\"\nmesh = \"t.obj\"\nmass = 0.1\nstiffness = 100.0\n";
    write(d, "m.toml", scene);
    refused(
        d,
        &[
            "run",
            "m.toml",
            "--out",
            "o",
            "--steps",
            "5",
            "--save-state",
            "t.obj",
        ],
        "would be written over t.obj",
    );
    assert_eq!(std::fs::read_to_string(d.join("t.obj")).unwrap(), mesh);
    // Resuming from s.bin and saving over it would leave no way back.
    write(d, "r.toml", ROPE);
    let run = [
        "run",
        "r.toml",
        "--out",
        "p",
        "--steps",
        "10",
        "--save-state",
        "s.bin",
    ];
    assert!(sprung(&run, d).status.success());
    let saved = std::fs::read(d.join("s.bin")).unwrap();
    refused(
        d,
        &[
            "run",
            "r.toml",
            "--out",
            "p",
            "--steps",
            "20",
            "--resume",
            "s.bin",
            "--save-state",
            "s.bin",
        ],
        "--save-state s.bin would be written over s.bin",
    );
    assert_eq!(std::fs::read(d.join("s.bin")).unwrap(), saved);
}

#[test]
fn a_scene_among_the_runs_own_outputs_is_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    std::fs::create_dir_all(d.join("o/frames")).unwrap();
    write(&d.join("o"), "diagnostics.csv.previous", ROPE);
    write(&d.join("o/frames"), "frame_000003.toml", ROPE);
    for scene in ["o/diagnostics.csv.previous", "o/frames/frame_000003.toml"] {
        refused(
            d,
            &[
                "run", scene, "--out", "o", "--steps", "5", "--format", "vtu",
            ],
            "the run's outputs in --out o would be written over",
        );
        assert_eq!(std::fs::read_to_string(d.join(scene)).unwrap(), ROPE);
    }
}

#[test]
fn a_state_path_that_cannot_be_written_is_refused_before_the_run() {
    // /proc takes no new file, even for root: found before the first step,
    // so the run's folder is never made.
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "r.toml", ROPE);
    refused(
        d,
        &[
            "run",
            "r.toml",
            "--out",
            "o",
            "--steps",
            "20000",
            "--save-state",
            "/proc/x.state",
        ],
        "--save-state /proc/x.state: cannot write a file in /proc",
    );
    assert!(!d.join("o").exists());
}
