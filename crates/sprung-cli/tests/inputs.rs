//! Inputs that could exhaust the machine are refused before they are read:
//! devices (also behind a link), files over the size limit; a scene that is
//! not UTF-8 is refused with the line and byte of its first bad byte.

mod common;

use std::process::Command;
use std::time::{Duration, Instant};

use common::{text, write};

/// Run `sprung` with `args` in `dir` (and `env`), expecting exit status 1
/// within a second with `needle` in the error, and nothing written.
fn refused_at_once(dir: &std::path::Path, args: &[&str], env: &[(&str, &str)], needle: &str) {
    let start = Instant::now();
    let output = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(args)
        .envs(env.iter().copied())
        .current_dir(dir)
        .output()
        .expect("sprung runs");
    let stderr = text(&output.stderr);
    assert!(
        start.elapsed() < Duration::from_secs(1),
        "{args:?} took {:?}",
        start.elapsed()
    );
    assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
    assert!(stderr.contains(needle), "{args:?}: {stderr}");
    assert!(!dir.join("o").exists(), "{args:?} wrote output");
}

#[test]
fn devices_are_not_read_even_behind_a_link() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    refused_at_once(
        d,
        &["run", "/dev/zero", "--out", "o"],
        &[],
        "not a regular file",
    );
    std::os::unix::fs::symlink("/dev/zero", d.join("zero.obj")).unwrap();
    write(
        d,
        "mesh.toml",
        "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"h\"\nmesh = \"zero.obj\"\n",
    );
    refused_at_once(
        d,
        &["run", "mesh.toml", "--out", "o"],
        &[],
        "zero.obj: cannot read the file: not a regular file",
    );
}

#[test]
fn files_over_the_size_limit_are_refused_with_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scene = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"p\"\nparticles = [[0.0, 0.0]]\n";
    write(d, "s.toml", scene);
    let size = scene.len().to_string();
    let limit = (scene.len() - 1).to_string();
    refused_at_once(
        d,
        &["run", "s.toml", "--out", "o"],
        &[("SPRUNG_MAX_INPUT_BYTES", &limit)],
        &format!("{size} bytes is more than the {limit} bytes an input file may have"),
    );
    // At the limit it runs.
    let output = Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(["run", "s.toml", "--out", "o", "--quiet"])
        .env("SPRUNG_MAX_INPUT_BYTES", &size)
        .current_dir(d)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", text(&output.stderr));
    // A limit that is not a whole number is refused, not replaced by the
    // default without a word.
    let fresh = tempfile::tempdir().unwrap();
    write(fresh.path(), "s.toml", scene);
    refused_at_once(
        fresh.path(),
        &["run", "s.toml", "--out", "o"],
        &[("SPRUNG_MAX_INPUT_BYTES", "1e3")],
        "SPRUNG_MAX_INPUT_BYTES=\"1e3\": expected a whole number of bytes",
    );
}

#[test]
fn a_scene_that_is_not_utf8_names_the_line_and_byte() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("latin1.toml"), b"[sim]\ndt = 1e-3\n# caf\xe9\n").unwrap();
    refused_at_once(
        d,
        &["run", "latin1.toml", "--out", "o"],
        &[],
        "latin1.toml: line 3, byte 6: the scene file is not UTF-8 text (byte 0xe9)",
    );
}

#[test]
fn numbers_that_would_overflow_are_refused_at_load() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let head = "[sim]\ndt = 1e-3\nsteps = 3\n\n[[body]]\nname = \"b\"\n";
    for (body, needle) in [
        // A particle at 1e200 m once gave `spring = inf` on the first row.
        (
            "particles = [[1e200, 0.0], [1e200, 1.0]]\nsprings = [[0, 1]]\n",
            "`particles`[0]: 1.000e200 is beyond the world's limit 1.000e6",
        ),
        (
            "particles = [[0.0, 0.0]]\nvelocity = [1e7, 0.0]\n",
            "`velocities`[0]: 1.000e7 is beyond the world's limit 1.000e6",
        ),
        // A mass of 1e307 kg once gave `gravity = inf` in every row.
        (
            "particles = [[0.0, 0.0]]\nmass = 1e307\n",
            "`masses`[0] = 1.000e307: too large",
        ),
        (
            "particles = [[0.0, 0.0], [1.0, 0.0]]\nsprings = [[0, 1]]\nstiffness = 1e300\n",
            "`stiffness`[0] = 1.000e300: too large",
        ),
    ] {
        write(d, "s.toml", &format!("{head}{body}"));
        refused_at_once(d, &["run", "s.toml", "--out", "o"], &[], needle);
    }
}

#[test]
fn work_beyond_the_budgets_is_refused_with_the_figures() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let scenes = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let flag = scenes.join("flag.toml");
    // `render` would keep a billion pictures in memory.
    refused_at_once(
        d,
        &[
            "render",
            flag.to_str().unwrap(),
            "--steps",
            "1000000000",
            "--out",
            "o",
        ],
        &[],
        "pictures of 600 particles would keep",
    );
    // refine = 5 on the 8000-triangle horse: 8.2 million triangles.
    let horse = scenes.join("meshes/horse.obj");
    write(
        d,
        "h.toml",
        &format!(
            "[sim]\ndt = 1e-4\nsteps = 2\n\n[[body]]\nname = \"h\"\nmesh = {:?}\nrefine = 5\n",
            horse.to_str().unwrap()
        ),
    );
    refused_at_once(
        d,
        &["run", "h.toml", "--out", "o"],
        &[],
        "`refine` = 5 would make 8.19e6 triangles",
    );
}

/// The peak heap `sprung check` reports while loading `scene`, and the
/// file's size, in bytes.
fn loading_memory(dir: &std::path::Path, scene: &str) -> (f64, f64) {
    let output = common::sprung(&["check", scene], dir);
    let stdout = text(&output.stdout);
    assert!(output.status.success(), "{}", text(&output.stderr));
    let line = stdout
        .lines()
        .find(|l| l.contains("memory while loading"))
        .expect("the loading line");
    let figure = |after: &str| -> f64 {
        let rest = &line[line.find(after).expect("figure") + after.len()..];
        let number: String = rest
            .trim_start()
            .chars()
            .take_while(|c| c.is_ascii_digit() || *c == '.')
            .collect();
        number.parse::<f64>().expect("a number") * 1e6
    };
    (figure("loading:"), figure("the file:"))
}

/// Loading a scene takes a small multiple of its file, many small bodies
/// or one body with long arrays alike: the TOML parser reads one body at a
/// time, and long arrays go straight into vectors (its tree of the whole
/// file took about 45 times the file). The bound, 16 times the file, is
/// the world the text describes (a particle of 25 bytes of text, `[0.123,
/// 4.567, 0.0], `, is about 200 bytes of state with its body's share)
/// with room for the parse of one body; the old parser fails it three
/// times over.
#[test]
fn loading_memory_is_a_small_multiple_of_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let mut ropes = String::from("[sim]\ndt = 1e-3\nsteps = 1\n");
    for i in 0..15_000 {
        ropes.push_str(&format!(
            "\n[[body]]\nname = \"r{i}\"\nrope = {{ particles = 3, length = 1.0 }}\nmass = 0.01\nstiffness = 10.0\ntranslate = [{i}.0, 0.0, 0.0]\n"
        ));
    }
    write(d, "ropes.toml", &ropes);
    let n = 200;
    let mut grid =
        String::from("[sim]\ndt = 1e-3\nsteps = 1\n\n[[body]]\nname = \"grid\"\nparticles = [\n");
    for k in 0..n * n {
        grid.push_str(&format!(
            "[{:.3}, {:.3}, 0.0],\n",
            (k % n) as f64 * 0.01,
            (k / n) as f64 * 0.01
        ));
    }
    grid.push_str("]\nsprings = [\n");
    for k in 0..n * n {
        if k % n + 1 < n {
            grid.push_str(&format!("[{k}, {}], ", k + 1));
        }
        if k + n < n * n {
            grid.push_str(&format!("[{k}, {}],\n", k + n));
        }
    }
    grid.push_str("]\nmass = 0.01\nstiffness = 100.0\n");
    write(d, "grid.toml", &grid);
    for scene in ["ropes.toml", "grid.toml"] {
        let (peak, file) = loading_memory(d, scene);
        assert!(
            file > 1e6,
            "{scene}: a file of {file} bytes is too small to tell"
        );
        assert!(
            peak < 16.0 * file,
            "{scene}: loading took {peak:.3e} bytes for a file of {file:.3e}"
        );
    }
}

#[test]
fn a_contact_thickness_far_beyond_the_spacing_is_refused_before_the_run() {
    // Two 60 × 60 cloths 10 cm apart with a 20 cm contact thickness: more
    // candidate pairs than the engine's limit (it used to take gigabytes
    // and abort). `check` and `run` refuse it with status 1, and `run`
    // writes nothing; at 6 cm `check` counts the pairs and the run goes.
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = |thickness: f64| {
        format!(
            "[sim]\ndt = 1e-4\nsteps = 2\n[contact]\nthickness = {thickness}\n\
             [[body]]\nname = \"c\"\ncloth = {{ nx = 60, ny = 60, width = 1.0, height = 1.0 }}\n\
             [[body]]\nname = \"d\"\ncloth = {{ nx = 60, ny = 60, width = 1.0, height = 1.0 }}\n\
             translate = [0.0, 0.0, 0.1]\n"
        )
    };
    write(dir.path(), "thick.toml", &scene(0.2));
    write(dir.path(), "thin.toml", &scene(0.06));
    for args in [
        &["check", "thick.toml"][..],
        &["run", "thick.toml", "--out", "o", "--quiet"],
    ] {
        let output = common::sprung(args, dir.path());
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(
            stderr.contains("candidate pairs") && stderr.contains("lower `[contact] thickness`"),
            "{stderr}"
        );
    }
    assert!(!dir.path().join("o").exists());
    let output = common::sprung(&["check", "thin.toml"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(text(&output.stdout).contains("candidate contact pairs at the start"));
    let output = common::sprung(&["run", "thin.toml", "--out", "o", "--quiet"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
}
