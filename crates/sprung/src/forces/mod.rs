//! Forces: small types that add their contribution to the force buffer.
//!
//! Each force sees the trial state through a [`ForceContext`] (integrators
//! evaluate forces at intermediate states, so forces never read the world's
//! stored positions directly) and adds into `force`. Conservative forces also
//! report their potential energy.
//!
//! To add a force: write a type implementing [`Force`] in its own file here,
//! and push it onto `World::forces` (or, for a built-in one driven by
//! `Settings`, call it from `world::Dynamics`).

mod drag;
mod gravity;
mod mouse;
mod pressure;
mod spring;
mod wind;
mod wind_field;

pub use drag::AirDrag;
pub use gravity::Gravity;
pub use mouse::MouseSpring;
pub use pressure::{pressure, GasPressure};
pub use spring::{spring_energy, SpringForce};
pub use wind::{Wind, WindModel, AIR_DENSITY};
pub use wind_field::{Gusts, Turbulence, WindField};

use crate::body::Body;
use crate::measure::Energies;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// The state a force is evaluated at.
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
    /// The world's springs.
    pub springs: &'a Springs,
    /// The world's bodies.
    pub bodies: &'a [Body],
}

/// A force acting on the particles.
pub trait Force: Send + Sync + std::fmt::Debug {
    /// A short name for messages.
    fn name(&self) -> &'static str;
    /// Add this force (N) to `force`, one entry per particle. `&mut self`
    /// lets a force keep scratch buffers (per-particle normals, say) sized
    /// on first use, so a step allocates nothing.
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]);
    /// Add this force's potential energy (J) to the right term of `energies`.
    fn add_energy(&self, _context: &ForceContext, _energies: &mut Energies) {}
}
