//! Coulomb friction between bodies, as impulses after each (sub)step.
//!
//! A penalty force can only approximate friction by a steep function of the
//! sliding speed, which lets a resting body creep downhill (and, steep
//! enough to stop the creep, limits the explicit step). So friction acts on
//! velocities instead, once per (sub)step after the integrator, the way the
//! projection colliders' does. It acts on the touches of the contact
//! force's last evaluation in the (sub)step ([`BodyContacts`]), each with
//! the normal force `f_n` it pushed with: the relative tangential velocity
//! `u_t` of the two closest points, after the step, is reduced by the
//! tangential impulse `J = min(|u_t| / W, μ f_n dt)` along `-u_t`, where `W
//! = Σ wᵢ² / mᵢ` is the pair's inverse effective mass. So each step's
//! friction impulse is at most `μ` times the normal force of the last
//! evaluation times the step: Coulomb's law for the step's normal impulse
//! where the forces are evaluated once a step (Euler, symplectic Euler),
//! its last stage's where they are evaluated several times (RK4, the
//! implicit solvers). Below the friction cone the sliding stops exactly
//! (static friction). A touch that begins within a step gets its first
//! friction in the next. Taking the force's touches rather than measuring
//! the pairs again after the step halves the cost of measuring contacts;
//! every integrator evaluates the forces at least once a step.
//! The impulse is shared by the closest-point weights, opposite on the two
//! sides (the weights sum to zero), so linear momentum is conserved. The
//! positions move by the velocity change times `dt` too, as if the impulse
//! had acted at the start of the (sub)step: otherwise each step's sliding,
//! taken before the friction stops it, would add up to a steady creep of a
//! resting body (`g sin θ dt` per second on a slope). The touches are taken
//! in their fixed order, each seeing the velocities the earlier ones left.
//!
//! [`BodyContacts`]: super::BodyContacts

use super::pairs::Touch;
use super::Contacts;
use crate::{Real, Vec3};

impl Contacts {
    /// Apply friction impulses to `velocity` (m/s) for the touches of
    /// `pushes`, each with the normal force (N) it pushed with over a
    /// (sub)step of `dt` (s), moving `position` (m) by the velocity change
    /// times `dt`.
    pub(crate) fn apply_friction<'a>(
        &self,
        pushes: impl Iterator<Item = (&'a Touch, Real)>,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        inverse_mass: &[Real],
        dt: Real,
    ) {
        let friction = self.settings.friction;
        if friction == 0.0 || self.pairs.is_empty() {
            return;
        }
        for (touch, push) in pushes {
            let relative = touch.relative(velocity);
            let normal_speed = relative.dot(touch.normal);
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
