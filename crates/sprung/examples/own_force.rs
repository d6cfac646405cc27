//! A force of one's own: a magnet under the end of a hanging rope.
//!
//! Shows: implementing `Force` (the force, its share of the stable step,
//! its energy under its own name, its Jacobians for the implicit solvers),
//! `world.forces.push`, and what the world makes of it: the stable step
//! shrinks as the magnet stiffens; `energies()` has a "magnet" term.
//!
//!     cargo run --release -p sprung --example own_force

use sprung::prelude::*;

/// Pulls particle `particle` towards the plane y = `level` like a spring
/// of stiffness `k` (N/m) along y: f = -k (y - level) ŷ, energy ½ k (y - level)².
#[derive(Debug)]
struct Magnet {
    particle: usize,
    level: Real,
    k: Real,
}

impl Force for Magnet {
    fn name(&self) -> &'static str {
        "magnet"
    }
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        force[self.particle].y -= self.k * (context.position[self.particle].y - self.level);
    }
    // K = -∂f/∂x is k in one yy entry: k/m on the stable-step bound.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        bounds.stiffness[self.particle] += self.k * context.inverse_mass[self.particle];
    }
    fn energy_name(&self) -> Option<&'static str> {
        Some("magnet")
    }
    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        *energy += 0.5 * self.k * (context.position[self.particle].y - self.level).powi(2);
    }
    fn linearize(&mut self, _: &ForceContext) -> Linearization {
        Linearization::Exact
    }
    // ∂f/∂x·p = -k p_y ŷ on the particle; the force has no ∂f/∂v.
    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        out[self.particle].y -= scale.position * self.k * p[self.particle].y;
    }
    fn add_jacobian_diagonal(&self, _: &ForceContext, scale: JacobianScale, diagonal: &mut [Vec3]) {
        diagonal[self.particle].y -= scale.position * self.k;
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!("   k (N/m)  stable dt (s)    end y (m)   magnet (J)");
    let mut steps = Vec::new();
    for k in [0.0, 10.0, 1000.0] {
        let mut world = World::new(IntegratorKind::ImplicitEuler);
        let rope = build::rope(10, 1.0)?
            .with_total_mass(0.1)
            .with_stiffness(50.0);
        world.add_body("rope", rope)?;
        let magnet = Magnet {
            particle: 9,
            level: -2.0,
            k,
        };
        world.forces.push(Box::new(magnet));
        let stable = world.stable_time_step();
        steps.push(stable);
        // Implicit Euler (the Jacobians) takes 10 ms steps, stable or not.
        for _ in 0..200 {
            world.step(0.01)?;
        }
        let end = world.particles.position[9].y;
        let energy = world.energies().get("magnet").expect("its own term");
        println!("{k:>10} {stable:>14.3e} {end:>12.3} {energy:>12.4}");
    }
    // A stiff magnet shortens the stable step of the explicit methods.
    assert!(steps[2] < steps[1] && steps[1] <= steps[0]);
    Ok(())
}
