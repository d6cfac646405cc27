//! Every integrator on one oscillator: energy drift against cost.
//!
//! Shows: `IntegratorKind::ALL`, the world's energy (`energies().total()`)
//! and its profile (`set_profiling`, `profile()`) counting the passes over
//! the forces each method pays for its accuracy (force evaluations, and
//! for the implicit methods their Jacobian products too).
//!
//! A 1 kg mass on a spring of 4π² N/m (a period of 1 s), released 0.2 m
//! from rest, run for 20 periods at 50 steps a period.
//!
//!     cargo run --release -p sprung --example integrators

use sprung::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (dt, steps) = (0.02, 1000);
    println!(
        "{:<17} {:>5} {:>13} {:>12} {:>10}",
        "integrator", "order", "E(20 s)/E(0)", "force passes", "wall (ms)"
    );
    for kind in IntegratorKind::ALL {
        let mut world = World::new(kind);
        world.set_gravity(Vec3::ZERO);
        // The anchor at the origin, pinned; the mass 1.2 m out, 1 m at rest.
        let mut oscillator =
            BodyData::from_positions(vec![Vec3::ZERO, 1.2 * Vec3::X]).with_pinned(vec![0]);
        oscillator.springs.push(SpringData {
            rest_length: Some(1.0),
            stiffness: 4.0 * std::f64::consts::PI.powi(2),
            ..SpringData::between(0, 1)
        });
        world.add_body("oscillator", oscillator)?;

        let start = world.energies().total();
        world.set_profiling(true);
        for _ in 0..steps {
            world.step(dt)?;
        }
        let profile = world.profile();
        let ratio = world.energies().total() / start;
        // Explicit Euler's energy grows by millions: shown in powers of ten.
        let shown = if ratio < 1e3 {
            format!("{ratio:.4}")
        } else {
            format!("{ratio:.1e}")
        };
        println!(
            "{:<17} {:>5} {shown:>13} {:>12} {:>10.2}",
            kind.name(),
            kind.order(),
            profile.calls(Stage::Forces),
            1e3 * profile.wall().as_secs_f64()
        );
        // The textbook's claims: explicit Euler gains energy, implicit
        // Euler loses it, RK4 and Verlet keep it.
        match kind {
            IntegratorKind::Euler => assert!(ratio > 2.0, "{ratio}"),
            IntegratorKind::ImplicitEuler => assert!(ratio < 0.5, "{ratio}"),
            IntegratorKind::Rk4 | IntegratorKind::Verlet => {
                assert!((ratio - 1.0).abs() < 1e-3, "{kind}: {ratio}")
            }
            _ => {}
        }
    }
    Ok(())
}
