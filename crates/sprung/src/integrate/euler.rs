//! Explicit (forward) Euler: `x += v dt; v += a dt`. Order 1; it gains
//! energy on every oscillator and is unstable for stiff springs. Kept for
//! teaching: it is the method that blows up.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// Explicit Euler with its acceleration buffer.
#[derive(Debug, Default)]
pub struct ExplicitEuler {
    acceleration: Vec<Vec3>,
}

impl Integrator for ExplicitEuler {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Euler
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
                *x += *v * dt;
                *v += *a * dt;
            }
        });
        Ok(StepReport::default())
    }
}
