//! `--device gpu` for `sprung run`: the steps on the GPU step
//! (`sprung-gpu`), the state read back at each row and frame.

use sprung_gpu::{GpuError, GpuWorld};
use sprung_io::{Device, Scene};

use crate::run::CliError;
use crate::RunOptions;

/// The most steps run on the GPU between two read-backs, so that an
/// interrupt is heard and the progress bar moves.
const MOST_STEPS_UNREAD: u64 = 1024;

/// The scene's world put on the GPU where `--device` (or else the scene's
/// `device`) says so, with a note naming the adapter unless `--quiet`;
/// `None` for the CPU. Refused, before anything is written, where the GPU
/// step lacks what the scene or the options ask.
pub fn start(scene: &Scene, options: &RunOptions) -> Result<Option<GpuWorld>, CliError> {
    if options.device.unwrap_or(scene.device) == Device::Cpu {
        return Ok(None);
    }
    let refuse = |what: &str| {
        Err(CliError::Input(format!(
            "--device gpu: {what} (run it with --device cpu)"
        )))
    };
    if options.resume.is_some() || options.save_state.is_some() {
        return refuse("the GPU step does not save or resume a state yet");
    }
    if options.profile {
        return refuse("--profile times the engine's stages, which the GPU step does not run");
    }
    let gpu = GpuWorld::new(&scene.world, scene.dt).map_err(|e| failed(&e))?;
    if !options.quiet {
        eprintln!("note: stepping on the GPU: {}", gpu.gpu().name());
    }
    Ok(Some(gpu))
}

/// A GPU error that is not a blow-up of the run, in words.
pub fn failed(error: &GpuError) -> CliError {
    CliError::Input(format!("--device gpu: {error}"))
}

/// The last step of the stretch that starts at `step` on the GPU: the
/// next step that records a row (`every`) or ends the run, at most
/// [`MOST_STEPS_UNREAD`] on.
pub fn stretch_end(step: u64, steps: u64, every: u64) -> u64 {
    let row = step.div_ceil(every) * every;
    row.min(steps).min(step + MOST_STEPS_UNREAD - 1)
}
