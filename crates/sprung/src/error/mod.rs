//! Errors of the engine: building a body from a user's description, and
//! stepping a world whose state has become non-finite or run away.
//!
//! Every message names the offending field (with the scene-file key the
//! user wrote) and the index, so a loader can add the file and line.

use crate::surface::SurfaceProblem;
use crate::units::Real;
use thiserror::Error;

mod step;

pub use step::{BlowUpReason, SolverError, StepError};

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
