//! `--device gpu` in the native viewer: the steps on the GPU step
//! (`sprung-gpu`, docs/gpu.md) while the world is one it can run, and on
//! the engine while it is not (a hand holds a particle: the hand is a
//! spring the GPU step has no kernel for), the state read back every frame
//! for drawing. Whatever the window changes in the world (a particle thrown,
//! a setting moved, the other integrator) is put on the GPU again before
//! its next steps.

use sprung::{Real, Vec3, World};
use sprung_gpu::{support, Gpu, GpuError, GpuWorld};

/// The GPU, and the world on it while it runs there.
#[derive(Debug)]
pub struct GpuRun {
    gpu: Gpu,
    on_gpu: Option<OnGpu>,
    /// The feature that last sent the steps to the engine, said once.
    lacked: Option<String>,
    /// Steps taken on the GPU so far.
    pub steps: u64,
}

/// A world on the GPU, with what it last read back: a world that no
/// longer matches it was changed by the window.
#[derive(Debug)]
struct OnGpu {
    world: GpuWorld,
    dt: Real,
    read: (Vec<Vec3>, Vec<Vec3>),
}

impl GpuRun {
    /// The GPU, or why there is none.
    pub fn new() -> Result<GpuRun, String> {
        let gpu = Gpu::new().map_err(|e| format!("--device gpu: {e}"))?;
        eprintln!("sprung-viewer: stepping on the GPU: {}", gpu.name());
        Ok(GpuRun {
            gpu,
            on_gpu: None,
            lacked: None,
            steps: 0,
        })
    }

    /// Forget the world on the GPU (its springs, gas or wind were changed):
    /// it is put there again before the next steps.
    pub fn invalidate(&mut self) {
        self.on_gpu = None;
    }

    /// Take `steps` steps of `dt` (s) of `world` on the GPU and read them
    /// back; `None` where the GPU step cannot run the world as it stands
    /// (the engine takes them).
    pub fn step(
        &mut self,
        world: &mut World,
        dt: Real,
        steps: usize,
    ) -> Option<Result<(), String>> {
        if let Err(GpuError::Unsupported(feature)) = support::check(world) {
            if self.lacked.as_deref() != Some(&feature) {
                eprintln!("sprung-viewer: the GPU step lacks {feature}: stepping on the CPU");
                self.lacked = Some(feature);
            }
            self.on_gpu = None;
            return None;
        }
        self.lacked = None;
        let current = self.on_gpu.as_ref().is_some_and(|on| {
            on.dt == dt
                && on.read.0 == world.particles.position
                && on.read.1 == world.particles.velocity
        });
        if !current {
            match GpuWorld::on(self.gpu.clone(), world, dt) {
                Ok(gpu_world) => {
                    self.on_gpu = Some(OnGpu {
                        world: gpu_world,
                        dt,
                        read: (Vec::new(), Vec::new()),
                    });
                }
                Err(error) => return Some(Err(format!("--device gpu: {error}"))),
            }
        }
        let on = self.on_gpu.as_mut()?;
        on.world.step(steps as u64);
        self.steps += steps as u64;
        let read = on.world.read_into(world);
        on.read.0.clone_from(&world.particles.position);
        on.read.1.clone_from(&world.particles.velocity);
        Some(read.map_err(|error| match error {
            GpuError::Step(step) => step.to_string(),
            other => format!("--device gpu: {other}"),
        }))
    }
}
