//! Explicit midpoint method (RK2): evaluate the derivative at the half step
//! reached by an Euler step, then take the full step with it. Order 2.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::{Real, Vec3};

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
        for i in 0..n {
            self.half_position[i] = position[i] + velocity[i] * half;
            self.half_velocity[i] = velocity[i] + self.acceleration[i] * half;
        }
        system.acceleration(
            time + half,
            &self.half_position,
            &self.half_velocity,
            &mut self.acceleration,
        );
        for i in 0..n {
            position[i] += self.half_velocity[i] * dt;
            velocity[i] += self.acceleration[i] * dt;
        }
        Ok(StepReport::default())
    }
}
