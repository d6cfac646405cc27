//! `sprung bench --device gpu`: the bench's cloths on the GPU step against
//! the engine on every thread of the same machine.

use std::time::Instant;

use sprung::{parallel, IntegratorKind, World};
use sprung_gpu::{Gpu, GpuError, GpuWorld, Precision};
use sprung_io::export::AtomicFile;

use super::cases;
use crate::error::CliError;

/// Steps a frame of the goal (60 frames a second, 10 steps each).
const STEPS_PER_FRAME: f64 = 10.0;

/// One cloth timed on the GPU and on the CPU.
#[derive(Debug, Clone)]
struct GpuRow {
    name: String,
    integrator: IntegratorKind,
    particles: usize,
    springs: usize,
    /// Seconds a step on the GPU, and on the CPU's threads.
    gpu_seconds: f64,
    cpu_seconds: f64,
    /// Force evaluations a step.
    evaluations: u32,
}

impl GpuRow {
    fn spring_updates(&self, seconds: f64) -> f64 {
        f64::from(self.evaluations) * self.springs as f64 / seconds
    }
}

fn gpu_error(error: GpuError) -> CliError {
    CliError::Input(format!("bench, the GPU step: {error}"))
}

/// Seconds a step of `world` on the GPU: a warm-up, then batches doubling
/// until one takes `least` seconds (the steps queued, then waited for;
/// nothing read back).
fn gpu_seconds(
    gpu: &Gpu,
    world: &World,
    dt: f64,
    least: f64,
    precision: Precision,
) -> Result<f64, GpuError> {
    let mut step = GpuWorld::in_precision(gpu.clone(), world, dt, precision)?;
    step.step(4);
    step.wait()?;
    let mut batch = 8u64;
    loop {
        let start = Instant::now();
        step.step(batch);
        step.wait()?;
        let elapsed = start.elapsed().as_secs_f64();
        if elapsed >= least || batch >= 1 << 20 {
            return Ok(elapsed / batch as f64);
        }
        batch *= 2;
    }
}

/// Seconds a step of `world` on the engine, on the pool it is called in.
fn cpu_seconds(world: &mut World, dt: f64, least: f64) -> Result<f64, CliError> {
    let step = |world: &mut World| {
        world
            .step(dt)
            .map_err(|e| CliError::Input(format!("bench --device gpu: {e}")))
    };
    step(world)?;
    let (mut taken, start) = (0u32, Instant::now());
    while taken < 3 || start.elapsed().as_secs_f64() < least {
        step(world)?;
        taken += 1;
    }
    Ok(start.elapsed().as_secs_f64() / f64::from(taken))
}

/// Time the cloths of `sizes` (and the largest under RK4) on the GPU in
/// `precision` and on `pool`, print the table, and write it to `csv` if
/// given.
pub fn run(
    pool: &parallel::Pool,
    sizes: &[usize],
    least: f64,
    precision: Precision,
    csv: Option<&std::path::Path>,
) -> Result<(), CliError> {
    let gpu = Gpu::new().map_err(gpu_error)?;
    println!("GPU: {}, in {precision}", gpu.name());
    let largest = sizes.iter().copied().max().unwrap_or(0);
    let mut cloths: Vec<(usize, IntegratorKind)> = sizes
        .iter()
        .map(|&s| (s, IntegratorKind::SymplecticEuler))
        .collect();
    if largest > 0 {
        cloths.push((largest, IntegratorKind::Rk4));
    }
    println!(
        "{:<16} {:<16} {:>9} {:>9} {:>11} {:>12} {:>11} {:>12} {:>8} {:>13}",
        "case",
        "integrator",
        "particles",
        "springs",
        "gpu ms",
        "gpu springs/s",
        "cpu ms",
        "cpu springs/s",
        "gpu/cpu",
        "frames/s (10)"
    );
    let mut rows = Vec::new();
    for (size, kind) in cloths {
        let mut world = cases::cloth(size, kind)?;
        let dt = 0.5 * world.stable_time_step();
        let gpu_seconds = match gpu_seconds(&gpu, &world, dt, least, precision) {
            Ok(seconds) => seconds,
            // The next cloth may fit no better, but the rows so far are
            // kept and the larger ones said.
            Err(too_large @ GpuError::TooLarge { .. }) => {
                println!("cloth {size}² ({}): {too_large}", kind.name());
                continue;
            }
            Err(other) => return Err(gpu_error(other)),
        };
        let cpu_seconds = pool.install(|| cpu_seconds(&mut world, dt, least))?;
        let row = GpuRow {
            name: format!("cloth {size}²"),
            integrator: kind,
            particles: world.particles.len(),
            springs: world.springs.len(),
            gpu_seconds,
            cpu_seconds,
            evaluations: kind.evaluations_per_step(),
        };
        println!(
            "{:<16} {:<16} {:>9} {:>9} {:>11.4} {:>12.3e} {:>11.4} {:>12.3e} {:>8.2} {:>13.1}",
            row.name,
            row.integrator.name(),
            row.particles,
            row.springs,
            1e3 * row.gpu_seconds,
            row.spring_updates(row.gpu_seconds),
            1e3 * row.cpu_seconds,
            row.spring_updates(row.cpu_seconds),
            row.cpu_seconds / row.gpu_seconds,
            1.0 / (STEPS_PER_FRAME * row.gpu_seconds),
        );
        rows.push(row);
    }
    println!(
        "cpu: the engine on {} thread{}; gpu/cpu: how many times faster the GPU steps; frames/s: at {STEPS_PER_FRAME} steps a frame",
        pool.threads(),
        if pool.threads() == 1 { "" } else { "s" }
    );
    if let Some(path) = csv {
        let mut text = String::from(
            "case,integrator,particles,springs,gpu,precision,gpu_seconds_per_step,gpu_spring_updates_per_second,cpu_threads,cpu_seconds_per_step,cpu_spring_updates_per_second\n",
        );
        for row in &rows {
            text.push_str(&format!(
                "{},{},{},{},{},{},{:e},{:e},{},{:e},{:e}\n",
                row.name,
                row.integrator.name(),
                row.particles,
                row.springs,
                // The adapter's name and kind, its commas made semicolons.
                gpu.name().replace(',', ";"),
                precision,
                row.gpu_seconds,
                row.spring_updates(row.gpu_seconds),
                pool.threads(),
                row.cpu_seconds,
                row.spring_updates(row.cpu_seconds),
            ));
        }
        AtomicFile::write(path, text.as_bytes())
            .map_err(|e| CliError::Io(format!("cannot write {}: {e}", path.display())))?;
        println!("table written to {}", path.display());
    }
    Ok(())
}
