//! The web viewer in a real browser: `web-tests/drag.mjs` serves the page
//! that scripts/build-web.sh built (target/web) from 127.0.0.1, drives
//! headless Chromium with Playwright, drags a particle with the mouse and
//! checks from the simulation's state that it followed the cursor, and that
//! a screenshot is not blank. Node, Playwright (`npm ci` in web-tests),
//! Chromium and the built page come from scripts/test.sh.

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
    for file in ["index.html", "gl.js", "sprung-viewer.wasm"] {
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

#[test]
fn dragging_a_particle_in_headless_chromium_moves_it_to_the_cursor() {
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
    let web = page();
    let shot = out_dir("web").join("ball2d.png");
    let _ = std::fs::remove_file(&shot);
    let output = run_with_limit(
        Command::new("node")
            .arg(tests.join("drag.mjs"))
            .arg(&web)
            .arg(&shot)
            .env("CHROMIUM", &chromium)
            .current_dir(&tests),
        Duration::from_secs(240),
    );
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}\n{stdout}");
    println!("{stdout}");
    assert_not_blank(&read_png(&shot), &shot);
}
