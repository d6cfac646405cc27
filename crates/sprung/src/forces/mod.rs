//! Forces: small types that add their contribution to the force buffer, and
//! their derivatives for the implicit solvers.
//!
//! Every force of a world lives in one [`ForceList`] (`World::forces`):
//! gravity, the springs, the gas, air drag, wind, the user's hand, penalty
//! contacts and anything a user adds. The explicit step, the energy, the
//! implicit solvers and the threads all walk that list, so a force is
//! written once and works everywhere.
//!
//! Each force sees the trial state through a [`ForceContext`] (integrators
//! evaluate forces at intermediate states, so forces never read the world's
//! stored positions directly) and
//!
//! - adds its force (N) into a buffer ([`Force::accumulate`]);
//! - adds its potential energy (J) to the right term ([`Force::add_energy`]);
//! - for the implicit solvers, linearises itself at a state
//!   ([`Force::linearize`]) and then gives the products of its Jacobians
//!   with any vector, `α ∂f/∂x·p + β ∂f/∂v·p` ([`Force::add_jacobian_products`]),
//!   and the diagonal of those Jacobians ([`Force::add_jacobian_diagonal`])
//!   for the preconditioner. None of these has a default: a force says how it
//!   takes part in an implicit solve ([`Linearization`]), so none is left out
//!   by accident.
//!
//! To add a force: a type implementing [`Force`] in its own file here, added
//! with `world.forces.push(...)` (or [`ForceList::set`] for one of a kind).

mod contact;
mod drag;
mod gravitation;
mod gravity;
mod list;
mod mouse;
mod pressure;
mod spring;
mod surfaces;
mod wind;
mod wind_field;

pub use contact::PenaltyContacts;
pub use drag::AirDrag;
pub use gravitation::{
    gravitating_pairs, gravitating_particles, Gravitation, GRAVITATIONAL_CONSTANT, MAX_GRAVITATING,
};
pub use gravity::Gravity;
pub use list::ForceList;
pub use mouse::MouseSpring;
pub use pressure::{pressure, GasPressure};
pub use spring::{pulls_alone, spring_energy, SpringForce};
pub use wind::{Wind, WindModel, AIR_DENSITY};
pub use wind_field::{Gusts, Turbulence, WindField};

use crate::body::Body;
use crate::collide::Collider;
use crate::contact::Contacts;
use crate::measure::Energies;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// The state a force is evaluated at, and the world it belongs to.
#[derive(Debug, Clone, Copy)]
pub struct ForceContext<'a> {
    /// Simulated time (s).
    pub time: Real,
    /// Trial positions (m).
    pub position: &'a [Vec3],
    /// Trial velocities (m/s).
    pub velocity: &'a [Vec3],
    /// Particle masses (kg).
    pub mass: &'a [Real],
    /// Inverse masses (1/kg), zero for pinned particles.
    pub inverse_mass: &'a [Real],
    /// The world's springs.
    pub springs: &'a Springs,
    /// The world's bodies.
    pub bodies: &'a [Body],
    /// The world's colliders (penalty contacts read them).
    pub colliders: &'a [Collider],
    /// Contact between bodies: settings and the step's candidate pairs.
    pub contacts: &'a Contacts,
}

/// The weights of a Jacobian product: `position ∂f/∂x·p + velocity ∂f/∂v·p`.
///
/// Implicit Euler's matrix `M - dt ∂f/∂v - dt² ∂f/∂x` takes the products
/// with `position = dt²`, `velocity = dt` (and subtracts them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianScale {
    /// Weight of the position Jacobian `∂f/∂x` (N/m per unit of `p`).
    pub position: Real,
    /// Weight of the velocity Jacobian `∂f/∂v` (N·s/m per unit of `p`).
    pub velocity: Real,
}

/// Whose Jacobians a solver asks the force list for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Jacobians {
    /// Every force's (implicit Euler).
    All,
    /// Every force's but the springs' (the projective solver stands in for
    /// the springs with its constant matrix `M + dt² L`).
    AllButSprings,
}

/// How a force takes part in an implicit solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Linearization {
    /// Its Jacobian products are exact (gravity, drag, the hand).
    Exact,
    /// Its Jacobian products are a symmetric, definite approximation of the
    /// exact ones (springs under compression, the curvature of a sphere
    /// collider, friction left out): the linear solve converges, and more
    /// Newton iterations still reach the exact backward-Euler solution
    /// because the residual uses the exact force.
    Approximate,
    /// It has no Jacobian products: within one linearised step it acts with
    /// its value at the start of the step (gas pressure, wind). Further
    /// Newton iterations re-evaluate it.
    Explicit,
}

/// A force acting on the particles.
///
/// `Any` lets a [`ForceList`] hand back a force of a given type
/// ([`ForceList::get`]), so a user can reach the wind or the hand by type.
pub trait Force: Send + Sync + std::fmt::Debug + std::any::Any {
    /// A short name for messages.
    fn name(&self) -> &'static str;
    /// Add this force (N) to `force`, one entry per particle. `&mut self`
    /// lets a force keep scratch buffers (per-particle normals, say) sized
    /// on first use, so a step allocates nothing.
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]);
    /// Write this force (N) into `force` in place of what is there, when it
    /// can do so in the same pass as adding it, and say so; `false` (the
    /// default): it wrote nothing. The first force of a [`ForceList`] that
    /// writes saves the pass that clears the forces.
    fn write(&mut self, context: &ForceContext, force: &mut [Vec3]) -> bool {
        let _ = (context, force);
        false
    }
    /// Add to `rate[i]` (1/s) a bound on how fast this force damps the
    /// velocity of particle `i`: its largest `|∂f/∂v|` (N·s/m) on the
    /// particle times the particle's `inverse_mass` (1/kg). The explicit
    /// methods' stable step counts it (a step of a damping rate `γ` is
    /// stable below `2 / γ`, [`crate::measure::stable_time_step`]). Nothing
    /// by default: the springs and contacts are counted there apart, and
    /// most forces do not damp (the colliders' penalty damping is not
    /// counted either).
    fn add_damping_rates(&self, inverse_mass: &[Real], rate: &mut [Real]) {
        let _ = (inverse_mass, rate);
    }
    /// Add this force's potential energy (J) to the right term of
    /// `energies`; a force without a potential (drag, wind) adds nothing.
    fn add_energy(&self, context: &ForceContext, energies: &mut Energies);
    /// Prepare the Jacobians at the state of `context` (cache what the
    /// products need) and say how exact they are.
    fn linearize(&mut self, context: &ForceContext) -> Linearization;
    /// Add `scale.position ∂f/∂x·p + scale.velocity ∂f/∂v·p` to `out`, one
    /// entry per particle, with the Jacobians at the state of the last
    /// [`Force::linearize`] (the same `context`).
    fn add_jacobian_products(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    );
    /// Add the diagonal entries of `scale.position ∂f/∂x + scale.velocity
    /// ∂f/∂v` (the x, y, z entries of each particle's own 3×3 block) to
    /// `diagonal`, at the state of the last [`Force::linearize`].
    fn add_jacobian_diagonal(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    );
}
