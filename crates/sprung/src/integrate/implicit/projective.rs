//! The fast mass-spring solver (Liu, Bargteil, O'Brien and Kavan, "Fast
//! simulation of mass-spring systems", SIGGRAPH Asia 2013): backward Euler
//! by local/global iterations over a matrix that does not change.
//!
//! Backward Euler is the minimum of
//! `g(x) = 1/(2 dt²) (x - y)ᵀ M (x - y) + E(x)`, `y = x_n + dt v_n`. Each
//! spring's energy `½ k (|x_i - x_j| - L0)²` is the least, over vectors `d`
//! of length `L0`, of `½ k |x_i - x_j - d|²`: the **local step** projects
//! each spring onto its rest length (`d = L0 t`), the **global step** solves
//! the linear system `(M + dt² L) x = M y + dt² J d`, with `L = Σ k A Aᵀ`
//! the stiffness-weighted graph Laplacian of the springs. That matrix is
//! the same at every iteration and every step while springs, masses, pins
//! and `dt` stay, so it is factored once by a sparse Cholesky decomposition
//! (faer) and each iteration is one forward and back substitution.
//!
//! **Every other force.** Since `L x - J d(x) = -f_springs(x)` (the elastic
//! spring force), the iteration can be written with the world's whole force
//! list. Backward Euler is `F(x) = M (x - y) - dt² f(x, v) = 0` with
//! `v = (x - x_n) / dt`, and Liu et al.'s iteration is the correction
//! `x_{k+1} = x_k + δ`, `(M + dt² L) δ = M (y - x_k) + dt² f(x_k, v_k)`:
//! `M + dt² L` stands in for the Jacobian of `F`. For springs alone this is
//! exactly the local/global iteration (the projection onto the rest length
//! happens inside the spring force). Forces that are not springs can be
//! much stiffer than `M / dt²` (a penalty floor), and a fixed-point
//! iteration on them diverges, so their Jacobians join the matrix:
//! `(M + dt² L - dt² K_o - dt D_o) δ = M (y - x_k) + dt² f(x_k, v_k)`, with
//! `K_o`, `D_o` the Jacobians of every force but the springs (see
//! [`Jacobians::AllButSprings`]). That system is solved by conjugate
//! gradients preconditioned with the factored `M + dt² L`; when the other
//! forces have no Jacobian products (gravity, wind, contacts with nothing
//! touching) and no projection collider holds a particle, the matrix is
//! the factored one and the solve is one substitution, as in the paper;
//! penalty contacts and the gas add a few CG iterations. A converged iteration is the exact backward-Euler step for every
//! force. The correction is small next to the positions, so its round-off
//! is too, and since the internal forces and the rows of `L` sum to zero,
//! the step conserves momentum.
//!
//! Projection colliders are constraints of each global solve (see
//! [`ContactConstraint`](crate::colliders::ContactConstraint)): a particle reaching one has its end position
//! along the normal prescribed. Pinned particles are left out of the unknowns (their rows and columns
//! removed, their springs' pull on free particles kept), not given large
//! masses. The iteration starts from the inertial guess `y` and takes a
//! fixed number of iterations (`iterations`, default 10), as in the paper.

use super::cg::Operator;
use super::laplacian::{self, Factor};
use super::{finite_difference, mass_minus, HeldSolve, SolverSettings};
use crate::error::SolverError;
use crate::forces::{JacobianScale, Jacobians};
use crate::integrate::{fit, Derivative, Integrator, IntegratorKind, State, StepReport};
use crate::parallel;
use crate::units::{Real, Vec3};

/// The projective solver with its factored matrix and buffers.
#[derive(Debug, Default)]
pub struct Projective {
    factor: Option<Factor>,
    start_position: Vec<Vec3>,
    inertial: Vec<Vec3>,
    force: Vec<Vec3>,
    residual: Vec<Vec3>,
    correction: Vec<Vec3>,
    held: HeldSolve,
}

/// The global step's matrix `M + dt² L - dt² K_o - dt D_o` at a state,
/// preconditioned by the factored `M + dt² L`.
struct GlobalMatrix<'a> {
    system: &'a dyn Derivative,
    state: State<'a>,
    factor: &'a mut Factor,
    dt: Real,
}

impl Operator for GlobalMatrix<'_> {
    fn apply(&mut self, p: &[Vec3], out: &mut [Vec3]) {
        let dt = self.dt;
        let scale = JacobianScale {
            position: dt * dt,
            velocity: dt,
        };
        self.system
            .jacobian_products(self.state, Jacobians::AllButSprings, scale, p, out);
        mass_minus(self.system.mass(), p, out);
        self.factor
            .add_laplacian_product(self.system.springs(), dt * dt, p, out);
    }

    fn precondition(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        self.factor.solve(r, z);
    }
}

impl Integrator for Projective {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Projective
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
            &mut self.inertial,
            &mut self.force,
            &mut self.residual,
            &mut self.correction,
        ] {
            fit(buffer, n);
        }
        let factor = laplacian::refreshed(&mut self.factor, dt, system)?;
        let start = State {
            time,
            position,
            velocity,
        };
        system.contact_constraints(start, dt, &mut self.held.contacts);
        self.start_position.copy_from_slice(position);
        let v = &*velocity;
        parallel::for_each_span((&mut *position, &mut self.inertial[..]), |start, (x, y)| {
            for (k, (x, y)) in x.iter_mut().zip(y).enumerate() {
                *y = *x + dt * v[start + k];
                *x = *y;
            }
        });
        let mut report = StepReport {
            iterations: Some(solver.iterations),
            residual: Some(0.0),
            ..StepReport::default()
        };
        let time = time + dt;
        let scale = super::step_scale(&*system, dt, 2);
        for iteration in 0..solver.iterations {
            // Asked to stop (`crate::interrupt`): the iterate so far.
            if iteration > 0 && crate::interrupt::requested() {
                report.iterations = Some(iteration);
                report.unconverged = true;
                break;
            }
            finite_difference(position, &self.start_position, dt, velocity);
            system.force(time, position, velocity, &mut self.force);
            let mass = system.mass();
            let (inertial, force, x) = (&self.inertial, &self.force, &*position);
            parallel::for_each_span(&mut self.residual[..], |start, r| {
                for (k, r) in r.iter_mut().enumerate() {
                    let i = start + k;
                    *r = mass[i] * (inertial[i] - x[i]) + dt * dt * force[i];
                }
            });
            let state = State {
                time,
                position,
                velocity,
            };
            let others = system.linearize(state, Jacobians::AllButSprings);
            let mass = system.mass();
            if !others.has_products() && self.held.contacts.is_empty() {
                // The matrix is the factored `M + dt² L` itself: one
                // substitution solves it, exactly to rounding.
                factor.solve(&self.residual, &mut self.correction);
                report.residual = Some(0.0);
                add_correction(position, &self.correction);
                continue;
            }
            let mut matrix = GlobalMatrix {
                system: &*system,
                state,
                factor: &mut *factor,
                dt,
            };
            // The first iteration decides which contacts hold: those that
            // pulled are released and the system solved again.
            let (x, start_position) = (&*position, &self.start_position);
            let mut counted = StepReport::default();
            self.held.solve(
                &mut matrix,
                (&self.residual, &mut self.correction),
                (system.inverse_mass(), solver, scale),
                iteration == 0,
                |c| {
                    let i = c.particle;
                    let reached = start_position[i] + dt * c.normal_velocity() * c.normal;
                    (reached - x[i]).dot(c.normal) * c.normal
                },
                &mut counted,
            );
            report.residual = counted.residual;
            report.unconverged |= counted.unconverged;
            // The impulse of a position-level solve is in kg·m: over m dt,
            // the velocity change.
            for (c, &impulse) in self.held.contacts.iter_mut().zip(&self.held.impulses) {
                c.normal_change = impulse.max(0.0) / (mass[c.particle] * dt);
            }
            add_correction(position, &self.correction);
        }
        finite_difference(position, &self.start_position, dt, velocity);
        for c in &self.held.contacts {
            let i = c.particle;
            c.apply_friction(&mut velocity[i]);
            position[i] = self.start_position[i] + dt * velocity[i];
        }
        Ok(report)
    }
}

/// `x += δ` over particle vectors.
fn add_correction(position: &mut [Vec3], correction: &[Vec3]) {
    parallel::for_each_span(position, |start, x| {
        for (x, d) in x.iter_mut().zip(&correction[start..]) {
            *x += *d;
        }
    });
}
