//! Semi-implicit (symplectic) Euler: `v += a dt; x += v dt`. Order 1, but
//! symplectic: the energy error stays bounded instead of drifting.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::{Real, Vec3};

/// Symplectic Euler with its acceleration buffer.
#[derive(Debug, Default)]
pub struct SymplecticEuler {
    acceleration: Vec<Vec3>,
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
        fit(&mut self.acceleration, position.len());
        system.acceleration(time, position, velocity, &mut self.acceleration);
        let acceleration = &self.acceleration;
        parallel::for_each_span((position, velocity), |start, (x, v)| {
            for ((x, v), a) in x.iter_mut().zip(v).zip(&acceleration[start..]) {
                *v += *a * dt;
                *x += *v * dt;
            }
        });
        Ok(StepReport::default())
    }
}
