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
//! Velocity (docs/physics.md §6): the central difference
//! `v_n = (x⁺ - x⁻) / (2 dt)` is computed *before* the positions are
//! shifted. The textbook listing shifts first and always gets zero, which
//! silently removes damping and wind. Since the step ends at time `n + 1`,
//! the stored velocity is carried to that time, `v_{n+1} = v_n + a_n dt`
//! (second-order accurate), so energy is measured at one instant.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::state::{StateError, WorldState};
use crate::units::{Real, Vec3};

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
        let (x, v, a) = (position, velocity, &self.acceleration);
        let (written_x, written_v) = (&self.written_position, &self.written_velocity);
        parallel::for_each_span(&mut self.previous_position[..], |start, previous| {
            for (k, previous) in previous.iter_mut().enumerate() {
                let i = start + k;
                if everything {
                    *previous = x[i] - v[i] * dt + 0.5 * a[i] * dt * dt;
                } else if x[i] != written_x[i] || v[i] != written_v[i] {
                    let moved = x[i] - written_x[i];
                    let kicked = v[i] - written_v[i];
                    *previous += moved - kicked * dt;
                }
            }
        });
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
        let acceleration = &self.acceleration;
        let state = (
            position,
            velocity,
            &mut self.previous_position[..],
            &mut self.written_position[..],
            &mut self.written_velocity[..],
        );
        parallel::for_each_span(state, |start, (x, v, previous, written_x, written_v)| {
            for k in 0..x.len() {
                let a = acceleration[start + k];
                let next = 2.0 * x[k] - previous[k] + a * dt2;
                let central_velocity = (next - previous[k]) / (2.0 * dt);
                previous[k] = x[k];
                x[k] = next;
                v[k] = central_velocity + a * dt;
                written_x[k] = x[k];
                written_v[k] = v[k];
            }
        });
        Ok(StepReport::default())
    }

    fn save_history(&self, state: &mut WorldState) {
        state.put_vectors("verlet.previous_position", &self.previous_position);
        state.put_vectors("verlet.written_position", &self.written_position);
        state.put_vectors("verlet.written_velocity", &self.written_velocity);
        state.put("verlet.last_dt", vec![self.last_dt]);
    }

    fn restore_history(&mut self, state: &WorldState, particles: usize) -> Result<(), StateError> {
        // A run saved before its first step has no history yet.
        let started = state.get("verlet.last_dt", 1)?[0] > 0.0;
        let count = if started { particles } else { 0 };
        self.previous_position = state.get_vectors("verlet.previous_position", count)?;
        self.written_position = state.get_vectors("verlet.written_position", count)?;
        self.written_velocity = state.get_vectors("verlet.written_velocity", count)?;
        self.last_dt = state.get("verlet.last_dt", 1)?[0];
        Ok(())
    }
}
