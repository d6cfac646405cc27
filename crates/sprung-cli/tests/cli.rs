//! The command-line contract of docs/guide.md, driven through the real binary:
//! outputs, exit codes, blow-up handling and bad input.

mod common;

use common::{assert_no_partial_files, csv, csv_text, sprung, text, write, BLOW_UP_SCENE};

use std::path::Path;

const PENDULUM: &str = r#"[sim]
dt = 1e-3
steps = 100
every = 10

[[body]]
name = "bob"
particles = [[0.0, 0.0], [1.0, 0.0]]
springs = [[0, 1]]
stiffness = 1000.0
mass = 0.5
pinned = [0]
"#;

#[test]
fn run_writes_the_contracted_columns() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "pendulum.toml", PENDULUM);
    let output = sprung(
        &[
            "run",
            "pendulum.toml",
            "--out",
            "res",
            "--probe",
            "1",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        output.stdout.is_empty() && output.stderr.is_empty(),
        "--quiet prints nothing"
    );
    let (header, rows) = csv(&dir.path().join("res/diagnostics.csv"));
    let expected = "step,time,kinetic,spring,gravity,gas,total,contact,gravitation,contacts,solver_iterations,solver_residual,substeps,step_size,ccd_impulses,ccd_zones,solver_preconditioner,solver_refactorings,bob.volume,bob.pressure,bob.cx,bob.cy,bob.cz,p1.x,p1.y,p1.z";
    assert_eq!(header.join(","), expected);
    // Step 0, then every 10th of 100 steps.
    assert_eq!(rows.len(), 11);
    assert_eq!(rows[10][0], 100.0);
    assert!(
        (rows[10][1] - 0.1).abs() < 1e-15,
        "time after 100 steps of 1 ms"
    );
    // The bob falls: its probed y goes down, and total = sum of the terms.
    let probe_y = header
        .iter()
        .position(|c| c == "p1.y")
        .expect("p1.y column");
    assert!(rows[10][probe_y] < 0.0);
    for row in &rows {
        let sum: f64 = row[2..6].iter().sum::<f64>() + row[7] + row[8];
        assert!((row[6] - sum).abs() <= 1e-12 * sum.abs().max(1.0));
    }
    assert_no_partial_files(dir.path());
}

#[test]
fn steps_time_every_and_integrator_options() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "p.toml", PENDULUM);
    let run = |args: &[&str]| {
        let mut all = vec!["run", "p.toml", "--out", "o", "--quiet"];
        all.extend_from_slice(args);
        let output = sprung(&all, dir.path());
        assert!(output.status.success(), "{}", text(&output.stderr));
        csv(&dir.path().join("o/diagnostics.csv")).1
    };
    assert_eq!(
        run(&["--steps", "30", "--every", "7"]).len(),
        1 + 4 + 1,
        "rows at 0, 7, 14, 21, 28 and the last step 30"
    );
    let rows = run(&["--time", "0.05", "--every", "1"]);
    assert_eq!(rows.len(), 51);
    let rk4 = run(&["--integrator", "rk4", "--steps", "100"]);
    let euler = run(&["--integrator", "euler", "--steps", "100"]);
    assert_ne!(
        rk4.last(),
        euler.last(),
        "the integrator override takes effect"
    );
}

#[test]
fn frames_in_vtu_vtk_and_obj() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "p.toml", PENDULUM);
    for format in ["vtu", "vtk", "obj"] {
        let output = sprung(
            &[
                "run", "p.toml", "--out", format, "--format", format, "--quiet",
            ],
            dir.path(),
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
        let frames = dir.path().join(format).join("frames");
        let mut names: Vec<String> = std::fs::read_dir(&frames)
            .expect("frames dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .filter(|n| n.starts_with("frame_"))
            .collect();
        names.sort();
        assert_eq!(names.len(), 11);
        assert_eq!(names[0], format!("frame_000000.{format}"));
        assert_eq!(names[10], format!("frame_000010.{format}"));
        let last = std::fs::read_to_string(frames.join(&names[10])).expect("frame");
        match format {
            "vtu" => {
                assert!(last.starts_with("<?xml"));
                assert!(last.contains("NumberOfPoints=\"2\" NumberOfCells=\"1\""));
                assert!(last.contains("compressor=\"vtkZLibDataCompressor\""));
                let series = std::fs::read_to_string(frames.join("frames.pvd")).expect("series");
                assert_eq!(series.matches("<DataSet ").count(), 11);
                assert!(series.contains("<!-- body 0: bob -->"), "{series}");
            }
            "vtk" => {
                assert!(last.starts_with("# vtk DataFile Version 4.2"));
                assert!(last.contains("DATASET UNSTRUCTURED_GRID"));
                assert!(last.contains("POINTS 2 double") && last.contains("CELLS 1 3\n2 0 1"));
                let series =
                    std::fs::read_to_string(frames.join("frames.vtk.series")).expect("series");
                assert_eq!(series.matches("\"name\"").count(), 11);
            }
            _ => assert_eq!(last.lines().filter(|l| l.starts_with("v ")).count(), 2),
        }
    }
}

#[test]
fn blow_up_stops_with_step_and_stable_dt_and_no_nan() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "boom.toml", BLOW_UP_SCENE);
    let output = sprung(&["run", "boom.toml", "--out", "o"], dir.path());
    assert_eq!(
        output.status.code(),
        Some(3),
        "a blow-up exits with status 3"
    );
    let stderr = text(&output.stderr);
    assert!(stderr.contains("blew up at step"), "{stderr}");
    assert!(
        stderr.contains("stable estimate is dt <= 3.162e-3 s"),
        "{stderr}"
    );
    let content =
        std::fs::read_to_string(dir.path().join("o/diagnostics.csv")).expect("diagnostics kept");
    let lower = content.to_lowercase();
    assert!(
        !lower.contains("nan") && !lower.contains("inf"),
        "no non-finite value written"
    );
    let rows = content.lines().count() - 1;
    assert!(
        rows > 1 && rows < 100_000,
        "stopped early with the good rows ({rows})"
    );
    assert_no_partial_files(dir.path());
}

#[test]
fn bad_scene_exits_1_and_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(
        dir.path(),
        "bad.toml",
        &PENDULUM.replace("mass = 0.5", "mass = -0.5"),
    );
    let output = sprung(&["run", "bad.toml", "--out", "o"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert_eq!(
        text(&output.stderr).trim(),
        "error: bad.toml:11: body \"bob\": `mass` = -0.5: mass must be positive and finite (kg)"
    );
    assert!(
        !dir.path().join("o").exists(),
        "nothing written for a refused scene"
    );
}

#[test]
fn missing_scene_file() {
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["run", "nowhere.toml"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("nowhere.toml: cannot read the scene file"));
}

#[test]
fn bad_options_are_refused_before_the_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "p.toml", PENDULUM);
    // A value no run could take is a usage error (2, clap's message naming
    // the option); a value this scene cannot take is an input error (1).
    for (args, message, code) in [
        (vec!["--probe", "9"], "--probe 9: no such particle", 1),
        (
            vec!["--steps", "0"],
            "'--steps <STEPS>': 0 steps: from 1 to 1e12",
            2,
        ),
        (
            vec!["--steps", "1000000000000000"],
            "1000000000000000 steps: from 1 to 1e12",
            2,
        ),
        (
            vec!["--time=-1"],
            "'--time <TIME>': -1: must be positive",
            2,
        ),
        (
            vec!["--time", "nan"],
            "'--time <TIME>': NaN: must be positive",
            2,
        ),
        (
            vec!["--every", "0"],
            "'--every <EVERY>': must be at least 1",
            2,
        ),
    ] {
        let mut all = vec!["run", "p.toml", "--out", "o"];
        all.extend(args);
        let output = sprung(&all, dir.path());
        assert_eq!(output.status.code(), Some(code), "{all:?}");
        assert!(
            text(&output.stderr).contains(message),
            "{}",
            text(&output.stderr)
        );
        assert!(!dir.path().join("o").exists());
    }
    let output = sprung(&["run", "p.toml", "--format", "png"], dir.path());
    assert_eq!(
        output.status.code(),
        Some(2),
        "clap refuses an unknown format"
    );
}

#[test]
fn demo_list_names_every_demo() {
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["demo", "--list"], dir.path());
    let listing = text(&output.stdout);
    for name in [
        "ball2d",
        "ball3d",
        "pillow",
        "horse",
        "balloon",
        "flag",
        "billow",
        "drape",
        "poke",
        "cloth",
        "rope",
        "rope_one_sided",
        "jelly",
        "chain",
        "lattice2d",
        "oscillator",
    ] {
        assert!(
            listing.lines().any(|l| l.starts_with(name)),
            "{name} missing from\n{listing}"
        );
    }
    let output = sprung(&["demo", "nosuch"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("no demo named \"nosuch\""));
}

#[test]
fn default_demo_runs_and_says_where_its_results_went() {
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["demo"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stdout = text(&output.stdout);
    assert!(stdout.contains("results in out/demo/ball2d"), "{stdout}");
    assert!(dir.path().join("out/demo/ball2d/diagnostics.csv").exists());
    assert!(dir
        .path()
        .join("out/demo/ball2d/frames/frame_000000.vtu")
        .exists());
    // stderr is not a terminal here: no progress bar is drawn.
    assert!(output.stderr.is_empty(), "{}", text(&output.stderr));
    // The ring with gas keeps its area on the floor, the one without folds
    // up: the claim the demo shows. Both start as the same 17-gon.
    let (header, rows) = csv(&dir.path().join("out/demo/ball2d/diagnostics.csv"));
    let column = |name: &str| header.iter().position(|h| h == name).expect(name);
    let (first, last) = (&rows[0], &rows[rows.len() - 1]);
    let (gas, flat) = (column("ball.volume"), column("no_gas.volume"));
    assert!(
        last[gas] > 0.9 * first[gas],
        "the gas ball keeps its area: {} -> {}",
        first[gas],
        last[gas]
    );
    assert!(
        last[flat] < 0.5 * first[flat],
        "without gas it collapses: {} -> {}",
        first[flat],
        last[flat]
    );
    assert!(last[column("ball.pressure")] > 0.0);
    let content =
        std::fs::read_to_string(dir.path().join("out/demo/ball2d/diagnostics.csv")).expect("csv");
    let no_gas_pressure = column("no_gas.pressure");
    assert!(
        content
            .lines()
            .skip(1)
            .all(|l| l.split(',').nth(no_gas_pressure) == Some("")),
        "no pressure without gas"
    );
}

#[test]
fn oscillator_demo_compares_integrators() {
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["demo", "oscillator", "--quiet"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let total = |kind: &str| -> (f64, f64) {
        let (header, rows) = csv(&dir
            .path()
            .join(format!("out/demo/oscillator/{kind}/diagnostics.csv")));
        let column = header
            .iter()
            .position(|h| h == "total")
            .expect("total column");
        (rows[0][column], rows[rows.len() - 1][column])
    };
    // E = ½ k A² = ½ · 4π² · 0.2² ≈ 0.79 J. Explicit Euler multiplies it by
    // (1 + (ω dt)²) each step: (1 + 0.0039)^2000 ≈ 2600 after 20 s.
    let (start, end) = total("euler");
    assert!(
        end > 100.0 * start,
        "explicit Euler gains energy: {start} -> {end}"
    );
    // Verlet's energy error is bounded by about (ω dt)²/4 ≈ 1e-3 of E.
    let (start, end) = total("verlet");
    assert!(
        (end - start).abs() < 2e-3 * start,
        "Verlet keeps its energy: {start} -> {end}"
    );
}

#[test]
fn repeated_probes_and_absurd_run_lengths_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "p.toml", PENDULUM);
    let output = sprung(
        &["run", "p.toml", "--out", "o", "--probe", "1,1"],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("particle 1 is named twice"),
        "{}",
        text(&output.stderr)
    );
    let output = sprung(
        &["run", "p.toml", "--out", "o", "--time", "1e300"],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("more than the 1e12"),
        "{}",
        text(&output.stderr)
    );
    assert!(!dir.path().join("o").exists());
}

#[test]
fn demos_with_meshes_run_from_any_folder_and_oscillator_refuses_one_integrator() {
    // The tempdir is far from the source tree: the cube mesh comes from the
    // binary itself.
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["demo", "pillow", "--steps", "3", "--quiet"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(dir.path().join("out/demo/pillow/diagnostics.csv").exists());
    let output = sprung(&["demo", "oscillator", "--integrator", "rk4"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("runs every integrator"),
        "{}",
        text(&output.stderr)
    );
}

/// A stiff cloth swinging down at the frame step, with implicit Euler
/// allowed only `max_iterations` conjugate-gradient iterations per solve.
fn stiff_cloth_scene(max_iterations: u32) -> String {
    format!(
        r#"[sim]
dt = 0.016666666666666666
integrator = "implicit_euler"
steps = 5
every = 1
solver_tolerance = 1e-8
max_iterations = {max_iterations}

[[body]]
name = "cloth"
cloth = {{ nx = 8, ny = 8, width = 1.0, height = 1.0 }}
mass = 0.002
stiffness = 2.0e4
rotate = [90.0, 0.0, 0.0]
pinned = [0, 7]
"#
    )
}

#[test]
fn the_auto_preconditioner_says_when_it_takes_the_factor() {
    // The 8² stiff cloth swinging down: Jacobi needs more iterations than
    // the factor of so small a cloth costs, so auto takes the factor at an
    // early step and says so once (a note, silenced by --quiet); the
    // factored solves converge, so nothing is warned.
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "auto.toml", &stiff_cloth_scene(1000));
    let output = sprung(&["run", "auto.toml", "--out", "auto"], dir.path());
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert_eq!(stderr.matches("note:").count(), 1, "{stderr}");
    assert!(
        stderr.contains("implicit_euler's auto preconditioner took the springs' stiffness factor"),
        "{stderr}"
    );
    assert!(!stderr.contains("warning:"), "{stderr}");
    let (header, rows) = csv(&dir.path().join("auto/diagnostics.csv"));
    let iterations = header
        .iter()
        .position(|c| c == "solver_iterations")
        .expect("iterations column");
    // The last steps are factored: one iteration with a new factor, after
    // at most a trial of the kept one within its 2 iterations (so small a
    // cloth factors for less than 2 iterations cost).
    assert!(rows[rows.len() - 1][iterations] <= 3.0);
    // The choice in the table: none in the first row (no step led to it),
    // Jacobi first, the stiffness factor from the step that took it on,
    // factored once at that step.
    let path = dir.path().join("auto/diagnostics.csv");
    let (chosen, refactorings) = (
        csv_text(&path, "solver_preconditioner"),
        csv_text(&path, "solver_refactorings"),
    );
    assert_eq!((chosen[0].as_str(), refactorings[0].as_str()), ("", ""));
    assert_eq!(chosen[1], "jacobi");
    let took = chosen
        .iter()
        .position(|c| c == "stiffness")
        .expect("took it");
    assert!(
        chosen[took..].iter().all(|c| c == "stiffness"),
        "{chosen:?}"
    );
    assert!(chosen[1..took].iter().all(|c| c == "jacobi"), "{chosen:?}");
    assert_eq!(refactorings[took], "1");
    assert!(
        refactorings[1..took].iter().all(|r| r == "0"),
        "{refactorings:?}"
    );
    let quiet = sprung(
        &["run", "auto.toml", "--out", "quiet", "--quiet"],
        dir.path(),
    );
    assert!(quiet.stderr.is_empty(), "{}", text(&quiet.stderr));
}

#[test]
fn implicit_solves_are_reported_and_a_solve_short_of_its_tolerance_is_warned_about() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "good.toml", &stiff_cloth_scene(1000));
    let output = sprung(
        &["run", "good.toml", "--out", "good", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(output.stderr.is_empty(), "{}", text(&output.stderr));
    let (header, rows) = csv(&dir.path().join("good/diagnostics.csv"));
    let column = |name: &str| header.iter().position(|c| c == name).expect(name);
    let (iterations, residual) = (column("solver_iterations"), column("solver_residual"));
    for row in &rows[1..] {
        assert!(row[iterations] >= 1.0, "iterations {}", row[iterations]);
        assert!(row[residual] <= 1e-8, "residual {}", row[residual]);
    }
    // Two iterations cannot reach 1e-8 on this system once it moves (the
    // first step, from rest under uniform gravity, converges in two): a
    // warning with the step and the residual at the first, and the count
    // at the end, even
    // with --quiet (which silences everything but errors and warnings).
    let jacobi = stiff_cloth_scene(2).replace(
        "max_iterations = 2\n",
        "max_iterations = 2\npreconditioner = \"jacobi\"\n",
    );
    write(dir.path(), "short.toml", &jacobi);
    let output = sprung(
        &["run", "short.toml", "--out", "short", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stderr = text(&output.stderr);
    assert_eq!(stderr.matches("warning:").count(), 2, "{stderr}");
    assert!(
        stderr.contains("warning: step 2 (t = 0.033333 s)"),
        "{stderr}"
    );
    assert!(stderr.contains("max_iterations = 2"), "{stderr}");
    // The preconditioner is named, and the stiffness factor offered.
    assert!(
        stderr.contains("the implicit_euler solver (jacobi preconditioner) stopped"),
        "{stderr}"
    );
    assert!(
        stderr.contains("try `preconditioner = \"stiffness\"`"),
        "{stderr}"
    );
    // With the Laplacian preconditioner, named, and the factor offered.
    let laplacian = stiff_cloth_scene(1).replace(
        "max_iterations = 1\n",
        "max_iterations = 1\npreconditioner = \"laplacian\"\n",
    );
    write(dir.path(), "laplacian.toml", &laplacian);
    let output = sprung(
        &["run", "laplacian.toml", "--out", "laplacian", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let named = text(&output.stderr);
    assert!(
        named.contains("the implicit_euler solver (laplacian preconditioner) stopped"),
        "{named}"
    );
    assert!(
        named.contains("try `preconditioner = \"stiffness\"`"),
        "{named}"
    );
    assert!(stderr.contains("relative residual"), "{stderr}");
    assert!(stderr.contains("in 4 of 5 steps"), "{stderr}");
    let (_, rows) = csv(&dir.path().join("short/diagnostics.csv"));
    for row in &rows[2..] {
        assert_eq!(row[iterations], 2.0);
        assert!(row[residual] > 1e-8);
    }
    // The explicit integrators leave both columns empty.
    let text_of = std::fs::read_to_string(dir.path().join("good/diagnostics.csv")).expect("csv");
    let explicit = stiff_cloth_scene(1000)
        .replace("integrator = \"implicit_euler\"", "integrator = \"rk4\"")
        .replace("solver_tolerance = 1e-8\nmax_iterations = 1000\n", "")
        .replace("dt = 0.016666666666666666", "dt = 1e-5");
    assert!(text_of.contains("solver_iterations,solver_residual"));
    write(dir.path(), "explicit.toml", &explicit);
    let output = sprung(
        &["run", "explicit.toml", "--out", "explicit", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let explicit_csv =
        std::fs::read_to_string(dir.path().join("explicit/diagnostics.csv")).expect("csv");
    for line in explicit_csv.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!((cells[iterations], cells[residual]), ("", ""), "{line}");
    }
}

#[test]
fn check_loads_a_scene_without_running_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let horse = scenes.join("horse.toml");
    let output = sprung(&["check", horse.to_str().unwrap()], dir.path());
    let stdout = text(&output.stdout);
    assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
    assert!(
        stdout.contains("4002 particles, 23423 springs, 8000 faces"),
        "{stdout}"
    );
    assert!(
        stdout.contains("stable step of the explicit integrators: about 4.841e-4 s"),
        "{stdout}"
    );
    assert!(
        text(&output.stderr).is_empty(),
        "the horse's dt is below its stable step"
    );
    // Explicit Euler at dt = 0.02 s on a chain stable below 3.2e-3 s: warned.
    write(dir.path(), "blow.toml", BLOW_UP_SCENE);
    let output = sprung(&["check", "blow.toml"], dir.path());
    assert_eq!(output.status.code(), Some(0));
    assert!(
        text(&output.stderr).contains("dt = 0.02 s is 6.32 times the stable estimate 3.162e-3 s"),
        "{}",
        text(&output.stderr)
    );
    // A scene that does not load: exit 1 with its error, nothing written.
    write(dir.path(), "bad.toml", "[sim]\ndt = -1\n");
    let output = sprung(&["check", "bad.toml"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(text(&output.stderr).contains("bad.toml"));
    assert_eq!(
        std::fs::read_dir(dir.path()).unwrap().count(),
        2,
        "check writes nothing"
    );
}

#[test]
fn a_body_that_starts_inside_a_collider_is_warned_about() {
    // A 1 m cloth of 12 × 12 particles laid through the centre of a
    // sphere of radius 0.3 m: the particles within 0.3 m of the centre
    // (32 of them; the nearest 0.0643 m from it, so 0.236 m deep) are
    // inside. The first steps push them onto the surface, and the cloth's
    // springs take up tens of joules. Claims: `check` and `run` warn,
    // naming the count, the body, the collider and the depth; with the
    // sphere moved clear, neither warns; a pinned particle inside is not
    // counted.
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"cloth\"\ncloth = { nx = 12, ny = 12, width = 1.0, height = 1.0 }\nmass = 0.01\nstiffness = 50.0\nrotate = [90.0, 0.0, 0.0]\ntranslate = [-0.5, 0.0, -0.5]\n\n[[collider]]\nplane = { point = [0.0, -5.0, 0.0], normal = [0.0, 1.0, 0.0] }\n\n[[collider]]\nsphere = { center = [0.0, 0.0, 0.0], radius = 0.3 }\n";
    let expected = "warning: 32 particles of body \"cloth\" start inside the sphere of collider 2";
    write(dir.path(), "inside.toml", scene);
    for args in [
        &["check", "inside.toml"][..],
        &["run", "inside.toml", "--quiet"],
    ] {
        let output = sprung(args, dir.path());
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
        let stderr = text(&output.stderr);
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(stderr.contains("up to 2.357e-1 m deep"), "{stderr}");
    }
    write(
        dir.path(),
        "clear.toml",
        &scene.replace("[0.0, 0.0, 0.0], radius", "[0.0, 2.0, 0.0], radius"),
    );
    let output = sprung(&["check", "clear.toml"], dir.path());
    assert!(text(&output.stderr).is_empty(), "{}", text(&output.stderr));
    // The centre particles pinned: 28 left (the four nearest the centre,
    // numbered 65, 66, 77 and 78, are pinned).
    write(
        dir.path(),
        "pinned.toml",
        &format!("{scene}\n").replace(
            "translate = [-0.5, 0.0, -0.5]",
            "translate = [-0.5, 0.0, -0.5]\npinned = [65, 66, 77, 78]",
        ),
    );
    let output = sprung(&["check", "pinned.toml"], dir.path());
    assert!(
        text(&output.stderr).contains("warning: 28 particles"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn a_velocity_given_to_pinned_particles_is_warned_about_by_check_and_run() {
    // A rope thrown sideways whose top is pinned: the top stays. Claim:
    // `check` and `run` both say so, with the file and the line of
    // `velocity`, and the run goes on.
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"rope\"\nrope = { particles = 4, length = 1.0 }\nvelocity = [1.0, 0.0, 0.0]\n";
    write(dir.path(), "thrown.toml", scene);
    let expected = "warning: thrown.toml:8: body \"rope\": particle 0 given a velocity is pinned";
    for args in [
        &["check", "thrown.toml"][..],
        &["run", "thrown.toml", "--quiet"],
    ] {
        let output = sprung(args, dir.path());
        assert!(output.status.success(), "{}", text(&output.stderr));
        let stderr = text(&output.stderr);
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
    }
}

#[test]
fn wind_on_bodies_it_cannot_push_is_warned_about() {
    // A rope (no faces, no segments) and a cloth in a wind: wind pushes on
    // faces, so the rope feels nothing. Claim: `check` names the rope, and
    // not the cloth; with the rope's `wind_scale = 0` nothing is said.
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"rope\"\nrope = { particles = 10, length = 1.0 }\npinned = [0]\n\n[[body]]\nname = \"flag\"\ncloth = { nx = 4, ny = 4, width = 1.0, height = 1.0 }\ntranslate = [3.0, 0.0, 0.0]\n\n[wind]\nvelocity = [5.0, 0.0, 0.0]\n";
    write(dir.path(), "wind.toml", scene);
    let output = sprung(&["check", "wind.toml"], dir.path());
    let stderr = text(&output.stderr);
    assert!(
        stderr.contains("warning: [wind] does not act on \"rope\": wind pushes on faces"),
        "{stderr}"
    );
    assert!(!stderr.contains("flag"), "{stderr}");
    let calm = scene.replace("pinned = [0]", "pinned = [0]\nwind_scale = 0.0");
    write(dir.path(), "calm.toml", &calm);
    let output = sprung(&["check", "calm.toml"], dir.path());
    assert!(text(&output.stderr).is_empty(), "{}", text(&output.stderr));
}

#[test]
fn automatic_substeps_with_an_integrator_they_do_not_split_are_warned_about() {
    // `substeps = "auto"` splits explicit fixed-step integrators only.
    // Claim: `check` says so for implicit_euler and rk45, and says nothing
    // of it for symplectic Euler.
    let dir = tempfile::tempdir().expect("tempdir");
    for (integrator, warned) in [
        ("implicit_euler", true),
        ("rk45", true),
        ("symplectic_euler", false),
    ] {
        let scene = format!("[sim]\ndt = 1e-3\nsteps = 2\nsubsteps = \"auto\"\nintegrator = \"{integrator}\"\n\n[[body]]\nname = \"rope\"\nrope = {{ particles = 5, length = 1.0 }}\n");
        write(dir.path(), "auto.toml", &scene);
        let output = sprung(&["check", "auto.toml"], dir.path());
        assert_eq!(output.status.code(), Some(0), "{}", text(&output.stderr));
        let stderr = text(&output.stderr);
        let expected = format!("warning: substeps = \"auto\" does nothing with {integrator}");
        assert_eq!(stderr.contains(&expected), warned, "{integrator}: {stderr}");
    }
}

#[cfg(unix)]
#[test]
fn output_into_a_closed_pipe_ends_quietly() {
    // `sprung demo --list | head -1`: the reader has gone when sprung
    // prints. Claim: it exits with 141 (128 + SIGPIPE) or, if it printed
    // before the pipe closed, 0, and never with a panic.
    use std::process::{Command, Stdio};
    for _ in 0..5 {
        let mut child = Command::new(env!("CARGO_BIN_EXE_sprung"))
            .args(["demo", "--list"])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("the sprung binary runs");
        drop(child.stdout.take());
        let output = child.wait_with_output().expect("it ends");
        let stderr = text(&output.stderr);
        assert!(!stderr.contains("panicked"), "{stderr}");
        assert!(
            matches!(output.status.code(), Some(0 | 141)),
            "{:?}: {stderr}",
            output.status
        );
    }
}

#[test]
fn an_output_folder_that_is_a_file_is_refused_in_those_words() {
    // It said "cannot create out: File exists"; the file is left as it is.
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::write(dir.path().join("out"), "mine").expect("a file");
    let output = sprung(&["demo", "--out", "out", "--steps", "2"], dir.path());
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("--out out: is a file, not a folder"),
        "{}",
        text(&output.stderr)
    );
    assert_eq!(
        std::fs::read_to_string(dir.path().join("out")).expect("still there"),
        "mine"
    );
}

#[test]
fn more_threads_than_the_engine_runs_on_are_refused_before_starting_them() {
    // Tens of thousands of threads took minutes to start; a million made
    // a worker panic and the process hang. Refused at once: the option as
    // a usage error, the variable as an input error.
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(&["--threads", "5000", "demo", "--list"], dir.path());
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("1..=1024"));
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(["demo", "--list"])
        .env("SPRUNG_THREADS", "1000000")
        .current_dir(dir.path())
        .output()
        .expect("the sprung binary runs");
    assert_eq!(output.status.code(), Some(1));
    assert!(
        text(&output.stderr).contains("1000000 threads: at most 1024"),
        "{}",
        text(&output.stderr)
    );
}

#[test]
fn threads_given_before_and_after_the_command_is_refused() {
    // Both places are accepted alone; given in both, one would win
    // silently.
    let dir = tempfile::tempdir().expect("tempdir");
    let output = sprung(
        &["--threads", "1", "demo", "--list", "--threads=2"],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("--threads is given 2 times"));
    for args in [
        &["--threads", "1", "demo", "--list"][..],
        &["demo", "--list", "--threads", "2"],
    ] {
        assert!(sprung(args, dir.path()).status.success(), "{args:?}");
    }
}

#[test]
fn the_scene_formats_key_block_loads_and_runs_as_written() {
    // docs/scenes.md gives the scene format as one block of every key (its
    // first toml block), which users copy. Claim: as written (its horse
    // mesh beside it), `check` loads it and `run` steps it for 0.05 s with
    // exit 0 (it blew up at step 2 when all its bodies were made on top of
    // each other, under the floor).
    let page = include_str!("../../../docs/scenes.md");
    let start = page.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let block = &page[start..start + page[start..].find("```").expect("its end")];
    assert!(block.contains("[[collider]]") && block.contains("mesh = \"meshes/horse.obj\""));
    let dir = tempfile::tempdir().expect("tempdir");
    std::fs::create_dir(dir.path().join("meshes")).expect("meshes folder");
    let horse = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/meshes/horse.obj");
    std::fs::copy(horse, dir.path().join("meshes/horse.obj")).expect("the horse");
    write(dir.path(), "scene.toml", block);
    let check = sprung(&["check", "scene.toml"], dir.path());
    assert!(check.status.success(), "{}", text(&check.stderr));
    let run = sprung(
        &[
            "run",
            "scene.toml",
            "--out",
            "res",
            "--time",
            "0.05",
            "--quiet",
        ],
        dir.path(),
    );
    assert_eq!(run.status.code(), Some(0), "{}", text(&run.stderr));
}
