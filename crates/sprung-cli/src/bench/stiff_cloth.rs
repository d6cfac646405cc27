//! The stiff cloth of the implicit solvers (PHYSICS.md §6): particles of
//! 2 g joined by springs of 2·10⁴ N/m, hanging from two corners of its top
//! edge and swinging down from flat, stepped at the frame rate dt = 1/60 s
//! by `implicit_euler` and `projective`, against the explicit integrator
//! that costs least per simulated second at its largest stable step.

use std::time::Instant;

use sprung::build::{self, ClothSprings};
use sprung::integrate::Preconditioner;
use sprung::{IntegratorKind, Real, Vec3, World};

use crate::run::CliError;

/// The frame step the implicit solvers take (s).
const FRAME: Real = 1.0 / 60.0;

/// The stiff cloth of `size × size` particles (1 m square) for `kind`.
pub fn stiff_cloth(size: usize, kind: IntegratorKind) -> Result<World, CliError> {
    let cloth = build::cloth(size, size, 1.0, 1.0, ClothSprings::default())
        .map_err(|e| CliError::Input(format!("stiff cloth {size}: {e}")))?
        .with_mass(0.002)
        .with_stiffness(2e4)
        .with_damping(0.01)
        .with_pinned(vec![size * (size - 1), size * size - 1])
        .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
    let mut world = World::new(kind);
    world
        .add_body("cloth", cloth)
        .map_err(|e| CliError::Input(e.to_string()))?;
    Ok(world)
}

/// Wall-clock seconds per step of `world` at `dt`, over `steps` steps after
/// `warm_up` untimed ones (which size the buffers and, for the projective
/// solver, factor the matrix).
fn seconds_per_step(
    world: &mut World,
    dt: Real,
    warm_up: u32,
    steps: u32,
) -> Result<Real, CliError> {
    let step = |world: &mut World| {
        world
            .step(dt)
            .map(|_| ())
            .map_err(|e| CliError::Input(format!("bench: {e}")))
    };
    for _ in 0..warm_up {
        step(world)?;
    }
    let start = Instant::now();
    for _ in 0..steps {
        step(world)?;
    }
    Ok(start.elapsed().as_secs_f64() / Real::from(steps))
}

/// Time the stiff cloth at 64², Liu et al.'s 81² and 128² with both implicit
/// solvers at 1/60 s and with symplectic Euler at its stable step, and print
/// the cost per step and the simulated seconds per wall-clock second.
pub fn run() -> Result<(), CliError> {
    println!(
        "stiff cloth (2 g particles, 2e4 N/m springs, swinging down from flat), 1 thread; frame step 1/60 s"
    );
    println!(
        "{:<9} {:>9} {:>8}  {:<18} {:>10} {:>11} {:>12} {:>12}",
        "size", "particles", "springs", "integrator", "dt (s)", "ms/step", "ms/frame", "sim s / s"
    );
    for size in [64, 81, 128] {
        // The explicit reference: symplectic Euler (the cheapest stable
        // explicit method per step) at the Gershgorin stable step, which
        // `sprung study stability` finds within a few % of the true limit
        // on this cloth.
        let mut explicit = stiff_cloth(size, IntegratorKind::SymplecticEuler)?;
        let stable = explicit.stable_time_step();
        let explicit_step = seconds_per_step(&mut explicit, stable, 5, 200)?;
        let explicit_frame = explicit_step * FRAME / stable;
        let label = format!("{size}×{size}");
        let (particles, springs) = (explicit.particles.len(), explicit.springs.len());
        let mut rows = vec![("symplectic_euler", stable, explicit_step)];
        for (name, kind, preconditioner) in [
            (
                "implicit_euler",
                IntegratorKind::ImplicitEuler,
                Preconditioner::Jacobi,
            ),
            (
                "  laplacian pc.",
                IntegratorKind::ImplicitEuler,
                Preconditioner::Laplacian,
            ),
            (
                "projective",
                IntegratorKind::Projective,
                Preconditioner::Jacobi,
            ),
        ] {
            let mut world = stiff_cloth(size, kind)?;
            world.settings.solver.preconditioner = preconditioner;
            let steps = if size > 64 { 10 } else { 30 };
            rows.push((name, FRAME, seconds_per_step(&mut world, FRAME, 3, steps)?));
        }
        for (name, dt, per_step) in rows {
            let per_frame = per_step * FRAME / dt;
            let ratio = if dt == FRAME {
                format!("  {:.1}× explicit", explicit_frame / per_frame)
            } else {
                String::new()
            };
            println!(
                "{:<9} {:>9} {:>8}  {:<18} {:>10.3e} {:>11.3} {:>12.3} {:>12.2}{ratio}",
                label,
                particles,
                springs,
                name,
                dt,
                per_step * 1e3,
                per_frame * 1e3,
                FRAME / per_frame
            );
        }
    }
    Ok(())
}
