//! `--device gpu` for `sprung run`: the steps on the GPU step
//! (`sprung-gpu`), the state read back at each row and frame.

use std::time::Instant;

use sprung::World;
use sprung_gpu::{Gpu, GpuError, GpuWorld, Precision};
use sprung_io::{Device, Scene};

use crate::error::CliError;
use crate::RunOptions;

/// The most steps run on the GPU between two read-backs.
const MOST_STEPS_UNREAD: u64 = 1024;

/// The longest a stretch of steps between two read-backs should take (s),
/// so that an interrupt is heard and the progress bar moves however slow
/// the GPU.
const STRETCH_SECONDS: f64 = 0.25;

/// A run's world on the GPU, with the pace of its last stretch.
#[derive(Debug)]
pub struct OnGpu {
    gpu: GpuWorld,
    /// Wall-clock seconds a step took in the last stretch (none before
    /// the first).
    seconds_per_step: Option<f64>,
}

/// The scene's world put on the GPU where `--device` (or else the scene's
/// `device`) says so, with a note naming the adapter unless `--quiet`;
/// `None` for the CPU. Refused, before anything is written, where the GPU
/// step lacks what the scene or the options ask.
pub fn start(scene: &Scene, options: &RunOptions) -> Result<Option<OnGpu>, CliError> {
    let device = options.device.unwrap_or(scene.device);
    if !device.is_gpu() {
        return Ok(None);
    }
    let refuse = |what: &str| {
        Err(CliError::Input(format!(
            "--device {device}: {what} (run it with --device cpu)"
        )))
    };
    if options.resume.is_some() || options.save_state.is_some() {
        return refuse("the GPU step does not save or resume a state yet");
    }
    if options.profile {
        return refuse("--profile times the engine's stages, which the GPU step does not run");
    }
    // What the scene asks is refused before an adapter is looked for, as
    // `sprung check` refuses it.
    sprung_gpu::support::check(&scene.world).map_err(|e| failed(&e))?;
    let gpu = put_on_gpu(&scene.world, scene.dt, device, options.quiet)?;
    Ok(Some(OnGpu {
        gpu,
        seconds_per_step: None,
    }))
}

/// A GPU error that is not a blow-up of the run, in words.
pub fn failed(error: &GpuError) -> CliError {
    match error {
        // Its words name the GPU step already.
        GpuError::Unsupported(_) => CliError::Input(error.to_string()),
        other => CliError::Input(format!("the GPU step: {other}")),
    }
}

/// The precision `device` asks for (f64 for `gpu_f64`).
pub fn precision(device: Device) -> Precision {
    match device {
        Device::GpuF64 => Precision::F64,
        _ => Precision::F32,
    }
}

/// `world` on a new GPU, to be stepped by `dt` (s) in the precision
/// `device` asks for, with a note naming the adapter unless `quiet`.
pub fn put_on_gpu(
    world: &World,
    dt: f64,
    device: Device,
    quiet: bool,
) -> Result<GpuWorld, CliError> {
    let gpu = Gpu::new().map_err(|e| failed(&e))?;
    let gpu = GpuWorld::in_precision(gpu, world, dt, precision(device)).map_err(|e| failed(&e))?;
    if !quiet {
        let (name, precision) = (gpu.gpu().name(), gpu.precision());
        eprintln!("note: stepping on the GPU in {precision}: {name}");
    }
    Ok(gpu)
}

impl OnGpu {
    /// The last step of the stretch that starts at `step`: the next step
    /// that records a row (`every`) or ends the run, at most
    /// [`MOST_STEPS_UNREAD`] on and about [`STRETCH_SECONDS`] at the last
    /// stretch's pace (one step, to measure it, first).
    pub fn stretch_end(&self, step: u64, steps: u64, every: u64) -> u64 {
        let most = match self.seconds_per_step {
            Some(seconds) if seconds > 0.0 => {
                ((STRETCH_SECONDS / seconds) as u64).clamp(1, MOST_STEPS_UNREAD)
            }
            Some(_) => MOST_STEPS_UNREAD,
            None => 1,
        };
        let row = step.div_ceil(every) * every;
        row.min(steps).min(step + most - 1)
    }

    /// Step `world` on the GPU to step `last` and read it back.
    pub fn advance(&mut self, world: &mut World, last: u64) -> Result<(), GpuError> {
        let count = last.saturating_sub(world.steps());
        let start = Instant::now();
        self.gpu.step(count);
        let read = self.gpu.read_into(world);
        self.seconds_per_step = Some(start.elapsed().as_secs_f64() / count.max(1) as f64);
        read
    }
}
