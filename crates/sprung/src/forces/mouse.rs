//! The user's hand (docs/physics.md §1, user forces): a damped spring between a
//! grabbed particle and the cursor, so a person can drag and throw a body.

use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::{Real, Vec3};

/// A spring of zero rest length from particle `particle` to `target`:
/// `f = k (target - x) - c v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MouseSpring {
    /// The grabbed particle.
    pub particle: usize,
    /// Where the cursor is (m).
    pub target: Vec3,
    /// Stiffness `k` (N/m).
    pub stiffness: Real,
    /// Damping `c` on the particle's velocity (N·s/m).
    pub damping: Real,
}

impl Force for MouseSpring {
    fn name(&self) -> &'static str {
        "mouse spring"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        if let (Some(f), Some(&x), Some(&v)) = (
            force.get_mut(self.particle),
            context.position.get(self.particle),
            context.velocity.get(self.particle),
        ) {
            *f += self.stiffness * (self.target - x) - self.damping * v;
        }
    }

    /// `c / m` on the grabbed particle's damping (its stiffness is left
    /// out: the hand is soft beside the springs it pulls).
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        if let (Some(rate), Some(w)) = (
            bounds.damping.get_mut(self.particle),
            context.inverse_mass.get(self.particle),
        ) {
            *rate += self.damping * w;
        }
    }

    /// The hand does work on the system: its spring is not counted as part
    /// of the system's energy.
    fn energy_name(&self) -> Option<&'static str> {
        None
    }

    fn add_potential_energy(&self, _: &ForceContext, _: &mut Real) {}

    /// `∂f/∂x = -k I`, `∂f/∂v = -c I` on the grabbed particle, exactly.
    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Exact
    }

    fn add_jacobian_products(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        if let (Some(o), Some(&p)) = (out.get_mut(self.particle), p.get(self.particle)) {
            *o -= self.diagonal(scale) * p;
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        if let Some(d) = diagonal.get_mut(self.particle) {
            *d -= Vec3::splat(self.diagonal(scale));
        }
    }
}

impl MouseSpring {
    /// `α k + β c`: minus the scaled Jacobians' (isotropic) diagonal.
    fn diagonal(&self, scale: JacobianScale) -> Real {
        scale.position * self.stiffness + scale.velocity * self.damping
    }
}
