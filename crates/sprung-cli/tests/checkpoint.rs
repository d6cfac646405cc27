//! Checkpoints: a run stopped half way with `--save-state` and resumed with
//! `--resume` writes the same bytes in `diagnostics.csv` and in every frame
//! as the run that never stopped; also after a signal, and after a kill
//! that left only a periodic checkpoint and `diagnostics.csv.partial`. A
//! damaged or foreign state file is refused and nothing is written.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{sprung, text, write};

/// A gas ball whose gas leaks from 0.02 s on, dropped on a floor.
const LEAKING_BALL: &str = r#"[sim]
dt = 2e-4
integrator = "symplectic_euler"
steps = 300

[[body]]
name = "ball"
sphere = { radius = 0.5, subdivisions = 1 }
total_mass = 1.0
stiffness = 2000.0
damping = 0.5
translate = [0.0, 0.52, 0.0]
gas = { nrt = 500.0, ramp_time = 0.01, leak_rate = 2.0, leak_start = 0.02 }

[[collider]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
restitution = 0.3
friction = 0.3
"#;

fn scene(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

/// Run `scene` (with `extra` options) for `steps` steps in one go, and again
/// stopped after `half` steps and resumed; every byte of the diagnostics
/// and the VTK frames must agree.
fn assert_resumes_exactly(scene: &str, extra: &[&str], steps: u64, half: u64) {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let run = |out: &str, steps: u64, more: &[&str]| {
        let steps = steps.to_string();
        let mut args = vec![
            "run", scene, "--steps", &steps, "--every", "10", "--format", "vtk", "--quiet",
            "--out", out,
        ];
        args.extend_from_slice(extra);
        args.extend_from_slice(more);
        let output = sprung(&args, d);
        assert!(output.status.success(), "{}", text(&output.stderr));
    };
    run("whole", steps, &[]);
    run("parts", half, &["--save-state", "state.bin"]);
    run("parts", steps, &["--resume", "state.bin"]);
    assert_same_outputs(&d.join("whole"), &d.join("parts"));
    common::assert_no_partial_files(d);
}

/// The same `diagnostics.csv` and the same frames, byte for byte.
fn assert_same_outputs(whole: &Path, parts: &Path) {
    let csv = |dir: &Path| std::fs::read(dir.join("diagnostics.csv")).expect("diagnostics.csv");
    let (a, b) = (csv(whole), csv(parts));
    assert!(
        a == b,
        "diagnostics differ:\n{}\n---\n{}",
        String::from_utf8_lossy(&a),
        String::from_utf8_lossy(&b)
    );
    let mut names: Vec<_> = std::fs::read_dir(whole.join("frames"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    names.sort();
    assert!(names.len() > 2, "frames were written");
    for name in names {
        let frame = |dir: &Path| std::fs::read(dir.join("frames").join(&name)).expect("frame");
        assert!(frame(whole) == frame(parts), "{name:?} differs");
    }
    let count = |dir: &Path| std::fs::read_dir(dir.join("frames")).unwrap().count();
    assert_eq!(count(whole), count(parts), "no extra frames");
}

#[test]
fn cloth_in_wind_resumes_exactly() {
    assert_resumes_exactly(&scene("flag.toml"), &[], 400, 170);
}

#[test]
fn leaking_gas_ball_resumes_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), "leak.toml", LEAKING_BALL);
    assert_resumes_exactly(path.to_str().unwrap(), &[], 300, 150);
}

#[test]
fn verlet_resumes_exactly_with_its_history() {
    assert_resumes_exactly(&scene("flag.toml"), &["--integrator", "verlet"], 300, 120);
}

#[test]
fn adaptive_rk45_resumes_exactly_with_its_next_step() {
    assert_resumes_exactly(&scene("orbit.toml"), &["--integrator", "rk45"], 200, 90);
}

#[test]
fn muscles_rods_and_rigid_bodies_resume_exactly() {
    assert_resumes_exactly(&scene("walker.toml"), &[], 400, 130);
    assert_resumes_exactly(&scene("dice.toml"), &[], 400, 210);
}

#[test]
fn implicit_solvers_resume_exactly() {
    let stiff = scene("stiff_cloth.toml");
    assert_resumes_exactly(&stiff, &["--integrator", "projective"], 20, 7);
    assert_resumes_exactly(&stiff, &["--integrator", "implicit_euler"], 20, 5);
}

/// A run resumed after springs broke (the `tear` cloth torn at about step
/// 250, the `burst` balloon at about 1,950) goes on with the same bits:
/// the state holds the broken springs, and the surfaces open along them
/// again when it is read.
#[test]
fn torn_and_burst_bodies_resume_exactly() {
    assert_resumes_exactly(&scene("tear.toml"), &[], 700, 420);
    assert_resumes_exactly(&scene("burst.toml"), &[], 2400, 2100);
}

/// Contact between bodies keeps the pairs of its last search for the
/// steps after (while the margin covers the motion): a resumed run has them
/// too, so it goes on with the same bits while bodies touch.
#[test]
fn touching_bodies_resume_exactly() {
    // The two balls meet at about step 750 and touch for some 300 steps.
    assert_resumes_exactly(&scene("collide.toml"), &[], 1200, 830);
    assert_resumes_exactly(&scene("pile2d.toml"), &[], 600, 370);
}

/// The flag run of the kill tests: 40,000 steps, a row and a VTK frame
/// every 500, into `out`, with `extra` options.
fn flag_run<'a>(flag: &'a str, out: &'a str, extra: &[&'a str]) -> Vec<&'a str> {
    let mut args = vec![
        "run", flag, "--steps", "40000", "--every", "500", "--format", "vtk", "--quiet", "--out",
        out,
    ];
    args.extend_from_slice(extra);
    args
}

/// Start `args` and kill it (SIGKILL) once it has saved a checkpoint newer
/// than `after` (the state file's modification time, if any).
fn kill_after_a_checkpoint(d: &Path, args: &[&str], after: Option<std::time::SystemTime>) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .current_dir(d)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("sprung starts");
    let start = Instant::now();
    let saved = || {
        std::fs::metadata(d.join("state.bin"))
            .and_then(|m| m.modified())
            .ok()
    };
    while saved().is_none() || saved() == after {
        assert!(start.elapsed() < Duration::from_secs(60), "no checkpoint");
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().expect("kill");
    child.wait().expect("sprung ends");
}

/// A run killed outright (SIGKILL) after a periodic checkpoint leaves the
/// state and `diagnostics.csv.partial`; resuming goes on from the
/// checkpoint with the same bytes as a run that never stopped, also when
/// the resumed run is killed in turn after a checkpoint of its own.
#[test]
fn a_killed_run_resumes_from_its_last_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flag = scene("flag.toml");
    let output = sprung(&flag_run(&flag, "whole", &[]), d);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let checkpoints = ["--save-state", "state.bin", "--checkpoint-every", "1000"];
    kill_after_a_checkpoint(d, &flag_run(&flag, "parts", &checkpoints), None);
    assert!(
        !d.join("parts/diagnostics.csv").exists(),
        "a killed run commits nothing"
    );
    // The resumed run checkpoints into another file (the state it resumes
    // from is an input, never written over), then resumes from that.
    std::fs::rename(d.join("state.bin"), d.join("first.bin")).unwrap();
    let resume = [
        "--resume",
        "first.bin",
        "--save-state",
        "state.bin",
        "--checkpoint-every",
        "1000",
    ];
    kill_after_a_checkpoint(d, &flag_run(&flag, "parts", &resume), None);
    let output = sprung(&flag_run(&flag, "parts", &["--resume", "state.bin"]), d);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_same_outputs(&d.join("whole"), &d.join("parts"));
    common::assert_no_partial_files(d);
    assert!(!d.join("parts/diagnostics.csv.previous").exists());
}

/// SIGINT with `--save-state` saves the state at the step it stopped at; the
/// resumed run completes the same table.
#[test]
fn an_interrupted_run_saves_its_state_and_resumes() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flag = scene("flag.toml");
    let args = [
        "run", &flag, "--steps", "40000", "--every", "500", "--format", "vtk", "--quiet",
    ];
    let output = sprung(&[&args[..], &["--out", "whole"]].concat(), d);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let child = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .args(["--out", "parts", "--save-state", "state.bin"])
        .current_dir(d)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sprung starts");
    let start = Instant::now();
    while std::fs::read_dir(d.join("parts/frames")).map_or(0, |f| f.count()) < 3 {
        assert!(start.elapsed() < Duration::from_secs(60), "no frames");
        std::thread::sleep(Duration::from_millis(5));
    }
    let status = Command::new("kill")
        .args(["-s", "INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(status.success());
    let output = child.wait_with_output().expect("sprung ends");
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(stderr.contains("state saved to state.bin"), "{stderr}");
    let output = sprung(
        &[&args[..], &["--out", "parts", "--resume", "state.bin"]].concat(),
        d,
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_same_outputs(&d.join("whole"), &d.join("parts"));
}

/// A damaged state, a state of another scene, one at or past the end of
/// the run, and one without the run's diagnostics are refused with a
/// sentence naming the file; the output folder is left as it was.
#[test]
fn bad_states_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flag = scene("flag.toml");
    let base = ["run", &flag, "--steps", "40", "--every", "10", "--quiet"];
    let output = sprung(
        &[&base[..], &["--out", "out", "--save-state", "state.bin"]].concat(),
        d,
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let before = std::fs::read(d.join("out/diagnostics.csv")).unwrap();
    let state = std::fs::read(d.join("state.bin")).unwrap();
    let refused = |args: &[&str], expected: &str| {
        let output = sprung(args, d);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert_eq!(
            std::fs::read(d.join("out/diagnostics.csv")).unwrap(),
            before
        );
    };
    fn resume<'a>(base: &[&'a str], file: &'a str) -> Vec<&'a str> {
        [
            &base[..2],
            &["--steps", "80", "--out", "out", "--resume", file],
        ]
        .concat()
    }
    // One bit flipped in a position: the checksum catches it.
    let mut damaged = state.clone();
    let middle = damaged.len() / 2;
    damaged[middle] ^= 0x10;
    std::fs::write(d.join("damaged.bin"), &damaged).unwrap();
    refused(
        &resume(&base, "damaged.bin"),
        "damaged.bin: the state file is damaged",
    );
    std::fs::write(d.join("short.bin"), &state[..state.len() - 9]).unwrap();
    refused(&resume(&base, "short.bin"), "damaged");
    std::fs::write(d.join("text.bin"), "[sim]\ndt = 1\n").unwrap();
    refused(&resume(&base, "text.bin"), "not a sprung state file");
    refused(&resume(&base, "missing.bin"), "missing.bin");
    let mut future = state.clone();
    future[13] = 9;
    std::fs::write(d.join("future.bin"), &future).unwrap();
    refused(&resume(&base, "future.bin"), "format 9");
    // The state of another scene.
    let ball = scene("ball3d.toml");
    refused(
        &[
            "run",
            &ball,
            "--steps",
            "80",
            "--out",
            "out",
            "--resume",
            "state.bin",
        ],
        "another scene",
    );
    // Another recording cadence would mix rows of two cadences.
    refused(
        &[
            &base[..2],
            &[
                "--steps",
                "80",
                "--every",
                "20",
                "--out",
                "out",
                "--resume",
                "state.bin",
            ],
        ]
        .concat(),
        "recording every 10 steps, this one records every 20",
    );
    // Frames the saved run did not write: its series file would list
    // frames that are not there (the run wrote none; one with vtu frames
    // resumed as vtk is the same case, and one with frames resumed with
    // none would leave rows without frames).
    refused(
        &[
            &base[..2],
            &[
                "--steps",
                "80",
                "--every",
                "10",
                "--out",
                "out",
                "--resume",
                "state.bin",
                "--format",
                "vtk",
            ],
        ]
        .concat(),
        "--resume with --format vtk: the run in out was started with no --format",
    );
    assert!(!d.join("out/frames").exists(), "no frames folder made");
    // Another integrator's history is not used: it starts afresh (allowed).
    // A state at the end of the run has nothing left to do.
    refused(
        &[&base[..], &["--out", "out", "--resume", "state.bin"]].concat(),
        "the state is at step 40",
    );
    // A folder without the run's diagnostics.
    let output = sprung(
        &[
            &base[..2],
            &[
                "--steps",
                "80",
                "--every",
                "10",
                "--out",
                "elsewhere",
                "--resume",
                "state.bin",
            ],
        ]
        .concat(),
        d,
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("no diagnostics.csv"));
    // A folder without the run's diagnostics is refused before it is made.
    assert!(!d.join("elsewhere").exists(), "--out made for nothing");
    // A state path that cannot be written, or that is one of the run's own
    // outputs, is refused before anything is run or made.
    for (state, expected) in [
        ("fresh/diagnostics.csv", "one of the run's own outputs"),
        ("fresh/frames/state.bin", "one of the run's own outputs"),
        (
            "fresh/../fresh/diagnostics.csv",
            "one of the run's own outputs",
        ),
        ("nowhere/state.bin", "there is no folder"),
        (".", "is a folder"),
        ("fresh", "is the run's folder"),
    ] {
        let output = sprung(
            &[&base[..], &["--out", "fresh", "--save-state", state]].concat(),
            d,
        );
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{state}: {stderr}");
        assert!(stderr.contains(expected), "{state}: {stderr}");
        assert!(!d.join("fresh").exists(), "{state}: --out made for nothing");
    }
    // A state file inside the run's own (new) folder is fine.
    let output = sprung(
        &[
            &base[..],
            &["--out", "inside", "--save-state", "inside/state.bin"],
        ]
        .concat(),
        d,
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(d.join("inside/state.bin").is_file());
    // --checkpoint-every needs --save-state: a usage error.
    let output = sprung(&[&base[..], &["--checkpoint-every", "5"]].concat(), d);
    assert_eq!(output.status.code(), Some(2));
}

#[test]
fn a_run_keeps_to_its_format_and_clears_what_an_earlier_run_left() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let flag = scene("flag.toml");
    let run = |extra: &[&str]| {
        let args = [
            &["run", &flag, "--every", "10", "--quiet", "--out", "out"][..],
            extra,
        ]
        .concat();
        sprung(&args, d)
    };
    let frames = |extension: &str| {
        std::fs::read_dir(d.join("out/frames")).map_or(0, |entries| {
            entries
                .flatten()
                .filter(|e| e.file_name().to_string_lossy().ends_with(extension))
                .count()
        })
    };
    // A vtu run, then a shorter vtk run, then one without frames, then a
    // glTF one, in the same folder: each leaves only its own outputs, so
    // no series file lists frames that are gone and no picture stays
    // beside another run's rows.
    assert!(run(&["--steps", "40", "--format", "vtu"]).status.success());
    assert_eq!((frames(".vtu"), frames(".pvd")), (5, 1));
    assert!(run(&["--steps", "20", "--format", "vtk"]).status.success());
    assert_eq!((frames(".vtu"), frames(".pvd"), frames(".vtk")), (0, 0, 3));
    assert!(d.join("out/frames/frames.vtk.series").is_file());
    assert!(run(&["--steps", "20", "--format", "gltf"]).status.success());
    assert_eq!((frames(".vtk"), frames(".series")), (0, 0));
    assert!(d.join("out/animation.glb").is_file());
    assert!(run(&["--steps", "20"]).status.success());
    assert!(!d.join("out/animation.glb").exists());
    // A resume keeps the format the run started with: none, or another,
    // is refused, and glTF cannot be resumed (nor its state saved).
    assert!(
        run(&["--steps", "40", "--format", "vtu", "--save-state", "s.bin"])
            .status
            .success()
    );
    for (extra, expected) in [
        (
            &["--resume", "s.bin"][..],
            "--resume with no --format: the run in out was started with --format vtu",
        ),
        (
            &["--resume", "s.bin", "--format", "obj"],
            "--resume with --format obj: the run in out was started with --format vtu",
        ),
        (
            &["--resume", "s.bin", "--format", "gltf"],
            "a glTF animation cannot be resumed",
        ),
    ] {
        let output = run(&[&["--steps", "80"], extra].concat());
        assert_eq!(output.status.code(), Some(1), "{extra:?}");
        assert!(
            text(&output.stderr).contains(expected),
            "{}",
            text(&output.stderr)
        );
    }
    assert_eq!(frames(".vtu"), 5);
    let output = run(&["--steps", "80", "--resume", "s.bin", "--format", "vtu"]);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_eq!(frames(".vtu"), 9);
    let output = run(&["--steps", "40", "--format", "gltf", "--save-state", "g.bin"]);
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("--save-state with --format gltf"));
}

#[test]
fn a_demo_of_every_integrator_saves_and_resumes_a_state_for_each() {
    // The oscillator demo runs each integrator into its own folder: each
    // saves its own state (`s.NAME.bin`) and resumes from it, so every run
    // stopped at step 100 and resumed to 200 writes the same bytes as one
    // that went straight to 200 (one shared file resumed all of them from
    // the last one's state).
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let demo = |extra: &[&str]| {
        let args = [&["demo", "oscillator", "--quiet"][..], extra].concat();
        let output = sprung(&args, d);
        assert!(
            output.status.success(),
            "{args:?}: {}",
            text(&output.stderr)
        );
    };
    demo(&["--out", "parts", "--steps", "100", "--save-state", "s.bin"]);
    demo(&["--out", "parts", "--steps", "200", "--resume", "s.bin"]);
    demo(&["--out", "whole", "--steps", "200"]);
    for kind in sprung::IntegratorKind::ALL {
        assert!(d.join(format!("s.{}.bin", kind.name())).is_file());
        let csv = |run: &str| {
            std::fs::read(d.join(run).join(kind.name()).join("diagnostics.csv")).unwrap()
        };
        assert_eq!(csv("parts"), csv("whole"), "{}", kind.name());
    }
}
