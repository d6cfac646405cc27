//! The TOML tables of a scene file, as serde reads them. Every table denies
//! unknown keys, so a misspelt key is an error naming it.

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;
use toml::Spanned;

/// The whole file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SceneFile {
    pub sim: Spanned<SimTable>,
    /// Bodies given in the rest of the file (an inline `body = [...]`, or
    /// every `[[body]]` of a file read whole); `Some` even when empty, so a
    /// `body` key beside `[[body]]` sections is seen.
    #[serde(default)]
    pub body: Option<Vec<Spanned<BodyTable>>>,
    #[serde(default)]
    pub collider: Vec<Spanned<ColliderTable>>,
    #[serde(default)]
    pub wind: Option<Spanned<WindTable>>,
    #[serde(default)]
    pub camera: Option<Spanned<CameraTable>>,
    #[serde(default)]
    pub contact: Option<Spanned<ContactTable>>,
    #[serde(default)]
    pub gravitation: Option<Spanned<GravitationTable>>,
    #[serde(default)]
    pub join: Vec<Spanned<JoinTable>>,
}

/// `[[join]]`: a spring or rod between particles of two bodies.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JoinTable {
    /// `["BODY", i]`: particle `i` of the body named `BODY`.
    pub a: (String, usize),
    /// The other end, as `a`.
    pub b: (String, usize),
    #[serde(default)]
    pub stiffness: Option<f64>,
    #[serde(default)]
    pub damping: Option<f64>,
    #[serde(default)]
    pub rest_length: Option<f64>,
    #[serde(default)]
    pub rod: Option<bool>,
    #[serde(default)]
    pub break_strain: Option<f64>,
}

/// One `[[body]]` section of the file, parsed on its own.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BodySection {
    pub body: Vec<Spanned<BodyTable>>,
}

/// `[gravitation]`: mutual gravitation between the bodies' particles.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GravitationTable {
    /// `G` (N·m²/kg²).
    #[serde(default)]
    pub constant: Option<f64>,
    /// Softening length (m).
    #[serde(default)]
    pub softening: Option<f64>,
}

/// `[contact]`: how bodies touch each other.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ContactTable {
    #[serde(default)]
    pub enabled: Option<bool>,
    #[serde(default)]
    pub thickness: Option<f64>,
    #[serde(default)]
    pub friction: Option<f64>,
    #[serde(default)]
    pub stiffness: Option<f64>,
    #[serde(default)]
    pub damping: Option<f64>,
    #[serde(default)]
    pub ccd: Option<bool>,
}

/// `[camera]`: where pictures of the scene are taken from.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct CameraTable {
    #[serde(default)]
    pub eye: Option<Vec<f64>>,
    #[serde(default)]
    pub target: Option<Vec<f64>>,
    #[serde(default)]
    pub fov: Option<f64>,
}

/// `[wind]`: wind on every surface.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct WindTable {
    pub velocity: Vec<f64>,
    #[serde(default)]
    pub model: Option<String>,
    #[serde(default)]
    pub coefficient: Option<f64>,
    #[serde(default)]
    pub air_density: Option<f64>,
    #[serde(default)]
    pub lift: Option<f64>,
    #[serde(default)]
    pub gust: Option<GustTable>,
    #[serde(default)]
    pub turbulence: Option<TurbulenceTable>,
    #[serde(default)]
    pub seed: Option<u64>,
}

/// `gust = { amplitude, period }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GustTable {
    pub amplitude: f64,
    pub period: f64,
}

/// `turbulence = { amplitude, length_scale, time_scale }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct TurbulenceTable {
    pub amplitude: f64,
    pub length_scale: f64,
    pub time_scale: f64,
}

/// `[sim]`: time stepping and world settings.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SimTable {
    /// Time step (s).
    pub dt: f64,
    /// Integrator name.
    #[serde(default)]
    pub integrator: Option<String>,
    /// Where the steps run: "cpu" or "gpu".
    #[serde(default)]
    pub device: Option<String>,
    /// Gravity (m/s²).
    #[serde(default)]
    pub gravity: Option<Vec<f64>>,
    /// Simulated duration (s).
    #[serde(default)]
    pub duration: Option<f64>,
    /// Number of steps.
    #[serde(default)]
    pub steps: Option<u64>,
    /// Global air drag (N·s/m).
    #[serde(default)]
    pub air_drag: Option<f64>,
    /// Record every K steps.
    #[serde(default)]
    pub every: Option<u64>,
    /// Blow-up limit on distance from the origin (m).
    #[serde(default)]
    pub max_distance: Option<f64>,
    /// Blow-up limit on speed (m/s).
    #[serde(default)]
    pub max_speed: Option<f64>,
    /// Relative residual of implicit Euler's linear solves.
    #[serde(default)]
    pub solver_tolerance: Option<f64>,
    /// Most conjugate-gradient iterations per solve (implicit Euler).
    #[serde(default)]
    pub max_iterations: Option<u32>,
    /// Newton iterations per step (implicit Euler).
    #[serde(default)]
    pub newton_iterations: Option<u32>,
    /// Local/global iterations per step (projective).
    #[serde(default)]
    pub iterations: Option<u32>,
    /// Implicit Euler's preconditioner: "auto", "jacobi", "laplacian" or
    /// "stiffness".
    #[serde(default)]
    pub preconditioner: Option<String>,
    /// rk45's local error tolerance.
    #[serde(default)]
    pub error_tolerance: Option<f64>,
    /// Substeps per step: a count, or "auto".
    #[serde(default)]
    pub substeps: Option<SubstepsValue>,
    /// Relative length error the rods' projection stops at.
    #[serde(default)]
    pub constraint_tolerance: Option<f64>,
    /// Most sweeps over the rods per step.
    #[serde(default)]
    pub constraint_iterations: Option<u32>,
}

/// `substeps = N` or `substeps = "auto"`; anything else (a fraction, a
/// list) is kept to be refused in words.
#[derive(Debug, Deserialize)]
#[serde(untagged)]
pub(crate) enum SubstepsValue {
    Count(i64),
    Name(String),
    Other(toml::Value),
}

/// `[[body]]`: one body, from a builder or given particle by particle.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct BodyTable {
    pub name: String,
    // Explicit body.
    #[serde(default)]
    pub particles: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    pub springs: Option<Vec<[usize; 2]>>,
    #[serde(default)]
    pub rest_lengths: Option<Vec<f64>>,
    #[serde(default)]
    pub faces: Option<Vec<[usize; 3]>>,
    #[serde(default)]
    pub segments: Option<Vec<[usize; 2]>>,
    // Builders.
    #[serde(default)]
    pub rope: Option<RopeTable>,
    #[serde(default)]
    pub cloth: Option<ClothTable>,
    #[serde(default)]
    pub lattice: Option<LatticeTable>,
    #[serde(default)]
    pub ring: Option<RingTable>,
    #[serde(default)]
    pub sphere: Option<SphereTable>,
    #[serde(default)]
    pub mesh: Option<String>,
    #[serde(default)]
    pub object: Option<String>,
    #[serde(default)]
    pub refine: Option<usize>,
    // Springs of surface bodies (sphere, mesh).
    #[serde(default)]
    pub bending: Option<bool>,
    #[serde(default)]
    pub internal: Option<String>,
    #[serde(default)]
    pub lattice_spacing: Option<f64>,
    // The gas inside a closed body.
    #[serde(default)]
    pub gas: Option<GasTable>,
    // The factor of the `[wind]` this body feels.
    #[serde(default)]
    pub wind_scale: Option<f64>,
    /// Collides with other bodies (default true).
    #[serde(default)]
    pub collide: Option<bool>,
    /// Collides with itself (default false).
    #[serde(default)]
    pub self_collision: Option<bool>,
    // Constraints and drives.
    #[serde(default)]
    pub rods: Option<Vec<[usize; 2]>>,
    #[serde(default)]
    pub rod_lengths: Option<Vec<f64>>,
    #[serde(default)]
    pub muscles: Option<Vec<MuscleTable>>,
    /// Keeps its shape (default false).
    #[serde(default)]
    pub rigid: Option<bool>,
    /// Takes part in `[gravitation]` (default true).
    #[serde(default)]
    pub gravitating: Option<bool>,
    /// Strain past which the body's springs break.
    #[serde(default)]
    pub break_strain: Option<f64>,
    /// Strain past which the body's springs' rest lengths move.
    #[serde(default)]
    pub yield_strain: Option<f64>,
    /// Linear hardening of the yield strain (default 0).
    #[serde(default)]
    pub hardening: Option<f64>,
    // Keys every body accepts.
    #[serde(default)]
    pub mass: Option<f64>,
    #[serde(default)]
    pub masses: Option<Vec<f64>>,
    #[serde(default)]
    pub total_mass: Option<f64>,
    #[serde(default)]
    pub stiffness: Option<PerSpring>,
    #[serde(default)]
    pub damping: Option<PerSpring>,
    #[serde(default)]
    pub one_sided: Option<bool>,
    #[serde(default)]
    pub pinned: Option<Vec<usize>>,
    #[serde(default)]
    pub velocity: Option<Vec<f64>>,
    #[serde(default)]
    pub velocities: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    pub spin: Option<Vec<f64>>,
    #[serde(default)]
    pub scale: Option<f64>,
    #[serde(default)]
    pub rotate: Option<Vec<f64>>,
    #[serde(default)]
    pub translate: Option<Vec<f64>>,
}

/// `muscles = [{ spring, amplitude, period, phase }, ...]`: one muscle.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct MuscleTable {
    /// Index of the spring (in the order the body made them).
    pub spring: usize,
    /// Relative amplitude of the rest length.
    pub amplitude: f64,
    /// Period (s).
    pub period: f64,
    /// Phase (rad).
    #[serde(default)]
    pub phase: Option<f64>,
}

/// `rope = { particles, length }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RopeTable {
    pub particles: usize,
    pub length: f64,
}

/// `cloth = { nx, ny, width, height, structural, shear, bending }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ClothTable {
    pub nx: usize,
    pub ny: usize,
    pub width: f64,
    pub height: f64,
    #[serde(default = "yes")]
    pub structural: bool,
    #[serde(default = "yes")]
    pub shear: bool,
    #[serde(default = "yes")]
    pub bending: bool,
}

fn yes() -> bool {
    true
}

/// `lattice = { nx, ny, nz, spacing }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct LatticeTable {
    pub nx: usize,
    pub ny: usize,
    pub nz: usize,
    pub spacing: f64,
}

/// `ring = { particles, radius }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct RingTable {
    pub particles: usize,
    pub radius: f64,
}

/// `sphere = { radius, subdivisions }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SphereTable {
    pub radius: f64,
    #[serde(default = "default_subdivisions")]
    pub subdivisions: usize,
}

fn default_subdivisions() -> usize {
    2
}

/// `gas = { nrt, ramp_time, schedule, leak_rate, leak_start, volume }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct GasTable {
    pub nrt: f64,
    #[serde(default)]
    pub ramp_time: Option<f64>,
    #[serde(default)]
    pub schedule: Option<Vec<[f64; 2]>>,
    #[serde(default)]
    pub leak_rate: Option<f64>,
    #[serde(default)]
    pub leak_start: Option<f64>,
    #[serde(default)]
    pub volume: Option<String>,
}

/// `[[collider]]`: a shape and its contact response.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct ColliderTable {
    #[serde(default)]
    pub plane: Option<PlaneTable>,
    #[serde(default)]
    pub sphere: Option<SphereColliderTable>,
    /// Keyframes `[time, x, y, z]`: the displacement of a moving collider.
    #[serde(default)]
    pub path: Option<Vec<Vec<f64>>>,
    #[serde(default)]
    pub restitution: Option<f64>,
    #[serde(default)]
    pub friction: Option<f64>,
    #[serde(default)]
    pub penalty_stiffness: Option<f64>,
    #[serde(default)]
    pub penalty_damping: Option<f64>,
}

/// `sphere = { centre, radius }` on a collider (`center` accepted too, as
/// `internal = "center"` is).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct SphereColliderTable {
    #[serde(alias = "center")]
    pub centre: Vec<f64>,
    pub radius: f64,
}

/// `plane = { point, normal }`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PlaneTable {
    pub point: Vec<f64>,
    pub normal: Vec<f64>,
}

/// A value for every spring, or one per spring.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum PerSpring {
    All(f64),
    Each(Vec<f64>),
}

impl<'de> Deserialize<'de> for PerSpring {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct PerSpringVisitor;
        impl<'de> Visitor<'de> for PerSpringVisitor {
            type Value = PerSpring;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a number or a list of numbers, one per spring")
            }
            fn visit_f64<E: de::Error>(self, v: f64) -> Result<PerSpring, E> {
                Ok(PerSpring::All(v))
            }
            fn visit_i64<E: de::Error>(self, v: i64) -> Result<PerSpring, E> {
                Ok(PerSpring::All(v as f64))
            }
            fn visit_u64<E: de::Error>(self, v: u64) -> Result<PerSpring, E> {
                Ok(PerSpring::All(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<PerSpring, A::Error> {
                let mut values = Vec::new();
                while let Some(v) = seq.next_element::<f64>()? {
                    values.push(v);
                }
                Ok(PerSpring::Each(values))
            }
        }
        deserializer.deserialize_any(PerSpringVisitor)
    }
}
