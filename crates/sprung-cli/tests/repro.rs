//! The reproducers of issue 49 (an outside battery of hostile inputs),
//! each as a claim of the command line's: refused with a message that
//! says why, or run cleanly; no file replaced, no row lost. The scenes are
//! in `tests/data/`.

mod common;

use std::ffi::OsStr;
use std::os::unix::ffi::OsStrExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::{assert_no_partial_files, sprung, text, write};

const ROPE: &str = "# a rope\n[sim]\ndt = 1e-3\n\n[[body]]\nname = \"rope\"\nrope = { particles = 5, length = 1.0 }\nmass = 0.1\nstiffness = 200.0\npinned = [0]\n";

/// A scene of `tests/data/`.
fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

/// Run the binary with arguments that may be any bytes.
fn sprung_os(args: &[&OsStr], dir: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("the sprung binary runs")
}

/// Run the binary under `sh` with `limits` (shell commands such as
/// `ulimit -f 40`) set first; SIGXFSZ is ignored, so a write past the file
/// size limit fails with EFBIG as on a full disk instead of killing the
/// process.
fn sprung_limited(limits: &str, args: &[&str], dir: &Path) -> Output {
    let binary = env!("CARGO_BIN_EXE_sprung");
    Command::new("sh")
        .arg("-c")
        .arg(format!("trap '' XFSZ; {limits}; exec \"$0\" \"$@\""))
        .arg(binary)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("sh runs")
}

#[test]
fn arguments_that_are_not_utf8_are_paths_or_clear_errors() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    // A Latin-1 file name: sc\xe9ne.toml, and an output folder o\xe9.
    let scene = OsStr::from_bytes(b"sc\xe9ne.toml");
    std::fs::write(d.join(scene), ROPE).expect("scene");
    let checked = sprung_os(&[OsStr::new("check"), scene], d);
    assert_eq!(checked.status.code(), Some(0), "{}", text(&checked.stderr));
    let out = OsStr::from_bytes(b"o\xe9");
    let ran = sprung_os(
        &[
            "run".as_ref(),
            scene,
            "--out".as_ref(),
            out,
            "--steps".as_ref(),
            "3".as_ref(),
            "--quiet".as_ref(),
        ],
        d,
    );
    assert_eq!(ran.status.code(), Some(0), "{}", text(&ran.stderr));
    assert!(d.join(out).join("diagnostics.csv").is_file());
    // A value is text: refused as a malformed command line, naming the byte.
    let value = OsStr::from_bytes(b"sim.integrator=\xff");
    let refused = sprung_os(&["check".as_ref(), scene, "--set".as_ref(), value], d);
    let stderr = text(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("byte 16 (0xff) of `sim.integrator=\u{fffd}` is not UTF-8"),
        "{stderr}"
    );
}

#[test]
fn a_deep_key_or_value_is_refused_naming_the_limit() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "r.toml", ROPE);
    // 20,000 dotted parts (40 KB) overflowed the stack of check, demo and
    // render; 5,000 that of run, which parses on a smaller stack.
    for parts in [5_000, 20_000] {
        let key = format!("sim.{}=1", vec!["a"; parts].join("."));
        for args in [
            vec!["check", "r.toml"],
            vec!["run", "r.toml", "--steps", "2", "--out", "o"],
            vec!["demo", "rope", "--steps", "2", "--out", "o"],
            vec!["render", "r.toml", "--steps", "2", "--out", "o"],
        ] {
            let args = [&args[..], &["--set", &key]].concat();
            let output = sprung(&args, d);
            let stderr = text(&output.stderr);
            assert_eq!(output.status.code(), Some(2), "{:?}: {stderr}", &args[..2]);
            assert!(stderr.contains("the 4096 a key may have"), "{stderr}");
        }
    }
    // 33 parts, within the bytes: the parts' limit.
    let key = format!("sim.{}=1", vec!["a"; 32].join("."));
    let output = sprung(&["check", "r.toml", "--set", &key], d);
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("more than the 32 dotted parts"));
    // A value nested 60,000 deep (120 KB, within the 128 KB an argument
    // may have), and a scene nested as deep.
    let deep = format!("{}1{}", "[".repeat(60_000), "]".repeat(60_000));
    let output = sprung(&["check", "r.toml", "--set", &format!("sim.dt={deep}")], d);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("nests arrays or tables more than 32 deep"),
        "{stderr}"
    );
    write(
        d,
        "deep.toml",
        &format!("[sim]\ndt = 1e-3\n\n[wind]\nx = {deep}\n"),
    );
    let output = sprung(&["check", "deep.toml"], d);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("deep.toml:5: arrays or tables nest more than 32 deep"),
        "{stderr}"
    );
    assert!(!d.join("o").exists(), "nothing run");
}

/// Make a FIFO at `path` (with mkfifo).
fn fifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().expect("mkfifo");
    assert!(made.success());
}

#[test]
fn an_output_never_replaces_a_link_a_fifo_or_a_device() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "r.toml", ROPE);
    write(d, "elsewhere.txt", "mine");
    std::os::unix::fs::symlink(d.join("elsewhere.txt"), d.join("link")).expect("link");
    fifo(&d.join("fifo"));
    // A device of its own (a second /dev/null) where the tests may make
    // one (as root); the system's own are never risked.
    let device = Command::new("mknod")
        .arg(d.join("null"))
        .args(["c", "1", "3"])
        .status()
        .is_ok_and(|s| s.success());
    let mut nodes = vec![("link", "a symbolic link"), ("fifo", "a FIFO")];
    if device {
        nodes.push(("null", "a device"));
    }
    let run = ["run", "r.toml", "--steps", "10", "--quiet"];
    for (node, what) in &nodes {
        let args = [&run[..], &["--out", "o", "--save-state", node]].concat();
        let output = sprung(&args, d);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{node}: {stderr}");
        assert!(
            stderr.contains(&format!(
                "--save-state {node}: not a regular file: {node} is {what}"
            )),
            "{stderr}"
        );
        assert!(!d.join("o").exists(), "{node}: nothing written");
    }
    // The same nodes where the run's own files go.
    std::fs::create_dir(d.join("out")).expect("out");
    for (file, (node, what)) in ["diagnostics.csv", "scene.toml", "diagnostics.csv.partial"]
        .iter()
        .zip(nodes.iter().cycle())
    {
        let path = d.join("out").join(file);
        std::fs::rename(d.join(node), &path).expect("moved into out");
        let output = sprung(&[&run[..], &["--out", "out"]].concat(), d);
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{file}: {stderr}");
        assert!(stderr.contains(&format!("is {what}")), "{stderr}");
        assert!(stderr.contains("(nothing was written)"), "{stderr}");
        std::fs::rename(&path, d.join(node)).expect("moved back");
    }
    // A frames folder that is a link would put the frames where it points.
    std::os::unix::fs::symlink(d, d.join("out/frames")).expect("link");
    let output = sprung(
        &[&run[..], &["--out", "out", "--format", "vtu"]].concat(),
        d,
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("its `frames` is a symbolic link"));
    // Every node is still what it was, the link's file untouched.
    let kind = |name: &str| {
        std::fs::symlink_metadata(d.join(name))
            .expect("there")
            .file_type()
    };
    assert!(kind("link").is_symlink());
    assert!(std::os::unix::fs::FileTypeExt::is_fifo(&kind("fifo")));
    if device {
        assert!(std::os::unix::fs::FileTypeExt::is_char_device(&kind(
            "null"
        )));
    }
    assert_eq!(
        std::fs::read_to_string(d.join("elsewhere.txt")).unwrap(),
        "mine"
    );
    assert_eq!(
        std::fs::read_dir(d.join("out")).unwrap().count(),
        1,
        "only the link"
    );
}

#[test]
fn the_run_folder_copy_never_replaces_the_scene_it_reads() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    std::fs::create_dir(d.join("r")).expect("folder");
    write(&d.join("r"), "scene.toml", ROPE);
    let output = sprung(
        &[
            "run",
            "r/scene.toml",
            "--out",
            "r",
            "--steps",
            "10",
            "--set",
            "sim.dt=5e-4",
        ],
        d,
    );
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("would write its copy of the scene over")
            && stderr.contains("with other bytes (the effective scene: overrides applied"),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read_to_string(d.join("r/scene.toml")).unwrap(),
        ROPE
    );
    assert!(!d.join("r/diagnostics.csv").exists(), "nothing run");
    // The same bytes (no override, no mesh): the run goes on, the file as
    // it was.
    let output = sprung(&["run", "r/scene.toml", "--out", "r", "--steps", "10"], d);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert_eq!(
        std::fs::read_to_string(d.join("r/scene.toml")).unwrap(),
        ROPE
    );
}

/// The rows of a `diagnostics.csv`: each whole (as many cells as the
/// header), their steps 0, 1, 2, ... (recorded every step).
fn whole_rows(path: &Path) -> usize {
    let table = std::fs::read_to_string(path).expect("diagnostics.csv in place");
    assert!(table.ends_with('\n'), "ends with a whole row");
    let mut lines = table.lines();
    let columns = lines.next().expect("header").split(',').count();
    let mut rows = 0;
    for (k, line) in lines.enumerate() {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells.len(), columns, "row {k}: {line}");
        assert_eq!(cells[0], k.to_string(), "row {k}'s step");
        rows += 1;
    }
    rows
}

#[test]
fn a_write_that_fails_mid_run_keeps_every_row_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let flag = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/flag.toml");
    let flag = flag.to_str().expect("utf-8 path");
    let every_step = ["--every", "1", "--quiet", "--threads", "1"];
    // The run's own folder fills (files of at most 100 KB): the rows up to
    // the failure are kept, whole, and the message counts them.
    let args = [
        &["run", flag, "--out", "full", "--steps", "100000"][..],
        &every_step,
    ]
    .concat();
    let output = sprung_limited("ulimit -f 200", &args, d);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    let rows = whole_rows(&d.join("full/diagnostics.csv"));
    assert!(rows > 100, "{rows}");
    assert!(
        stderr.contains("File too large")
            && stderr.contains(&format!("kept: {rows} rows in full/diagnostics.csv")),
        "{stderr}"
    );
    assert_no_partial_files(&d.join("full"));
    // A checkpoint that fails (the state, 29 KB, past the 20 KB limit):
    // the 21 rows before it are kept, and no state is said to be saved.
    let state = ["--save-state", "s.bin", "--checkpoint-every", "20"];
    let args = [
        &["run", flag, "--out", "c", "--steps", "100"][..],
        &state,
        &every_step,
    ]
    .concat();
    let output = sprung_limited("ulimit -f 40", &args, d);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(whole_rows(&d.join("c/diagnostics.csv")), 21);
    assert!(
        stderr.contains("kept: 21 rows in c/diagnostics.csv; no state was saved"),
        "{stderr}"
    );
    assert!(!d.join("s.bin").exists());
    // Only the final state fails: every row kept, and the message says
    // the state was not saved.
    let args = [
        &["run", flag, "--out", "f", "--steps", "30"][..],
        &state[..2],
        &every_step,
    ]
    .concat();
    let output = sprung_limited("ulimit -f 40", &args, d);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(whole_rows(&d.join("f/diagnostics.csv")), 31);
    assert!(
        stderr.contains(
            "(the state was not saved; the run's results are kept: 31 rows in f/diagnostics.csv)"
        ),
        "{stderr}"
    );
    assert!(!stderr.contains("state saved to"), "{stderr}");
    assert_no_partial_files(d);
}

#[test]
fn check_refuses_a_scene_for_its_device_in_the_words_of_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = data("gpu_scene_with_rods.toml");
    let scene = scene.to_str().expect("utf-8 path");
    let words = "error: the GPU step lacks rods: run this scene with --device cpu";
    let checked = sprung(&["check", scene], dir.path());
    assert_eq!(checked.status.code(), Some(1));
    assert!(
        text(&checked.stderr).contains(words),
        "{}",
        text(&checked.stderr)
    );
    // `run` refuses it before looking for an adapter, in the same words.
    let ran = sprung(&["run", scene, "--out", "o"], dir.path());
    assert_eq!(ran.status.code(), Some(1));
    assert!(text(&ran.stderr).contains(words), "{}", text(&ran.stderr));
    // For the CPU, both take it.
    let checked = sprung(&["check", scene, "--device", "cpu"], dir.path());
    assert_eq!(checked.status.code(), Some(0), "{}", text(&checked.stderr));
}

#[test]
fn ccd_stops_a_runaway_motion_at_once() {
    let dir = tempfile::tempdir().expect("tempdir");
    // Both ran tens of seconds a step in the CCD before the guard
    // stopped them at step 2 or 3: now the guard's checks come first.
    for (scene, step, why) in [
        ("stiff_ball_into_cloth.toml", 2, "moved 1.186e2 m against the rest of its body in one step, more than 100 times the body's size 3.499e-1 m"),
        ("cover_air_drag.toml", 2, "ran away at 4.662e8 m/s"),
    ] {
        let path = data(scene);
        let args = ["--threads", "1", "run", path.to_str().unwrap(), "--out", scene, "--quiet"];
        let output = sprung(&args, dir.path());
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(3), "{scene}: {stderr}");
        assert!(stderr.contains(&format!("blew up at step {step} ")), "{stderr}");
        assert!(stderr.contains(why), "{stderr}");
        assert_eq!(whole_rows(&dir.path().join(scene).join("diagnostics.csv")), 1);
    }
}

#[test]
fn sheets_that_start_on_top_of_each_other_are_warned_of_and_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = data("coplanar_cloths.toml");
    let scene = scene.to_str().unwrap();
    let checked = sprung(&["check", scene], dir.path());
    let stderr = text(&checked.stderr);
    assert_eq!(checked.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains("warning: bodies \"strong\" and \"weak\" start pressed into each other"),
        "{stderr}"
    );
    let args = [
        "run", scene, "--out", "o", "--steps", "50", "--every", "1", "--quiet",
    ];
    let output = sprung(&args, dir.path());
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert_eq!(whole_rows(&dir.path().join("o/diagnostics.csv")), 51);
}

#[test]
fn sigint_stops_the_slowest_ccd_reproducer_within_half_a_second() {
    let dir = tempfile::tempdir().expect("tempdir");
    let out = dir.path().join("o");
    let scene = data("coplanar_cloths.toml");
    let child = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(["--threads", "1", "run", scene.to_str().unwrap()])
        .args(["--every", "1", "--quiet", "--out"])
        .arg(&out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sprung starts");
    // Its rows are flushed 8 KB at a time: wait for the first.
    let partial = out.join("diagnostics.csv.partial");
    let start = Instant::now();
    while std::fs::metadata(&partial).map_or(0, |m| m.len()) == 0 {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no rows written"
        );
        std::thread::sleep(Duration::from_millis(20));
    }
    let sent = Instant::now();
    let killed = Command::new("kill")
        .args(["-s", "INT", &child.id().to_string()])
        .status()
        .expect("kill runs");
    assert!(killed.success());
    let output = child.wait_with_output().expect("sprung ends");
    let took = sent.elapsed();
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(130), "{stderr}");
    assert!(
        took < Duration::from_millis(500),
        "stopped {took:?} after SIGINT"
    );
    let rows = whole_rows(&out.join("diagnostics.csv"));
    assert!(stderr.contains(&format!("{rows} rows")), "{stderr}");
    assert_no_partial_files(&out);
}
