//! The native viewer in a real window, on a private X server (Xvfb) with
//! Mesa's software OpenGL: it draws non-blank frames of a 3D and a 2D demo
//! and exits cleanly when asked (`--frames N --screenshot FILE`,
//! `--exit-after S`), and a scene it cannot load is shown on screen and
//! reported in the terminal, not a crash.

mod common;

use std::process::Command;
use std::time::Duration;

use common::{assert_not_blank, count_colour, out_dir, read_png, run_with_limit, Xvfb};

const LIMIT: Duration = Duration::from_secs(120);

fn viewer(xvfb: &Xvfb) -> Command {
    let mut command = Command::new(env!("CARGO_BIN_EXE_sprung-viewer"));
    command.env("DISPLAY", &xvfb.display);
    command
}

#[test]
fn draws_a_non_blank_frame_of_a_3d_and_a_2d_demo_and_exits() {
    let xvfb = Xvfb::start();
    for demo in ["ball3d", "ball2d"] {
        let shot = out_dir("native").join(format!("{demo}.png"));
        let _ = std::fs::remove_file(&shot);
        let output = run_with_limit(
            viewer(&xvfb)
                .args(["--demo", demo, "--frames", "30", "--screenshot"])
                .arg(&shot),
            LIMIT,
        );
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert!(
            output.status.success(),
            "{demo}: {:?}\n{stderr}",
            output.status
        );
        let picture = read_png(&shot);
        assert_eq!((picture.width(), picture.height()), (1280, 800));
        assert_not_blank(&picture, &shot);
    }
}

#[test]
fn exits_cleanly_after_the_time_asked() {
    let xvfb = Xvfb::start();
    let output = run_with_limit(
        viewer(&xvfb).args(["--demo", "flag", "--exit-after", "1", "--size", "640x400"]),
        LIMIT,
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{:?}\n{stderr}", output.status);
}

#[test]
fn a_scene_it_cannot_load_is_shown_on_screen_and_in_the_terminal() {
    let dir = out_dir("bad-scene");
    let scene = dir.join("bad.toml");
    let text = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"rope\"\nrope = { particles = 10, length = 2.0 }\nstiffnes = 100.0\n";
    if let Err(e) = std::fs::write(&scene, text) {
        panic!("cannot write {}: {e}", scene.display());
    }
    let shot = dir.join("error.png");
    let _ = std::fs::remove_file(&shot);
    let xvfb = Xvfb::start();
    let output = run_with_limit(
        viewer(&xvfb)
            .arg(&scene)
            .args(["--frames", "5", "--screenshot"])
            .arg(&shot),
        LIMIT,
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    // The loader's message: the file, the line and the unknown key.
    assert!(stderr.contains("cannot load the scene"), "{stderr}");
    assert!(stderr.contains("bad.toml:7"), "{stderr}");
    assert!(stderr.contains("stiffnes"), "{stderr}");
    // On screen: the red title and the box's red edge (palette::ERROR).
    let picture = read_png(&shot);
    let red = count_colour(&picture, [0xff, 0x6b, 0x6b], 60);
    assert!(
        red > 200,
        "{}: {red} red pixels, no error box",
        shot.display()
    );
    assert_not_blank(&picture, &shot);
}

#[test]
fn a_bad_command_line_is_refused_before_any_window() {
    let output = run_with_limit(
        Command::new(env!("CARGO_BIN_EXE_sprung-viewer")).args(["--frames", "many"]),
        LIMIT,
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("--frames many"), "{stderr}");
}

/// `--device gpu`: the flag steps on the GPU step (Mesa's software Vulkan
/// driver in the test command) and is drawn as on the engine: the frames'
/// simulated time is the same, and the picture is not blank (skipped where
/// this machine has no adapter and `SPRUNG_GPU_TESTS` is not `require`).
#[test]
fn steps_on_the_gpu_with_device_gpu() {
    let xvfb = Xvfb::start();
    let shot = out_dir("native").join("flag-gpu.png");
    let _ = std::fs::remove_file(&shot);
    let output = run_with_limit(
        viewer(&xvfb)
            .args([
                "--demo",
                "flag",
                "--device",
                "gpu",
                "--frames",
                "20",
                "--screenshot",
            ])
            .arg(&shot),
        LIMIT,
    );
    let stderr = String::from_utf8_lossy(&output.stderr);
    if stderr.contains("no GPU adapter found")
        && std::env::var("SPRUNG_GPU_TESTS").as_deref() != Ok("require")
    {
        eprintln!("skipped: {stderr}");
        return;
    }
    assert!(output.status.success(), "{:?}\n{stderr}", output.status);
    assert!(stderr.contains("stepping on the GPU: "), "{stderr}");
    assert!(!stderr.contains("stepping on the CPU"), "{stderr}");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(stdout.contains("20 frames"), "{stdout}");
    assert!(!stdout.contains("simulated 0.00 s"), "{stdout}");
    assert_not_blank(&read_png(&shot), &shot);
}
