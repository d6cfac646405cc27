//! Explicit midpoint method (RK2): evaluate the derivative at the half step
//! reached by an Euler step, then take the full step with it. Order 2.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// The midpoint method with its half-step buffers.
#[derive(Debug, Default)]
pub struct Midpoint {
    acceleration: Vec<Vec3>,
    half_position: Vec<Vec3>,
    half_velocity: Vec<Vec3>,
}

impl Integrator for Midpoint {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Midpoint
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
        let n = position.len();
        fit(&mut self.acceleration, n);
        fit(&mut self.half_position, n);
        fit(&mut self.half_velocity, n);
        let half = 0.5 * dt;
        system.acceleration(time, position, velocity, &mut self.acceleration);
        let (x, v, a) = (&*position, &*velocity, &self.acceleration);
        let halves = (&mut self.half_position[..], &mut self.half_velocity[..]);
        parallel::for_each_span(halves, |start, (half_x, half_v)| {
            for (k, (half_x, half_v)) in half_x.iter_mut().zip(half_v).enumerate() {
                let i = start + k;
                *half_x = x[i] + v[i] * half;
                *half_v = v[i] + a[i] * half;
            }
        });
        system.acceleration(
            time + half,
            &self.half_position,
            &self.half_velocity,
            &mut self.acceleration,
        );
        let (half_v, a) = (&self.half_velocity, &self.acceleration);
        parallel::for_each_span((position, velocity), |start, (x, v)| {
            for (k, (x, v)) in x.iter_mut().zip(v).enumerate() {
                *x += half_v[start + k] * dt;
                *v += a[start + k] * dt;
            }
        });
        Ok(StepReport::default())
    }
}
