//! The ccd stage: the guarantee behind the penalty contacts and the
//! colliders ([`crate::contact::ccd`]), over each (sub)step's motion.

use crate::colliders::Shape;
use crate::contact::ccd::{kept_pairs_most_bytes, sweep_colliders, CcdReport, Motion};
use crate::Real;

use super::World;

impl World {
    /// The most memory (bytes) the guarantee's lists of the pairs of
    /// elements it may test can take, at the peak of a search, where it
    /// guards bodies against each other or themselves (from
    /// [`crate::contact::ccd::kept_pairs_most`]); 0 where it does not.
    /// Bodies that press together at speed come near it; a search past
    /// it keeps nothing. Not counted: the collisions found in a step and
    /// the penalty contacts' candidate pairs.
    pub fn guarantee_memory_most(&self) -> usize {
        let settings = &self.contacts.settings;
        if settings.enabled && settings.ccd {
            kept_pairs_most_bytes(&self.bodies)
        } else {
            0
        }
    }

    /// Whether this step's guarantee has anything to do (it is on, and
    /// bodies may meet each other or themselves, or a sphere collider
    /// may be passed through); where not, its buffer of start positions
    /// is emptied, so the stage does nothing.
    pub(super) fn mark_guarded(&mut self) -> bool {
        let guarded = self.is_guarded();
        if !guarded {
            self.ccd_start.clear();
        }
        guarded
    }

    /// Whether the guarantee that no particle passes through a surface
    /// has work in this world: it is on (`ContactSettings::ccd`), and
    /// bodies may meet each other or themselves, or a sphere collider may
    /// be passed through.
    pub fn is_guarded(&self) -> bool {
        let spheres = self
            .colliders
            .iter()
            .any(|c| matches!(c.shape_at(self.time), Shape::Sphere { .. }));
        self.contacts.settings.ccd && (self.bodies_may_touch() || spheres)
    }

    /// Whether contact between bodies is on and has bodies to act on: two
    /// that collide, or one that collides with itself.
    pub fn bodies_may_touch(&self) -> bool {
        let colliding = self.bodies.iter().filter(|b| b.contact.collide).count();
        self.contacts.settings.enabled
            && (colliding >= 2
                || self
                    .bodies
                    .iter()
                    .any(|b| b.contact.collide && b.contact.self_collision))
    }

    /// The ccd stage at the end of a (sub)step of `dt` (s): no particle
    /// passes through a sphere collider, then none through another body's
    /// surface or its own where it collides with itself.
    pub(super) fn guarantee(&mut self, dt: Real) -> CcdReport {
        if self.ccd_start.len() != self.particles.len() {
            return CcdReport::default();
        }
        let particles = &mut self.particles;
        let stopped = sweep_colliders(
            &self.colliders,
            self.time,
            dt,
            &self.bodies,
            &self.ccd_start,
            &mut particles.position,
            &mut particles.velocity,
            &particles.inverse_mass,
        );
        let settings = self.contacts.settings;
        let mut report = CcdReport {
            impulses: stopped,
            zones: 0,
        };
        if settings.enabled {
            let motion = Motion {
                start: &self.ccd_start,
                position: &mut particles.position,
                velocity: &mut particles.velocity,
                inverse_mass: &particles.inverse_mass,
            };
            report = report.then(self.contacts.guarantee.resolve(
                &self.bodies,
                &self.rigid.list,
                motion,
                settings.thickness,
                settings.friction,
                dt,
            ));
        }
        report
    }
}
