//! `--device gpu` and `device = "gpu"`: the GPU step from the command line
//! (on Mesa's software Vulkan driver in the test command).

mod common;

use common::{csv, sprung, text, write};

/// A 16² cloth, 0.05 kg, 300 N/m, held by two corners and let go to swing
/// down for 0.2 s under symplectic Euler: no contact, so the GPU follows
/// the engine within f32's round-off.
const SWING: &str = r#"[sim]
dt = 2e-4
duration = 0.2
every = 100
device = "gpu"

[[body]]
name = "cloth"
cloth = { nx = 16, ny = 16, width = 1.0, height = 1.0 }
total_mass = 0.05
stiffness = 300.0
damping = 0.01
rotate = [-90.0, 0.0, 0.0]
pinned = [240, 255]
"#;

/// Whether this machine has no adapter and the tests may skip (where
/// `SPRUNG_GPU_TESTS` is not `require`); the reason is printed.
fn no_gpu(stderr: &str) -> bool {
    let absent = stderr.contains("no GPU adapter found");
    if absent {
        assert_ne!(
            std::env::var("SPRUNG_GPU_TESTS").as_deref(),
            Ok("require"),
            "SPRUNG_GPU_TESTS=require, but: {stderr}"
        );
        eprintln!("skipped: {stderr}");
    }
    absent
}

/// The scene's `device = "gpu"` runs it on the GPU; `--device cpu` on the
/// engine: the same rows at the same times, the probed particle within
/// 10⁻⁵ m (1000 steps of f32 round-off at 1 m, 6·10⁻⁸ m each, add up as
/// a random walk to about 2·10⁻⁶ m; the particle falls 0.2 m);
/// `--device gpu_f64` within 10⁻¹⁰ m.
#[test]
fn a_scene_runs_on_the_gpu_as_on_the_engine() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "swing.toml", SWING);
    let scene = scene.to_str().unwrap();
    let probe = ["--probe", "0"];
    let gpu = sprung(
        &[&["run", scene, "--out", "gpu"][..], &probe].concat(),
        dir.path(),
    );
    let stderr = text(&gpu.stderr);
    if no_gpu(&stderr) {
        return;
    }
    assert!(gpu.status.success(), "{stderr}");
    assert!(
        stderr.contains("note: stepping on the GPU in f32: "),
        "{stderr}"
    );
    let args = ["run", scene, "--out", "cpu", "--device", "cpu"];
    let cpu = sprung(&[&args[..], &probe].concat(), dir.path());
    assert!(cpu.status.success(), "{}", text(&cpu.stderr));
    assert!(!text(&cpu.stderr).contains("GPU"));
    let (header, on_gpu) = csv(&dir.path().join("gpu/diagnostics.csv"));
    let (_, on_cpu) = csv(&dir.path().join("cpu/diagnostics.csv"));
    assert_eq!(
        on_gpu.len(),
        11,
        "a row every 100 steps and one at the start"
    );
    assert_eq!(on_gpu.len(), on_cpu.len());
    let column = |name: &str| header.iter().position(|h| h == name).expect(name);
    let (time, y) = (column("time"), column("p0.y"));
    for (g, c) in on_gpu.iter().zip(&on_cpu) {
        assert_eq!(g[time], c[time]);
        assert!((g[y] - c[y]).abs() < 1e-5, "y {} against {}", g[y], c[y]);
    }
    let fall = on_cpu[0][y] - on_cpu[10][y];
    assert!(fall > 0.1, "the corner fell {fall} m");
    // In f64 the GPU step is the engine to f64's round-off, 2²⁹ times
    // finer: 10⁻¹⁰ m (as crates/sprung-gpu/tests/against_cpu.rs argues).
    let args = ["run", scene, "--out", "f64", "--device", "gpu_f64"];
    let f64_run = sprung(&[&args[..], &probe].concat(), dir.path());
    let stderr = text(&f64_run.stderr);
    assert!(f64_run.status.success(), "{stderr}");
    assert!(
        stderr.contains("note: stepping on the GPU in f64: "),
        "{stderr}"
    );
    let (_, in_f64) = csv(&dir.path().join("f64/diagnostics.csv"));
    assert_eq!(in_f64.len(), on_cpu.len());
    for (g, c) in in_f64.iter().zip(&on_cpu) {
        assert_eq!(g[time], c[time]);
        assert!((g[y] - c[y]).abs() < 1e-10, "y {} against {}", g[y], c[y]);
    }
}

/// A scene the GPU step cannot run is refused before anything is
/// written, with the feature named; `--device cpu` runs it.
#[test]
fn a_scene_the_gpu_step_lacks_is_refused_before_anything_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let implicit = SWING.replace(
        "device = \"gpu\"",
        "device = \"gpu\"\nintegrator = \"implicit_euler\"",
    );
    let scene = write(dir.path(), "implicit.toml", &implicit);
    let scene = scene.to_str().unwrap();
    let out = sprung(&["run", scene, "--out", "gpu"], dir.path());
    let stderr = text(&out.stderr);
    if no_gpu(&stderr) {
        return;
    }
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("the GPU step lacks the implicit_euler integrator"),
        "{stderr}"
    );
    assert!(stderr.contains("--device cpu"), "{stderr}");
    assert!(!dir.path().join("gpu").exists());
    let cpu = sprung(
        &[
            "run", scene, "--out", "cpu", "--device", "cpu", "--steps", "3",
        ],
        dir.path(),
    );
    assert!(cpu.status.success(), "{}", text(&cpu.stderr));
}

/// An unknown device is the scene's error, with its line and key; the
/// command line's is clap's.
#[test]
fn an_unknown_device_is_named_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "tpu.toml", &SWING.replace("\"gpu\"", "\"tpu\""));
    let out = sprung(&["run", scene.to_str().unwrap()], dir.path());
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("tpu.toml:5"), "{stderr}");
    assert!(
        stderr.contains("unknown device \"tpu\" (known: cpu, gpu, gpu_f64)"),
        "{stderr}"
    );
    let out = sprung(
        &["run", scene.to_str().unwrap(), "--device", "tpu"],
        dir.path(),
    );
    assert_eq!(out.status.code(), Some(2));
}

/// A machine with no driver for the backend asked for: a clear error that
/// says what to install, and nothing written.
#[test]
fn no_adapter_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "swing.toml", SWING);
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_sprung"))
        .args(["run", scene.to_str().unwrap(), "--out", "gpu"])
        .env("WGPU_BACKEND", "gl") // a backend this build has none of
        .current_dir(dir.path())
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("the GPU step: no GPU adapter found"),
        "{stderr}"
    );
    assert!(stderr.contains("mesa-vulkan-drivers"), "{stderr}");
    assert!(!dir.path().join("gpu").exists());
}

/// `render --device gpu` draws a scene stepped on the GPU: as many
/// pictures as on the engine, the state read back for each.
#[test]
fn render_draws_a_scene_stepped_on_the_gpu() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(dir.path(), "swing.toml", SWING);
    let scene = scene.to_str().unwrap();
    let args = [
        "render", scene, "--every", "250", "--width", "64", "--height", "48",
    ];
    let gpu = sprung(&[&args[..], &["--out", "gpu"]].concat(), dir.path());
    let stderr = text(&gpu.stderr);
    if no_gpu(&stderr) {
        return;
    }
    assert!(gpu.status.success(), "{stderr}");
    assert!(
        stderr.contains("note: stepping on the GPU in f32: "),
        "{stderr}"
    );
    let cpu = sprung(
        &[&args[..], &["--out", "cpu", "--device", "cpu"]].concat(),
        dir.path(),
    );
    assert!(cpu.status.success(), "{}", text(&cpu.stderr));
    let pictures = |folder: &str| std::fs::read_dir(dir.path().join(folder)).unwrap().count();
    assert_eq!(pictures("gpu"), 5, "the start and every 250 of 1000 steps");
    assert_eq!(pictures("gpu"), pictures("cpu"));
}

/// `check` says whether the GPU step can run a scene, and what it lacks
/// where it cannot (no GPU needed).
#[test]
fn check_says_whether_the_gpu_step_can_run_a_scene() {
    let dir = tempfile::tempdir().unwrap();
    let swing = write(dir.path(), "swing.toml", SWING);
    let out = sprung(&["check", swing.to_str().unwrap()], dir.path());
    assert!(out.status.success());
    assert!(text(&out.stdout).contains("  the GPU step (--device gpu) can run it\n"));
    let implicit = SWING.replace("device = \"gpu\"", "integrator = \"implicit_euler\"");
    let implicit = write(dir.path(), "implicit.toml", &implicit);
    let out = sprung(&["check", implicit.to_str().unwrap()], dir.path());
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("the GPU step (--device gpu) lacks the implicit_euler integrator"),
        "{stdout}"
    );
}
