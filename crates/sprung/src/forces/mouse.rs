//! The user's hand (PHYSICS.md §1, user forces): a damped spring between a
//! grabbed particle and the cursor, so a person can drag and throw a body.

use super::{Force, ForceContext};
use crate::{Real, Vec3};

/// A spring of zero rest length from particle `particle` to `target`:
/// `f = k (target - x) - c v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MouseSpring {
    /// The grabbed particle.
    pub particle: usize,
    /// Where the cursor is (m).
    pub target: Vec3,
    /// Stiffness `k` (N/m).
    pub stiffness: Real,
    /// Damping `c` on the particle's velocity (N·s/m).
    pub damping: Real,
}

impl Force for MouseSpring {
    fn name(&self) -> &'static str {
        "mouse spring"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        if let (Some(f), Some(&x), Some(&v)) = (
            force.get_mut(self.particle),
            context.position.get(self.particle),
            context.velocity.get(self.particle),
        ) {
            *f += self.stiffness * (self.target - x) - self.damping * v;
        }
    }
}
