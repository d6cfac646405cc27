//! Colliders: shapes the particles must stay out of, at rest or moving
//! along a prescribed path (docs/physics.md §5).
//!
//! A [`Collider`] is a [`Shape`] (which side is outside, and how deep a
//! point is), a [`ContactResponse`] and an optional kinematic [`Path`]. The
//! responses are the *projection* form, a stage after integration that moves
//! a penetrating particle back to the surface and reflects its velocity, and
//! the *penalty* form, a virtual spring that acts as a force while the
//! particle is inside (docs/physics.md §5; Witkin & Baraff, *Physically Based
//! Modeling*, SIGGRAPH course notes, on particle collisions and contact).
//! Both only ask the shape for a signed distance and an outward normal, and
//! the collider for its surface velocity, so each works with every shape.
//!
//! **To add a shape**: a variant of [`Shape`] with a checked constructor,
//! its signed distance and outward unit normal in
//! [`Shape::distance_and_normal`], and its rigid translation in
//! [`Shape::translated`]. The responses, the penalty energy and the stable
//! time-step estimate need nothing more.
//!
//! **To move a collider**: give it a [`Path`] with
//! [`Collider::with_path`]. The shape is translated by
//! [`Path::offset_at`]`(t)` (the sphere's centre, the plane's point), and
//! contacts use the velocity relative to the surface, `v - u(t)` with
//! `u =` [`Path::velocity_at`]: the projection form reflects and applies
//! friction to the relative velocity (so a moving sphere pushes particles
//! along and a moving floor carries what rests on it), and the penalty
//! damping acts on the relative normal velocity. The path is prescribed: the
//! particles do not push the collider back.

mod constraint;
mod path;
mod response;

pub(crate) use constraint::add_contact_constraints;
pub use constraint::ContactConstraint;
pub use path::Path;
pub use response::FRICTION_REGULARISATION;
pub(crate) use response::{penalty_force, project};

use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// The geometry of a collider.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// The half-space below the plane through `point` (m) with unit `normal`
    /// pointing to the free side.
    Plane {
        /// A point on the plane (m).
        point: Vec3,
        /// Unit normal pointing out of the solid.
        normal: Vec3,
    },
    /// The solid ball of radius `radius` (m) about `centre` (m).
    Sphere {
        /// Centre (m).
        centre: Vec3,
        /// Radius (m), positive.
        radius: Real,
    },
}

impl Shape {
    /// A plane through `point` (m) with outward `normal` (any length but
    /// zero; it is normalised).
    ///
    /// ```
    /// use sprung::{BuildError, Shape, Vec3};
    ///
    /// let floor = Shape::plane(Vec3::new(0.0, -1.0, 0.0), Vec3::new(0.0, 3.0, 0.0)).unwrap();
    /// let (distance, normal) = floor.distance_and_normal(Vec3::new(7.0, -1.25, 2.0));
    /// assert_eq!((distance, normal), (-0.25, Vec3::Y)); // 25 cm inside
    /// let flat = Shape::plane(Vec3::ZERO, Vec3::ZERO);
    /// assert!(matches!(flat, Err(BuildError::OutOfRange { field: "plane.normal", .. })));
    /// ```
    pub fn plane(point: Vec3, normal: Vec3) -> Result<Self, BuildError> {
        if let Some(value) = point.to_array().into_iter().find(|c| !c.is_finite()) {
            return Err(BuildError::NotFinite {
                field: "plane.point",
                index: 0,
                value,
            });
        }
        let length = normal.length();
        if !(length.is_finite() && length > 0.0) {
            return Err(BuildError::OutOfRange {
                field: "plane.normal",
                value: length,
                reason: "the plane needs a non-zero, finite normal",
            });
        }
        Ok(Shape::Plane {
            point,
            normal: normal / length,
        })
    }

    /// A sphere (solid ball) about `centre` (m) of radius `radius` (m).
    /// Refused: a non-finite centre (field `sphere.centre`, index of the
    /// component) or a radius that is not positive and finite
    /// (`sphere.radius`).
    ///
    /// ```
    /// use sprung::{Shape, Vec3};
    ///
    /// let ball = Shape::sphere(Vec3::new(1.0, 0.0, 0.0), 0.5).unwrap();
    /// let (distance, normal) = ball.distance_and_normal(Vec3::new(1.0, 2.0, 0.0));
    /// assert_eq!((distance, normal), (1.5, Vec3::Y));
    /// assert!(Shape::sphere(Vec3::ZERO, 0.0).is_err());
    /// ```
    pub fn sphere(centre: Vec3, radius: Real) -> Result<Self, BuildError> {
        if let Some((index, value)) = centre
            .to_array()
            .into_iter()
            .enumerate()
            .find(|(_, c)| !c.is_finite())
        {
            return Err(BuildError::NotFinite {
                field: "sphere.centre",
                index,
                value,
            });
        }
        if !(radius.is_finite() && radius > 0.0) {
            return Err(BuildError::OutOfRange {
                field: "sphere.radius",
                value: radius,
                reason: "the sphere needs a positive, finite radius (m)",
            });
        }
        Ok(Shape::Sphere { centre, radius })
    }

    /// Signed distance of `x` from the surface (m, negative inside) and the
    /// outward unit normal there. For a sphere: `|x - c| - r` and
    /// `(x - c) / |x - c|`, with the normal `+y` at the centre itself.
    pub fn distance_and_normal(&self, x: Vec3) -> (Real, Vec3) {
        match *self {
            Shape::Plane { point, normal } => ((x - point).dot(normal), normal),
            Shape::Sphere { centre, radius } => {
                let offset = x - centre;
                let length = offset.length();
                if length > 0.0 {
                    (length - radius, offset / length)
                } else {
                    (-radius, Vec3::Y)
                }
            }
        }
    }

    /// The same shape moved rigidly by `offset` (m).
    pub fn translated(&self, offset: Vec3) -> Self {
        match *self {
            Shape::Plane { point, normal } => Shape::Plane {
                point: point + offset,
                normal,
            },
            Shape::Sphere { centre, radius } => Shape::Sphere {
                centre: centre + offset,
                radius,
            },
        }
    }
}

/// How a collider answers a particle that has gone inside it.
///
/// A particle resting on a penalty floor sinks until the virtual spring
/// holds its weight, `k depth = m g`. Critically damped (`c = 2 √(k m)`),
/// its transient dies out as `(1 + ω t) e^(-ω t)`, `ω = √(k/m) = 100/s`:
///
/// ```
/// use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Shape, Vec3, World};
///
/// let (k, m, g) = (1e4, 1.0, 9.81);
/// let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
/// let damping = 2.0 * f64::sqrt(k * m);
/// let spring = ContactResponse::Penalty { stiffness: k, damping, friction: 0.0 };
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// world.colliders.push(Collider::new(floor, spring).unwrap());
/// world.add_body("ball", BodyData::from_positions(vec![Vec3::ZERO]).with_mass(m)).unwrap();
/// for _ in 0..300 {
///     world.step(1e-3).unwrap();
/// }
/// let depth = -world.particles.position[0].y;
/// assert!((depth - m * g / k).abs() < 1e-6 * m * g / k);
/// let energy = world.energies().get("contact").unwrap();
/// assert!((energy - 0.5 * k * depth * depth).abs() < 1e-15);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactResponse {
    /// Move the particle onto the surface; reflect the normal velocity
    /// (relative to the surface) times `restitution` and slow the relative
    /// tangential velocity by Coulomb friction.
    Projection {
        /// Coefficient of restitution `e` in [0, 1]: a drop from `h`
        /// bounces to `e² h`.
        restitution: Real,
        /// Coulomb friction coefficient `μ` ≥ 0: each contact removes up to
        /// `μ` times the normal velocity change from the tangential speed.
        friction: Real,
    },
    /// A virtual spring `f = k (depth) n - c ((v - u)·n) n` while inside,
    /// `u` the surface velocity, with regularised Coulomb friction along the
    /// surface (see [`Collider::penalty_force`]).
    Penalty {
        /// Penalty stiffness `k_c` (N/m).
        stiffness: Real,
        /// Penalty damping along the normal (N·s/m).
        damping: Real,
        /// Coulomb friction coefficient `μ` ≥ 0 (0 for none).
        friction: Real,
    },
}

impl ContactResponse {
    /// Check the coefficients: restitution in [0, 1], friction, stiffness
    /// and damping non-negative and finite.
    pub fn validate(&self) -> Result<(), BuildError> {
        let checks: &[(&'static str, Real, Real, &'static str)] = match self {
            ContactResponse::Projection {
                restitution,
                friction,
            } => &[
                (
                    "restitution",
                    *restitution,
                    1.0,
                    "restitution must be in [0, 1]",
                ),
                (
                    "friction",
                    *friction,
                    Real::INFINITY,
                    "friction must not be negative",
                ),
            ],
            ContactResponse::Penalty {
                stiffness,
                damping,
                friction,
            } => &[
                (
                    "friction",
                    *friction,
                    Real::INFINITY,
                    "friction must not be negative",
                ),
                (
                    "penalty_stiffness",
                    *stiffness,
                    Real::INFINITY,
                    "penalty stiffness must be positive",
                ),
                (
                    "penalty_damping",
                    *damping,
                    Real::INFINITY,
                    "penalty damping must not be negative",
                ),
            ],
        };
        for &(field, value, max, reason) in checks {
            if !value.is_finite() || value < 0.0 || value > max {
                return Err(BuildError::OutOfRange {
                    field,
                    value,
                    reason,
                });
            }
        }
        if let ContactResponse::Penalty { stiffness, .. } = self {
            if *stiffness <= 0.0 {
                return Err(BuildError::OutOfRange {
                    field: "penalty_stiffness",
                    value: *stiffness,
                    reason: "penalty stiffness must be positive",
                });
            }
        }
        Ok(())
    }
}

/// A shape, the way it answers contacts, and optionally the path it moves
/// along.
#[derive(Debug, Clone, PartialEq)]
pub struct Collider {
    /// The geometry at rest (at displacement zero).
    pub shape: Shape,
    /// Projection or penalty.
    pub response: ContactResponse,
    /// Kinematic motion: the shape is translated by `path.offset_at(t)`.
    /// `None`: static.
    pub path: Option<Path>,
}

impl Collider {
    /// A static collider, with its coefficients checked.
    ///
    /// # Examples
    ///
    /// A particle thrown sideways onto a floor that stops it dead
    /// (restitution 0) and lets it slide (no friction) ends on the floor,
    /// moving on as fast as it was thrown:
    ///
    /// ```
    /// use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Shape, Vec3, World};
    ///
    /// let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    /// let stop = ContactResponse::Projection { restitution: 0.0, friction: 0.0 };
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.colliders.push(Collider::new(floor, stop).unwrap());
    /// let ball = BodyData::from_positions(vec![Vec3::new(0.0, 0.1, 0.0)]).with_velocity(Vec3::X);
    /// world.add_body("ball", ball).unwrap();
    /// for _ in 0..500 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// let (x, v) = (world.particles.position[0], world.particles.velocity[0]);
    /// assert_eq!((x.y, v), (0.0, Vec3::X));
    /// let bouncy = ContactResponse::Projection { restitution: 1.5, friction: 0.0 };
    /// assert!(Collider::new(floor, bouncy).is_err()); // restitution is at most 1
    /// ```
    pub fn new(shape: Shape, response: ContactResponse) -> Result<Self, BuildError> {
        response.validate()?;
        Ok(Collider {
            shape,
            response,
            path: None,
        })
    }

    /// Refuse a collider whose surface lies farther than `max_distance`
    /// (m) from the origin at a keyframe of its path (a plane's distance
    /// `|n·p|`, a sphere's `||c| − r|`), or whose penalty stiffness could
    /// hold more than [`crate::error::ENERGY_LIMIT`] at a depth of
    /// `2 max_distance` (the deepest a particle within the world can be
    /// below a surface that reaches it): the same bound as a spring's.
    pub fn validate_within(&self, max_distance: Real) -> Result<(), BuildError> {
        // The engine checks every step: nothing allocated.
        let offsets = self.path.iter().flat_map(|path| path.offsets());
        let offsets = offsets.chain(self.path.is_none().then_some(Vec3::ZERO));
        for (index, offset) in offsets.enumerate() {
            let (field, distance) = match self.shape {
                Shape::Plane { point, normal } => ("point", normal.dot(point + offset).abs()),
                Shape::Sphere { centre, radius } => {
                    ("centre", ((centre + offset).length() - radius).abs())
                }
            };
            if distance.is_nan() || distance > max_distance {
                return Err(BuildError::BeyondLimit {
                    field,
                    index,
                    value: distance,
                    limit: max_distance,
                });
            }
        }
        if let ContactResponse::Penalty { stiffness, .. } = self.response {
            let depth = 2.0 * max_distance;
            let energy = 0.5 * stiffness * depth * depth;
            if energy.is_nan() || energy >= crate::error::ENERGY_LIMIT {
                return Err(BuildError::EnergyOverflow {
                    field: "penalty_stiffness",
                    index: 0,
                    value: stiffness,
                    energy,
                });
            }
        }
        Ok(())
    }

    /// The same collider moving along `path` (its shape translated by the
    /// path's displacement at each time).
    ///
    /// # Examples
    ///
    /// A floor rising at 0.5 m/s lifts what rests on it:
    ///
    /// ```
    /// use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Path, Shape, Vec3, World};
    ///
    /// let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    /// let stop = ContactResponse::Projection { restitution: 0.0, friction: 0.0 };
    /// let lift = Path::new(vec![(0.0, Vec3::ZERO), (1.0, Vec3::new(0.0, 0.5, 0.0))]).unwrap();
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.colliders.push(Collider::new(floor, stop).unwrap().with_path(lift));
    /// world.add_body("box", BodyData::from_positions(vec![Vec3::ZERO])).unwrap();
    /// for _ in 0..500 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// // At t = 0.5 s the floor is at 0.25 m, the box on it and moving with it
    /// // (to the rounding of the time summed over 500 steps).
    /// let (x, v) = (world.particles.position[0], world.particles.velocity[0]);
    /// assert!((x.y - 0.25).abs() < 1e-12 && (v.y - 0.5).abs() < 1e-12);
    /// ```
    pub fn with_path(mut self, path: Path) -> Self {
        self.path = Some(path);
        self
    }

    /// The shape where it is at `time` (s).
    pub fn shape_at(&self, time: Real) -> Shape {
        match &self.path {
            Some(path) => self.shape.translated(path.offset_at(time)),
            None => self.shape,
        }
    }

    /// Velocity of the surface at `time` (m/s): the path's velocity, zero
    /// for a static collider.
    pub fn velocity_at(&self, time: Real) -> Vec3 {
        match &self.path {
            Some(path) => path.velocity_at(time),
            None => Vec3::ZERO,
        }
    }

    /// Penalty stiffness (N/m), or 0 for the projection form: it bounds the
    /// stable time step like a spring does.
    pub fn penalty_stiffness(&self) -> Real {
        match self.response {
            ContactResponse::Penalty { stiffness, .. } => stiffness,
            ContactResponse::Projection { .. } => 0.0,
        }
    }

    /// Add this collider's penalty force (N) on particles at `position`
    /// (m) with `velocity` (m/s) at `time` (s) to `force`: a virtual spring
    /// `k depth n` pushing each particle inside out, with damping on its
    /// normal velocity relative to the surface and regularised Coulomb
    /// friction; nothing for the projection form (docs/physics.md §5).
    pub fn penalty_force(
        &self,
        time: Real,
        position: &[Vec3],
        velocity: &[Vec3],
        force: &mut [Vec3],
    ) {
        penalty_force(self, time, position, velocity, force);
    }

    /// Elastic energy `Σ ½ k_c depth²` stored in the penalty springs of
    /// particles at `position` (m) against the shape where it is at `time`
    /// (s), in J; zero for the projection form.
    pub fn contact_energy(&self, time: Real, position: &[Vec3]) -> Real {
        let stiffness = self.penalty_stiffness();
        if stiffness == 0.0 {
            return 0.0;
        }
        let shape = self.shape_at(time);
        position
            .iter()
            .map(|&x| shape.distance_and_normal(x).0.min(0.0))
            .map(|depth| 0.5 * stiffness * depth * depth)
            .sum()
    }
}
