//! Bodies: the description a builder or a scene gives ([`BodyData`], local
//! indices, checked before use) and the body as the world stores it
//! ([`Body`], ranges into the world's particle and spring arrays).

use std::collections::HashMap;
use std::ops::Range;
use std::sync::Arc;

use crate::error::BuildError;
use crate::gas::Gas;
use crate::surface;
use crate::{Real, Vec3};

/// Rods agree to a billionth of their length (the tolerance the constrain
/// stage converges to by default).
const ROD_SLACK: Real = 1e-9;

/// Steps the search for paths of rods shorter than a rod may take (a
/// particle reached, or a rod looked at), over all of a body's rods: past
/// it, the remaining rods are not checked.
pub const ROD_SEARCH_LIMIT: usize = 10_000_000;

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
    pub fn with_mass(mut self, mass: Real) -> Self {
        self.mass = vec![mass; self.position.len()];
        self
    }

    /// Share `total_mass` (kg) equally among the particles.
    pub fn with_total_mass(self, total_mass: Real) -> Self {
        let count = self.position.len().max(1) as Real;
        self.with_mass(total_mass / count)
    }

    /// Give every spring the stiffness `stiffness` (N/m).
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
    pub fn with_pinned(mut self, indices: Vec<usize>) -> Self {
        self.pinned = indices;
        self
    }

    /// Give every particle the velocity `velocity` (m/s).
    pub fn with_velocity(mut self, velocity: Vec3) -> Self {
        self.velocity = vec![velocity; self.position.len()];
        self
    }

    /// Place the body: scale by `scale` (uniform, about the origin), then
    /// rotate by `rotate_degrees` about x, then y, then z, then translate
    /// by `translate` (m). Explicit rest lengths scale too; velocities turn
    /// with the rotation.
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

    /// Check everything a user could get wrong; the first problem found is
    /// returned, naming the scene key and index.
    pub fn validate(&self) -> Result<(), BuildError> {
        let count = self.position.len();
        if count == 0 {
            return Err(BuildError::NoParticles);
        }
        self.validate_particles(count)?;
        self.validate_springs(count)?;
        self.validate_faces(count)?;
        self.validate_segments(count)?;
        self.validate_gas()?;
        self.validate_rods(count)?;
        self.validate_muscles()?;
        if self.rigid && count < 2 {
            return Err(BuildError::RigidTooSmall);
        }
        if self.rigid && !self.pinned.is_empty() {
            return Err(BuildError::RigidPinned);
        }
        if self.rigid && !self.muscles.is_empty() {
            return Err(BuildError::RigidMuscles);
        }
        if self.contact.self_collision && self.faces.is_empty() && self.segments.is_empty() {
            return Err(BuildError::SelfCollisionWithoutSurface);
        }
        if self.contact.self_collision && !self.contact.collide {
            return Err(BuildError::SelfCollisionWithoutCollide);
        }
        Ok(())
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

    fn validate_segments(&self, count: usize) -> Result<(), BuildError> {
        for (segment, &[a, b]) in self.segments.iter().enumerate() {
            if a >= count || b >= count || a == b {
                return Err(BuildError::BadSegment {
                    segment,
                    indices: [a, b],
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_gas(&self) -> Result<(), BuildError> {
        let Some(gas) = &self.gas else {
            return Ok(());
        };
        gas.validate()?;
        let closed = if !self.faces.is_empty() {
            surface::check_closed_faces(&self.faces)
        } else if !self.segments.is_empty() {
            surface::check_closed_loop(&self.segments)
        } else {
            return Err(BuildError::GasWithoutSurface);
        };
        closed.map_err(|problem| BuildError::OpenSurface { problem })?;
        if self.faces.is_empty() {
            // A 2D gas takes the area its loop encloses in the xy-plane. A
            // z of a billionth of the body's size (or speed) is rounding: a
            // ring turned half a turn about x has z of some 1e-17.
            let off = |vectors: &[Vec3], what| {
                let size = vectors
                    .iter()
                    .fold(0.0, |m: Real, v| m.max(v.x.abs()).max(v.y.abs()));
                vectors
                    .iter()
                    .position(|v| v.z.abs() > 1e-9 * size)
                    .map(|particle| BuildError::GasOffPlane {
                        particle,
                        what,
                        value: vectors[particle].z,
                    })
            };
            if let Some(error) =
                off(&self.position, "z").or_else(|| off(&self.velocity, "velocity z"))
            {
                return Err(error);
            }
        }
        Ok(())
    }

    fn validate_particles(&self, count: usize) -> Result<(), BuildError> {
        check_len("masses", self.mass.len(), count, "particles")?;
        if !self.velocity.is_empty() {
            check_len("velocities", self.velocity.len(), count, "particles")?;
        }
        for (index, p) in self.position.iter().enumerate() {
            check_finite_vec("particles", index, *p)?;
        }
        for (index, v) in self.velocity.iter().enumerate() {
            check_finite_vec("velocities", index, *v)?;
        }
        for (index, &m) in self.mass.iter().enumerate() {
            if !(m.is_finite() && m > 0.0) {
                return Err(BuildError::BadMass {
                    field: "masses",
                    index,
                    value: m,
                });
            }
        }
        for (entry, &index) in self.pinned.iter().enumerate() {
            if index >= count {
                return Err(BuildError::PinnedOutOfRange {
                    entry,
                    index,
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_springs(&self, count: usize) -> Result<(), BuildError> {
        let mut seen: HashMap<(usize, usize), usize> = HashMap::with_capacity(self.springs.len());
        for (index, s) in self.springs.iter().enumerate() {
            let (first, second) = (s.first, s.second);
            if let Some(bad) = [first, second].into_iter().find(|&i| i >= count) {
                return Err(BuildError::SpringIndexOutOfRange {
                    spring: index,
                    first,
                    second,
                    bad,
                    particles: count,
                });
            }
            if first == second {
                return Err(BuildError::SelfSpring {
                    spring: index,
                    particle: first,
                });
            }
            let key = (first.min(second), first.max(second));
            if let Some(&earlier) = seen.get(&key) {
                return Err(BuildError::DuplicateSpring {
                    spring: index,
                    earlier,
                    first,
                    second,
                });
            }
            seen.insert(key, index);
            for (field, value) in [("stiffness", s.stiffness), ("damping", s.damping)] {
                if !value.is_finite() {
                    return Err(BuildError::NotFinite {
                        field,
                        index,
                        value,
                    });
                }
                if value < 0.0 {
                    return Err(BuildError::NegativeSpringCoefficient {
                        field,
                        spring: index,
                        value,
                    });
                }
            }
            let length = self.rest_length(s);
            if !length.is_finite() {
                return Err(BuildError::NotFinite {
                    field: "rest_lengths",
                    index,
                    value: length,
                });
            }
            if length <= 0.0 {
                return Err(BuildError::ZeroLengthSpring {
                    spring: index,
                    first,
                    second,
                    length,
                });
            }
        }
        Ok(())
    }

    fn validate_faces(&self, count: usize) -> Result<(), BuildError> {
        for (face, &indices) in self.faces.iter().enumerate() {
            let reason = if indices.iter().any(|&i| i >= count) {
                Some("particle index out of range")
            } else if indices[0] == indices[1]
                || indices[1] == indices[2]
                || indices[0] == indices[2]
            {
                Some("a face needs three different particles")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(BuildError::BadFace {
                    face,
                    indices,
                    reason,
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_rods(&self, count: usize) -> Result<(), BuildError> {
        for (rod, r) in self.rods.iter().enumerate() {
            if let Some(bad) = [r.first, r.second].into_iter().find(|&i| i >= count) {
                return Err(BuildError::RodIndexOutOfRange {
                    rod,
                    bad,
                    particles: count,
                });
            }
            let length = self.rod_length(r);
            if r.first == r.second || !(length.is_finite() && length > 0.0) {
                return Err(BuildError::BadRodLength { rod, length });
            }
            let pinned = |i| self.pinned.contains(&i);
            if pinned(r.first) && pinned(r.second) {
                return Err(BuildError::PinnedRod { rod });
            }
        }
        self.validate_rod_lengths()
    }

    /// Refuse rods whose lengths cannot all hold at once: two on the same
    /// two particles at different lengths, or a rod longer than a path of
    /// other rods joining its two ends (they would have to stretch; the
    /// constrain stage would pull forever and pump energy in). Three rods
    /// on a triangle, one longer than the other two together, are the
    /// commonest case. Each rod's ends are joined by the shortest path of
    /// the others shorter than it (Dijkstra's search, given up at the
    /// rod's length, so a rod among longer ones costs no more than its
    /// neighbours; it starts from the end with fewer rods); past
    /// [`ROD_SEARCH_LIMIT`] steps in all, the remaining rods are not
    /// checked. Lengths all taken from the positions always hold.
    fn validate_rod_lengths(&self) -> Result<(), BuildError> {
        // Lengths taken from the positions hold at once (they are the
        // distances of one placement), to rounding far below the slack.
        if self.rods.iter().all(|r| r.length.is_none()) {
            return Ok(());
        }
        let mut rod_of: HashMap<(usize, usize), usize> = HashMap::with_capacity(self.rods.len());
        let mut ends: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
        for (rod, r) in self.rods.iter().enumerate() {
            let key = (r.first.min(r.second), r.first.max(r.second));
            if let Some(&other) = rod_of.get(&key) {
                let (length, other_length) =
                    (self.rod_length(r), self.rod_length(&self.rods[other]));
                if (length - other_length).abs() > ROD_SLACK * length.max(other_length) {
                    return Err(BuildError::ConflictingRods {
                        rod,
                        length,
                        other,
                        other_length,
                    });
                }
                continue;
            }
            rod_of.insert(key, rod);
            ends.entry(key.0).or_default().push((key.1, rod));
            ends.entry(key.1).or_default().push((key.0, rod));
        }
        let mut budget = ROD_SEARCH_LIMIT;
        for (rod, r) in self.rods.iter().enumerate() {
            let key = (r.first.min(r.second), r.first.max(r.second));
            if rod_of.get(&key) != Some(&rod) {
                continue;
            }
            let length = self.rod_length(r);
            // From the end with fewer rods: a hub of many rods is reached
            // last, if at all.
            let degree = |p: usize| ends.get(&p).map_or(0, Vec::len);
            let (from, to) = if degree(r.first) <= degree(r.second) {
                (r.first, r.second)
            } else {
                (r.second, r.first)
            };
            let Some((mut path, together)) =
                self.shorter_path(&ends, rod, from, to, length, &mut budget)
            else {
                if budget == 0 {
                    break;
                }
                continue;
            };
            if from != r.first {
                path.reverse();
            }
            return Err(BuildError::RodLoop {
                rod,
                length,
                path,
                together,
            });
        }
        Ok(())
    }

    /// The rods (in order from `from` to `to`) of the shortest path between
    /// them through rods other than `rod`, and its length (m), if it is
    /// shorter than `length` (m) by more than [`ROD_SLACK`]. Each particle
    /// reached takes one from `budget`, and one for each of its rods;
    /// `None` as well when it runs out.
    fn shorter_path(
        &self,
        ends: &HashMap<usize, Vec<(usize, usize)>>,
        rod: usize,
        from: usize,
        to: usize,
        length: Real,
        budget: &mut usize,
    ) -> Option<(Vec<usize>, Real)> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        /// A distance (m) ordered for the heap: lengths are finite and
        /// positive (checked before).
        struct Distance(Real);
        impl PartialEq for Distance {
            fn eq(&self, other: &Self) -> bool {
                self.cmp(other).is_eq()
            }
        }
        impl Eq for Distance {}
        impl PartialOrd for Distance {
            fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for Distance {
            fn cmp(&self, other: &Self) -> std::cmp::Ordering {
                self.0.total_cmp(&other.0)
            }
        }
        // Paths at least this long can hold with the rod.
        let bound = length / (1.0 + ROD_SLACK);
        // Per particle reached: its distance and the rod it was reached by.
        let mut reached: HashMap<usize, (Real, usize)> = HashMap::new();
        let mut heap = BinaryHeap::new();
        reached.insert(from, (0.0, rod));
        heap.push(Reverse((Distance(0.0), from)));
        while let Some(Reverse((Distance(distance), particle))) = heap.pop() {
            if distance >= bound || *budget == 0 {
                return None;
            }
            if reached.get(&particle).is_some_and(|&(d, _)| d < distance) {
                continue;
            }
            // A particle reached, and each of its rods looked at.
            let rods = ends.get(&particle).map_or(0, Vec::len);
            *budget = budget.saturating_sub(1 + rods);
            if particle == to {
                let mut path = Vec::new();
                let mut at = to;
                while at != from {
                    let via = reached[&at].1;
                    path.push(via);
                    let r = &self.rods[via];
                    at = if r.first == at { r.second } else { r.first };
                }
                path.reverse();
                return Some((path, distance));
            }
            for &(next, via) in ends.get(&particle).into_iter().flatten() {
                if via == rod {
                    continue;
                }
                let through = distance + self.rod_length(&self.rods[via]);
                if through < bound && reached.get(&next).is_none_or(|&(d, _)| through < d) {
                    reached.insert(next, (through, via));
                    heap.push(Reverse((Distance(through), next)));
                }
            }
        }
        None
    }

    fn validate_muscles(&self) -> Result<(), BuildError> {
        for (muscle, m) in self.muscles.iter().enumerate() {
            if self.muscles[..muscle].iter().any(|e| e.spring == m.spring) {
                return Err(BuildError::BadMuscle {
                    muscle,
                    field: "spring",
                    value: m.spring as Real,
                    reason: "another muscle drives this spring already: one muscle per spring",
                });
            }
            if m.spring >= self.springs.len() {
                return Err(BuildError::MuscleSpringOutOfRange {
                    muscle,
                    spring: m.spring,
                    springs: self.springs.len(),
                });
            }
            if let MuscleDrive::Sine {
                amplitude,
                period,
                phase,
            } = m.drive
            {
                let bad = |field, value, reason| {
                    Err(BuildError::BadMuscle {
                        muscle,
                        field,
                        value,
                        reason,
                    })
                };
                if !(amplitude.is_finite() && amplitude.abs() < 1.0) {
                    return bad(
                        "amplitude",
                        amplitude,
                        "|amplitude| must be below 1 (the rest length would reach zero)",
                    );
                }
                if !(period.is_finite() && period > 0.0) {
                    return bad("period", period, "must be a positive time (s)");
                }
                if !phase.is_finite() {
                    return bad("phase", phase, "must be a finite angle (rad)");
                }
            }
        }
        Ok(())
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

/// The particles of the bodies that `keep` says (and that have any), as
/// runs of consecutive bodies' particles: each run a range of particles
/// that a loop can take in one piece.
pub(crate) fn runs_of<'a>(
    bodies: &'a [Body],
    keep: impl Fn(&Body) -> bool + 'a,
) -> impl Iterator<Item = Range<usize>> + 'a {
    let mut index = 0;
    let kept = move |b: &Body| keep(b) && !b.particles.is_empty();
    std::iter::from_fn(move || {
        let first = index + bodies[index..].iter().position(&kept)?;
        let mut run = bodies[first].particles.clone();
        index = first + 1;
        while index < bodies.len()
            && kept(&bodies[index])
            && bodies[index].particles.start == run.end
        {
            run.end = bodies[index].particles.end;
            index += 1;
        }
        Some(run)
    })
}

fn check_len(
    field: &'static str,
    found: usize,
    expected: usize,
    what: &'static str,
) -> Result<(), BuildError> {
    if found == expected {
        Ok(())
    } else {
        Err(BuildError::LengthMismatch {
            field,
            expected,
            found,
            what,
        })
    }
}

fn check_finite_vec(field: &'static str, index: usize, v: Vec3) -> Result<(), BuildError> {
    match v.to_array().into_iter().find(|c| !c.is_finite()) {
        Some(value) => Err(BuildError::NotFinite {
            field,
            index,
            value,
        }),
        None => Ok(()),
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

/// A body as the world stores it: a name and ranges into the world's
/// particle and spring arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name, used for diagnostics columns (`NAME.cx`, ...).
    pub name: String,
    /// Indices of the body's particles in the world.
    pub particles: Range<usize>,
    /// Indices of the body's springs in the world.
    pub springs: Range<usize>,
    /// Triangles with world particle indices, counter-clockwise seen from
    /// outside when the body is closed.
    pub faces: Vec<[u32; 3]>,
    /// Segments of a closed 2D loop with world particle indices,
    /// counter-clockwise.
    pub segments: Vec<[u32; 2]>,
    /// Whether `faces` (or `segments`) enclose a volume (area).
    pub closed: bool,
    /// The gas inside, if any.
    pub gas: Option<Gas>,
    /// The edges of `faces`, each once (for edge–edge contacts).
    pub edges: Vec<[u32; 2]>,
    /// How the body takes part in contacts between bodies.
    pub contact: BodyContact,
    /// Indices of the body's rods in the world's [`crate::Rods`].
    pub rods: Range<usize>,
    /// The body is rigid (see [`BodyData::rigid`]).
    pub rigid: bool,
    /// The body takes part in mutual gravitation.
    pub gravitating: bool,
    /// Where the body's own numbering of its particles has no locality:
    /// per particle of the body, its number within the body in the order
    /// its springs are stored in and the spring force reads them in
    /// (reverse Cuthill–McKee, `order::locality_numbering`); `None` where
    /// the force reads them in the body's own numbering.
    pub(crate) spring_numbering: Option<Vec<u32>>,
    /// Per spring of the body in the scene's order (its
    /// [`BodyData::springs`]), its place in `springs` counted from the
    /// range's start: the world stores a body's springs in an order of its
    /// own (runs first, for the spring force).
    pub(crate) scene_springs: Vec<u32>,
}

impl Body {
    /// The body's springs (indices in the world's [`crate::Springs`]) in
    /// the order the scene gave them ([`BodyData::springs`]), the order its
    /// spring indices (muscles, outputs) count in; `springs` ranges over
    /// them in the order the world stores them.
    pub fn springs_in_scene_order(&self) -> impl Iterator<Item = usize> + '_ {
        self.scene_springs
            .iter()
            .map(|&k| self.springs.start + k as usize)
    }

    /// True for a 2D body (bounded by segments in the xy-plane).
    pub fn is_planar(&self) -> bool {
        self.faces.is_empty() && !self.segments.is_empty()
    }

    /// The exact enclosed volume (m³), or area in 2D (m²), at `position`;
    /// `None` for a body that is not closed.
    pub fn enclosed_volume(&self, position: &[Vec3]) -> Option<Real> {
        if !self.closed {
            None
        } else if self.is_planar() {
            Some(surface::enclosed_area(position, &self.segments))
        } else {
            Some(surface::enclosed_volume(position, &self.faces))
        }
    }
}
