//! `sprung render` through the real binary: picture sizes from a scene and
//! from a run folder, the GIF, default output folders, determinism, and
//! the errors (a missing source, a run folder without frames, a malformed
//! frame, bad sizes), each naming the path and writing nothing.

mod common;

use common::{assert_no_partial_files, png_size, sprung, text, write, BLOW_UP_SCENE};

use std::path::{Path, PathBuf};

/// Width and height from a GIF's logical screen descriptor; checks the
/// signature and the trailer.
fn gif_size(path: &Path) -> (u16, u16) {
    let bytes = std::fs::read(path).expect("gif");
    assert_eq!(&bytes[..6], b"GIF89a", "{}", path.display());
    assert_eq!(
        bytes.last(),
        Some(&0x3b),
        "a complete GIF ends with its trailer"
    );
    let le = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]);
    (le(6), le(8))
}

/// The `frame_*.png` files in `dir`, sorted.
fn pictures(dir: &Path) -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("output dir")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    files.sort();
    files
}

/// A pendulum and a small 2D ring on a floor (a 2D scene).
const SCENE: &str = r#"[sim]
dt = 1e-3
steps = 100

[[body]]
name = "bob"
particles = [[0.0, 0.0], [1.0, 0.0]]
springs = [[0, 1]]
stiffness = 1000.0
mass = 0.5
pinned = [0]

[[body]]
name = "ball"
ring = { particles = 8, radius = 0.3 }
stiffness = 2000.0
translate = [0.0, -1.0, 0.0]
gas = { nrt = 20.0, ramp_time = 0.05 }

[[collider]]
plane = { point = [0.0, -1.5, 0.0], normal = [0.0, 1.0, 0.0] }
"#;

#[test]
fn a_scene_gives_pngs_and_a_gif_of_the_size_asked() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "s.toml", SCENE);
    let output = sprung(
        &[
            "render", "s.toml", "--steps", "40", "--every", "10", "--width", "120", "--height",
            "90", "--gif", "--out", "pics",
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let out = dir.path().join("pics");
    let files = pictures(&out);
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_name().expect("name").to_string_lossy().into_owned())
        .collect();
    assert_eq!(names.first().map(String::as_str), Some("frame_000000.png"));
    assert_eq!(names.len(), 5, "steps 0, 10, 20, 30, 40: {names:?}");
    for file in &files {
        assert_eq!(png_size(file), (120, 90));
    }
    assert_eq!(gif_size(&out.join("animation.gif")), (120, 90));
    assert!(text(&output.stdout).contains("5 pictures of 120×90 and animation.gif in pics"));
    assert_no_partial_files(dir.path());
}

#[test]
fn the_default_is_800_by_600_at_25_pictures_per_second_in_out_scene_render() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "swing.toml", SCENE);
    // 0.2 s at 25 pictures per second: 5 intervals, 6 pictures.
    let output = sprung(
        &["render", "swing.toml", "--time", "0.2", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(output.stdout.is_empty(), "--quiet prints nothing");
    let files = pictures(&dir.path().join("out/swing/render"));
    assert_eq!(files.len(), 6);
    assert_eq!(png_size(&files[0]), (800, 600));
}

#[test]
fn a_run_folder_is_drawn_from_its_vtk_frames() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "s.toml", SCENE);
    let run = sprung(
        &[
            "run", "s.toml", "--out", "r", "--format", "vtk", "--every", "20", "--quiet",
        ],
        dir.path(),
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let output = sprung(
        &["render", "r", "--width", "100", "--height", "64", "--gif"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    // Rest lengths are in the frames: no note about grey springs.
    assert!(output.stderr.is_empty(), "{}", text(&output.stderr));
    let out = dir.path().join("r/render");
    let files = pictures(&out);
    assert_eq!(files.len(), 6, "frames at steps 0, 20, ..., 100");
    for file in &files {
        assert_eq!(png_size(file), (100, 64));
    }
    assert_eq!(gif_size(&out.join("animation.gif")), (100, 64));
    // Every second frame.
    let output = sprung(
        &[
            "render", "r", "--every", "2", "--out", "half", "--width", "100", "--height", "64",
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert_eq!(
        pictures(&dir.path().join("half")).len(),
        4,
        "frames 0, 2, 4 and the last, 5"
    );
}

/// `.vtu` and legacy `.vtk` frames of the same run carry the same model
/// and the same positions (bit for bit): their pictures are the same bytes.
#[test]
fn vtu_and_vtk_run_folders_draw_the_same_pictures() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "s.toml", SCENE);
    for format in ["vtu", "vtk"] {
        let run = sprung(
            &[
                "run", "s.toml", "--out", format, "--format", format, "--every", "20", "--quiet",
            ],
            dir.path(),
        );
        assert!(run.status.success(), "{}", text(&run.stderr));
        let output = sprung(
            &[
                "render", format, "--width", "100", "--height", "64", "--quiet",
            ],
            dir.path(),
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
    }
    let vtu = pictures(&dir.path().join("vtu/render"));
    let vtk = pictures(&dir.path().join("vtk/render"));
    assert_eq!(vtu.len(), 6);
    for (a, b) in vtu.iter().zip(&vtk) {
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{}",
            a.display()
        );
    }
}

#[test]
fn rendering_twice_gives_the_same_bytes() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "s.toml", SCENE);
    for out in ["one", "two"] {
        let output = sprung(
            &[
                "render", "s.toml", "--steps", "60", "--every", "20", "--width", "160", "--height",
                "120", "--gif", "--out", out, "--quiet",
            ],
            dir.path(),
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
    }
    let one = dir.path().join("one");
    let two = dir.path().join("two");
    let mut names: Vec<PathBuf> = pictures(&one);
    names.push(one.join("animation.gif"));
    assert_eq!(names.len(), 5);
    for file in names {
        let name = file.file_name().expect("name");
        assert_eq!(
            std::fs::read(&file).expect("first"),
            std::fs::read(two.join(name)).expect("second"),
            "{}",
            name.to_string_lossy()
        );
    }
}

/// Runs `args` in `dir`, expects exit status 1 with `needle` in the error,
/// and nothing written to `out`.
fn refused(args: &[&str], dir: &Path, needle: &str) {
    refused_with(1, args, dir, needle);
}

/// Like [`refused`], for a malformed value of an option: exit status 2.
fn malformed(args: &[&str], dir: &Path, needle: &str) {
    refused_with(2, args, dir, needle);
}

fn refused_with(code: i32, args: &[&str], dir: &Path, needle: &str) {
    let output = sprung(args, dir);
    let stderr = text(&output.stderr);
    assert_eq!(output.status.code(), Some(code), "{args:?}: {stderr}");
    assert!(
        stderr.contains(needle),
        "{args:?}: expected {needle:?} in {stderr}"
    );
    assert!(!dir.join("o").exists(), "{args:?} wrote output");
}

#[test]
fn errors_name_the_path_and_write_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "s.toml", SCENE);
    refused(
        &["render", "nowhere.toml", "--out", "o"],
        d,
        "nowhere.toml: no such scene file or run folder",
    );
    std::fs::create_dir_all(d.join("empty")).expect("dir");
    refused(
        &["render", "empty", "--out", "o"],
        d,
        "no VTK frames in empty/frames",
    );
    for (width, height, bad) in [
        ("0", "600", "0"),
        ("800", "0", "0"),
        ("100000", "600", "100000"),
    ] {
        malformed(
            &[
                "render", "s.toml", "--width", width, "--height", height, "--out", "o",
            ],
            d,
            &format!("{bad} pixels: from 8 to 8192"),
        );
    }
    malformed(
        &["render", "s.toml", "--strain", "-0.1", "--out", "o"],
        d,
        "'--strain <STRAIN>': -0.1: must be positive",
    );
    malformed(
        &["render", "s.toml", "--fps", "0", "--out", "o"],
        d,
        "'--fps <FPS>': 0: must be positive",
    );
    malformed(
        &["render", "s.toml", "--every", "0", "--out", "o"],
        d,
        "'--every <EVERY>': must be at least 1",
    );
    malformed(
        &["render", "s.toml", "--fov", "0", "--out", "o"],
        d,
        "'--fov <FOV>': 0: must be between 0 and 180",
    );
    refused(
        &[
            "render", "s.toml", "--eye", "1,1,1", "--target", "1,1,1", "--out", "o",
        ],
        d,
        "same point",
    );
    let bad_scene = write(d, "bad.toml", "[sim]\ndt = -1\n");
    refused(
        &["render", "bad.toml", "--out", "o"],
        d,
        &bad_scene.file_name().expect("name").to_string_lossy(),
    );
    // A run folder with a malformed frame: the file and its line.
    let run = sprung(
        &[
            "run", "s.toml", "--out", "r", "--format", "vtk", "--every", "50", "--quiet",
        ],
        d,
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let frame = d.join("r/frames/frame_000001.vtk");
    let content = std::fs::read_to_string(&frame).expect("frame");
    // Break the first point, on the line after `POINTS`.
    let mut lines: Vec<String> = content.lines().map(String::from).collect();
    let index = lines
        .iter()
        .position(|l| l.starts_with("POINTS"))
        .expect("points")
        + 1;
    lines[index] = "0 zero 0".into();
    std::fs::write(&frame, lines.join("\n")).expect("write");
    let line = index + 1;
    refused(
        &["render", "r", "--out", "o"],
        d,
        &format!("frame_000001.vtk:{line}:"),
    );
    refused(
        &["render", "r", "--steps", "10", "--out", "o"],
        d,
        "run folder",
    );
    assert_no_partial_files(d);
}

#[test]
fn a_blow_up_keeps_the_pictures_before_it_and_says_so() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "boom.toml", BLOW_UP_SCENE);
    let output = sprung(
        &[
            "render",
            "boom.toml",
            "--every",
            "1",
            "--width",
            "80",
            "--height",
            "60",
            "--out",
            "o",
        ],
        dir.path(),
    );
    let stderr = text(&output.stderr);
    assert_eq!(
        output.status.code(),
        Some(3),
        "a blow-up exits with 3: {stderr}"
    );
    assert!(
        stderr.contains("pictures up to the last good step are in o"),
        "{stderr}"
    );
    assert!(!pictures(&dir.path().join("o")).is_empty());
    assert_no_partial_files(dir.path());
}

#[test]
fn the_scene_camera_is_used_and_the_command_line_overrides_it() {
    let dir = tempfile::tempdir().expect("tempdir");
    let camera = "\n[camera]\neye = [0.5, -0.5, 4.0]\ntarget = [0.5, -0.8, 0.0]\nfov = 30.0\n";
    write(dir.path(), "plain.toml", SCENE);
    write(dir.path(), "framed.toml", &format!("{SCENE}{camera}"));
    let render = |scene: &str, out: &str, extra: &[&str]| {
        let mut args = vec![
            "render", scene, "--steps", "1", "--every", "1", "--width", "160", "--height", "120",
            "--out", out, "--quiet",
        ];
        args.extend_from_slice(extra);
        let output = sprung(&args, dir.path());
        assert!(output.status.success(), "{}", text(&output.stderr));
        std::fs::read(dir.path().join(out).join("frame_000001.png")).expect("picture")
    };
    let automatic = render("plain.toml", "a", &[]);
    let from_scene = render("framed.toml", "b", &[]);
    let same_by_hand = render(
        "plain.toml",
        "c",
        &[
            "--eye",
            "0.5,-0.5,4.0",
            "--target",
            "0.5,-0.8,0.0",
            "--fov",
            "30",
        ],
    );
    let overridden = render("framed.toml", "d", &["--eye", "3.0,0.0,3.0"]);
    assert_ne!(
        automatic, from_scene,
        "the scene's camera changes the picture"
    );
    assert_eq!(
        from_scene, same_by_hand,
        "the scene's camera is the one given by hand"
    );
    assert_ne!(overridden, from_scene, "--eye overrides the scene's eye");
}
