//! Forces applied from outside the model: a controller's push on each
//! particle, held for the coming steps.

use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::units::{Real, Vec3};

/// A force (N) on each particle given from outside the simulation (a
/// controller, a user's script), constant over the steps it is set for:
/// `f_i += F_i`. Particles beyond the list get none; pinned particles
/// ignore it, as every force.
///
/// It has no potential (the work it does comes from outside, so the
/// energy columns do not include it) and no stiffness.
///
/// ```
/// use sprung::forces::AppliedForces;
/// use sprung::{BodyData, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// world.set_gravity(Vec3::ZERO);
/// world.add_body("puck", BodyData::from_positions(vec![Vec3::ZERO])).unwrap();
/// world.forces.set(AppliedForces { force: vec![Vec3::new(2.0, 0.0, 0.0)] });
/// world.step(0.5).unwrap();
/// // a = F / m = 2 m/s² (a 1 kg particle) for 0.5 s
/// assert_eq!(world.particles.velocity[0].x, 1.0);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct AppliedForces {
    /// The force on each particle (N), by particle index.
    pub force: Vec<Vec3>,
}

impl Force for AppliedForces {
    fn name(&self) -> &'static str {
        "applied forces"
    }

    fn accumulate(&mut self, _: &ForceContext, force: &mut [Vec3]) {
        for (f, applied) in force.iter_mut().zip(&self.force) {
            *f += *applied;
        }
    }

    /// A force that does not depend on the state: neither stiff nor
    /// damping.
    fn add_stiffness(&self, _: &ForceContext, _: &mut StiffnessBounds) {}

    /// Work from outside has no potential.
    fn energy_name(&self) -> Option<&'static str> {
        None
    }

    fn add_potential_energy(&self, _: &ForceContext, _: &mut Real) {}

    /// Independent of the state: both Jacobians are exactly zero.
    fn linearize(&mut self, _: &ForceContext) -> Linearization {
        Linearization::Zero
    }

    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }

    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}
