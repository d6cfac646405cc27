//! Errors of the engine: building a body from a user's description, and
//! stepping a world whose state has become non-finite or run away.
//!
//! Every message names the offending field (with the scene-file key the
//! user wrote) and the index, so a loader can add the file and line.

use crate::surface::SurfaceProblem;
use crate::units::Real;
use thiserror::Error;

/// Why a body (or a world setting) was refused before the run.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BuildError {
    /// A body with no particles.
    #[error("the body has no particles")]
    NoParticles,
    /// A per-particle or per-spring list whose length disagrees with the count it describes.
    #[error("`{field}` has {found} entries but the body has {expected} {what}")]
    LengthMismatch {
        /// Scene key of the list.
        field: &'static str,
        /// Entries expected.
        expected: usize,
        /// Entries found.
        found: usize,
        /// What is counted ("particles" or "springs").
        what: &'static str,
    },
    /// A new numbering of a body's particles that does not number each
    /// of them once ([`crate::BodyData::renumbered`]).
    #[error("the new numbering is not one of the body's {particles} particles: entry {index} is {value}, out of range or given before")]
    NotARenumbering {
        /// Particles of the body.
        particles: usize,
        /// The first bad entry (its particle's old number).
        index: usize,
        /// Its new number.
        value: usize,
    },
    /// A mass that is zero, negative or not finite.
    #[error("`{field}`[{index}] = {value}: mass must be positive and finite (kg)")]
    BadMass {
        /// Scene key (`mass`, `masses` or `total_mass`).
        field: &'static str,
        /// Particle index.
        index: usize,
        /// The value given (kg).
        value: Real,
    },
    /// A number that is NaN or infinite.
    #[error("`{field}`[{index}] is not a finite number ({value})")]
    NotFinite {
        /// Scene key of the value.
        field: &'static str,
        /// Index of the entry (particle, spring, ...).
        index: usize,
        /// The value given.
        value: Real,
    },
    /// A rod naming a particle that does not exist.
    #[error(
        "`rods`[{rod}]: particle index {bad} is out of range (the body has {particles} particles)"
    )]
    RodIndexOutOfRange {
        /// Rod index.
        rod: usize,
        /// The index out of range.
        bad: usize,
        /// Particles in the body.
        particles: usize,
    },
    /// A rod of zero (or non-finite) length, or from a particle to itself.
    #[error(
        "`rods`[{rod}] has length {length} m: a rod joins two particles a positive distance apart"
    )]
    BadRodLength {
        /// Rod index.
        rod: usize,
        /// Its length (m).
        length: Real,
    },
    /// A 2D gas body (bounded by `segments`) off the plane z = 0, or moving
    /// out of it: its gas takes the area its loop encloses in the xy-plane.
    #[error("a 2D gas body (bounded by `segments`) must lie and move in the plane z = 0, where its gas takes the area the loop encloses: particle {particle} has {what} = {}", Readable(*value))]
    GasOffPlane {
        /// The first particle off the plane.
        particle: usize,
        /// `z` or `velocity z`.
        what: &'static str,
        /// Its value (m or m/s).
        value: Real,
    },
    /// Two rods on the same two particles at different lengths.
    #[error("`rods`[{rod}] ({length} m) and `rods`[{other}] ({other_length} m) join the same two particles at different lengths: both cannot hold")]
    ConflictingRods {
        /// The later rod's index.
        rod: usize,
        /// Its length (m).
        length: Real,
        /// The earlier rod's index.
        other: usize,
        /// Its length (m).
        other_length: Real,
    },
    /// A rod longer than a path of other rods joining its two ends (three
    /// rods on a triangle, one longer than the other two together, or a
    /// longer loop): their lengths cannot all hold at once.
    #[error("`rods`[{rod}] ({length} m) is longer than the path of `rods` {path:?} joining its ends ({together} m together): their lengths cannot all hold at once")]
    RodLoop {
        /// The rod's index.
        rod: usize,
        /// Its length (m).
        length: Real,
        /// The rods of the path, from the rod's first particle to its
        /// second.
        path: Vec<usize>,
        /// Their lengths added (m).
        together: Real,
    },
    /// A rod between two pinned particles: it can hold nothing.
    #[error("`rods`[{rod}] joins two pinned particles: a rod needs a free end")]
    PinnedRod {
        /// Rod index.
        rod: usize,
    },
    /// A muscle naming a spring that does not exist.
    #[error(
        "`muscles`[{muscle}].spring = {spring}: out of range (the body has {springs} springs)"
    )]
    MuscleSpringOutOfRange {
        /// Muscle index.
        muscle: usize,
        /// The spring index given.
        spring: usize,
        /// Springs in the body.
        springs: usize,
    },
    /// A muscle parameter outside its range.
    #[error("`muscles`[{muscle}].{field} = {}: {reason}", Readable(*value))]
    BadMuscle {
        /// Muscle index.
        muscle: usize,
        /// Key of the parameter.
        field: &'static str,
        /// The value given.
        value: Real,
        /// What the allowed range is.
        reason: &'static str,
    },
    /// `rigid = true` on a body of fewer than two particles.
    #[error("`rigid` = true needs at least two particles")]
    RigidTooSmall,
    /// `rigid = true` on a body with muscles: its shape is held, so a
    /// muscle's changing rest length moves nothing.
    #[error("`rigid` = true cannot be combined with `muscles` (a rigid body keeps its shape, so a muscle's spring moves nothing)")]
    RigidMuscles,
    /// `rigid = true` on a body with pinned particles.
    #[error("`rigid` = true cannot be combined with `pinned` particles (a rope pins its first particle unless told `pinned = []`)")]
    RigidPinned,
    /// A parameter outside its allowed range.
    #[error("`{field}` = {}: {reason}", Readable(*value))]
    OutOfRange {
        /// Scene key of the parameter.
        field: &'static str,
        /// The value given.
        value: Real,
        /// What the allowed range is.
        reason: &'static str,
    },
    /// A builder asked for more particles or springs than a scene may hold
    /// ([`crate::build::MAX_PARTICLES`], [`crate::build::MAX_SPRINGS`]),
    /// refused before they are made.
    #[error("`{field}`: {count} {what}, more than the {limit} a scene may hold")]
    TooMany {
        /// Scene key of the parameter that sets the count.
        field: &'static str,
        /// What is counted ("particles" or "springs").
        what: &'static str,
        /// How many there would be.
        count: usize,
        /// The most allowed.
        limit: usize,
    },
    /// A spring with negative stiffness or damping.
    #[error("`{field}`[{spring}] = {value}: must not be negative")]
    NegativeSpringCoefficient {
        /// Scene key (`stiffness` or `damping`).
        field: &'static str,
        /// Spring index.
        spring: usize,
        /// The value given (N/m or N·s/m).
        value: Real,
    },
    /// A spring naming a particle that does not exist.
    #[error("`springs`[{spring}] = [{first}, {second}]: particle index {bad} is out of range (the body has {particles} particles)")]
    SpringIndexOutOfRange {
        /// Spring index.
        spring: usize,
        /// First particle index given.
        first: usize,
        /// Second particle index given.
        second: usize,
        /// The out-of-range index.
        bad: usize,
        /// Number of particles in the body.
        particles: usize,
    },
    /// A spring joining a particle to itself.
    #[error("`springs`[{spring}] = [{particle}, {particle}] joins a particle to itself")]
    SelfSpring {
        /// Spring index.
        spring: usize,
        /// The particle index.
        particle: usize,
    },
    /// Two springs joining the same pair of particles (refused, not merged).
    #[error("`springs`[{spring}] = [{first}, {second}] duplicates `springs`[{earlier}]: each pair of particles may have one spring (duplicates are refused, not merged)")]
    DuplicateSpring {
        /// Index of the later spring.
        spring: usize,
        /// Index of the earlier spring with the same pair.
        earlier: usize,
        /// First particle index.
        first: usize,
        /// Second particle index.
        second: usize,
    },
    /// A spring whose rest length is zero or negative.
    #[error("`springs`[{spring}] = [{first}, {second}] has rest length {length} m: a spring needs a positive rest length (are the two particles at the same place?)")]
    ZeroLengthSpring {
        /// Spring index.
        spring: usize,
        /// First particle index.
        first: usize,
        /// Second particle index.
        second: usize,
        /// The rest length (m).
        length: Real,
    },
    /// A pinned index that names no particle.
    #[error("`pinned`[{entry}] = {index} is out of range (the body has {particles} particles)")]
    PinnedOutOfRange {
        /// Position in the `pinned` list.
        entry: usize,
        /// The index given.
        index: usize,
        /// Number of particles.
        particles: usize,
    },
    /// A face naming a particle that does not exist, or repeating one.
    #[error("`faces`[{face}] = {indices:?}: {reason} (the body has {particles} particles)")]
    BadFace {
        /// Face index.
        face: usize,
        /// The three particle indices.
        indices: [usize; 3],
        /// What is wrong.
        reason: &'static str,
        /// Number of particles.
        particles: usize,
    },
    /// A 2D segment naming a particle that does not exist, or joining one to itself.
    #[error("`segments`[{segment}] = {indices:?}: a segment needs two different particles in range (the body has {particles} particles)")]
    BadSegment {
        /// Segment index.
        segment: usize,
        /// The two particle indices.
        indices: [usize; 2],
        /// Number of particles.
        particles: usize,
    },
    /// Self-collision asked of a body with no faces or segments.
    #[error("`self_collision` needs a surface: give the body `faces` (3D) or `segments` (2D); bodies without one collide with others as particles")]
    SelfCollisionWithoutSurface,
    /// Self-collision asked of a body that does not collide.
    #[error("`self_collision` = true needs `collide` = true: a body left out of contact does not collide with itself either")]
    SelfCollisionWithoutCollide,
    /// A gas in a body with no faces or segments.
    #[error("`gas` needs a closed surface: give the body `faces` (3D) or `segments` (2D), or use a ring, sphere or closed mesh")]
    GasWithoutSurface,
    /// A gas in a body whose surface is not closed.
    #[error("`gas` needs a closed surface, but {problem}")]
    OpenSurface {
        /// The first problem found.
        problem: SurfaceProblem,
    },
    /// A particle starting beyond the blow-up limits of the world, or a
    /// rod longer than the world is wide.
    #[error("`{field}`[{index}]: {value:.3e} is beyond the world's limit {limit:.3e} (`max_distance` in m, `max_speed` in m/s, in [sim]; a rod at most twice `max_distance`): the run would stop at once")]
    BeyondLimit {
        /// `particles` (distance from the origin), `velocities` (speed) or
        /// `rod_lengths` (m).
        field: &'static str,
        /// The particle (or rod).
        index: usize,
        /// Its distance (m) or speed (m/s).
        value: Real,
        /// The limit (m or m/s).
        limit: Real,
    },
    /// A mass or stiffness so large that an energy of the run would
    /// overflow the numbers written.
    #[error("`{field}`[{index}] = {value:.3e}: too large, its energy within the world's limits (`max_distance`, `max_speed` in [sim]) could exceed the {ENERGY_LIMIT:.0e} J the diagnostics can sum")]
    EnergyOverflow {
        /// `masses` or `stiffness`.
        field: &'static str,
        /// The particle or spring.
        index: usize,
        /// The mass (kg) or stiffness (N/m).
        value: Real,
        /// The energy it could reach (J; may be infinite).
        energy: Real,
    },
    /// A body name that is empty or would break the columns of
    /// `diagnostics.csv` (a comma, a quote or a line break).
    #[error("body name {0:?}: a name must be non-empty, without commas, quotes or line breaks")]
    BadName(String),
    /// Two bodies with the same name.
    #[error("a body named \"{0}\" already exists: body names must be unique")]
    DuplicateName(String),
    /// A join's end names a body the world does not have.
    #[error(
        "join `{end}` names body \"{body}\", which the world does not have (add the bodies first)"
    )]
    JoinUnknownBody {
        /// `a` or `b`.
        end: &'static str,
        /// The name given.
        body: String,
    },
    /// A join's end names a particle its body does not have.
    #[error("join `{end}` = [\"{body}\", {particle}]: particle index out of range (the body has {particles} particles)")]
    JoinParticleOutOfRange {
        /// `a` or `b`.
        end: &'static str,
        /// The body's name.
        body: String,
        /// The index given.
        particle: usize,
        /// The body's particles.
        particles: usize,
    },
    /// A join whose ends are the same particle, or two pinned ones.
    #[error("join: {0}")]
    BadJoin(&'static str),
    /// Limits that contradict each other: a yield strain at or above the
    /// break strain.
    #[error("`yield_strain` = {}: must be below `break_strain` = {} (a spring would break before it could yield)", Readable(*yield_strain), Readable(*break_strain))]
    YieldAboveBreak {
        /// The yield strain given.
        yield_strain: Real,
        /// The break strain given.
        break_strain: Real,
    },
}

/// The largest energy (J) one particle or spring may reach within the
/// world's limits: sums of up to a billion such terms stay finite.
pub const ENERGY_LIMIT: Real = 1e290;

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

/// A number for a message, as written in a scene: plainly between 1e-4
/// and 1e15 in size (and zero), in exponent form beyond (`1e300`, not its
/// three hundred digits).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Readable(pub Real);

impl std::fmt::Display for Readable {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let size = self.0.abs();
        if size == 0.0 || !size.is_finite() || (1e-4..1e15).contains(&size) {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

/// A simulated time (s) for a message: to the microsecond up to 1e9 s, in
/// exponent form beyond.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Seconds(pub Real);

impl std::fmt::Display for Seconds {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        if self.0.abs() < 1e9 || !self.0.is_finite() {
            write!(f, "{:.6}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_in_messages_are_written_as_in_a_scene() {
        // Plain between 1e-4 and 1e15, exponent form beyond: 1e300 is
        // four characters, not 301 digits.
        for (x, shown) in [
            (0.0, "0"),
            (0.25, "0.25"),
            (-3.0, "-3"),
            (1e300, "1e300"),
            (-1e308, "-1e308"),
            (2.5e-7, "2.5e-7"),
            (Real::INFINITY, "inf"),
        ] {
            assert_eq!(Readable(x).to_string(), shown);
        }
        assert_eq!(Seconds(1.5).to_string(), "1.500000");
        assert_eq!(Seconds(1e300).to_string(), "1e300");
    }
}
