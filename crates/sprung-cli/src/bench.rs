//! `sprung bench`: spring updates per second for one step of a square cloth
//! (structural, shear and bending springs) under each integrator.

use std::time::Instant;

use sprung::build::{self, ClothSprings};
use sprung::{IntegratorKind, World};

use crate::run::CliError;

/// Time `steps` steps of a `size × size` cloth with every integrator and
/// print a table.
pub fn run(size: usize, steps: u32) -> Result<(), CliError> {
    if steps == 0 {
        return Err(CliError::Input("--steps must be at least 1".into()));
    }
    let cloth = build::cloth(size, size, 1.0, 1.0, ClothSprings::default())
        .map_err(|e| CliError::Input(format!("--size {size}: {e}")))?
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.01)
        .with_pinned(vec![(size - 1) * size, size * size - 1]);
    let mut template = World::new(IntegratorKind::SymplecticEuler);
    template
        .add_body("cloth", cloth.clone())
        .map_err(|e| CliError::Input(e.to_string()))?;
    let dt = 0.5 * template.stable_time_step();
    println!(
        "cloth {size}×{size}: {} particles, {} springs, dt = {dt:.3e} s, {steps} steps per integrator, 1 thread",
        template.particles.len(),
        template.springs.len()
    );
    println!(
        "{:<18} {:>10} {:>14} {:>22}",
        "integrator", "evals/step", "steps/s", "spring updates/s"
    );
    for kind in IntegratorKind::ALL {
        let mut world = World::new(kind);
        world
            .add_body("cloth", cloth.clone())
            .map_err(|e| CliError::Input(e.to_string()))?;
        // One warm-up step sizes the integrator's buffers.
        let step = |world: &mut World| world.step(dt).map_err(|e| CliError::Input(e.to_string()));
        step(&mut world)?;
        let start = Instant::now();
        for _ in 0..steps {
            step(&mut world)?;
        }
        let seconds = start.elapsed().as_secs_f64();
        let steps_per_second = f64::from(steps) / seconds;
        let evaluations = kind.evaluations_per_step();
        let updates = steps_per_second * f64::from(evaluations) * world.springs.len() as f64;
        println!(
            "{:<18} {:>10} {:>14.1} {:>22.3e}",
            kind.name(),
            evaluations,
            steps_per_second,
            updates
        );
    }
    Ok(())
}
