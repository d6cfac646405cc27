//! Colliders: static shapes the particles must stay out of (PHYSICS.md §5).
//!
//! A collider is a [`Shape`] (which side is outside, and how deep a point
//! is) and a [`ContactResponse`]: either the *projection* form, a stage
//! after integration that moves a penetrating particle back to the surface
//! and reflects its velocity, or the *penalty* form, a virtual spring that
//! acts as a force while the particle is inside.
//!
//! To add a shape: a variant of [`Shape`] and its signed distance and
//! outward normal in [`Shape::distance_and_normal`].

mod response;

pub use response::{penalty_force, project};

use crate::error::BuildError;
use crate::{Real, Vec3};

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
}

impl Shape {
    /// A plane through `point` (m) with outward `normal` (any length but
    /// zero; it is normalised).
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

    /// Signed distance of `x` from the surface (m, negative inside) and the
    /// outward unit normal there.
    pub fn distance_and_normal(&self, x: Vec3) -> (Real, Vec3) {
        match *self {
            Shape::Plane { point, normal } => ((x - point).dot(normal), normal),
        }
    }
}

/// How a collider answers a particle that has gone inside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContactResponse {
    /// Move the particle onto the surface; reflect the normal velocity times
    /// `restitution` and slow the tangential velocity by Coulomb friction.
    Projection {
        /// Coefficient of restitution `e` in [0, 1]: a drop from `h`
        /// bounces to `e² h`.
        restitution: Real,
        /// Coulomb friction coefficient `μ` ≥ 0: each contact removes up to
        /// `μ` times the normal velocity change from the tangential speed.
        friction: Real,
    },
    /// A virtual spring `f = k (depth) n - c (v·n) n` while inside.
    Penalty {
        /// Penalty stiffness `k_c` (N/m).
        stiffness: Real,
        /// Penalty damping along the normal (N·s/m).
        damping: Real,
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
            ContactResponse::Penalty { stiffness, damping } => &[
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

/// A shape and the way it answers contacts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Collider {
    /// The geometry.
    pub shape: Shape,
    /// Projection or penalty.
    pub response: ContactResponse,
}

impl Collider {
    /// A collider, with its coefficients checked.
    pub fn new(shape: Shape, response: ContactResponse) -> Result<Self, BuildError> {
        response.validate()?;
        Ok(Collider { shape, response })
    }

    /// Penalty stiffness (N/m), or 0 for the projection form: it bounds the
    /// stable time step like a spring does.
    pub fn penalty_stiffness(&self) -> Real {
        match self.response {
            ContactResponse::Penalty { stiffness, .. } => stiffness,
            ContactResponse::Projection { .. } => 0.0,
        }
    }

    /// Elastic energy stored in the penalty springs of particles at
    /// `position` (J); zero for the projection form.
    pub fn contact_energy(&self, position: &[Vec3]) -> Real {
        let stiffness = self.penalty_stiffness();
        if stiffness == 0.0 {
            return 0.0;
        }
        position
            .iter()
            .map(|&x| self.shape.distance_and_normal(x).0.min(0.0))
            .map(|depth| 0.5 * stiffness * depth * depth)
            .sum()
    }
}
