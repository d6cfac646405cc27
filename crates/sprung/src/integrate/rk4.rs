//! Classic fourth-order Runge-Kutta: four derivative evaluations per step,
//! weighted 1, 2, 2, 1. Order 4: the most accurate per step, at four times
//! the cost of Euler.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// RK4 with its stage buffers: the trial state, the stage force and
/// the running weighted sums of the stage derivatives.
#[derive(Debug, Default)]
pub struct RungeKutta4 {
    trial_position: Vec<Vec3>,
    trial_velocity: Vec<Vec3>,
    stage_force: Vec<Vec3>,
    sum_velocity: Vec<Vec3>,
    sum_acceleration: Vec<Vec3>,
}

impl Integrator for RungeKutta4 {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Rk4
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
        for buffer in [
            &mut self.trial_position,
            &mut self.trial_velocity,
            &mut self.stage_force,
            &mut self.sum_velocity,
            &mut self.sum_acceleration,
        ] {
            fit(buffer, n);
        }
        self.trial_position.copy_from_slice(position);
        self.trial_velocity.copy_from_slice(velocity);
        self.sum_velocity.fill(Vec3::ZERO);
        self.sum_acceleration.fill(Vec3::ZERO);
        // Stage k: derivative at the trial state, added with its weight; the
        // next trial state is the start plus `next_offset * dt` times it.
        let stages = [
            (0.0, 1.0, 0.5),
            (0.5, 2.0, 0.5),
            (0.5, 2.0, 1.0),
            (1.0, 1.0, 0.0),
        ];
        for (time_offset, weight, next_offset) in stages {
            // The force, turned into the acceleration `f / m` in the pass
            // below (as `Derivative::acceleration` would, a pass earlier).
            system.force(
                time + time_offset * dt,
                &self.trial_position,
                &self.trial_velocity,
                &mut self.stage_force,
            );
            let (x, v, f) = (&*position, &*velocity, &self.stage_force);
            let inverse_mass = system.inverse_mass();
            let buffers = (
                &mut self.sum_velocity[..],
                &mut self.sum_acceleration[..],
                &mut self.trial_position[..],
                &mut self.trial_velocity[..],
            );
            parallel::for_each_span(buffers, |start, (sum_v, sum_a, trial_x, trial_v)| {
                for k in 0..sum_v.len() {
                    let i = start + k;
                    let (stage_velocity, stage_acceleration) = (trial_v[k], f[i] * inverse_mass[i]);
                    sum_v[k] += weight * stage_velocity;
                    sum_a[k] += weight * stage_acceleration;
                    trial_x[k] = x[i] + next_offset * dt * stage_velocity;
                    trial_v[k] = v[i] + next_offset * dt * stage_acceleration;
                }
            });
        }
        let sixth = dt / 6.0;
        let (sum_v, sum_a) = (&self.sum_velocity, &self.sum_acceleration);
        parallel::for_each_span((position, velocity), |start, (x, v)| {
            for (k, (x, v)) in x.iter_mut().zip(v).enumerate() {
                *x += sixth * sum_v[start + k];
                *v += sixth * sum_a[start + k];
            }
        });
        Ok(StepReport::default())
    }
}
