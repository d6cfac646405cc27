//! The ccd stage: the guarantee behind the penalty contacts and the
//! colliders ([`crate::contact::ccd`]), over each (sub)step's motion.

use crate::colliders::Shape;
use crate::contact::ccd::{kept_pairs_most_bytes, sweep_colliders, CcdReport, Motion, OverBudget};
use crate::error::{BlowUpReason, StepError};
use crate::{Real, Vec3};

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
    /// surface or its own where it collides with itself. Not run on a
    /// motion that ran away ([`World::ran_away`]), whose collisions would
    /// cost far more than the step, nor past its budget: either is kept
    /// in `ccd_stop`, and the guard stage stops the run on it.
    pub(super) fn guarantee(&mut self, dt: Real) -> CcdReport {
        if self.ccd_start.len() != self.particles.len() || self.ccd_stop.is_some() {
            return CcdReport::default();
        }
        if let Some(stop) = self.ran_away() {
            self.ccd_stop = Some(stop);
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
            let resolved = self.contacts.guarantee.resolve(
                &self.bodies,
                &self.rigid.list,
                motion,
                settings.thickness,
                settings.friction,
                dt,
            );
            match resolved {
                Ok(done) => report = report.then(done),
                Err(over) => self.ccd_stop = Some(CcdStop::OverBudget(over)),
            }
        }
        report
    }

    /// Whether the (sub)step's motion ran away before the guarantee: a
    /// particle beyond the world's limits (`max_distance`, `max_speed`),
    /// or one of a colliding body that moved, against the body's mean
    /// move, farther than [`RUNAWAY_SIZES`] times the body's own size at
    /// the start (or the contact thickness, for a smaller body): a motion
    /// whose collisions could span the whole scene.
    fn ran_away(&self) -> Option<CcdStop> {
        if self.guard(0.0).is_err() {
            return Some(CcdStop::Limits);
        }
        let (start, end) = (&self.ccd_start, &self.particles.position);
        let thickness = self.contacts.settings.thickness;
        for (index, body) in self.bodies.iter().enumerate() {
            if !body.contact.collide || body.particles.is_empty() {
                continue;
            }
            let range = body.particles.clone();
            let count = range.len() as Real;
            let mean = range.clone().map(|i| end[i] - start[i]).sum::<Vec3>() / count;
            let (mut low, mut high) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            let (mut farthest, mut worst) = (0.0, range.start);
            for i in range {
                low = low.min(start[i]);
                high = high.max(start[i]);
                let stray = (end[i] - start[i] - mean).length_squared();
                if stray > farthest {
                    (farthest, worst) = (stray, i);
                }
            }
            let size = (high - low).length().max(thickness);
            let stray = farthest.sqrt();
            if stray > RUNAWAY_SIZES * size {
                return Some(CcdStop::OutOfShape {
                    body: index,
                    particle: worst,
                    stray,
                    size,
                });
            }
        }
        None
    }
}

/// How many times its own size (at the start of the step) a particle of a
/// colliding body may move against its body's mean move in one step before
/// the motion counts as run away. The guarantee puts back motions of a few
/// sizes (a cloth particle flung by a deep penalty contact moved 2.9 m
/// against its 1.7 m cloth in one step of a 150 m/s ball's catch, and was
/// put back); an unstable ball of stiffness 2.1e9 N/m moved 340 times its
/// size in its first step.
pub const RUNAWAY_SIZES: Real = 100.0;

/// Why the ccd stage of a step did not clear its collisions; the guard
/// stage stops the run on it.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum CcdStop {
    /// A particle beyond the world's limits: the guard finds which.
    Limits,
    /// `particle` of body `body` moved `stray` (m) against its body's mean
    /// move, more than the body's `size` (m).
    OutOfShape {
        body: usize,
        particle: usize,
        stray: Real,
        size: Real,
    },
    /// The collisions would take more than the step's budget.
    OverBudget(OverBudget),
}

impl World {
    /// The error of a step whose guarantee stopped short (`stop`), at the
    /// end of a step of `dt` (s); the guard found no particle beyond the
    /// limits.
    pub(super) fn ccd_error(&self, stop: CcdStop, dt: Real) -> StepError {
        let named = |body: usize| format!("\"{}\"", self.bodies[body].name);
        match stop {
            CcdStop::OutOfShape {
                body,
                particle,
                stray,
                size,
            } => StepError::BlowUp {
                step: self.steps,
                time: self.time,
                particle,
                body: format!(
                    "body {}, its particle {}",
                    named(body),
                    particle - self.bodies[body].particles.start
                ),
                reason: BlowUpReason::OutOfShape { stray, size },
                dt,
                stable_dt: self.stable_time_step(),
            },
            CcdStop::OverBudget(over) => StepError::GuaranteeOverBudget {
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
