//! The step's data, split as a step reads it: the [`Model`], what a step
//! reads and leaves as it is (masses, springs, bodies, colliders, the
//! contact pairs found for it), and the [`State`], what it advances (time,
//! positions, velocities). The forces see the two together
//! ([`crate::forces::ForceContext::new`]); an integrator advances the state
//! given the model and the force list ([`crate::integrate::Dynamics`]),
//! whose driving terms (a controller's applied forces, the user's hand, a
//! gas's amount) are the step's controls:
//! `(model, state, forces, dt) → state`, the way Newton's solvers step
//! `(model, state_in, control, contacts, dt) → state_out`.
//!
//! Both are views into a [`crate::world::World`], which owns the data
//! ([`World::model`](crate::world::World::model)); this room imports only
//! the data rooms beneath it.

use crate::body::Body;
use crate::colliders::Collider;
use crate::contact::Contacts;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

/// What a step reads and leaves as it is: the world's data, apart from the
/// state it advances and the forces it evaluates.
///
/// The springs' rest lengths (the muscles' stage) and the springs that
/// give way (the give stage) change between the step's integrations, not
/// during one; the contact pairs are those the detect stage found for the
/// step.
#[derive(Debug, Clone, Copy)]
pub struct Model<'a> {
    /// Particle masses (kg).
    pub mass: &'a [Real],
    /// Inverse masses (1/kg), zero for pinned particles.
    pub inverse_mass: &'a [Real],
    /// The world's springs (ends, rest lengths in m, stiffness in N/m,
    /// damping in N·s/m).
    pub springs: &'a Springs,
    /// The world's bodies (ranges into the particles, gas, faces).
    pub bodies: &'a [Body],
    /// The world's colliders (planes and spheres, with their paths).
    pub colliders: &'a [Collider],
    /// Contact between bodies: settings and the step's candidate pairs.
    pub contacts: &'a Contacts,
}

/// What a step advances: time, positions and velocities (a view; the
/// integrator writes the next ones in place).
#[derive(Debug, Clone, Copy)]
pub struct State<'a> {
    /// Simulated time (s).
    pub time: Real,
    /// Positions (m).
    pub position: &'a [Vec3],
    /// Velocities (m/s).
    pub velocity: &'a [Vec3],
}
