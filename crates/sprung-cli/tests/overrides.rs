//! `--set KEY=VALUE` on `run`, `check` and `render`, a scene read from
//! standard input (`run -`), and the effective scene a run keeps in its
//! folder (`scene.toml`, with its meshes), which repeats the run.

mod common;

use common::{assert_no_partial_files, sprung, text, write};

use std::io::Write;
use std::path::Path;
use std::process::{Command, Output, Stdio};

const ROPE: &str = r#"# a hanging rope
[sim]
dt = 1e-3
steps = 40
every = 10

[[body]]
name = "rope"
rope = { particles = 6, length = 1.0 }
stiffness = 500.0
"#;

/// The bytes of `dir/name`.
fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The `time` column (the second) of a diagnostics.csv.
fn times(csv: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(csv)
        .lines()
        .skip(1)
        .map(|row| row.split(',').nth(1).expect("time").to_string())
        .collect()
}

/// Run `sprung` with `args` in `dir`, `input` on its standard input.
fn sprung_with_input(args: &[&str], dir: &Path, input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the sprung binary runs");
    child
        .stdin
        .take()
        .expect("stdin")
        .write_all(input.as_bytes())
        .expect("write stdin");
    child.wait_with_output().expect("sprung ends")
}

#[test]
fn set_dt_runs_what_the_edited_file_runs() {
    // Claim: `--set sim.dt=2e-3` writes the diagnostics.csv, byte for byte,
    // of the file with `dt = 2e-3` written in: rows at t = 0.02, 0.04, ...
    // instead of 0.01, 0.02, ...
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "rope.toml", ROPE);
    write(
        dir.path(),
        "edited.toml",
        &ROPE.replace("dt = 1e-3", "dt = 2e-3"),
    );
    let run = |args: &[&str]| {
        let output = sprung(args, dir.path());
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    };
    run(&["run", "rope.toml", "--out", "plain", "--quiet"]);
    run(&[
        "run",
        "rope.toml",
        "--out",
        "set",
        "--set",
        "sim.dt=2e-3",
        "--quiet",
    ]);
    run(&["run", "edited.toml", "--out", "edited", "--quiet"]);
    let plain = read(dir.path(), "plain/diagnostics.csv");
    let set = read(&dir.path().join("set"), "diagnostics.csv");
    assert_eq!(set, read(dir.path(), "edited/diagnostics.csv"));
    assert_eq!(times(&plain)[..3], ["0", "0.01", "0.02"]);
    assert_eq!(times(&set)[..3], ["0", "0.02", "0.04"]);
    // The run's folder keeps the effective scene: the file as given when
    // nothing is overridden, else the tables with the override.
    assert_eq!(read(dir.path(), "plain/scene.toml"), ROPE.as_bytes());
    let effective = String::from_utf8(read(dir.path(), "set/scene.toml")).expect("utf-8");
    assert!(
        effective.starts_with("[sim]\ndt = 0.002\nsteps = 40\n"),
        "{effective}"
    );
    assert_no_partial_files(dir.path());
}

#[test]
fn a_bad_override_exits_1_naming_its_key() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "rope.toml", ROPE);
    for (set, fragment) in [
        (
            "body.rope.stifness=1",
            "rope.toml: `--set body.rope.stifness`: unknown field `stifness`, expected one of `name`, ",
        ),
        (
            "body.chain.mass=1",
            "rope.toml: `--set body.chain.mass`: there is no body named \"chain\": the bodies are \"rope\"",
        ),
        (
            "sim.dt=\"fast\"",
            "rope.toml: `--set sim.dt`: invalid type: string \"fast\", expected f64",
        ),
        (
            "collider.0.friction=1",
            "rope.toml: `--set collider.0.friction`: there is no collider 0: the scene has no colliders",
        ),
    ] {
        for command in ["run", "check", "render"] {
            let output = sprung(&[command, "rope.toml", "--set", set], dir.path());
            let stderr = text(&output.stderr);
            assert_eq!(output.status.code(), Some(1), "{command} {set}: {stderr}");
            assert!(stderr.contains(fragment), "{command} {set}: {stderr}");
        }
    }
    // Nothing was run, nothing written.
    assert_eq!(std::fs::read_dir(dir.path()).expect("dir").count(), 1);
    // Not KEY=VALUE: a malformed command line, exit 2.
    let output = sprung(&["run", "rope.toml", "--set", "sim.dt"], dir.path());
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("`sim.dt`: expected KEY=VALUE"));
}

#[test]
fn check_reports_the_overridden_scene() {
    // `check --set` loads the scene with the overrides: 40 steps of the
    // new dt, and the integrator named by a bare word.
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "rope.toml", ROPE);
    let output = sprung(
        &[
            "check",
            "rope.toml",
            "--set",
            "sim.dt=5e-4",
            "--set",
            "sim.integrator=rk4",
        ],
        dir.path(),
    );
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        stdout.contains("40 steps of dt = 0.0005 s with rk4 (0.02 s)"),
        "{stdout}"
    );
}

#[test]
fn a_scene_from_standard_input_runs_as_the_file_does() {
    // `run -` reads the scene from standard input: the same diagnostics as
    // the file, in out/stdin by default; its meshes are found from the
    // current folder, or from --base-dir.
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "rope.toml", ROPE);
    let file = sprung(&["run", "rope.toml", "--quiet"], dir.path());
    assert_eq!(file.status.code(), Some(0), "{}", text(&file.stderr));
    let piped = sprung_with_input(&["run", "-", "--quiet"], dir.path(), ROPE);
    assert_eq!(piped.status.code(), Some(0), "{}", text(&piped.stderr));
    assert_eq!(
        read(dir.path(), "out/stdin/diagnostics.csv"),
        read(dir.path(), "out/rope/diagnostics.csv")
    );
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let poke = std::fs::read_to_string(scenes.join("poke.toml")).expect("poke");
    let args = ["run", "-", "--steps", "1", "--out", "poke", "--quiet"];
    let lost = sprung_with_input(&args, dir.path(), &poke);
    assert_eq!(lost.status.code(), Some(1));
    assert!(
        text(&lost.stderr).contains("<stdin>:12: body \"horse\": meshes/horse.obj: cannot read"),
        "{}",
        text(&lost.stderr)
    );
    let base = scenes.to_str().expect("utf-8 path");
    let found = sprung_with_input(
        &[&args[..], &["--base-dir", base]].concat(),
        dir.path(),
        &poke,
    );
    assert_eq!(found.status.code(), Some(0), "{}", text(&found.stderr));
    // --base-dir is for standard input only.
    let output = sprung(&["run", "rope.toml", "--base-dir", "."], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("--base-dir .: applies to a scene read from standard input")
    );
}

#[test]
fn the_scene_kept_in_the_run_folder_repeats_the_run_from_the_folder_alone() {
    // poke.toml's horse mesh, overridden: the run's folder holds scene.toml
    // and meshes/horse.obj, and the folder moved elsewhere runs again to
    // the same diagnostics.csv, byte for byte.
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/poke.toml");
    let options = ["--steps", "6", "--every", "2", "--quiet"];
    let first = sprung(
        &[
            &[
                "run",
                scene.to_str().expect("utf-8 path"),
                "--out",
                "first",
                "--set",
                "body.horse.gas.nrt=300",
                "--set",
                "sim.dt=2e-4",
            ][..],
            &options,
        ]
        .concat(),
        dir.path(),
    );
    assert_eq!(first.status.code(), Some(0), "{}", text(&first.stderr));
    let kept = String::from_utf8(read(dir.path(), "first/scene.toml")).expect("utf-8");
    assert!(kept.contains("mesh = \"meshes/horse.obj\"\n"), "{kept}");
    assert!(
        kept.contains("dt = 0.0002\n") && kept.contains("nrt = 300\n"),
        "{kept}"
    );
    assert_eq!(
        read(dir.path(), "first/meshes/horse.obj"),
        std::fs::read(scene.with_file_name("meshes/horse.obj")).expect("the horse")
    );
    std::fs::rename(dir.path().join("first"), dir.path().join("moved")).expect("move");
    let again = sprung(
        &[&["run", "moved/scene.toml", "--out", "again"][..], &options].concat(),
        dir.path(),
    );
    assert_eq!(again.status.code(), Some(0), "{}", text(&again.stderr));
    assert_eq!(
        read(dir.path(), "again/diagnostics.csv"),
        read(dir.path(), "moved/diagnostics.csv")
    );
    // Run into its own folder, the kept scene and mesh are rewritten in
    // place, whole.
    let own = sprung(
        &[&["run", "moved/scene.toml", "--out", "moved"][..], &options].concat(),
        dir.path(),
    );
    assert_eq!(own.status.code(), Some(0), "{}", text(&own.stderr));
    assert_eq!(read(dir.path(), "moved/scene.toml"), kept.as_bytes());
    assert_eq!(
        read(dir.path(), "moved/meshes/horse.obj"),
        read(dir.path(), "again/meshes/horse.obj")
    );
    assert_no_partial_files(dir.path());
}
