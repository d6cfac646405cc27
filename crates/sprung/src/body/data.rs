//! A body as a builder or a scene describes it, particle by particle with
//! indices local to the body ([`BodyData`]), and its springs, rods and
//! muscles; checked by [`BodyData::validate`] (`validate.rs`) before it
//! joins a world.

use std::sync::Arc;

use crate::error::BuildError;
use crate::gas::Gas;
use crate::surface;
use crate::tearing::StrainLimits;
use crate::units::{Real, Vec3};

/// One spring of a [`BodyData`], with particle indices local to the body.
#[derive(Debug, Clone, PartialEq)]
pub struct SpringData {
    /// First (parent) particle index.
    pub first: usize,
    /// Second (child) particle index.
    pub second: usize,
    /// Rest length (m); `None` means the distance at creation.
    pub rest_length: Option<Real>,
    /// Stiffness (N/m).
    pub stiffness: Real,
    /// Damping along the spring (N·s/m).
    pub damping: Real,
    /// Apply the force to the second particle only (docs/physics.md §1).
    pub one_sided: bool,
}

impl SpringData {
    /// A spring between `first` and `second` at its creation length, with
    /// zero stiffness and damping (set them with the body's `with_*`).
    ///
    /// ```
    /// use sprung::{BodyData, SpringData, Vec3};
    ///
    /// let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(3.0, 4.0, 0.0)]);
    /// body.springs.push(SpringData::between(0, 1));
    /// assert_eq!(body.rest_length(&body.springs[0]), 5.0); // the distance at creation
    /// assert_eq!((body.springs[0].stiffness, body.springs[0].damping), (0.0, 0.0));
    /// body.springs[0].rest_length = Some(4.0); // pre-stretched
    /// assert_eq!(body.rest_length(&body.springs[0]), 4.0);
    /// ```
    pub fn between(first: usize, second: usize) -> Self {
        SpringData {
            first,
            second,
            rest_length: None,
            stiffness: 0.0,
            damping: 0.0,
            one_sided: false,
        }
    }
}

/// A rigid rod (distance constraint) of a [`BodyData`], with particle
/// indices local to the body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RodData {
    /// First particle index.
    pub first: usize,
    /// Second particle index.
    pub second: usize,
    /// Length (m); `None` means the distance at creation.
    pub length: Option<Real>,
}

/// How a muscle's rest length changes in time: the factor `s(t)` of
/// `L(t) = L0 s(t)`, with `t` the simulated time (s).
#[derive(Clone)]
pub enum MuscleDrive {
    /// `s(t) = 1 + amplitude sin(2π t / period + phase)`.
    Sine {
        /// Relative amplitude `a` (dimensionless, `|a| < 1`).
        amplitude: Real,
        /// Period `T` (s), positive.
        period: Real,
        /// Phase `φ` (rad).
        phase: Real,
    },
    /// Any function of time (s) giving a positive factor.
    Function(Arc<dyn Fn(Real) -> Real + Send + Sync>),
}

impl MuscleDrive {
    /// The factor `s(t)` at time `time` (s).
    pub fn factor(&self, time: Real) -> Real {
        match self {
            MuscleDrive::Sine {
                amplitude,
                period,
                phase,
            } => 1.0 + amplitude * (std::f64::consts::TAU * time / period + phase).sin(),
            MuscleDrive::Function(f) => f(time),
        }
    }
}

impl std::fmt::Debug for MuscleDrive {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            MuscleDrive::Sine {
                amplitude,
                period,
                phase,
            } => f
                .debug_struct("Sine")
                .field("amplitude", amplitude)
                .field("period", period)
                .field("phase", phase)
                .finish(),
            MuscleDrive::Function(_) => f.write_str("Function(..)"),
        }
    }
}

impl PartialEq for MuscleDrive {
    /// Sines with equal parameters, or the same function.
    fn eq(&self, other: &Self) -> bool {
        match (self, other) {
            (
                MuscleDrive::Sine {
                    amplitude: a,
                    period: p,
                    phase: f,
                },
                MuscleDrive::Sine {
                    amplitude: b,
                    period: q,
                    phase: g,
                },
            ) => a == b && p == q && f == g,
            (MuscleDrive::Function(a), MuscleDrive::Function(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

/// A muscle of a [`BodyData`]: a spring whose rest length changes in time.
#[derive(Debug, Clone, PartialEq)]
pub struct MuscleData {
    /// Index of the spring in [`BodyData::springs`].
    pub spring: usize,
    /// How its rest length `L0 s(t)` changes ([`MuscleDrive`]).
    pub drive: MuscleDrive,
}

/// A body described particle by particle, before it joins a world.
///
/// Builders ([`crate::build`]) return one; scene files fill one in. Nothing
/// is trusted: [`BodyData::validate`] (called by `World::add_body`) refuses
/// bad masses, indices, duplicate or zero-length springs with a message
/// naming the field.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyData {
    /// Particle positions (m).
    pub position: Vec<Vec3>,
    /// Particle velocities (m/s): one per particle, or empty for all zero.
    pub velocity: Vec<Vec3>,
    /// Particle masses (kg): one per particle.
    pub mass: Vec<Real>,
    /// Indices of pinned particles (left out of integration).
    pub pinned: Vec<usize>,
    /// Springs between particles of this body.
    pub springs: Vec<SpringData>,
    /// Triangles (particle indices, counter-clockwise seen from outside) for
    /// normals, wind, pressure and rendering; may be empty.
    pub faces: Vec<[usize; 3]>,
    /// Segments `[from, to]` of a closed 2D loop in the xy-plane
    /// (counter-clockwise), the 2D counterpart of `faces`; may be empty.
    pub segments: Vec<[usize; 2]>,
    /// The gas inside, for a closed body (`faces` or `segments` closed).
    pub gas: Option<Gas>,
    /// How the body takes part in contacts between bodies.
    pub contact: BodyContact,
    /// Rigid rods between particles of this body (distance constraints).
    pub rods: Vec<RodData>,
    /// Springs of this body whose rest lengths change in time.
    pub muscles: Vec<MuscleData>,
    /// The body keeps every pairwise distance (a rigid body; shape
    /// matching in the constraint stage). Default false.
    pub rigid: bool,
    /// The body takes part in mutual gravitation when the world has a
    /// [`crate::forces::Gravitation`] force. Default true.
    pub gravitating: bool,
    /// The strains past which the body's springs yield and break (scene
    /// keys `yield_strain`, `break_strain`, `hardening`). Default: never.
    pub limits: StrainLimits,
}

impl Default for BodyData {
    fn default() -> Self {
        BodyData {
            position: Vec::new(),
            velocity: Vec::new(),
            mass: Vec::new(),
            pinned: Vec::new(),
            springs: Vec::new(),
            faces: Vec::new(),
            segments: Vec::new(),
            gas: None,
            contact: BodyContact::default(),
            rods: Vec::new(),
            muscles: Vec::new(),
            rigid: false,
            gravitating: true,
            limits: StrainLimits::default(),
        }
    }
}

/// How a body takes part in contacts between bodies (per-body keys
/// `collide` and `self_collision`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BodyContact {
    /// Collides with other bodies. Default true.
    pub collide: bool,
    /// Collides with itself (a cloth folding onto itself). Default false.
    /// Needs faces or segments.
    pub self_collision: bool,
}

impl Default for BodyContact {
    fn default() -> Self {
        BodyContact {
            collide: true,
            self_collision: false,
        }
    }
}

impl BodyData {
    /// A body with particles at `position` (m), each of mass 1 kg, at rest,
    /// with no springs.
    ///
    /// ```
    /// use sprung::{BodyData, Vec3};
    ///
    /// let body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    /// assert_eq!(body.particle_count(), 2);
    /// assert_eq!(body.mass, [1.0, 1.0]);
    /// assert!(body.velocity.is_empty() && body.springs.is_empty() && body.pinned.is_empty());
    /// assert_eq!(body.validate(), Ok(()));
    /// ```
    pub fn from_positions(position: Vec<Vec3>) -> Self {
        let mass = vec![1.0; position.len()];
        BodyData {
            position,
            mass,
            ..Default::default()
        }
    }

    /// Number of particles.
    pub fn particle_count(&self) -> usize {
        self.position.len()
    }

    /// Give every particle the mass `mass` (kg).
    ///
    /// ```
    /// use sprung::{BodyData, Vec3};
    ///
    /// let body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y]).with_mass(0.5);
    /// assert_eq!(body.mass, [0.5; 3]);
    /// ```
    pub fn with_mass(mut self, mass: Real) -> Self {
        self.mass = vec![mass; self.position.len()];
        self
    }

    /// Share `total_mass` (kg) equally among the particles.
    ///
    /// ```
    /// use sprung::build;
    ///
    /// let rope = build::rope(8, 1.0).unwrap().with_total_mass(2.0);
    /// assert_eq!(rope.mass, [0.25; 8]);
    /// ```
    pub fn with_total_mass(self, total_mass: Real) -> Self {
        let count = self.position.len().max(1) as Real;
        self.with_mass(total_mass / count)
    }

    /// Give every spring the stiffness `stiffness` (N/m).
    ///
    /// A spring of `k = 300 N/m` stretched by 1/8 m stores `½ k (1/8)²`
    /// (exact: binary fractions throughout):
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, Vec3, World};
    ///
    /// let rope = build::rope(3, 1.0).unwrap().with_stiffness(300.0).with_damping(2.0);
    /// assert!(rope.springs.iter().all(|s| s.stiffness == 300.0 && s.damping == 2.0));
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.set_gravity(Vec3::ZERO);
    /// world.add_body("rope", rope).unwrap();
    /// world.particles.position[2].y -= 0.125; // the last spring: 0.5 m to 0.625 m
    /// assert_eq!(world.energies().get("spring"), Some(0.5 * 300.0 * 0.125 * 0.125));
    /// ```
    pub fn with_stiffness(mut self, stiffness: Real) -> Self {
        self.springs
            .iter_mut()
            .for_each(|s| s.stiffness = stiffness);
        self
    }

    /// Give every spring the damping `damping` (N·s/m).
    pub fn with_damping(mut self, damping: Real) -> Self {
        self.springs.iter_mut().for_each(|s| s.damping = damping);
        self
    }

    /// Make every spring one-sided (or two-sided again).
    pub fn with_one_sided(mut self, one_sided: bool) -> Self {
        self.springs
            .iter_mut()
            .for_each(|s| s.one_sided = one_sided);
        self
    }

    /// The same body with its particles numbered anew: particle `p` becomes
    /// particle `number[p]`, in every list that names particles (positions,
    /// velocities, masses, pins, springs, faces, segments, rods). Refused
    /// unless `number` numbers each particle once. The world reads a
    /// numbering with no locality more slowly (its springs' particles are
    /// gathered from all over), and renumbers the springs it finds so for
    /// its spring force on its own; this is for tests, benchmarks and
    /// meshes a user wants in another order.
    pub fn renumbered(&self, number: &[usize]) -> Result<BodyData, BuildError> {
        let particles = self.position.len();
        let mut seen = vec![false; particles];
        for (index, &value) in number.iter().enumerate() {
            if value >= particles || seen[value] {
                return Err(BuildError::NotARenumbering {
                    particles,
                    index,
                    value,
                });
            }
            seen[value] = true;
        }
        if number.len() != particles {
            return Err(BuildError::LengthMismatch {
                field: "number",
                expected: particles,
                found: number.len(),
                what: "particles",
            });
        }
        let new = |p: usize| number.get(p).copied().unwrap_or(p);
        let mut body = self.clone();
        body.position = moved(number, &self.position);
        body.velocity = moved(number, &self.velocity);
        body.mass = moved(number, &self.mass);
        body.pinned = self.pinned.iter().map(|&p| new(p)).collect();
        for spring in &mut body.springs {
            (spring.first, spring.second) = (new(spring.first), new(spring.second));
        }
        for face in &mut body.faces {
            *face = face.map(new);
        }
        for segment in &mut body.segments {
            *segment = segment.map(new);
        }
        for rod in &mut body.rods {
            (rod.first, rod.second) = (new(rod.first), new(rod.second));
        }
        Ok(body)
    }

    /// Pin the particles at `indices`.
    ///
    /// A cloth hung by its two top corners: they stay put, the rest falls:
    ///
    /// ```
    /// use sprung::build::{self, ClothSprings};
    /// use sprung::{IntegratorKind, Vec3, World};
    ///
    /// let cloth = build::cloth(3, 3, 1.0, 1.0, ClothSprings::default()).unwrap();
    /// let cloth = cloth.with_stiffness(100.0).with_pinned(vec![6, 8]); // (0, 2), (2, 2)
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.add_body("cloth", cloth).unwrap();
    /// for _ in 0..100 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// assert!(world.particles.is_pinned(6));
    /// assert_eq!(world.particles.position[6], Vec3::new(0.0, 1.0, 0.0));
    /// assert_eq!(world.particles.position[8], Vec3::new(1.0, 1.0, 0.0));
    /// assert!(world.particles.position[0].y < 0.0);
    /// ```
    pub fn with_pinned(mut self, indices: Vec<usize>) -> Self {
        self.pinned = indices;
        self
    }

    /// Give every particle the velocity `velocity` (m/s).
    pub fn with_velocity(mut self, velocity: Vec3) -> Self {
        self.velocity = vec![velocity; self.position.len()];
        self
    }

    /// Add the velocity of a spin `spin` (rad/s, about an axis through the
    /// body's centre of mass) to every particle's: `ω × (x − c)`, with `c`
    /// the centre of mass (its particles' masses; their mean where those
    /// do not add up to a positive mass). Pinned particles (see
    /// [`BodyData::pinned`]) keep their velocity.
    ///
    /// ```
    /// use sprung::{BodyData, Vec3};
    ///
    /// let body = BodyData::from_positions(vec![-Vec3::X, Vec3::X]).with_spin(2.0 * Vec3::Z);
    /// assert_eq!(body.velocity, [-2.0 * Vec3::Y, 2.0 * Vec3::Y]);
    /// ```
    pub fn with_spin(mut self, spin: Vec3) -> Self {
        let total: Real = self.mass.iter().sum();
        let centre = if total > 0.0 && total.is_finite() {
            self.position
                .iter()
                .zip(&self.mass)
                .map(|(x, m)| *x * *m)
                .sum::<Vec3>()
                / total
        } else {
            self.position.iter().sum::<Vec3>() / self.position.len().max(1) as Real
        };
        self.velocity.resize(self.position.len(), Vec3::ZERO);
        for (i, (v, x)) in self.velocity.iter_mut().zip(&self.position).enumerate() {
            if !self.pinned.contains(&i) {
                *v += spin.cross(*x - centre);
            }
        }
        self
    }

    /// Place the body: scale by `scale` (uniform, about the origin), then
    /// rotate by `rotate_degrees` about x, then y, then z, then translate
    /// by `translate` (m). Explicit rest lengths scale too; velocities turn
    /// with the rotation.
    ///
    /// Scaled twice, turned a quarter turn about z, moved 5 m along x:
    ///
    /// ```
    /// use sprung::{BodyData, SpringData, Vec3};
    ///
    /// let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]).with_velocity(Vec3::X);
    /// body.springs = vec![SpringData { rest_length: Some(0.8), ..SpringData::between(0, 1) }];
    /// let body = body.placed(2.0, Vec3::new(0.0, 0.0, 90.0), Vec3::new(5.0, 0.0, 0.0));
    /// assert_eq!(body.position[0], Vec3::new(5.0, 0.0, 0.0));
    /// // cos 90° is not exactly 0 in floating point: a rounding off.
    /// assert!(body.position[1].distance(Vec3::new(5.0, 2.0, 0.0)) < 1e-15);
    /// assert!(body.velocity[1].distance(Vec3::Y) < 1e-15); // turned, not scaled
    /// assert_eq!(body.springs[0].rest_length, Some(1.6));
    /// ```
    pub fn placed(mut self, scale: Real, rotate_degrees: Vec3, translate: Vec3) -> Self {
        let rotation = glam::DQuat::from_rotation_z(rotate_degrees.z.to_radians())
            * glam::DQuat::from_rotation_y(rotate_degrees.y.to_radians())
            * glam::DQuat::from_rotation_x(rotate_degrees.x.to_radians());
        for p in &mut self.position {
            *p = rotation * (*p * scale) + translate;
        }
        for v in &mut self.velocity {
            *v = rotation * *v;
        }
        for s in &mut self.springs {
            if let Some(length) = s.rest_length.as_mut() {
                *length *= scale;
            }
        }
        for r in &mut self.rods {
            if let Some(length) = r.length.as_mut() {
                *length *= scale;
            }
        }
        self
    }

    /// True when the faces form a closed, consistently oriented surface, or
    /// the segments closed loops (so the body encloses a volume or area).
    pub fn is_closed(&self) -> bool {
        if !self.faces.is_empty() {
            surface::check_closed_faces(&self.faces).is_ok()
        } else {
            !self.segments.is_empty() && surface::check_closed_loop(&self.segments).is_ok()
        }
    }

    /// Length of `rod` (m): the given one, or the distance at creation.
    pub fn rod_length(&self, rod: &RodData) -> Real {
        rod.length
            .unwrap_or_else(|| self.position[rod.first].distance(self.position[rod.second]))
    }

    /// Rest length of `spring` (m): the given one, or the distance at creation.
    pub fn rest_length(&self, spring: &SpringData) -> Real {
        spring
            .rest_length
            .unwrap_or_else(|| self.position[spring.first].distance(self.position[spring.second]))
    }
}

/// `list` with entry `p` moved to `number[p]`, when it has one entry per
/// renumbered particle; as it is otherwise (an empty list of velocities).
fn moved<T: Copy>(number: &[usize], list: &[T]) -> Vec<T> {
    let mut out = list.to_vec();
    if list.len() == number.len() {
        for (p, &n) in number.iter().enumerate() {
            out[n] = list[p];
        }
    }
    out
}
