//! `sprung-viewer`: the interactive viewer of sprung scenes, in a native
//! window and, built for `wasm32-unknown-unknown`, in a web page (one code
//! base, macroquad). `sprung view` starts it; see `args::USAGE`.

mod app;
mod args;
mod camera;
mod demos;
#[cfg(target_arch = "wasm32")]
// The getrandom hook is an `extern` function writing through a raw pointer.
#[allow(unsafe_code)]
mod entropy;
mod gpu;
mod hand;
mod hud;
mod input;
mod palette;
mod panel;
// Exported `#[no_mangle]` functions the web page reads the state with.
#[allow(unsafe_code)]
mod probe;
mod render;
mod render2d;
mod render3d;
mod shading;
mod shot;
mod sim;
mod ui;

use macroquad::miniquad;
use macroquad::time::get_time;
use macroquad::window::next_frame;

use crate::app::App;
use crate::args::Options;
use crate::demos::Source;
use sprung_io::demos::DEMOS;

fn main() {
    let options = match args::parse(std::env::args().skip(1)) {
        Ok(options) => options,
        Err(message) => {
            eprintln!("sprung-viewer: {message}\n\n{}", args::USAGE);
            std::process::exit(2);
        }
    };
    if options.help {
        println!("{}", args::USAGE);
        return;
    }
    let source = match source(&options) {
        Ok(source) => source,
        Err(message) => {
            eprintln!("sprung-viewer: {message}");
            std::process::exit(2);
        }
    };
    if let Err(message) = display_available() {
        eprintln!("sprung-viewer: {message}");
        std::process::exit(1);
    }
    let conf = macroquad::conf::Conf {
        miniquad_conf: miniquad::conf::Conf {
            window_title: format!("sprung: {}", source.label()),
            window_width: options.size.0 as i32,
            window_height: options.size.1 as i32,
            high_dpi: false,
            sample_count: 4,
            ..Default::default()
        },
        // Big meshes go out in chunks of this size (see render3d).
        draw_call_vertex_capacity: 30_000,
        draw_call_index_capacity: 30_000,
        ..Default::default()
    };
    macroquad::Window::from_config(conf, run(source, options));
}

/// The scene the command line names (default: the first demo).
fn source(options: &Options) -> Result<Source, String> {
    match (&options.scene, &options.demo) {
        (Some(path), _) => Ok(Source::File(path.clone())),
        (None, Some(name)) => demos::find(name).map(Source::Demo).ok_or_else(|| {
            let names: Vec<&str> = DEMOS.iter().map(|d| d.name).collect();
            format!("no demo named \"{name}\" (demos: {})", names.join(", "))
        }),
        (None, None) => Ok(Source::Demo(0)),
    }
}

/// On Linux, a window needs an X server: say so plainly instead of letting
/// the windowing library panic.
fn display_available() -> Result<(), String> {
    if cfg!(target_os = "linux") && std::env::var_os("DISPLAY").is_none_or(|d| d.is_empty()) {
        return Err("no display to open a window on: DISPLAY is not set \
                    (run it in a desktop session, or under Xvfb: `xvfb-run -a sprung view ...`)"
            .into());
    }
    Ok(())
}

/// The frame loop; with `--frames` or `--exit-after`, save the screenshot
/// and exit (status 1 if the scene could not be loaded).
async fn run(source: Source, options: Options) {
    let mut app = App::new(source, options.device);
    let failed = app.error.is_some();
    let start = get_time();
    loop {
        app.frame();
        let frames_done = options.frames.is_some_and(|n| u64::from(app.frames) >= n);
        let time_done = options.exit_after.is_some_and(|s| get_time() - start >= s);
        if frames_done || time_done {
            let wall = (get_time() - start).max(1e-9);
            let simulated = app.sim.as_ref().map_or(0.0, |s| s.world.time());
            let (physics, steps) = app.physics_total;
            println!(
                "sprung-viewer: {} frames in {wall:.2} s ({:.1} fps); simulated {simulated:.2} s \
                 ({:.2} of real time); {steps} steps, {:.1} us each",
                app.frames,
                f64::from(app.frames) / wall,
                simulated / wall,
                1e6 * physics / steps.max(1) as f64,
            );
            let mut status = i32::from(failed);
            if let Some(path) = &options.screenshot {
                if let Err(message) = shot::save(path) {
                    eprintln!("sprung-viewer: {message}");
                    status = 1;
                }
            }
            std::process::exit(status);
        }
        next_frame().await;
    }
}
