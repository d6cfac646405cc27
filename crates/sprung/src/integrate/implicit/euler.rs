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
//! The preconditioner ([`Preconditioner`]) is the diagonal (Jacobi); the
//! factored matrix `M + dt² L` of the projective solver (the springs'
//! stiffness as if it acted in every direction): one back-substitution per
//! iteration, several times a product's cost, but several times fewer
//! iterations where the motion stretches the springs (a cloth hanging in
//! its plane), while where it bends them (a cloth swinging out of its
//! plane) it gains less than it costs; or the springs' own Newton matrix,
//! factored each step (`stiffness.rs`): one iteration for a world of
//! springs, whatever their directions. The default, auto, tries Jacobi
//! within the iterations a factored step costs and takes the factor from
//! the first solve that needs more (that solve is done again with it).
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
use super::stiffness::{self, StiffnessFactor};
use super::{mass_minus, HeldSolve, Preconditioner, SolverSettings};
use crate::colliders::ContactConstraint;
use crate::error::SolverError;
use crate::forces::{JacobianScale, Jacobians};
use crate::integrate::{fit, Derivative, Integrator, IntegratorKind, State, StepReport};
use crate::parallel;
use crate::springs::Springs;
use crate::state::{StateError, WorldState};
use crate::units::{Real, Vec3};

/// The name of the auto preconditioner's choice in a saved state.
const FACTORED: &str = "implicit_euler.factored";
/// The name of its kept factor's step and positions in a saved state:
/// `dt` (s), then x, y, z (m) per particle.
const FACTORED_AT: &str = "implicit_euler.factored_at";
/// The name of the kept factor's back-off in a saved state: the steps to
/// factor without trying the kept factor, and the span of the next wait.
const BACKOFF: &str = "implicit_euler.backoff";
/// The name of the springs' rest lengths (m), stiffness (N/m) and damping
/// (N·s/m) the kept factor was made with, in a saved state (muscles and
/// yielding change them after).
const FACTORED_SPRINGS: &str = "implicit_euler.factored_springs";

/// The longest wait, in steps, before the kept factor is tried again.
const LONGEST_WAIT: u32 = 16;

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
    /// The factored springs' Newton matrix of the stiffness preconditioner.
    stiffness: Option<StiffnessFactor>,
    /// Where the auto preconditioner's kept stiffness factor was made: the
    /// step (s) and the positions (m) it was factored at; no positions
    /// while it has none (Jacobi until a solve needs more).
    factored_at: (Real, Vec<Vec3>),
    /// The springs' rest lengths, stiffness and damping it was made with,
    /// one after the other.
    factored_springs: Vec<Real>,
    /// The kept factor is to be made again at `factored_at` before it is
    /// used (a resumed run).
    stale: bool,
    /// Steps to factor at once, without trying the kept factor, and the
    /// wait after the next kept factor that does not pay: after one fails,
    /// it waits 1 step, then 2, 4, … up to [`LONGEST_WAIT`]; one that pays
    /// ends the waits.
    backoff: (u32, u32),
    /// The step's contacts, kept while Jacobi is tried.
    contacts_held: Vec<ContactConstraint>,
}

/// The matrix `M - dt D - dt² K` at a state, with its preconditioner: the
/// inverse diagonal (Jacobi), or the factored `M + dt² L` of the springs.
struct NewtonMatrix<'a> {
    system: &'a dyn Derivative,
    state: State<'a>,
    scale: JacobianScale,
    inverse_diagonal: &'a [Vec3],
    factor: Factored<'a>,
}

/// The step's linearisation, from which its Newton matrix is made with
/// each preconditioner.
struct Linearized<'a> {
    system: &'a dyn Derivative,
    state: State<'a>,
    scale: JacobianScale,
    inverse_diagonal: &'a [Vec3],
    /// The step (s).
    dt: Real,
}

impl Linearized<'_> {
    /// Solve the Newton system `(right_side, x)` with `preconditioner` (not
    /// auto), its factor refreshed in `factors` (the Laplacian's, the
    /// stiffness one's: factored at this state with `refactor`, else the one
    /// it holds), the contacts held by `held` (released where they pull,
    /// with `release`), measured against `scale` ([`super::cg::Limits`]).
    /// The report carries the solve's iterations, residual, convergence,
    /// preconditioner and refactorings.
    #[allow(clippy::too_many_arguments)]
    fn solve(
        &self,
        (preconditioner, refactor): (Preconditioner, bool),
        factors: &mut (&mut Option<Factor>, &mut Option<StiffnessFactor>),
        held: &mut HeldSolve,
        (right_side, x): (&[Vec3], &mut [Vec3]),
        settings: &SolverSettings,
        scale: Real,
        release: bool,
    ) -> Result<StepReport, SolverError> {
        let mut refactorings = 0;
        let factor = match preconditioner {
            Preconditioner::Laplacian => {
                Factored::Laplacian(laplacian::refreshed(factors.0, self.dt, self.system)?)
            }
            Preconditioner::Stiffness => {
                let factor = stiffness::prepared(factors.1, self.system)?;
                if refactor || !factor.is_factored() {
                    factor.factor(self.dt, self.system, self.state.position)?;
                    refactorings = 1;
                }
                Factored::Stiffness(factor)
            }
            Preconditioner::Jacobi | Preconditioner::Auto => Factored::None,
        };
        let mut matrix = NewtonMatrix {
            system: self.system,
            state: self.state,
            scale: self.scale,
            inverse_diagonal: self.inverse_diagonal,
            factor,
        };
        let mut report = StepReport {
            iterations: Some(0),
            preconditioner: Some(preconditioner),
            refactorings: Some(refactorings),
            ..StepReport::default()
        };
        let v = self.state.velocity;
        held.solve(
            &mut matrix,
            (right_side, x),
            (self.system.inverse_mass(), settings, scale),
            release,
            |c| (c.normal_velocity() - v[c.particle].dot(c.normal)) * c.normal,
            &mut report,
        );
        Ok(report)
    }
}

/// Note where a kept factor was made: the step `dt` (s), the positions
/// (m), the springs' rest lengths, stiffness and damping (no allocation
/// once the buffers have their size).
fn keep(
    (kept_dt, at): &mut (Real, Vec<Vec3>),
    kept_springs: &mut Vec<Real>,
    dt: Real,
    position: &[Vec3],
    springs: &Springs,
) {
    *kept_dt = dt;
    at.clear();
    at.extend_from_slice(position);
    kept_springs.clear();
    for values in [&springs.rest_length, &springs.stiffness, &springs.damping] {
        kept_springs.extend_from_slice(values);
    }
}

/// Add the iterations and refactorings of `solved` to `report`'s.
fn add_iterations(report: &mut StepReport, solved: StepReport) {
    if let (Some(total), Some(more)) = (report.iterations.as_mut(), solved.iterations) {
        *total += more;
    }
    if let (Some(total), Some(more)) = (report.refactorings.as_mut(), solved.refactorings) {
        *total += more;
    }
}

/// The factored preconditioner of a [`NewtonMatrix`], if any.
enum Factored<'a> {
    None,
    Laplacian(&'a mut Factor),
    Stiffness(&'a mut StiffnessFactor),
}

impl Operator for NewtonMatrix<'_> {
    fn apply(&mut self, p: &[Vec3], out: &mut [Vec3]) {
        self.system
            .jacobian_products(self.state, Jacobians::All, self.scale, p, out);
        mass_minus(self.system.mass(), p, out);
    }

    fn precondition(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        match &mut self.factor {
            Factored::Laplacian(f) => f.solve(r, z),
            Factored::Stiffness(f) => f.solve(r, z),
            Factored::None => jacobi(self.inverse_diagonal, r, z),
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
            refactorings: Some(0),
            ..StepReport::default()
        };
        let scale = super::step_scale(&*system, dt, 1);
        // Backward Euler takes every force at the end time, where moving
        // colliders and the gas schedule have got to.
        let time = time + dt;
        for newton in 0..solver.newton_iterations {
            // Asked to stop (`crate::interrupt`): the iterate so far.
            if newton > 0 && crate::interrupt::requested() {
                report.unconverged = true;
                break;
            }
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
            let linearized = Linearized {
                system: &*system,
                state,
                scale: matrix_scale,
                inverse_diagonal: &self.inverse_diagonal,
                dt,
            };
            let mut factors = (&mut self.factor, &mut self.stiffness);
            // The first iteration decides which contacts hold: those that
            // pulled are released and the system solved again.
            let release = newton == 0;
            let solve = (&self.right_side[..], &mut self.correction[..]);
            let kept = !self.factored_at.1.is_empty();
            let (choice, limit) = match solver.preconditioner {
                Preconditioner::Auto if kept && self.backoff.0 > 0 => {
                    if newton == 0 {
                        self.backoff.0 -= 1;
                    }
                    ((Preconditioner::Stiffness, true), None)
                }
                Preconditioner::Auto if kept => {
                    // The kept factor, made again first where a resumed
                    // run left it (with the springs as they were), tried
                    // within the iterations a new factor costs. Where the
                    // particles or springs changed since, a new one.
                    let factor = stiffness::prepared(factors.1, &*system)?;
                    let (kept_dt, at) = &self.factored_at;
                    let springs = system.springs();
                    let fits = at.len() == n && self.factored_springs.len() == 3 * springs.len();
                    let remake = self.stale || !factor.is_factored();
                    self.stale = false;
                    if remake && !fits {
                        ((Preconditioner::Stiffness, true), None)
                    } else {
                        if remake {
                            let mut kept_springs = springs.clone();
                            let (rest, rates) = self.factored_springs.split_at(springs.len());
                            let (stiffness, damping) = rates.split_at(springs.len());
                            kept_springs.rest_length.copy_from_slice(rest);
                            kept_springs.stiffness.copy_from_slice(stiffness);
                            kept_springs.damping.copy_from_slice(damping);
                            factor.factor_with(*kept_dt, (&kept_springs, system.mass()), at)?;
                        }
                        let limit = factor.refactor_after().min(solver.max_iterations);
                        ((Preconditioner::Stiffness, false), Some(limit))
                    }
                }
                Preconditioner::Auto => {
                    // A factor dearer than the most iterations a solve may
                    // take is never worth it (and may be large: a big 3D
                    // body's fill): Jacobi then, as the limits say.
                    let budget = stiffness::prepared(factors.1, &*system)?.budget();
                    let trial = (budget < solver.max_iterations).then_some(budget);
                    ((Preconditioner::Jacobi, false), trial)
                }
                chosen => ((chosen, true), None),
            };
            if limit.is_some() {
                self.contacts_held.clone_from(&self.held.contacts);
            }
            let settings = SolverSettings {
                max_iterations: limit.unwrap_or(solver.max_iterations),
                ..*solver
            };
            let mut solved = linearized.solve(
                choice,
                &mut factors,
                &mut self.held,
                solve,
                &settings,
                scale,
                release,
            )?;
            if choice == (Preconditioner::Stiffness, false) && !solved.unconverged {
                self.backoff = (0, 0);
            }
            // A trial cut short by a stop (`crate::interrupt`) says nothing
            // of its cost: the choice waits for a whole one.
            if limit.is_some() && solved.unconverged && !crate::interrupt::requested() {
                if kept {
                    let wait = self.backoff.1.clamp(1, LONGEST_WAIT);
                    self.backoff = (wait, (2 * wait).min(LONGEST_WAIT));
                }
                // Jacobi, or the kept factor, would cost more than a new
                // factor: factor at this state, and keep it.
                add_iterations(&mut report, solved);
                self.held.contacts.clone_from(&self.contacts_held);
                let solve = (&self.right_side[..], &mut self.correction[..]);
                solved = linearized.solve(
                    (Preconditioner::Stiffness, true),
                    &mut factors,
                    &mut self.held,
                    solve,
                    solver,
                    scale,
                    release,
                )?;
            }
            // Auto keeps every factor it makes: after a missed trial, in a
            // back-off, or where the kept one no longer fits.
            let refactored = solved.refactorings.is_some_and(|made| made > 0);
            if solver.preconditioner == Preconditioner::Auto && refactored {
                keep(
                    &mut self.factored_at,
                    &mut self.factored_springs,
                    dt,
                    state.position,
                    system.springs(),
                );
            }
            add_iterations(&mut report, solved);
            report.residual = solved.residual;
            report.unconverged |= solved.unconverged;
            report.preconditioner = solved.preconditioner;
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

    /// The auto preconditioner's kept factor, where it has one: a resumed
    /// run makes it again at the same positions and goes on with it, as
    /// the run it was saved from does.
    fn save_history(&self, state: &mut WorldState) {
        let (dt, at) = &self.factored_at;
        state.put(FACTORED, vec![Real::from(u8::from(!at.is_empty()))]);
        if !at.is_empty() {
            let values = std::iter::once(*dt).chain(at.iter().flat_map(|x| x.to_array()));
            state.put(FACTORED_AT, values.collect());
            let (wait, next) = self.backoff;
            state.put(BACKOFF, vec![Real::from(wait), Real::from(next)]);
            state.put(FACTORED_SPRINGS, self.factored_springs.clone());
        }
    }

    fn restore_history(&mut self, state: &WorldState, particles: usize) -> Result<(), StateError> {
        // States saved before the auto preconditioner have none: Jacobi;
        // those saved before the kept factor, a flag alone: Jacobi too.
        let factored = match state.get_any(FACTORED) {
            Err(_) => false,
            Ok([flag]) if *flag == 0.0 || *flag == 1.0 => *flag == 1.0,
            Ok(values) => {
                return Err(StateError::BadValue {
                    name: FACTORED.to_string(),
                    index: 0,
                    value: values.first().copied().unwrap_or(Real::NAN),
                })
            }
        };
        self.factored_at.1.clear();
        (self.stale, self.backoff) = (false, (0, 0));
        if let (true, Ok(values)) = (factored, state.get_any(FACTORED_AT)) {
            let bad = |index: usize, value: Real| StateError::BadValue {
                name: FACTORED_AT.to_string(),
                index,
                value,
            };
            if values.len() != 1 + 3 * particles {
                return Err(bad(values.len(), Real::NAN));
            }
            if let Some(k) = values.iter().position(|v| !v.is_finite()) {
                return Err(bad(k, values[k]));
            }
            if values[0] <= 0.0 {
                return Err(bad(0, values[0]));
            }
            self.factored_at.0 = values[0];
            self.factored_at.1.extend(
                values[1..]
                    .chunks_exact(3)
                    .map(|c| Vec3::new(c[0], c[1], c[2])),
            );
            self.stale = true;
            self.factored_springs.clear();
            if let Ok(values) = state.get_any(FACTORED_SPRINGS) {
                if let Some(k) = values.iter().position(|v| !v.is_finite() || *v < 0.0) {
                    return Err(bad_springs(k, values[k]));
                }
                self.factored_springs.extend_from_slice(values);
            }
            self.backoff = match state.get_any(BACKOFF) {
                Ok(&[wait, next])
                    if [wait, next].iter().all(|v| {
                        v.fract() == 0.0 && (0.0..=Real::from(LONGEST_WAIT)).contains(v)
                    }) =>
                {
                    (wait as u32, next as u32)
                }
                Err(_) => (0, 0),
                Ok(values) => {
                    return Err(StateError::BadValue {
                        name: BACKOFF.to_string(),
                        index: 0,
                        value: values.first().copied().unwrap_or(Real::NAN),
                    })
                }
            };
        }
        Ok(())
    }
}

/// A saved kept factor's spring value that cannot be one.
fn bad_springs(index: usize, value: Real) -> StateError {
    StateError::BadValue {
        name: FACTORED_SPRINGS.to_string(),
        index,
        value,
    }
}
