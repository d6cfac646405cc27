//! Adaptive Runge–Kutta: the embedded Dormand–Prince 5(4) pair (Dormand
//! and Prince, "A family of embedded Runge-Kutta formulae", J. Comput.
//! Appl. Math. 6, 1980). Seven stages give a fifth-order step and a
//! fourth-order one; their difference estimates the error, and each step
//! of the world is covered by as many internal steps as keep that estimate
//! within `error_tolerance`: short ones through a fast event (a bounce, a
//! close pass), long ones through slow motion. The last stage of an
//! accepted step is the first of the next ("first same as last"), so an
//! internal step costs six force evaluations.
//!
//! Error measure: the largest over particles and components of
//! `|x₅ - x₄| / (tol (1 m + |x|))` and `|v₅ - v₄| / (tol (1 m/s + |v|))`,
//! so `error_tolerance` is a relative error above 1 m or 1 m/s and an
//! absolute one (m, m/s) below. A step is accepted when that is at most 1;
//! the next step is `0.9 err^(-1/5)` times longer, between 0.2 and 5 times.

use super::{fit, Derivative, Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::error::SolverError;
use crate::parallel;
use crate::state::{StateError, WorldState};
use crate::units::{Real, Vec3};

/// Dormand–Prince coefficients `a[i][j]` (stage `i` from stages `j < i`).
const A: [[Real; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];

/// The stage times `c[i]` (fractions of the step).
const C: [Real; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];

/// Fifth-order weights minus fourth-order weights: the error estimate.
const E: [Real; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// Most internal steps in one step of the world before giving up.
const MAX_STEPS: u32 = 1_000_000;

/// The Dormand–Prince integrator with its stages and the step size it
/// chose last.
#[derive(Debug, Default)]
pub struct RungeKutta45 {
    /// Stage velocities and accelerations.
    stage_velocity: [Vec<Vec3>; 7],
    stage_acceleration: [Vec<Vec3>; 7],
    trial_position: Vec<Vec3>,
    trial_velocity: Vec<Vec3>,
    /// The internal step to try first (s); 0 before the first step.
    next_step: Real,
}

impl RungeKutta45 {
    /// Stage `stage`'s trial state from the start `(x, v)` and step `h`.
    fn trial(&mut self, stage: usize, h: Real, x: &[Vec3], v: &[Vec3]) {
        let (stage_v, stage_a) = (&self.stage_velocity, &self.stage_acceleration);
        let trial = (&mut self.trial_position[..], &mut self.trial_velocity[..]);
        parallel::for_each_span(trial, |start, (trial_x, trial_v)| {
            for k in 0..trial_x.len() {
                let i = start + k;
                let (mut dx, mut dv) = (Vec3::ZERO, Vec3::ZERO);
                for (j, &a) in A[stage].iter().enumerate().take(stage) {
                    if a != 0.0 {
                        dx += a * stage_v[j][i];
                        dv += a * stage_a[j][i];
                    }
                }
                trial_x[k] = x[i] + h * dx;
                trial_v[k] = v[i] + h * dv;
            }
        });
    }
}

impl Integrator for RungeKutta45 {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Rk45
    }

    fn step(
        &mut self,
        time: Real,
        dt: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        system: &mut dyn Derivative,
        solver: &SolverSettings,
    ) -> Result<StepReport, SolverError> {
        let n = position.len();
        for buffer in self
            .stage_velocity
            .iter_mut()
            .chain(self.stage_acceleration.iter_mut())
            .chain([&mut self.trial_position, &mut self.trial_velocity])
        {
            fit(buffer, n);
        }
        let tolerance = solver.error_tolerance;
        // The step the controller proposes; the first ever is the whole step.
        let mut proposed = if self.next_step > 0.0 {
            self.next_step
        } else {
            dt
        };
        let (mut done, mut accepted, mut attempts) = (0.0, 0, 0);
        let mut last = proposed;
        // The first stage at the start; afterwards the last stage of the
        // accepted step.
        self.stage_velocity[0].copy_from_slice(velocity);
        system.acceleration(time, position, velocity, &mut self.stage_acceleration[0]);
        while done < dt {
            attempts += 1;
            if attempts > MAX_STEPS || proposed <= dt * 1e-12 {
                return Err(SolverError::StepTooSmall { step: proposed });
            }
            let remaining = dt - done;
            let finishing = proposed >= remaining * (1.0 - 1e-12);
            let h = if finishing { remaining } else { proposed };
            for (stage, &c) in C.iter().enumerate().skip(1) {
                self.trial(stage, h, position, velocity);
                self.stage_velocity[stage].copy_from_slice(&self.trial_velocity);
                system.acceleration(
                    time + done + c * h,
                    &self.trial_position,
                    &self.trial_velocity,
                    &mut self.stage_acceleration[stage],
                );
            }
            // The fifth-order solution is stage 7's trial state.
            let (stage_v, stage_a) = (&self.stage_velocity, &self.stage_acceleration);
            let (trial_x, trial_v) = (&self.trial_position, &self.trial_velocity);
            let (x, v) = (&*position, &*velocity);
            let error = parallel::max(n, |range| {
                let mut error: Real = 0.0;
                for i in range {
                    let (mut ex, mut ev) = (Vec3::ZERO, Vec3::ZERO);
                    for (j, &e) in E.iter().enumerate() {
                        ex += e * stage_v[j][i];
                        ev += e * stage_a[j][i];
                    }
                    let scale_x = tolerance * (1.0 + x[i].abs().max(trial_x[i].abs()));
                    let scale_v = tolerance * (1.0 + v[i].abs().max(trial_v[i].abs()));
                    error = error.max(((h * ex) / scale_x).abs().max_element());
                    error = error.max(((h * ev) / scale_v).abs().max_element());
                }
                error
            });
            if !error.is_finite() {
                // A trial state that overflowed: retry much shorter.
                proposed = 0.1 * h;
                continue;
            }
            let factor = if error > 0.0 {
                (0.9 * error.powf(-0.2)).clamp(0.2, 5.0)
            } else {
                5.0
            };
            if error <= 1.0 {
                position.copy_from_slice(&self.trial_position);
                velocity.copy_from_slice(&self.trial_velocity);
                done = if finishing { dt } else { done + h };
                accepted += 1;
                last = h;
                // First same as last.
                self.stage_velocity.swap(0, 6);
                self.stage_acceleration.swap(0, 6);
                // A last step cut short to end on the world's step says
                // nothing against the longer one proposed.
                proposed = if finishing && h < proposed {
                    (h * factor).max(proposed)
                } else {
                    h * factor
                };
            } else {
                proposed = h * factor;
            }
        }
        self.next_step = proposed;
        Ok(StepReport {
            substeps: Some(accepted),
            step_size: Some(last),
            ..StepReport::default()
        })
    }
    fn save_history(&self, state: &mut WorldState) {
        state.put("rk45.next_step", vec![self.next_step]);
    }

    fn restore_history(&mut self, state: &WorldState, _particles: usize) -> Result<(), StateError> {
        self.next_step = state.get("rk45.next_step", 1)?[0];
        Ok(())
    }
}
