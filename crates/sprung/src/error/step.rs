//! Errors of a step: a solve that failed, and a world whose state has
//! become non-finite or run away, each with the step, the time and what
//! to do.

use super::{BuildError, Seconds};
use crate::units::Real;
use thiserror::Error;

/// Why an implicit solver could not take a step.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SolverError {
    /// A sparse Cholesky factorisation failed: the projective solver's and
    /// the Laplacian preconditioner's `M + dt² L`, or the stiffness
    /// preconditioner's `M - dt D - dt² K` of the springs (each should be
    /// positive definite; this means non-finite masses or stiffnesses, or
    /// too little memory for the factor).
    #[error("an implicit solver could not factor its matrix (M + dt² L, or the springs' M - dt D - dt² K): {0}")]
    Factorization(String),
    /// The adaptive integrator could not keep its error estimate within the
    /// tolerance even with tiny steps (a non-finite or violently stiff
    /// state).
    #[error("rk45 could not meet error_tolerance: its step fell to {step:.3e} s")]
    StepTooSmall {
        /// The step it had come down to (s).
        step: Real,
    },
}

/// Why a step could not be taken, or why the run must stop.
///
/// Explicit Euler multiplies an oscillation's amplitude by `√(1 + ω² dt²)`
/// each step: at a hundred times the stable step `2 / ω_max`, the fastest
/// mode grows some 200-fold a step until a particle runs past the world's
/// limits, and the error says which, and what the stable step would be:
///
/// ```
/// use sprung::{build, IntegratorKind, StepError, World};
///
/// let mut world = World::new(IntegratorKind::Euler);
/// world.add_body("rope", build::rope(4, 1.0).unwrap().with_stiffness(1e4)).unwrap();
/// let stable = world.stable_time_step();
/// let dt = 100.0 * stable;
/// let error = (0..100).find_map(|_| world.step(dt).err()).expect("a blow-up");
/// let StepError::BlowUp { dt: used, stable_dt, ref body, .. } = error else {
///     panic!("{error}");
/// };
/// assert_eq!((used, stable_dt), (dt, stable));
/// assert!(body.starts_with("body \"rope\""));
/// assert!(error.to_string().contains("is too large for these springs and masses"));
/// ```
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StepError {
    /// Solver settings out of range (`World::settings.solver`).
    #[error("solver settings: {0}")]
    InvalidSettings(BuildError),
    /// The implicit solver failed at this step.
    #[error("step {step} (t = {} s): {source}", Seconds(*time))]
    Solver {
        /// Number of the step that failed (1 = first step).
        step: u64,
        /// Simulated time at the start of that step (s).
        time: Real,
        /// What went wrong.
        source: SolverError,
    },
    /// A time step that is zero, negative or not finite.
    #[error("time step dt = {dt} s: it must be positive and finite")]
    InvalidTimeStep {
        /// The time step given (s).
        dt: Real,
    },
    /// The detect stage found more candidate contact pairs than
    /// [`crate::contact::pair_limit`] allows: the contact thickness is many
    /// times the spacing of the particles. Nothing moved in the step.
    #[error("step {step} (t = {} s): contact between bodies found more than {limit} candidate pairs (the limit: {per_element} per particle or surface element that can touch, {least} at least): the contact thickness {thickness} m, widened by the distance the particles close in a step, is too large for the spacing of the particles; lower `[contact] thickness` (or `dt`, if the bodies move fast)", Seconds(*time))]
    TooManyContacts {
        /// Number of the step refused (1 = first step).
        step: u64,
        /// Simulated time at its start (s).
        time: Real,
        /// The most the scene may have.
        limit: usize,
        /// The pairs allowed per element that can touch
        /// ([`crate::contact::PAIRS_PER_ELEMENT`]).
        per_element: usize,
        /// The pairs allowed however few the elements
        /// ([`crate::contact::MIN_PAIR_LIMIT`]).
        least: usize,
        /// The contact thickness (m).
        thickness: Real,
    },
    /// A rod stayed off its length by more than [`crate::constrain::ROD_FAILURE`]
    /// (relative) after the constrain stage's sweeps: the rods could not be
    /// held, and the motion is no longer that of the scene.
    #[error("step {step} (t = {} s): rod {rod} of {body} is off its length by {error:.4e} (relative), beyond {limit:.1e}, after {sweeps} sweeps (constraint_iterations = {iterations}): the rods cannot be held at this step (rods between very unequal masses converge slowly: raise `constraint_iterations`, lower `dt`, or even out the masses; rods whose lengths cannot all hold at once, as between pinned particles or rigid bodies, never converge)", Seconds(*time))]
    RodOff {
        /// Number of the step that failed (1 = first step).
        step: u64,
        /// Simulated time at the end of that step (s).
        time: Real,
        /// The rod's index in its body (the scene's order).
        rod: usize,
        /// Its body, in words: `body "chain"`.
        body: String,
        /// Its relative length error, `|d - L| / L`.
        error: Real,
        /// The error a step may leave: [`crate::constrain::ROD_FAILURE`],
        /// or `constraint_tolerance` where that is looser.
        limit: Real,
        /// The sweeps the stage took.
        sweeps: u32,
        /// The most sweeps it may take (`constraint_iterations`).
        iterations: u32,
    },
    /// The CCD that keeps every particle from passing through a surface could not
    /// clear a step's collisions within its budget
    /// ([`crate::contact::ccd::work_budget`]): bodies that start the step
    /// overlapping, or move far into each other in it, collide everywhere.
    /// The state is that of the step before the CCD: the run must
    /// stop.
    #[error("step {step} (t = {} s): the CCD that keeps every particle from passing through a surface could not clear the collisions of {bodies} within its budget ({work} tests and zone moves, at most {budget} a step; {collisions} collisions left after {rounds} rounds): lower `dt`, start the bodies apart (`sprung check` warns of bodies that start overlapping), or turn the CCD off (`[contact] ccd = false`)", Seconds(*time))]
    CcdOverBudget {
        /// Number of the step that failed (1 = first step).
        step: u64,
        /// Simulated time at the end of that step (s).
        time: Real,
        /// The bodies of the collisions left, in words: `"ball", "cloth"`.
        bodies: String,
        /// The work done (narrow tests and particles moved in zones).
        work: u64,
        /// The most a step may do.
        budget: u64,
        /// Collisions left.
        collisions: usize,
        /// Rounds of impulses and zones taken.
        rounds: usize,
    },
    /// The state became non-finite or ran away: the run must stop.
    #[error("simulation blew up at step {step} (t = {} s): particle {particle} ({body}) {reason}; {}", Seconds(*time), advice(*dt, *stable_dt))]
    BlowUp {
        /// Number of the step that produced the bad state (1 = first step).
        step: u64,
        /// Simulated time at the end of that step (s).
        time: Real,
        /// A particle whose state is bad (index in the world).
        particle: usize,
        /// Which body it belongs to, in words: `body "rope", its particle 5`.
        body: String,
        /// What is wrong with it.
        reason: BlowUpReason,
        /// The time step used (s).
        dt: Real,
        /// Stable time-step estimate from the springs and masses (s).
        stable_dt: Real,
    },
    /// A quantity the run reports (the time, an energy, a body's volume,
    /// pressure or centre) came out infinite or NaN from a finite state:
    /// the run must stop before it is written anywhere.
    #[error("simulation blew up at step {step} (t = {} s): {quantity} = {value}, not a finite number; {}", Seconds(*time), advice(*dt, *stable_dt))]
    NotFinite {
        /// Number of the step that produced it (0: the starting state).
        step: u64,
        /// Simulated time at the end of that step (s).
        time: Real,
        /// What it is, as its column is named (`time`, `spring`, ...).
        quantity: String,
        /// Its value: infinite or NaN.
        value: Real,
        /// The time step used (s).
        dt: Real,
        /// Stable time-step estimate from the springs and masses (s).
        stable_dt: Real,
    },
}

/// What to do about a blow-up at time step `dt` given the stable estimate.
fn advice(dt: Real, stable_dt: Real) -> String {
    if !stable_dt.is_finite() {
        format!("nothing in the scene limits the time step dt = {dt:e} s (no springs or contacts), so look at the forces and the starting state")
    } else if dt > stable_dt {
        format!("the time step dt = {dt:e} s is too large for these springs and masses: a stable estimate is dt <= {stable_dt:.3e} s")
    } else {
        format!("the time step dt = {dt:e} s is already below the stable estimate {stable_dt:.3e} s, so look at the forces (one-sided springs need critical damping; explicit Euler gains energy at any dt)")
    }
}

/// What made the blow-up detector stop a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BlowUpReason {
    /// Position or velocity is NaN or infinite.
    NonFinite,
    /// Distance from the origin above the world's limit (m).
    TooFar(Real),
    /// Speed above the world's limit (m/s).
    TooFast(Real),
    /// In one step, moved `stray` (m) against its body's mean move,
    /// farther than [`crate::contact::ccd::RUNAWAY_SIZES`] times the body's `size`
    /// (m, its extent at the start of the step, or the contact thickness
    /// for a smaller body): found before
    /// the CCD that keeps every particle from passing through a surface, whose
    /// work grows with the motion.
    OutOfShape {
        /// How far it moved against its body's mean move (m).
        stray: Real,
        /// Its body's size (m).
        size: Real,
        /// The most it may move, in sizes of its body
        /// ([`crate::contact::ccd::RUNAWAY_SIZES`]).
        sizes: Real,
    },
}

impl std::fmt::Display for BlowUpReason {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BlowUpReason::NonFinite => write!(f, "has a non-finite position or velocity"),
            BlowUpReason::TooFar(d) => write!(f, "ran away to {d:.3e} m from the origin"),
            BlowUpReason::TooFast(v) => write!(f, "ran away at {v:.3e} m/s"),
            BlowUpReason::OutOfShape { stray, size, sizes } => write!(
                f,
                "moved {stray:.3e} m against the rest of its body in one step, more than {sizes} times the body's size {size:.3e} m"
            ),
        }
    }
}
