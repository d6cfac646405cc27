//! Particles as a structure of arrays: one `Vec` per quantity, indexed by
//! particle number, so hot loops run over slices.

use crate::units::{Real, Vec3};

/// The point masses of a world, stored as parallel arrays.
///
/// A pinned particle has `inverse_mass == 0`: it is left out of integration
/// (infinite mass) and keeps zero velocity. Its `mass` is kept for gravity
/// energy bookkeeping.
#[derive(Debug, Clone, Default)]
pub struct Particles {
    /// Position of each particle (m).
    pub position: Vec<Vec3>,
    /// Velocity of each particle (m/s).
    pub velocity: Vec<Vec3>,
    /// Force accumulated on each particle by the latest force evaluation (N).
    pub force: Vec<Vec3>,
    /// Mass of each particle (kg), positive.
    pub mass: Vec<Real>,
    /// Inverse mass of each particle (1/kg); 0 for a pinned particle.
    pub inverse_mass: Vec<Real>,
}

impl Particles {
    /// Number of particles.
    pub fn len(&self) -> usize {
        self.position.len()
    }

    /// True when there are no particles.
    pub fn is_empty(&self) -> bool {
        self.position.is_empty()
    }

    /// True when particle `index` is pinned (left out of integration).
    pub fn is_pinned(&self, index: usize) -> bool {
        self.inverse_mass[index] == 0.0
    }

    /// Append one particle at `position` (m) with `velocity` (m/s) and
    /// `mass` (kg); `pinned` particles get zero velocity and inverse mass.
    pub fn push(&mut self, position: Vec3, velocity: Vec3, mass: Real, pinned: bool) {
        self.position.push(position);
        self.velocity
            .push(if pinned { Vec3::ZERO } else { velocity });
        self.force.push(Vec3::ZERO);
        self.mass.push(mass);
        self.inverse_mass
            .push(if pinned { 0.0 } else { 1.0 / mass });
    }
}
