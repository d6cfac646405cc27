//! The implicit integrators (docs/physics.md §6): backward Euler, stable at time
//! steps far beyond the explicit limit `2/ω_max`, solved two ways.
//!
//! - [`ImplicitEuler`]: Newton's method on the backward-Euler equations,
//!   each linear solve by preconditioned conjugate gradients (Baraff and
//!   Witkin, "Large steps in cloth simulation", SIGGRAPH 1998). Every force
//!   of the world's list takes part through its Jacobian products.
//! - [`Projective`]: the local/global iterations of the fast mass-spring
//!   solver (Liu, Bargteil, O'Brien and Kavan, SIGGRAPH Asia 2013), with the
//!   constant matrix `M + dt² L` factored once by a sparse Cholesky
//!   decomposition.

mod cg;
mod euler;
mod figures;
mod laplacian;
mod projective;
mod stiffness;
mod substitution;

pub use euler::ImplicitEuler;
pub use figures::{measure_substitution, SubstitutionFigures};
pub use projective::Projective;

use cg::{ConjugateGradient, Limits, Operator};

use crate::colliders::ContactConstraint;
use crate::error::BuildError;
use crate::integrate::{Derivative, StepReport};
use crate::parallel;
use crate::units::{Real, Vec3};

/// The preconditioner of implicit Euler's conjugate gradients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Preconditioner {
    /// Jacobi while its solves cost less than a step with the stiffness
    /// factor would (the number of iterations a fixed cost model gives for
    /// the springs' pattern), the stiffness factor from the first solve
    /// that needs more on (it is solved again with it); Jacobi throughout
    /// where that budget is not below `max_iterations`. The default.
    Auto,
    /// The inverse of the matrix's diagonal: cheap per iteration, slow to
    /// converge where the springs are stiff against the masses.
    Jacobi,
    /// The factored `M + dt² L` (the springs' graph Laplacian): costlier per
    /// iteration, far fewer iterations where the motion stretches the
    /// springs.
    Laplacian,
    /// The springs' own Newton matrix `M - dt D - dt² K`, factored at
    /// each linearisation: as stiff along each spring as the spring, and
    /// only as stiff across it as its tension, so it gains where the motion
    /// bends a cloth as much as where it stretches it.
    Stiffness,
}

impl Preconditioner {
    /// The name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Preconditioner::Auto => "auto",
            Preconditioner::Jacobi => "jacobi",
            Preconditioner::Laplacian => "laplacian",
            Preconditioner::Stiffness => "stiffness",
        }
    }

    /// The preconditioner named `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        [
            Preconditioner::Auto,
            Preconditioner::Jacobi,
            Preconditioner::Laplacian,
            Preconditioner::Stiffness,
        ]
        .into_iter()
        .find(|p| p.name() == name)
    }
}

/// The tightest `error_tolerance` rk45 may be given (relative above 1 m or
/// 1 m/s): a thousand times the rounding of its error estimate.
pub const MIN_ERROR_TOLERANCE: Real = 1e-12;
/// Most conjugate-gradient iterations a solve may be allowed: a solve
/// that has not converged in that many will not (the default is 1000).
pub const MAX_CG_ITERATIONS: u32 = 100_000;
/// Most Newton iterations a step of implicit Euler may take: each is a
/// full linear solve, and a few reach the backward-Euler solution.
pub const MAX_NEWTON_ITERATIONS: u32 = 100;
/// Most local/global iterations a step of the projective solver may take
/// (the default is 10).
pub const MAX_PROJECTIVE_ITERATIONS: u32 = 10_000;

/// The tolerances and iteration limits of the implicit integrators (the
/// `[sim]` keys `solver_tolerance`, `max_iterations`, `newton_iterations`,
/// `iterations` and `preconditioner`).
///
/// Implicit Euler with the Laplacian preconditioner takes a stiff rope
/// (`k = 10⁴ N/m`, 1 kg particles) at a hundred times the explicit stable
/// step. For a straight rope moving along its length the preconditioner
/// `M + dt² L` is the solve's very matrix, so conjugate gradients converge
/// in one iteration; and backward Euler damps the swing away, leaving the
/// rope at its static stretch, each spring stretched by the weight it
/// holds over `k`: the lowest particle `1 + m g (1 + 2 + … + 19) / k` m
/// down (each solve stops within 1e-10 of the step's gravity impulse, a
/// force balance to that share of each weight, far below the 1e-9 m
/// claimed):
///
/// ```
/// use sprung::integrate::{Preconditioner, SolverSettings};
/// use sprung::{build, IntegratorKind, World};
///
/// let mut world = World::new(IntegratorKind::ImplicitEuler);
/// world.settings.solver = SolverSettings {
///     preconditioner: Preconditioner::Laplacian,
///     tolerance: 1e-10,
///     ..SolverSettings::default()
/// };
/// let (k, m, g) = (1e4, 1.0, 9.81);
/// world.add_body("rope", build::rope(20, 1.0).unwrap().with_stiffness(k)).unwrap();
/// let dt = 100.0 * world.stable_time_step();
/// for _ in 0..20 {
///     let report = world.step(dt).unwrap();
///     // One iteration; none once the rope is at rest (within the
///     // tolerance of the step's gravity impulse).
///     assert!(report.iterations.is_some_and(|i| i <= 1));
///     assert!(report.residual.unwrap() <= 1e-10);
/// }
/// assert_eq!(world.solver_stats().unconverged_steps, 0);
/// let stretched = 1.0 + m * g * 190.0 / k;
/// assert!((world.particles.position[19].y + stretched).abs() < 1e-9);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Relative residual `|b - A x| / max(|b|, s)` at which conjugate
    /// gradients stop (each linear solve of implicit Euler, each global
    /// step of the projective solver), `s` the step's own scale: gravity's
    /// impulse on the free particles `|dt g M|` (kg·m/s; `dt² |g M|`, kg·m,
    /// for projective), so that a body at rest takes no iterations.
    /// Default 1e-6.
    pub tolerance: Real,
    /// Most conjugate-gradient iterations per linear solve; reaching it
    /// above the tolerance is reported. Default 1000.
    pub max_iterations: u32,
    /// Newton iterations per step of implicit Euler. Default 1: the
    /// linearised step of Baraff and Witkin; more iterate towards the exact
    /// backward-Euler solution.
    pub newton_iterations: u32,
    /// Local/global iterations per step of the projective solver. Default 10.
    pub iterations: u32,
    /// Implicit Euler's preconditioner. Default [`Preconditioner::Auto`].
    pub preconditioner: Preconditioner,
    /// `rk45`'s tolerance on the local error of each internal step: relative
    /// above 1 m (1 m/s), absolute below. Default 1e-6.
    pub error_tolerance: Real,
}

impl Default for SolverSettings {
    fn default() -> Self {
        SolverSettings {
            tolerance: 1e-6,
            max_iterations: 1000,
            newton_iterations: 1,
            iterations: 10,
            preconditioner: Preconditioner::Auto,
            error_tolerance: 1e-6,
        }
    }
}

impl SolverSettings {
    /// Check the settings: a positive, finite tolerance below 1 and at least
    /// one iteration of each kind. Errors name the scene key.
    pub fn validate(&self) -> Result<(), BuildError> {
        if !(self.error_tolerance.is_finite() && self.error_tolerance >= MIN_ERROR_TOLERANCE) {
            return Err(BuildError::OutOfRange {
                field: "error_tolerance",
                value: self.error_tolerance,
                reason: "the local error to keep within must be finite and at least 1e-12: positive, and above what the rounding of a state near 1 m leaves in rk45's error estimate (about 1e-15), which a tighter tolerance could never meet",
            });
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0 && self.tolerance < 1.0) {
            return Err(BuildError::OutOfRange {
                field: "solver_tolerance",
                value: self.tolerance,
                reason: "the relative residual to reach must be positive and below 1",
            });
        }
        for (field, value, most, reason) in [
            (
                "max_iterations",
                self.max_iterations,
                MAX_CG_ITERATIONS,
                "must be from 1 to 100 000 conjugate-gradient iterations a solve",
            ),
            (
                "newton_iterations",
                self.newton_iterations,
                MAX_NEWTON_ITERATIONS,
                "must be from 1 to 100 Newton iterations a step",
            ),
            (
                "iterations",
                self.iterations,
                MAX_PROJECTIVE_ITERATIONS,
                "must be from 1 to 10 000 local/global iterations a step",
            ),
        ] {
            if !(1..=most).contains(&value) {
                return Err(BuildError::OutOfRange {
                    field,
                    value: Real::from(value),
                    reason,
                });
            }
        }
        Ok(())
    }
}

/// `out = M p - out` (`M` the diagonal of `mass`, kg): the mass term of the
/// solvers' matrices, less the force Jacobians' product already in `out`.
fn mass_minus(mass: &[Real], p: &[Vec3], out: &mut [Vec3]) {
    parallel::for_each_span(out, |start, out| {
        for (k, o) in out.iter_mut().enumerate() {
            *o = mass[start + k] * p[start + k] - *o;
        }
    });
}

/// `v = (x - x_start) / dt` (m/s), the velocity of a step of `dt` (s).
fn finite_difference(position: &[Vec3], start_position: &[Vec3], dt: Real, velocity: &mut [Vec3]) {
    parallel::for_each_span(velocity, |start, v| {
        for (k, v) in v.iter_mut().enumerate() {
            *v = (position[start + k] - start_position[start + k]) / dt;
        }
    });
}

/// `|dt^power a M|` over the free particles (a norm over particle vectors):
/// the impulse (`power` 1, kg·m/s) or the displacement times mass (`power`
/// 2, kg·m) the uniform acceleration `a` (m/s², gravity's) gives them in a
/// step of `dt` (s). The implicit solvers' residuals are measured against
/// it where the right side is smaller (see [`cg::Limits::scale`]).
fn step_scale(system: &dyn Derivative, dt: Real, power: i32) -> Real {
    let (mass, inverse_mass) = (system.mass(), system.inverse_mass());
    let free = parallel::sum(mass.len(), |range| {
        range
            .filter(|&i| inverse_mass[i] != 0.0)
            .map(|i| mass[i] * mass[i])
            .sum()
    });
    let scale = dt.powi(power) * system.uniform_acceleration().length() * free.sqrt();
    // Masses so large that the sum overflows: no floor.
    if scale.is_finite() {
        scale
    } else {
        0.0
    }
}

/// Most times a solve is done again after releasing contacts that pulled.
const RELEASE_PASSES: usize = 3;

/// The linear solves of both implicit integrators with the projection
/// colliders' contacts held, and their buffers.
#[derive(Debug, Default)]
struct HeldSolve {
    cg: ConjugateGradient,
    /// The step's contacts with projection colliders; those that pull are
    /// let go.
    contacts: Vec<ContactConstraint>,
    /// Each contact's impulse in the last solve.
    impulses: Vec<Real>,
}

impl HeldSolve {
    /// Solve `matrix x = right_side` by conjugate gradients from the guess
    /// `start` gives each contact's particle (along its normal; zero
    /// elsewhere), each contact's particle kept on its guess along the
    /// normal. With `release`, the contacts that pull (a negative impulse)
    /// are let go and the system solved again, up to [`RELEASE_PASSES`]
    /// times. The contacts' impulses end in `self.impulses`; the
    /// iterations (where `report` counts them), the last residual and any
    /// unconverged solve go to `report`.
    fn solve(
        &mut self,
        matrix: &mut dyn Operator,
        (right_side, x): (&[Vec3], &mut [Vec3]),
        (inverse_mass, solver, scale): (&[Real], &SolverSettings, Real),
        release: bool,
        start: impl Fn(&ContactConstraint) -> Vec3,
        report: &mut StepReport,
    ) {
        let passes = if release { RELEASE_PASSES } else { 1 };
        for pass in 0..passes {
            x.fill(Vec3::ZERO);
            for c in &self.contacts {
                x[c.particle] = start(c);
            }
            let limits = Limits {
                inverse_mass,
                contacts: &self.contacts,
                tolerance: solver.tolerance,
                scale,
                max_iterations: solver.max_iterations,
            };
            let outcome = self.cg.solve(matrix, right_side, x, limits);
            if let Some(iterations) = report.iterations.as_mut() {
                *iterations += outcome.iterations;
            }
            report.residual = Some(outcome.residual);
            report.unconverged |= !outcome.converged;
            self.cg
                .contact_impulses(matrix, right_side, x, &self.contacts, &mut self.impulses);
            let pulled = self.impulses.iter().any(|&j| j < 0.0);
            if !pulled || pass + 1 == passes {
                break;
            }
            let mut index = 0;
            let impulses = &self.impulses;
            self.contacts.retain(|_| {
                index += 1;
                impulses[index - 1] >= 0.0
            });
        }
    }
}
