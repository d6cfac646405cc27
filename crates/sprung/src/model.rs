//! The step's data, split as an integration reads it: the [`Model`], what
//! it reads and leaves as it is (masses, springs, bodies, colliders, the
//! contact pairs found for the step), and the [`State`], the time,
//! positions and velocities the forces are evaluated at. The forces see
//! the two together ([`crate::forces::ForceContext::new`]); an integrator
//! advances the positions and velocities in place given the model and the
//! force list ([`crate::integrate::Dynamics`]), whose driving terms (a
//! controller's applied forces, the user's hand, a gas's amount) are the
//! step's controls: `(model, state, forces, dt) → state`, the way the
//! solvers of NVIDIA's Newton step `(model, state_in, control, contacts,
//! dt) → state_out`.
//!
//! Both are views into a [`crate::world::World`], which owns the data: a
//! `Model` from [`World::model`](crate::world::World::model), a `State`
//! from its time and particles. This room imports only the data rooms
//! beneath it.

use crate::body::Body;
use crate::colliders::Collider;
use crate::contact::Contacts;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

/// What an integration reads and leaves as it is: the world's data, apart
/// from the state it advances and the forces it evaluates.
///
/// The springs' rest lengths (the muscles' stage) and the springs that
/// give way (the give stage) change between the step's integrations, not
/// during one; the contact pairs are those the detect stage found for the
/// step (the detect and CCD stages write the contacts' buffers, outside
/// the integrations).
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

/// A state of the system: time, positions and velocities, a read-only
/// view (the forces are evaluated at it; an integrator writes the next
/// positions and velocities through the slices it is given).
#[derive(Debug, Clone, Copy)]
pub struct State<'a> {
    /// Simulated time (s).
    pub time: Real,
    /// Positions (m).
    pub position: &'a [Vec3],
    /// Velocities (m/s).
    pub velocity: &'a [Vec3],
}
