//! Joins between bodies (docs/physics.md §11): a spring or a rigid rod
//! from a particle of one body to a particle of another (or the same), the
//! scene's `[[join]]` tables.
//!
//! A spring join is one more spring of the world's [`crate::Springs`],
//! outside every body's range: the spring force, the implicit solvers and
//! the stable-step estimate take it like any other, and it may break
//! ([`crate::tearing`]). A rod join is one more rod of [`crate::Rods`].

use crate::error::BuildError;
use crate::units::Real;

/// One end of a join: particle `particle` (its index within the body) of
/// the body named `body`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct JoinEnd {
    /// The body's name.
    pub body: String,
    /// The particle's index within the body.
    pub particle: usize,
}

impl JoinEnd {
    /// Particle `particle` of body `body`.
    pub fn new(body: &str, particle: usize) -> Self {
        JoinEnd {
            body: body.to_string(),
            particle,
        }
    }
}

/// A join as a scene describes it, before it joins a world
/// ([`crate::World::add_join`]).
#[derive(Debug, Clone, PartialEq)]
pub struct JoinData {
    /// The first end (the scene's `a`).
    pub a: JoinEnd,
    /// The second end (the scene's `b`).
    pub b: JoinEnd,
    /// Stiffness of a spring join (N/m). Default 0.
    pub stiffness: Real,
    /// Damping along a spring join (N·s/m). Default 0.
    pub damping: Real,
    /// Rest length (m); `None`: the ends' distance when the join is added.
    pub rest_length: Option<Real>,
    /// A rigid rod (distance constraint) instead of a spring.
    pub rod: bool,
    /// Strain past which a spring join breaks; `None`: never.
    pub break_strain: Option<Real>,
}

impl JoinData {
    /// A spring join from `a` to `b` at the ends' distance, with zero
    /// stiffness and damping and no break strain.
    pub fn between(a: JoinEnd, b: JoinEnd) -> Self {
        JoinData {
            a,
            b,
            stiffness: 0.0,
            damping: 0.0,
            rest_length: None,
            rod: false,
            break_strain: None,
        }
    }

    /// Check the numbers: stiffness and damping non-negative and finite, a
    /// rest length positive and finite, a break strain positive and finite
    /// and only on a spring.
    pub fn validate(&self) -> Result<(), BuildError> {
        let non_negative = |field, value: Real| {
            if value.is_finite() && value >= 0.0 {
                Ok(())
            } else {
                Err(BuildError::OutOfRange {
                    field,
                    value,
                    reason: "must be non-negative and finite",
                })
            }
        };
        non_negative("stiffness", self.stiffness)?;
        non_negative("damping", self.damping)?;
        if let Some(length) = self.rest_length {
            if !(length.is_finite() && length > 0.0) {
                return Err(BuildError::OutOfRange {
                    field: "rest_length",
                    value: length,
                    reason: "must be positive and finite (m)",
                });
            }
        }
        let limits = crate::tearing::StrainLimits {
            break_strain: self.break_strain,
            ..Default::default()
        };
        limits.validate()?;
        if self.rod && self.break_strain.is_some() {
            return Err(BuildError::BadJoin(
                "`break_strain` needs a spring join: a rod (`rod = true`) holds its length, so its strain never grows",
            ));
        }
        Ok(())
    }
}

/// What links a join's ends in the world.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JoinLink {
    /// A spring: its index in the world's [`crate::Springs`].
    Spring(usize),
    /// A rod: its index in the world's [`crate::Rods`].
    Rod(usize),
}

/// A join in a world.
#[derive(Debug, Clone, PartialEq)]
pub struct Join {
    /// The join as it was given.
    pub data: JoinData,
    /// The ends' particles (world indices).
    pub particles: [u32; 2],
    /// The spring or rod that links them.
    pub link: JoinLink,
}
