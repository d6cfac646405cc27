//! Implicit (backward) Euler by Newton's method (docs/physics.md §6; Baraff and
//! Witkin, "Large steps in cloth simulation", SIGGRAPH 1998).
//!
//! Backward Euler asks for the velocity `v` at the end of the step with
//!
//! ```text
//! M (v - v_n) = dt f(x_n + dt v, v),      x = x_n + dt v.
//! ```
//!
//! Each Newton iteration linearises the forces at the iterate `(x_k, v_k)`
//! (`K = ∂f/∂x`, `D = ∂f/∂v`) and solves, for the correction `δ`,
//!
//! ```text
//! (M - dt D - dt² K) δ = dt f_k - M (v_k - v_n) + dt K (x_n + dt v_k - x_k)
//! ```
//!
//! by conjugate gradients, every force taken
//! at the end time `t_n + dt`. The first iteration starts at the state of
//! the step's start (`x_0 = x_n`, `v_0 = v_n`), where this is Baraff and Witkin's
//! linearised step `(M - dt D - dt² K) Δv = dt (f_n + dt K v_n)`; later
//! iterates satisfy `x_k = x_n + dt v_k`, so the last term vanishes and the
//! iteration is Newton's method on the equation above.
//! With `newton_iterations = 1` (the default) one linear solve per step.
//!
//! The preconditioner ([`Preconditioner`]) is the diagonal (Jacobi, the
//! default), or the factored matrix `M + dt² L` of the projective solver
//! (the springs' stiffness as if it acted in every direction): one
//! back-substitution per iteration, several times a product's cost, but
//! several times fewer iterations where the motion stretches the springs
//! (a cloth hanging in its plane); where it bends them (a cloth swinging
//! out of its plane), it gains less than it costs.
//! For linear forces (a spring moving along its axis) one iteration is
//! exact, and the energy of an oscillator shrinks by `1/(1 + ω² dt²)` per
//! step.
//!
//! Projection colliders are velocity constraints of the solve (see
//! [`ContactConstraint`](crate::colliders::ContactConstraint)): a particle reaching one has its normal velocity
//! prescribed, and its body answers within the same solve.
//!
//! Forces take part through their Jacobian products (see
//! [`Linearization`](crate::forces::Linearization)): springs with their
//! compressive part made definite, gas pressure and wind explicit. Pinned
//! particles are constraints of the solve (their velocity stays zero), not
//! large masses.

use super::cg::{jacobi, Operator};
use super::laplacian::{self, Factor};
use super::{mass_minus, HeldSolve, Preconditioner, SolverSettings};
use crate::error::SolverError;
use crate::forces::{JacobianScale, Jacobians};
use crate::integrate::{fit, Derivative, Integrator, IntegratorKind, State, StepReport};
use crate::parallel;
use crate::{Real, Vec3};

/// Backward Euler with its Newton and conjugate-gradient buffers.
#[derive(Debug, Default)]
pub struct ImplicitEuler {
    start_position: Vec<Vec3>,
    start_velocity: Vec<Vec3>,
    force: Vec<Vec3>,
    right_side: Vec<Vec3>,
    product: Vec<Vec3>,
    inverse_diagonal: Vec<Vec3>,
    correction: Vec<Vec3>,
    held: HeldSolve,
    /// The factored `M + dt² L` of the Laplacian preconditioner.
    factor: Option<Factor>,
}

/// The matrix `M - dt D - dt² K` at a state, with its preconditioner: the
/// inverse diagonal (Jacobi), or the factored `M + dt² L` of the springs.
struct NewtonMatrix<'a> {
    system: &'a dyn Derivative,
    state: State<'a>,
    scale: JacobianScale,
    inverse_diagonal: &'a [Vec3],
    factor: Option<&'a mut Factor>,
}

impl Operator for NewtonMatrix<'_> {
    fn apply(&mut self, p: &[Vec3], out: &mut [Vec3]) {
        self.system
            .jacobian_products(self.state, Jacobians::All, self.scale, p, out);
        mass_minus(self.system.mass(), p, out);
    }

    fn precondition(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        match self.factor.as_mut() {
            Some(f) => f.solve(r, z),
            None => jacobi(self.inverse_diagonal, r, z),
        }
    }
}

impl Integrator for ImplicitEuler {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::ImplicitEuler
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
        for buffer in [
            &mut self.start_position,
            &mut self.start_velocity,
            &mut self.force,
            &mut self.right_side,
            &mut self.product,
            &mut self.inverse_diagonal,
            &mut self.correction,
        ] {
            fit(buffer, n);
        }
        self.start_position.copy_from_slice(position);
        self.start_velocity.copy_from_slice(velocity);
        let start = State {
            time,
            position,
            velocity,
        };
        system.contact_constraints(start, dt, &mut self.held.contacts);
        let matrix_scale = JacobianScale {
            position: dt * dt,
            velocity: dt,
        };
        let mut report = StepReport {
            iterations: Some(0),
            ..StepReport::default()
        };
        // Backward Euler takes every force at the end time, where moving
        // colliders and the gas schedule have got to.
        let time = time + dt;
        for newton in 0..solver.newton_iterations {
            system.force(time, position, velocity, &mut self.force);
            let state = State {
                time,
                position,
                velocity,
            };
            system.linearize(state, Jacobians::All);
            let mass = system.mass();
            let (force, start_velocity, v) = (&self.force, &self.start_velocity, &*velocity);
            parallel::for_each_span(&mut self.right_side[..], |start, b| {
                for (k, b) in b.iter_mut().enumerate() {
                    let i = start + k;
                    *b = dt * force[i] - mass[i] * (v[i] - start_velocity[i]);
                }
            });
            if newton == 0 {
                // dt K (x_n + dt v_n - x_n) = dt² K v_n.
                let scale = JacobianScale {
                    position: dt * dt,
                    velocity: 0.0,
                };
                system.jacobian_products(
                    state,
                    Jacobians::All,
                    scale,
                    &self.start_velocity,
                    &mut self.product,
                );
                let product = &self.product;
                parallel::for_each_span(&mut self.right_side[..], |start, b| {
                    for (b, q) in b.iter_mut().zip(&product[start..]) {
                        *b += *q;
                    }
                });
            }
            system.jacobian_diagonal(
                state,
                Jacobians::All,
                matrix_scale,
                &mut self.inverse_diagonal,
            );
            parallel::for_each_span(&mut self.inverse_diagonal[..], |start, d| {
                for (d, &m) in d.iter_mut().zip(&mass[start..]) {
                    let entry = Vec3::splat(m) - *d;
                    *d = if entry.min_element() > 0.0 && entry.is_finite() {
                        entry.recip()
                    } else {
                        Vec3::splat(1.0 / m)
                    };
                }
            });
            let factor = match solver.preconditioner {
                Preconditioner::Jacobi => None,
                Preconditioner::Laplacian => {
                    Some(laplacian::refreshed(&mut self.factor, dt, &*system)?)
                }
            };
            let mut matrix = NewtonMatrix {
                system: &*system,
                state,
                scale: matrix_scale,
                inverse_diagonal: &self.inverse_diagonal,
                factor,
            };
            // The first iteration decides which contacts hold: those that
            // pulled are released and the system solved again.
            let v = &*velocity;
            self.held.solve(
                &mut matrix,
                (&self.right_side, &mut self.correction),
                (system.inverse_mass(), solver),
                newton == 0,
                |c| (c.normal_velocity() - v[c.particle].dot(c.normal)) * c.normal,
                &mut report,
            );
            for (c, &impulse) in self.held.contacts.iter_mut().zip(&self.held.impulses) {
                c.normal_change = impulse.max(0.0) / mass[c.particle];
            }
            let (correction, start_position) = (&self.correction, &self.start_position);
            parallel::for_each_span((&mut *position, &mut *velocity), |start, (x, v)| {
                for (k, (x, v)) in x.iter_mut().zip(v).enumerate() {
                    *v += correction[start + k];
                    *x = start_position[start + k] + dt * *v;
                }
            });
        }
        for c in &self.held.contacts {
            c.apply_friction(&mut velocity[c.particle]);
            position[c.particle] = self.start_position[c.particle] + dt * velocity[c.particle];
        }
        Ok(report)
    }
}
