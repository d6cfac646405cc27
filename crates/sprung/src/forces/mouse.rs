//! The user's hand (docs/physics.md §1, user forces): a damped spring between a
//! grabbed particle and the cursor, so a person can drag and throw a body.

use super::jacobian::{add_isotropic_diagonal, add_isotropic_product};
use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::units::{Real, Vec3};

/// A spring of zero rest length from particle `particle` to `target`:
/// `f = k (target - x) - c v`.
///
/// ```
/// use sprung::forces::MouseSpring;
/// use sprung::{BodyData, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::ImplicitEuler);
/// world.set_gravity(Vec3::ZERO);
/// let ball = BodyData::from_positions(vec![Vec3::ZERO]).with_velocity(Vec3::X);
/// world.add_body("ball", ball).unwrap();
/// let target = Vec3::new(0.0, 2.0, 0.0);
/// let hand = MouseSpring { particle: 0, target, stiffness: 50.0, damping: 3.0 };
/// world.forces.push(Box::new(hand));
/// world.evaluate_forces();
/// assert_eq!(world.particles.force[0], Vec3::new(-3.0, 100.0, 0.0)); // k (target - x) - c v
/// // The cursor moves onto the particle: only the damping is left.
/// world.forces.get_mut::<MouseSpring>().unwrap().target = Vec3::ZERO;
/// world.evaluate_forces();
/// assert_eq!(world.particles.force[0], Vec3::new(-3.0, 0.0, 0.0));
/// ```
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
        let i = self.particle;
        if i < out.len().min(p.len()) {
            add_isotropic_product(self.coefficients(), scale, p, i, &mut out[i..=i]);
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        if let Some(d) = diagonal.get_mut(self.particle..=self.particle) {
            add_isotropic_diagonal(self.coefficients(), scale, d);
        }
    }
}

impl MouseSpring {
    /// Its stiffness `k` (N/m) and damping `c` (N·s/m): the isotropic
    /// Jacobians `-k I`, `-c I` on the grabbed particle.
    fn coefficients(&self) -> (Real, Real) {
        (self.stiffness, self.damping)
    }
}
