//! Semi-implicit (symplectic) Euler: `v += a dt; x += v dt`. Order 1, but
//! symplectic: the energy error stays bounded instead of drifting.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// Symplectic Euler with its force buffer.
#[derive(Debug, Default)]
pub struct SymplecticEuler {
    /// The force at the start of the step (N).
    force: Vec<Vec3>,
}

impl Integrator for SymplecticEuler {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::SymplecticEuler
    }

    fn step(
        &mut self,
        time: Real,
        dt: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        system: &mut dyn Derivative,
        _solver: &SolverSettings,
    ) -> Result<StepReport, SolverError> {
        fit(&mut self.force, position.len());
        system.force(time, position, velocity, &mut self.force);
        // `a = f / m` is taken in the same pass as the update, rather than
        // in a pass of its own (`Derivative::acceleration`): the same
        // products, one pass over the particles fewer.
        let (force, inverse_mass) = (&self.force, system.inverse_mass());
        parallel::for_each_span((position, velocity), |start, (x, v)| {
            advance(x, v, &force[start..], &inverse_mass[start..], dt);
        });
        Ok(StepReport::default())
    }
}

vectorised! {
    /// `v += f w dt; x += v dt` over a span of particles.
    fn advance(x: &mut [Vec3], v: &mut [Vec3], force: &[Vec3], inverse_mass: &[Real], dt: Real) {
        let particles = x.iter_mut().zip(v);
        for ((x, v), (&f, &w)) in particles.zip(force.iter().zip(inverse_mass)) {
            *v += f * w * dt;
            *x += *v * dt;
        }
    }
}
