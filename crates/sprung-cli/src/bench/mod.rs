//! `sprung bench`: spring updates per second for one step of a square cloth
//! (structural, shear and bending springs) under each integrator, steps per
//! second of a gas-filled ball at 642 and 10 242 vertices, and the stiff
//! cloth under the implicit solvers ([`stiff_cloth`]), and contact between
//! bodies ([`contacts`]).

mod contacts;
mod stiff_cloth;

use std::time::Instant;

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::{Gas, IntegratorKind, Vec3, World};

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
    println!();
    gas_balls(steps)?;
    println!();
    stiff_cloth::run()?;
    println!();
    contacts::run()
}

/// Steps per second of a gas-filled icosphere at 642 and 10 242 vertices
/// (3 and 5 subdivisions), symplectic Euler: springs on every edge and
/// across every pair of triangles, pressure from the exact volume.
fn gas_balls(steps: u32) -> Result<(), CliError> {
    println!(
        "{:<30} {:>10} {:>10} {:>12} {:>20}",
        "gas ball, symplectic Euler", "particles", "springs", "steps/s", "pressure faces/s"
    );
    for subdivisions in [3, 5] {
        let mut ball = build::icosphere(1.0, subdivisions, SurfaceSprings::default())
            .map_err(|e| CliError::Input(e.to_string()))?
            .with_total_mass(1.0)
            .with_stiffness(1000.0)
            .with_damping(0.01);
        ball.gas = Some(Gas::new(100.0, 0.0));
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        world
            .add_body("ball", ball)
            .map_err(|e| CliError::Input(e.to_string()))?;
        let dt = 0.5 * world.stable_time_step();
        let step = |world: &mut World| world.step(dt).map_err(|e| CliError::Input(e.to_string()));
        step(&mut world)?;
        let start = Instant::now();
        for _ in 0..steps {
            step(&mut world)?;
        }
        let steps_per_second = f64::from(steps) / start.elapsed().as_secs_f64();
        let faces = world.bodies[0].faces.len() as f64;
        println!(
            "{:<30} {:>10} {:>10} {:>12.1} {:>20.3e}",
            format!("icosphere, {subdivisions} subdivisions"),
            world.particles.len(),
            world.springs.len(),
            steps_per_second,
            steps_per_second * faces
        );
    }
    Ok(())
}
