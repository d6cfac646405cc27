//! Coulomb friction between bodies, as impulses after each (sub)step.
//!
//! A penalty force can only approximate friction by a steep function of the
//! sliding speed, which lets a resting body creep downhill (and, steep
//! enough to stop the creep, limits the explicit step). So friction acts on
//! velocities instead, once per (sub)step after the integrator, the way the
//! projection colliders' does: for each pair in contact, with normal force
//! `f_n = max(0, k (h - d) - c (u·n))`, the relative tangential velocity
//! `u_t` of its two closest points is reduced by the tangential impulse
//! `J = min(|u_t| / W, μ f_n dt)` along `-u_t`, where `W = Σ wᵢ² / mᵢ` is the
//! pair's inverse effective mass. Below the friction cone the sliding stops
//! exactly (static friction); above it, the impulse is Coulomb's `μ f_n dt`.
//! The impulse is shared by the closest-point weights, opposite on the two
//! sides (the weights sum to zero), so linear momentum is conserved. The
//! positions move by the velocity change times `dt` too, as if the impulse
//! had acted at the start of the (sub)step: otherwise each step's sliding,
//! taken before the friction stops it, would add up to a steady creep of a
//! resting body (`g sin θ dt` per second on a slope). The pairs are all
//! measured at the positions the step left (in parallel), then taken in
//! their fixed order, each seeing the velocities the earlier ones left.

use super::Contacts;
use crate::{Real, Vec3};

impl Contacts {
    /// Apply friction impulses to `velocity` (m/s) for the pairs touching at
    /// `position` (m) over a (sub)step of `dt` (s), moving the positions by
    /// the velocity change times `dt`.
    pub fn apply_friction(
        &mut self,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        mass: &[Real],
        inverse_mass: &[Real],
        dt: Real,
    ) {
        let friction = self.settings.friction;
        if friction == 0.0 || self.pairs.is_empty() {
            return;
        }
        let touches = &mut self.touches;
        touches.measure(&self.pairs, position, self.settings.thickness);
        for touch in touches.iter() {
            let (k, c) = self
                .settings
                .coefficients(mass[touch.particles[0] as usize]);
            let relative = touch.relative(velocity);
            let normal_speed = relative.dot(touch.normal);
            let push = (k * touch.depth - c * normal_speed).max(0.0);
            let sliding = relative - normal_speed * touch.normal;
            let speed = sliding.length();
            let inverse_effective_mass: Real = (0..touch.count)
                .map(|i| touch.weights[i].powi(2) * inverse_mass[touch.particles[i] as usize])
                .sum();
            if push == 0.0 || speed == 0.0 || inverse_effective_mass == 0.0 {
                continue;
            }
            let impulse = (speed / inverse_effective_mass).min(friction * push * dt);
            let along = -impulse / speed * sliding;
            for i in 0..touch.count {
                let p = touch.particles[i] as usize;
                let change = touch.weights[i] * inverse_mass[p] * along;
                velocity[p] += change;
                position[p] += change * dt;
            }
        }
    }
}
