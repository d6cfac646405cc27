//! `sprung`: run scene files and demos, write diagnostics and frames, and
//! measure speed. The command line is a contract (README.md, "Usage"): add to it,
//! never change it.
//!
//! Exit status: 0 on success, 1 for bad input or a file that cannot be
//! written, 2 for a malformed command line, 3 when the simulation blew up.

mod bench;
mod check;
mod checkpoint;

/// Counts heap use, for the bench's peak memory and allocations per step.
#[global_allocator]
static ALLOCATOR: bench::memory::Counting = bench::memory::Counting;
mod demos;
mod error;
mod interrupt;
mod intersections;
mod on_gpu;
mod outputs;
mod plot;
mod render;
mod run;
mod scene_file;
mod study;
mod values;
mod view;

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use sprung::IntegratorKind;
use sprung_io::export::OutputFormat;
use sprung_io::{Device, Override};

/// A mass-spring-damper simulator of elastic materials.
#[derive(Debug, Parser)]
#[command(name = "sprung", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Threads the engine runs on (default: SPRUNG_THREADS, else every
    /// core; at most 1024). Results are the same bits on any number.
    #[arg(long, global = true, value_parser = clap::value_parser!(u16).range(1..=sprung::parallel::MAX_THREADS as i64))]
    threads: Option<u16>,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a scene file and write DIR/diagnostics.csv (and frames, with --format).
    Run {
        /// The scene file (TOML), or `-` to read it from standard input.
        scene: PathBuf,
        /// Where the relative paths (meshes) of a scene read from standard
        /// input start (default: the current folder).
        #[arg(long, value_name = "DIR")]
        base_dir: Option<PathBuf>,
        #[command(flatten)]
        options: RunOptions,
    },
    /// Run a built-in demo scene (no NAME: the default demo).
    Demo {
        /// The demo to run (see --list).
        name: Option<String>,
        /// List the demos and exit.
        #[arg(long)]
        list: bool,
        #[command(flatten)]
        options: RunOptions,
    },
    /// Load and validate a scene without running it: counts, memory, and dt against the stable step.
    Check {
        /// The scene file (TOML); with `--intersections`, a run's output
        /// folder.
        scene: PathBuf,
        /// Count, frame by frame, particles that passed through a surface
        /// and edges through triangles in the run folder's frames.
        #[arg(long)]
        intersections: bool,
        /// Set a key of the scene: `sim.dt=1e-4`, `body.NAME.stiffness=200`,
        /// `collider.0.friction=0.5` (repeatable; docs/scenes.md, "Overrides").
        #[arg(long = "set", value_name = "KEY=VALUE", value_parser = crate::values::OverrideArg)]
        set: Vec<Override>,
        /// Check it for this device (cpu, gpu, gpu_f64) instead of the
        /// scene's `device`: an error where `run` would refuse it there.
        #[arg(long)]
        device: Option<Device>,
    },
    /// Draw a scene or a finished run: PNG frames and an animated GIF.
    Render(render::RenderArgs),
    /// Plot a run's diagnostics.csv: energies, volume and pressure, probes (PNG).
    Plot(plot::PlotArgs),
    /// Open the interactive viewer on a scene.
    View(view::ViewArgs),
    /// Studies of a scene: `stability` (each integrator's largest stable dt and its cost).
    #[command(subcommand)]
    Study(study::StudyCommand),
    /// Measure the engine's speed: cloths, every integrator, gas balls, the stiff cloth, contact; on 1 thread and all.
    Bench(bench::BenchArgs),
}

/// Options shared by `run` and `demo`.
#[derive(Debug, Args, Clone, Default)]
pub struct RunOptions {
    /// Output folder (default: out/SCENE for run, out/demo/NAME for demo).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Number of steps to run (instead of the scene's duration).
    #[arg(long, conflicts_with = "time", value_parser = values::steps)]
    steps: Option<u64>,
    /// Simulated time to run (s), instead of the scene's duration.
    #[arg(long, value_parser = values::positive)]
    time: Option<f64>,
    /// Record a diagnostics row (and a frame) every K steps (default: the
    /// scene's `every`, else 50 records per simulated second).
    #[arg(long, value_parser = values::at_least_one)]
    every: Option<u64>,
    /// Write frames to DIR/frames in this format (vtu, vtk, obj), or the
    /// whole run as one glTF animation, DIR/animation.glb (gltf).
    #[arg(long)]
    format: Option<OutputFormat>,
    /// Particle indices whose positions go to diagnostics.csv, e.g. 0,5,9.
    #[arg(long, value_delimiter = ',')]
    probe: Vec<usize>,
    /// Print nothing but errors and warnings.
    #[arg(long)]
    quiet: bool,
    /// Override the scene's integrator.
    #[arg(long)]
    integrator: Option<IntegratorKind>,
    /// Set a key of the scene: `sim.dt=1e-4`, `body.NAME.stiffness=200`,
    /// `collider.0.friction=0.5` (repeatable; docs/scenes.md, "Overrides").
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = crate::values::OverrideArg)]
    set: Vec<Override>,
    /// Save the world's state to FILE at the end of the run (also when it
    /// is interrupted), to go on later with --resume.
    #[arg(long, value_name = "FILE")]
    save_state: Option<PathBuf>,
    /// Also save the state every K steps (with --save-state), replacing the
    /// last one atomically.
    #[arg(long, value_name = "K", requires = "save_state", value_parser = values::at_least_one)]
    checkpoint_every: Option<u64>,
    /// Time each stage of the step (detect, forces, integrate, collide,
    /// friction, constrain, ...) and print, at the end of the run, each
    /// stage's total time, share of the steps' time and calls.
    #[arg(long)]
    profile: bool,
    /// Go on with a run from the state it saved: the same scene and --out;
    /// --steps and --time count from the start, and the rows and frames
    /// written are the same bytes as a run that never stopped.
    #[arg(long, value_name = "FILE")]
    resume: Option<PathBuf>,
    /// Where the steps run: cpu (the engine), gpu (the GPU step in f32,
    /// for the scenes it can run: docs/gpu.md) or gpu_f64 (in f64, on
    /// adapters that have it), instead of the scene's `device`.
    #[arg(long)]
    device: Option<Device>,
}

fn main() -> ExitCode {
    interrupt::quiet_on_broken_pipe();
    // `--threads` may stand before or after the command; given in both
    // places, clap would keep the last without a word.
    // Arguments are bytes (a file name need not be UTF-8): read as they are.
    let given = std::env::args_os()
        .take_while(|a| a != "--")
        .filter(|a| a == "--threads" || a.as_encoded_bytes().starts_with(b"--threads="))
        .count();
    if given > 1 {
        eprintln!(
            "error: --threads is given {given} times (before and after the command): give it once"
        );
        return ExitCode::from(2);
    }
    let cli = Cli::parse();
    if let Err(error) = sprung::parallel::configure(cli.threads.map(usize::from)) {
        eprintln!("error: {error}");
        return ExitCode::from(1);
    }
    let result = match cli.command {
        Command::Run {
            scene,
            base_dir,
            options,
        } => sprung::parallel::in_pool(|| run::run_file(&scene, base_dir.as_deref(), &options)),
        Command::Demo {
            name,
            list,
            options,
        } => {
            if list {
                demos::list();
                Ok(())
            } else {
                sprung::parallel::in_pool(|| demos::run(name.as_deref(), &options))
            }
        }
        Command::Bench(args) => bench::run(&args),
        Command::Check {
            scene,
            intersections: true,
            ..
        } => intersections::run(&scene),
        Command::Check {
            scene, set, device, ..
        } => check::run(&scene, &set, device),
        Command::Render(args) => render::run(&args),
        Command::Plot(args) => plot::run(&args),
        Command::View(args) => view::run(&args),
        Command::Study(command) => study::run(&command),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => {
            eprintln!("error: {error}");
            ExitCode::from(error.exit_code())
        }
    }
}
