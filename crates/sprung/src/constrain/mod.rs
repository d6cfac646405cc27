//! The constrain stage of the step: what must hold exactly after every
//! step, whatever the integrator did.
//!
//! - [`Rods`]: rigid rods (distance constraints) between particles, by
//!   iterative mass-weighted projection ([`Rods::project`]);
//! - [`RigidBodies`]: bodies that keep every pairwise distance, by shape
//!   matching with the momentum and angular momentum kept
//!   ([`RigidBodies::project`]);
//! - [`Muscles`]: springs whose rest length follows a function of time,
//!   set before each (sub)step ([`Muscles::apply`]).
//!
//! The stage runs after the colliders and friction, so rods and rigid
//! bodies hold exactly at the end of every step, and a collider's impulse
//! on one particle of a rigid body moves the whole body.

mod muscles;
mod rigid;
mod rods;

pub use muscles::{Muscle, Muscles};
pub(crate) use rigid::Motion;
pub use rigid::{RigidBodies, RigidBody};
pub use rods::{RodReport, Rods};

use crate::error::BuildError;
use crate::units::Real;

/// Most passes over the rods a step may take: a hundred times the default,
/// enough for rods that can hold; it bounds the time of a step whose rods
/// cannot.
pub const MAX_CONSTRAINT_ITERATIONS: u32 = 100_000;

/// The relative length error `|d - L| / L` of a rod after the constrain
/// stage beyond which a step fails ([`crate::StepError::RodOff`]): a
/// hundred times less is already far outside any tolerance a user sets,
/// and a rod 1 % off moves its ends visibly (the constrain stage's sweeps
/// failing on very unequal masses left rods 93 % off).
pub const ROD_FAILURE: Real = 1e-2;

/// Tolerances of the constrain stage (`[sim]` keys).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstraintSettings {
    /// Largest relative error of a rod's length, `|d - L| / L`, the
    /// projection stops at. Default 1e-9.
    pub tolerance: Real,
    /// Most sweeps over the rods per step. Default 1000.
    pub iterations: u32,
}

impl Default for ConstraintSettings {
    fn default() -> Self {
        ConstraintSettings {
            tolerance: 1e-9,
            iterations: 1000,
        }
    }
}

impl ConstraintSettings {
    /// Refuse a tolerance that is not positive and finite, or no iterations.
    pub fn validate(&self) -> Result<(), BuildError> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(BuildError::OutOfRange {
                field: "constraint_tolerance",
                value: self.tolerance,
                reason: "must be a positive relative length error",
            });
        }
        if !(1..=MAX_CONSTRAINT_ITERATIONS).contains(&self.iterations) {
            return Err(BuildError::OutOfRange {
                field: "constraint_iterations",
                value: Real::from(self.iterations),
                reason: "must be from 1 to 100 000 passes a step (a scene whose rods need more cannot hold them: their lengths disagree, or their masses are too unequal)",
            });
        }
        Ok(())
    }
}
