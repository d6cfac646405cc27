//! What the viewer's tests share: paths, a private X server (Xvfb) for the
//! native window, running a program with a time limit, and a check that a
//! picture is not blank. A tool that is missing fails the test with a
//! message naming `scripts/test.sh`, which installs it.

#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// The repository's root.
pub fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Cargo's target folder (where the viewer binary's profile folder is).
pub fn target_dir() -> PathBuf {
    let exe = Path::new(env!("CARGO_BIN_EXE_sprung-viewer"));
    exe.ancestors()
        .nth(2)
        .map_or_else(|| root().join("target"), Path::to_path_buf)
}

/// A folder for this test's outputs (screenshots stay there to look at).
pub fn out_dir(name: &str) -> PathBuf {
    let dir = target_dir().join("viewer-tests").join(name);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        panic!("cannot create {}: {e}", dir.display());
    }
    dir
}

/// Fail, saying that `what` is missing and that scripts/test.sh sets it up.
pub fn missing(what: &str) -> ! {
    panic!(
        "{what}: this test needs it, and scripts/test.sh installs it \
         (run the tests with scripts/test.sh, not only `cargo test`)"
    )
}

/// `program` runs (its `--version`, or `args`).
pub fn runs(program: &str, args: &[&str]) -> bool {
    Command::new(program)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Run `command` to the end, killing it after `limit`.
pub fn run_with_limit(command: &mut Command, limit: Duration) -> Output {
    let mut child = match command
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        Ok(child) => child,
        Err(e) => panic!("cannot start {command:?}: {e}"),
    };
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(_)) => break,
            Ok(None) if start.elapsed() > limit => {
                let _ = child.kill();
                let output = collect(child);
                panic!(
                    "{command:?} ran past {limit:?}; it printed:\n{}\n{}",
                    String::from_utf8_lossy(&output.stdout),
                    String::from_utf8_lossy(&output.stderr)
                );
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(50)),
            Err(e) => panic!("cannot wait for {command:?}: {e}"),
        }
    }
    collect(child)
}

fn collect(mut child: Child) -> Output {
    let mut stdout = Vec::new();
    let mut stderr = Vec::new();
    if let Some(mut out) = child.stdout.take() {
        let _ = out.read_to_end(&mut stdout);
    }
    if let Some(mut err) = child.stderr.take() {
        let _ = err.read_to_end(&mut stderr);
    }
    let status = match child.wait() {
        Ok(status) => status,
        Err(e) => panic!("cannot wait for the child: {e}"),
    };
    Output {
        status,
        stdout,
        stderr,
    }
}

/// A private X server, stopped when dropped.
pub struct Xvfb {
    child: Child,
    /// Its display, e.g. `:137`.
    pub display: String,
}

static NEXT: AtomicU32 = AtomicU32::new(0);

impl Xvfb {
    /// Start Xvfb on a free display and wait until it accepts clients.
    pub fn start() -> Xvfb {
        if !runs("Xvfb", &["-help"]) {
            missing("Xvfb (Debian package xvfb) is not installed");
        }
        let base = 100 + (std::process::id() % 300) * 8;
        for attempt in 0..40 {
            let number = base + NEXT.fetch_add(1, Ordering::Relaxed) + attempt;
            if Path::new(&format!("/tmp/.X{number}-lock")).exists() {
                continue;
            }
            let display = format!(":{number}");
            let child = Command::new("Xvfb")
                .args([&display, "-screen", "0", "1280x800x24", "-nolisten", "tcp"])
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn();
            let Ok(mut child) = child else {
                missing("Xvfb (Debian package xvfb) does not start");
            };
            let socket = PathBuf::from(format!("/tmp/.X11-unix/X{number}"));
            let start = Instant::now();
            while start.elapsed() < Duration::from_secs(10) {
                if socket.exists() {
                    return Xvfb { child, display };
                }
                if let Ok(Some(_)) = child.try_wait() {
                    break; // taken by another server: try the next number
                }
                std::thread::sleep(Duration::from_millis(50));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
        panic!("Xvfb did not start on any display from :{base}");
    }
}

impl Drop for Xvfb {
    /// Stop it with SIGTERM, so that it removes its lock file and socket;
    /// SIGKILL if it has not gone after two seconds.
    fn drop(&mut self) {
        let pid = self.child.id().to_string();
        let _ = Command::new("kill").args(["-TERM", &pid]).status();
        let start = Instant::now();
        while start.elapsed() < Duration::from_secs(2) {
            if let Ok(Some(_)) = self.child.try_wait() {
                return;
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// Read a PNG as RGBA.
pub fn read_png(path: &Path) -> image::RgbaImage {
    match image::open(path) {
        Ok(picture) => picture.to_rgba8(),
        Err(e) => panic!("cannot read the screenshot {}: {e}", path.display()),
    }
}

/// Assert that `picture` is not blank: many colours, and a good share of
/// pixels unlike its top-right corner (the background).
pub fn assert_not_blank(picture: &image::RgbaImage, path: &Path) {
    let corner = *picture.get_pixel(picture.width() - 1, 0);
    let mut colours = std::collections::HashSet::new();
    let mut differing = 0usize;
    for pixel in picture.pixels() {
        colours.insert([pixel[0] >> 3, pixel[1] >> 3, pixel[2] >> 3]);
        let d: u32 = (0..3).map(|c| pixel[c].abs_diff(corner[c]) as u32).sum();
        differing += usize::from(d > 24);
    }
    let share = differing as f64 / (picture.width() * picture.height()) as f64;
    assert!(
        colours.len() >= 50 && share > 0.05,
        "{} looks blank: {} colours, {:.1}% unlike the background",
        path.display(),
        colours.len(),
        100.0 * share
    );
}

/// Pixels of `picture` within `tolerance` (sum over r, g, b) of `colour`.
pub fn count_colour(picture: &image::RgbaImage, colour: [u8; 3], tolerance: u32) -> usize {
    picture
        .pixels()
        .filter(|p| (0..3).map(|c| p[c].abs_diff(colour[c]) as u32).sum::<u32>() <= tolerance)
        .count()
}
