//! `sprung plot` through the real binary: PNGs of the right size for a real
//! run, the same bytes twice, comparisons of runs, and clear errors (file
//! and line) for malformed diagnostics.

mod common;

use common::{assert_no_partial_files, png_size, sprung, text};

use std::path::{Path, PathBuf};

fn succeed(args: &[&str], dir: &Path) -> std::process::Output {
    let output = sprung(args, dir);
    assert!(
        output.status.success(),
        "sprung {args:?}: {}",
        text(&output.stderr)
    );
    output
}

/// A small 2D gas ring (the textbook ball, 12 particles) dropped on a floor.
const BALL: &str = r#"[sim]
dt = 5e-4
integrator = "symplectic_euler"
every = 20

[[body]]
name = "ball"
ring = { particles = 12, radius = 0.5 }
mass = 0.1
stiffness = 5000.0
damping = 2.0
translate = [0.0, 1.0, 0.0]
gas = { nrt = 100.0, ramp_time = 0.1 }

[[collider]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
restitution = 0.3
"#;

/// Run the ball for 0.4 s with two probes into `dir/out`.
fn ball_run(dir: &Path, out: &str, integrator: &str) -> PathBuf {
    std::fs::write(dir.join("ball.toml"), BALL).expect("write scene");
    succeed(
        &[
            "run",
            "ball.toml",
            "--out",
            out,
            "--time",
            "0.4",
            "--probe",
            "0,6",
            "--integrator",
            integrator,
            "--quiet",
        ],
        dir,
    );
    dir.join(out)
}

#[test]
fn a_real_run_gives_energy_gas_and_probe_plots() {
    let dir = tempfile::tempdir().expect("tempdir");
    let run = ball_run(dir.path(), "ball", "symplectic_euler");
    let output = succeed(&["plot", "ball"], dir.path());
    let listed = text(&output.stdout);
    for name in ["energy.png", "gas.png", "probes.png"] {
        let file = run.join("plots").join(name);
        assert_eq!(png_size(&file), (1000, 600), "{name}");
        assert!(
            listed.contains(&format!("ball/plots/{name}")),
            "{name} not listed: {listed}"
        );
    }
    // Another size, into another folder, from the CSV named directly.
    let output = succeed(
        &[
            "plot",
            "ball/diagnostics.csv",
            "--out",
            "small",
            "--width",
            "640",
            "--height",
            "360",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(output.stdout.is_empty(), "--quiet prints nothing");
    for name in ["energy.png", "gas.png", "probes.png"] {
        assert_eq!(
            png_size(&dir.path().join("small").join(name)),
            (640, 360),
            "{name}"
        );
    }
    assert_no_partial_files(dir.path());
}

#[test]
fn the_same_run_gives_the_same_bytes() {
    let dir = tempfile::tempdir().expect("tempdir");
    ball_run(dir.path(), "ball", "verlet");
    succeed(&["plot", "ball", "--out", "a", "--quiet"], dir.path());
    succeed(&["plot", "ball", "--out", "b", "--quiet"], dir.path());
    for name in ["energy.png", "gas.png", "probes.png"] {
        let read = |d: &str| std::fs::read(dir.path().join(d).join(name)).expect("png");
        assert!(
            read("a") == read("b"),
            "{name} differs between two plots of one run"
        );
    }
}

#[test]
fn runs_are_compared_by_folder_name() {
    let dir = tempfile::tempdir().expect("tempdir");
    ball_run(dir.path(), "cmp/verlet", "verlet");
    ball_run(dir.path(), "cmp/rk4", "rk4");
    let output = succeed(&["plot", "--compare", "cmp/verlet,cmp/rk4"], dir.path());
    let file = dir.path().join("cmp/plots/compare.png");
    assert_eq!(png_size(&file), (1000, 600));
    assert!(
        text(&output.stdout).contains("cmp/plots/compare.png"),
        "{}",
        text(&output.stdout)
    );
    // Space-separated (as a shell glob gives them), another column, log scale.
    succeed(
        &[
            "plot",
            "--compare",
            "cmp/verlet",
            "cmp/rk4",
            "--column",
            "ball.volume",
            "--scale",
            "log",
            "--out",
            "c",
        ],
        dir.path(),
    );
    assert_eq!(
        png_size(&dir.path().join("c/compare-ball.volume.png")),
        (1000, 600)
    );
    // A glob over the folder (`cmp/*`) also gives the plots' own folder:
    // skipped.
    succeed(
        &["plot", "--compare", "cmp/plots", "cmp/rk4", "cmp/verlet"],
        dir.path(),
    );
    assert_eq!(png_size(&file), (1000, 600));
    let output = sprung(
        &[
            "plot",
            "--compare",
            "cmp/verlet,cmp/rk4",
            "--column",
            "nope",
        ],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("no column `nope`"),
        "{}",
        text(&output.stderr)
    );
}

/// `sprung plot` on a run whose diagnostics.csv is `csv`: exit status 1
/// and the error, which must name the file and the line.
fn plot_error(csv: &str, line: usize) -> String {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("bad")).expect("mkdir");
    std::fs::write(dir.path().join("bad/diagnostics.csv"), csv).expect("write");
    let output = sprung(&["plot", "bad"], dir.path());
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains(&format!("bad/diagnostics.csv, line {line}")),
        "{stderr}"
    );
    assert!(
        !dir.path().join("bad/plots/energy.png").exists(),
        "nothing plotted"
    );
    stderr
}

#[test]
fn malformed_diagnostics_are_refused_with_file_and_line() {
    let header = "step,time,kinetic,spring,gravity,gas,total,contact";
    let row = "0,0,1,2,3,0,6,0";
    let wrong_count = plot_error(&format!("{header}\n{row}\n1,0.1,1,2\n"), 3);
    assert!(
        wrong_count.contains("4 values, expected 8"),
        "{wrong_count}"
    );
    let not_a_number = plot_error(&format!("{header}\n{row}\n1,0.1,1,two,3,0,6,0\n"), 3);
    assert!(
        not_a_number.contains("column 4 (`spring`): `two` is not a number"),
        "{not_a_number}"
    );
    let no_header = plot_error(&format!("{row}\n{row}\n"), 1);
    assert!(no_header.contains("header"), "{no_header}");
    let empty = plot_error("", 1);
    assert!(empty.contains("empty file"), "{empty}");
}

#[test]
fn missing_diagnostics_and_folders_are_named() {
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("empty")).expect("mkdir");
    let output = sprung(&["plot", "empty"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("empty has no diagnostics.csv"), "{stderr}");

    let output = sprung(&["plot", "nowhere"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("cannot read nowhere"), "{stderr}");
}

#[test]
fn bad_options_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    ball_run(dir.path(), "a", "verlet");
    ball_run(dir.path(), "b", "verlet");
    let refused = |args: &[&str], code: i32, words: &str| {
        let output = sprung(args, dir.path());
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
        assert!(
            stderr.contains(words),
            "{args:?}: `{words}` not in {stderr}"
        );
    };
    // A size out of range is a usage error (status 2), as for `render`.
    refused(
        &["plot", "a", "--width", "10"],
        2,
        "'--width <WIDTH>': 10 pixels: from 200 to 4000",
    );
    refused(
        &["plot", "a", "--height", "4001"],
        2,
        "'--height <HEIGHT>': 4001 pixels: from 200 to 4000",
    );
    refused(&["plot", "a", "b", "--out", "o"], 1, "--out takes one DIR");
    refused(&["plot"], 2, "required");
    refused(&["plot", "a", "--scale", "cubic"], 2, "unknown scale");
    refused(&["plot", "a", "--dimension", "4"], 2, "unknown dimension");
    // Several folders without --out: each into its own plots/.
    succeed(&["plot", "a", "b", "--quiet"], dir.path());
    assert!(
        dir.path().join("a/plots/energy.png").exists()
            && dir.path().join("b/plots/energy.png").exists()
    );
}
