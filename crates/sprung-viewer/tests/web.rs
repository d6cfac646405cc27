//! The web viewer in a real browser: the scripts in `web-tests` serve the
//! page that scripts/build-web.sh built (target/web) from 127.0.0.1 and
//! drive headless Chromium with Playwright. `drag.mjs` drags a particle with
//! the mouse and checks from the simulation's state that it followed the
//! cursor, and that a screenshot is not blank; `scene.mjs` opens a user's
//! scene through the file picker and through `#scene=URL` and checks from
//! the simulation's state that it runs, and that a broken scene and an
//! unknown demo name are reported on the page. Node, Playwright (`npm ci`
//! in web-tests), Chromium and the built page come from scripts/test.sh.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, SystemTime};

use common::{
    assert_not_blank, missing, out_dir, read_png, root, run_with_limit, runs, target_dir,
};

/// The newest modification time of the files under `dir`.
fn newest(dir: &Path) -> SystemTime {
    let mut latest = SystemTime::UNIX_EPOCH;
    let Ok(entries) = std::fs::read_dir(dir) else {
        return latest;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        let time = if path.is_dir() {
            newest(&path)
        } else {
            entry
                .metadata()
                .and_then(|m| m.modified())
                .unwrap_or(SystemTime::UNIX_EPOCH)
        };
        latest = latest.max(time);
    }
    latest
}

/// The built page, checked to be newer than the code it was built from.
fn page() -> PathBuf {
    let web = target_dir().join("web");
    let wasm = web.join("sprung-viewer.wasm");
    for file in [
        "index.html",
        "gl.js",
        "sprung-viewer.js",
        "sprung-viewer.wasm",
    ] {
        if !web.join(file).is_file() {
            missing(&format!(
                "the web page is not built ({} is missing; scripts/build-web.sh builds it)",
                web.join(file).display()
            ));
        }
    }
    let built = std::fs::metadata(&wasm)
        .and_then(|m| m.modified())
        .unwrap_or(SystemTime::UNIX_EPOCH);
    let sources = [
        "crates/sprung-viewer/src",
        "crates/sprung-viewer/web",
        "crates/sprung-gpu/src",
        "crates/sprung/src",
        "crates/sprung-io/src",
        "scenes",
    ];
    if let Some(stale) = sources.iter().find(|s| newest(&root().join(s)) > built) {
        missing(&format!(
            "the web page in {} is older than {stale}: rebuild it (scripts/build-web.sh)",
            web.display()
        ));
    }
    web
}

/// Run the browser test `script` with `args` after the built page, within
/// four minutes; it must succeed (its report is printed).
fn run_script(script: &str, args: &[&Path]) {
    let (tests, chromium) = browser_tests();
    let web = page();
    let output = run_with_limit(
        Command::new("node")
            .arg(tests.join(script))
            .arg(&web)
            .args(args)
            .env("CHROMIUM", &chromium)
            .current_dir(&tests),
        Duration::from_secs(240),
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}\n{stdout}");
    println!("{stdout}");
}

/// The browser tests' folder and Chromium, checked to be there.
fn browser_tests() -> (PathBuf, String) {
    let tests = root().join("crates/sprung-viewer/web-tests");
    if !runs("node", &["--version"]) {
        missing("node (Node.js) is not installed");
    }
    if !tests.join("node_modules/playwright-core").is_dir() {
        missing("playwright-core is not installed (`npm ci` in crates/sprung-viewer/web-tests)");
    }
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !Path::new(&chromium).is_file() {
        missing(&format!(
            "Chromium is not at {chromium} (Debian package chromium)"
        ));
    }
    (tests, chromium)
}

/// A rope of 4 particles and the textbook cube (8), falling; the scene
/// `scene.mjs` opens through the picker and through `#scene=`.
const MINE: &str = r#"[sim]
dt = 1e-3
duration = 100.0

[[body]]
name = "rope"
rope = { particles = 4, length = 1.0 }
mass = 0.1
stiffness = 200.0
translate = [-2.0, 1.0, 0.0]

[[body]]
name = "box"
mesh = "meshes/box.asc"
total_mass = 1.0
stiffness = 500.0
translate = [2.0, 2.0, 0.0]
"#;

/// A scene whose line 6 asks for a rope of -4 particles.
const BROKEN: &str =
    "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"rope\"\nrope = { particles = -4, length = 1.0 }\n";

#[test]
fn a_users_scene_opens_through_the_picker_and_the_address() {
    let scenes = out_dir("web-scenes");
    std::fs::create_dir_all(scenes.join("meshes")).expect("scenes folder");
    std::fs::write(scenes.join("mine.toml"), MINE).expect("scene");
    std::fs::write(scenes.join("broken.toml"), BROKEN).expect("scene");
    // Broken on line 6 too, until scene.mjs mends it and presses R.
    std::fs::write(scenes.join("fix.toml"), BROKEN).expect("scene");
    // Names a mesh that is not served (though one of that name is built
    // into sprung): an error on line 6.
    std::fs::write(
        scenes.join("nomesh.toml"),
        "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"horse\"\nmesh = \"meshes/horse.obj\"\n",
    )
    .expect("scene");
    let cube = std::fs::read(root().join("scenes/meshes/cube.asc")).expect("the cube");
    // Picked beside the scene, and served where the scene says it is.
    std::fs::write(scenes.join("box.asc"), &cube).expect("mesh");
    std::fs::write(scenes.join("meshes/box.asc"), &cube).expect("mesh");
    run_script("scene.mjs", &[&scenes]);
}

#[test]
fn dragging_a_particle_in_headless_chromium_moves_it_to_the_cursor() {
    let shot = out_dir("web").join("ball2d.png");
    let _ = std::fs::remove_file(&shot);
    run_script("drag.mjs", &[&shot]);
    assert_not_blank(&read_png(&shot), &shot);
}

/// An 8² cloth, 0.7 m square, falling freely from rest on the GPU:
/// symplectic Euler, no drag, nothing to touch.
const FALL: &str = r#"[sim]
dt = 1e-3
integrator = "symplectic_euler"
gravity = [0.0, -9.81, 0.0]
duration = 100.0
device = "gpu"

[[body]]
name = "cloth"
cloth = { nx = 8, ny = 8, width = 0.7, height = 0.7 }
total_mass = 0.2
stiffness = 100.0
damping = 0.01
translate = [0.0, 1.0, 0.0]
"#;

/// The web viewer on the browser's WebGPU (`gpu.mjs`): a falling cloth
/// where free fall puts it, the flag demo by `?device=gpu`, and the engine
/// with a word where the browser has no WebGPU.
#[test]
fn the_web_viewer_steps_on_the_browsers_webgpu() {
    let scenes = out_dir("web-gpu");
    std::fs::create_dir_all(&scenes).expect("scenes folder");
    std::fs::write(scenes.join("fall.toml"), FALL).expect("scene");
    let shot = scenes.join("flag.png");
    let _ = std::fs::remove_file(&shot);
    run_script("gpu.mjs", &[&scenes, &shot]);
    assert_not_blank(&read_png(&shot), &shot);
}
