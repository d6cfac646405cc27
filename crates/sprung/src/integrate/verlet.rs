//! Position (Störmer) Verlet: `x⁺ = 2x - x⁻ + a dt²`. Order 2, symplectic.
//!
//! The method keeps the previous positions `x⁻`. It is bootstrapped with a
//! Taylor step `x⁻ = x - v dt + ½ a dt²` on its first step and after a
//! change of `dt` (a switch from another integrator on a running world
//! starts this way). A particle whose position or velocity was changed from
//! outside since the last step (by `Δx` and `Δv`: a collision, friction, a
//! user's drag) keeps its history, shifted: `x⁻ += Δx - Δv dt`, so the next
//! step carries exactly the change in position and in velocity. A fresh
//! Taylor step instead would break the momentum balance between particles
//! changed and not changed.
//!
//! Velocity (PHYSICS.md §6): the central difference
//! `v_n = (x⁺ - x⁻) / (2 dt)` is computed *before* the positions are
//! shifted. The textbook listing shifts first and always gets zero, which
//! silently removes damping and wind. Since the step ends at time `n + 1`,
//! the stored velocity is carried to that time, `v_{n+1} = v_n + a_n dt`
//! (second-order accurate), so energy is measured at one instant.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::{Real, Vec3};

/// Position Verlet with its previous positions and the state it last wrote.
#[derive(Debug, Default)]
pub struct Verlet {
    acceleration: Vec<Vec3>,
    previous_position: Vec<Vec3>,
    written_position: Vec<Vec3>,
    written_velocity: Vec<Vec3>,
    last_dt: Real,
}

impl Verlet {
    /// Derive `x⁻` by a Taylor step for every particle on the first step
    /// and after a change of `dt`; shift it by the outside change for a
    /// particle whose state is not the one this integrator wrote.
    fn bootstrap(&mut self, dt: Real, position: &[Vec3], velocity: &[Vec3]) {
        let n = position.len();
        let everything = self.last_dt != dt || self.written_position.len() != n;
        fit(&mut self.previous_position, n);
        fit(&mut self.written_position, n);
        fit(&mut self.written_velocity, n);
        for i in 0..n {
            if everything {
                self.previous_position[i] =
                    position[i] - velocity[i] * dt + 0.5 * self.acceleration[i] * dt * dt;
            } else if position[i] != self.written_position[i]
                || velocity[i] != self.written_velocity[i]
            {
                let moved = position[i] - self.written_position[i];
                let kicked = velocity[i] - self.written_velocity[i];
                self.previous_position[i] += moved - kicked * dt;
            }
        }
        self.last_dt = dt;
    }
}

impl Integrator for Verlet {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Verlet
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
        self.bootstrap(dt, position, velocity);
        let dt2 = dt * dt;
        for i in 0..position.len() {
            let a = self.acceleration[i];
            let next = 2.0 * position[i] - self.previous_position[i] + a * dt2;
            let central_velocity = (next - self.previous_position[i]) / (2.0 * dt);
            self.previous_position[i] = position[i];
            position[i] = next;
            velocity[i] = central_velocity + a * dt;
            self.written_position[i] = position[i];
            self.written_velocity[i] = velocity[i];
        }
        Ok(StepReport::default())
    }
}
