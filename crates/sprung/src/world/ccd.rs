//! The ccd stage: the CCD behind the penalty contacts and the
//! colliders ([`crate::contact::ccd`]), over each (sub)step's motion.

use crate::colliders::Shape;
use crate::contact::ccd::{
    kept_pairs_most_bytes, sweep_colliders, CcdReport, Motion, Runaway, Stopped,
};
use crate::error::{BlowUpReason, StepError};
use crate::units::Real;

use super::World;

impl World {
    /// The most memory (bytes) the CCD's lists of the pairs of
    /// elements it may test can take, at the peak of a search, where it
    /// guards bodies against each other or themselves (from
    /// [`crate::contact::ccd::kept_pairs_most`]); 0 where it does not.
    /// Bodies that press together at speed come near it; a search past
    /// it keeps nothing. Not counted: the collisions found in a step and
    /// the penalty contacts' candidate pairs.
    pub fn ccd_memory_most(&self) -> usize {
        let settings = &self.contacts.settings;
        if settings.enabled && settings.ccd {
            kept_pairs_most_bytes(&self.bodies)
        } else {
            0
        }
    }

    /// Whether this step's CCD has anything to do (it is on, and
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

    /// Whether the CCD that keeps every particle from passing through a surface
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
    /// surface or its own where it collides with itself. Not run past the
    /// world's limits (`max_distance`, `max_speed`); refused by the
    /// CCD on a motion that ran away
    /// ([`crate::contact::ccd::RUNAWAY_SIZES`]) or past its budget, whose
    /// collisions would cost far more than the step: each is kept in
    /// `ccd_stop`, and the guard stage stops the run on it.
    pub(super) fn ccd(&mut self, dt: Real) -> CcdReport {
        if self.ccd_start.len() != self.particles.len() {
            return CcdReport::default();
        }
        if self.guard(0.0).is_err() {
            self.ccd_stop = Some(CcdStop::Limits);
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
            let resolved = self.contacts.ccd.resolve(
                &self.bodies,
                &self.rigid.list,
                motion,
                settings.thickness,
                settings.friction,
                dt,
            );
            match resolved {
                Ok(done) => report = report.then(done),
                Err(stop) => self.ccd_stop = Some(CcdStop::Resolve(stop)),
            }
        }
        report
    }
}

/// Why the ccd stage of a step did not clear its collisions; the guard
/// stage stops the run on it.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum CcdStop {
    /// A particle beyond the world's limits: the guard finds which.
    Limits,
    /// The CCD's own refusal.
    Resolve(Stopped),
}

impl World {
    /// The error of a step whose CCD stopped short (`stop`), at the
    /// end of a step of `dt` (s); the guard found no particle beyond the
    /// limits.
    pub(super) fn ccd_error(&self, stop: CcdStop, dt: Real) -> StepError {
        let named = |body: usize| format!("\"{}\"", self.bodies[body].name);
        match stop {
            CcdStop::Resolve(Stopped::Runaway(Runaway {
                particle,
                stray,
                size,
            })) => {
                // The bodies hold the particles in runs, in order.
                let body = self.bodies.partition_point(|b| b.particles.end <= particle);
                StepError::BlowUp {
                    step: self.steps,
                    time: self.time,
                    particle,
                    body: match self.bodies.get(body) {
                        Some(b) => format!(
                            "body {}, its particle {}",
                            named(body),
                            particle - b.particles.start
                        ),
                        None => "no body".into(),
                    },
                    reason: BlowUpReason::OutOfShape {
                        stray,
                        size,
                        sizes: crate::contact::ccd::RUNAWAY_SIZES,
                    },
                    dt,
                    stable_dt: self.stable_time_step(),
                }
            }
            CcdStop::Resolve(Stopped::OverBudget(over)) => StepError::CcdOverBudget {
                step: self.steps,
                time: self.time,
                bodies: over
                    .bodies
                    .iter()
                    .map(|&b| named(b))
                    .collect::<Vec<_>>()
                    .join(", "),
                work: over.work,
                budget: over.budget,
                collisions: over.collisions,
                rounds: over.rounds,
            },
            // The guard stage finds the particle beyond the limits first.
            CcdStop::Limits => match self.guard(dt) {
                Err(error) => error,
                Ok(()) => StepError::InvalidTimeStep { dt },
            },
        }
    }
}
