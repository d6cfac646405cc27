//! Friction on the touches that take a rigid body's particles, through
//! the body's motion.
//!
//! A rigid body's particles are put back on its shape after friction
//! ([`crate::constrain::RigidBodies::project`]), which keeps the momentum
//! and angular momentum the particles have. An impulse sized for one
//! particle's mass is therefore spread over the whole body, and stops only
//! that share of its sliding: a block resting on a slope of another body
//! crept down it. So a touch with a rigid body's particles takes its
//! impulse on the body's motion ([`Motion`], from the particles' momentum
//! and angular momentum before the projection), sized with the body's
//! effective mass at the touch, `W²/M + (a × t)·I⁻¹ (a × t)` with `W =
//! Σ wᵢ` and `a = Σ wᵢ (xᵢ - c)` over its particles, as sequential
//! impulses: [`PASSES`] passes over these touches in order, each touch's
//! accumulated impulse at most `μ f_n dt` (Coulomb), as the rigid bodies'
//! colliders do.
//!
//! The friction at the touches under a body turns it (a block pushed
//! back at its foot tips forward), which the contact forces resist only
//! in the next step: the turn drove a block's front edge in and lifted its
//! back, and it crept down a 20° slope at 0.5 mm/s where it should hold.
//! So each pass first gives the touch a normal impulse that brings its
//! normal speed back to what the forces left, as the contact's stiff
//! push would within the step: an impulse that may take back at most the
//! forces' own push over the step (`f_n dt`), so that the touch never
//! pulls (pushing only, it still crept at 0.3 mm/s: the back edge must
//! bear less of the weight, as on a real slope). Touches all of whose
//! particles are one rigid body's are left out: a body does not rub on
//! itself.
//!
//! Afterwards each body's particles take the change of its motion, `Δv =
//! ΔV + Δω × (x - c)`, which the projection then keeps, and move by the
//! change of its drift times the step, as if the impulses had acted from
//! its start (not turned, as at the colliders: a turn about the centre
//! would drive other corners into the surface). The particles of other
//! bodies in these touches take their impulses as in [`super::friction`].
//!
//! These touches are taken on one thread, after the others, in their
//! order: the same bits whatever the number of threads.

use super::pairs::Touch;
use crate::constrain::{Motion, RigidBody};
use crate::units::{Real, Vec3};

/// Passes of sequential impulses over the touches with rigid bodies.
pub const PASSES: usize = 16;

/// The rigid bodies' particles, to find a particle's body.
#[derive(Debug, Clone, Copy)]
pub(crate) struct RigidParts<'a> {
    /// The rigid bodies.
    bodies: &'a [RigidBody],
    /// Every particle's mass (kg).
    mass: &'a [Real],
    /// Whether the bodies come in the order of their particles (as
    /// `World::add_body` adds them), for a binary search.
    in_order: bool,
}

impl<'a> RigidParts<'a> {
    /// The rigid `bodies` of a world whose particles have masses `mass`
    /// (kg).
    pub fn new(bodies: &'a [RigidBody], mass: &'a [Real]) -> Self {
        let in_order = bodies
            .windows(2)
            .all(|pair| pair[0].particles.end <= pair[1].particles.start);
        RigidParts {
            bodies,
            mass,
            in_order,
        }
    }

    /// True when there are no rigid bodies.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// The rigid body (its index) whose particle `particle` is, if any.
    pub fn body_of(&self, particle: u32) -> Option<usize> {
        let p = particle as usize;
        if !self.in_order {
            return self.bodies.iter().position(|b| b.particles.contains(&p));
        }
        let after = self.bodies.partition_point(|b| b.particles.start <= p);
        let body = after.checked_sub(1)?;
        self.bodies[body].particles.contains(&p).then_some(body)
    }

    /// True when the touch takes a rigid body's particle.
    pub fn takes(&self, touch: &Touch) -> bool {
        !self.is_empty()
            && touch.particles[..touch.count]
                .iter()
                .any(|&p| self.body_of(p).is_some())
    }

    /// True when all the touch's particles are one rigid body's: a body
    /// touching itself, which does not rub (its friction would only
    /// brake its own spin).
    pub fn within_one(&self, touch: &Touch) -> bool {
        let mut bodies = touch.particles[..touch.count]
            .iter()
            .map(|&p| self.body_of(p));
        let first = bodies.next().flatten();
        first.is_some() && bodies.all(|b| b == first)
    }

    /// Apply the friction impulses of the touches in `scratch` (each with
    /// the normal force (N) it pushed with; each takes a rigid body's
    /// particle) to `velocity` (m/s), moving `position` (m) too, with
    /// friction coefficient `friction` over a (sub)step of `dt` (s); see
    /// the module docs.
    pub fn apply_friction(
        &self,
        scratch: &mut Scratch,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        inverse_mass: &[Real],
        friction: Real,
        dt: Real,
    ) {
        let Scratch {
            found,
            touches,
            start,
            motion,
        } = scratch;
        if found.is_empty() {
            return;
        }
        // The motions of the bodies these touches take, before any impulse.
        start.clear();
        start.resize(self.bodies.len(), None);
        for (touch, _) in found.iter() {
            for &p in &touch.particles[..touch.count] {
                if let Some(b) = self.body_of(p) {
                    let range = self.bodies[b].particles.clone();
                    start[b].get_or_insert_with(|| {
                        Motion::of(
                            &position[range.clone()],
                            &velocity[range.clone()],
                            &self.mass[range],
                        )
                    });
                }
            }
        }
        motion.clone_from(start);
        touches.clear();
        touches.extend(
            found
                .iter()
                .map(|&(touch, push)| RigidTouch::new(touch, push, self, position, start)),
        );
        for touch in touches.iter_mut() {
            touch.normal_speed = touch.relative(velocity, motion).dot(touch.touch.normal);
        }
        for _ in 0..PASSES {
            for touch in touches.iter_mut() {
                let loose = (&mut *position, &mut *velocity, inverse_mass);
                touch.pass(friction * dt, loose, motion, dt);
            }
        }
        for ((body, before), after) in self.bodies.iter().zip(start.iter()).zip(motion.iter()) {
            let (Some(before), Some(after)) = (before, after) else {
                continue;
            };
            let (drift, spin) = (after.drift - before.drift, after.spin - before.spin);
            let range = body.particles.clone();
            for (x, v) in position[range.clone()].iter_mut().zip(&mut velocity[range]) {
                *v += drift + spin.cross(*x - before.centre);
                *x += drift * dt;
            }
        }
    }
}

/// Buffers kept from step to step, so that a step does not allocate.
#[derive(Debug, Clone, Default)]
pub(crate) struct Scratch {
    /// The touches with rigid bodies' particles, with their normal forces
    /// (N), as the friction stage finds them.
    pub found: Vec<(Touch, Real)>,
    touches: Vec<RigidTouch>,
    /// Per rigid body, its motion before the impulses and as they leave
    /// it, where a touch takes it.
    start: Vec<Option<Motion>>,
    motion: Vec<Option<Motion>>,
}

/// The share of a touch that one rigid body takes.
#[derive(Debug, Clone, Copy)]
struct Share {
    /// The body.
    body: usize,
    /// The sum of its particles' weights in the touch.
    weight: Real,
    /// The sum of their weighted arms `wᵢ (xᵢ - c)` from its centre (m).
    arm: Vec3,
}

/// A touch with a rigid body's particles, as sequential impulses see it.
#[derive(Debug, Clone)]
struct RigidTouch {
    touch: Touch,
    /// The normal force it pushed with (N).
    push: Real,
    /// Per particle of the touch, whether it is a rigid body's.
    rigid: [bool; 4],
    /// The rigid bodies it takes, each once.
    shares: [Option<Share>; 4],
    /// The normal speed (m/s) the forces left, positive apart.
    normal_speed: Real,
    /// The normal impulse (N·s) so far: at least `-f_n dt`, so that with
    /// the forces' own push over the step it never pulls.
    pushed: Real,
    /// The friction impulse so far (N·s).
    rubbed: Vec3,
}

impl RigidTouch {
    /// `touch`, which pushed with `push` (N), among the bodies of `parts`
    /// moving as `motion` at `position` (m).
    fn new(
        touch: Touch,
        push: Real,
        parts: &RigidParts<'_>,
        position: &[Vec3],
        motion: &[Option<Motion>],
    ) -> Self {
        let mut rigid = [false; 4];
        let mut shares: [Option<Share>; 4] = [None; 4];
        for (k, is_rigid) in rigid.iter_mut().enumerate().take(touch.count) {
            let p = touch.particles[k];
            let Some((body, m)) = parts.body_of(p).and_then(|b| motion[b].map(|m| (b, m))) else {
                continue;
            };
            *is_rigid = true;
            // A touch has at most four particles, so four shares hold its
            // bodies: a slot is always found.
            let Some(share) = shares
                .iter_mut()
                .find(|share| share.is_none_or(|s| s.body == body))
            else {
                unreachable!("a touch has at most four particles");
            };
            let share = share.get_or_insert(Share {
                body,
                weight: 0.0,
                arm: Vec3::ZERO,
            });
            share.weight += touch.weights[k];
            share.arm += touch.weights[k] * (position[p as usize] - m.centre);
        }
        RigidTouch {
            touch,
            push,
            rigid,
            shares,
            normal_speed: 0.0,
            pushed: 0.0,
            rubbed: Vec3::ZERO,
        }
    }

    /// The loose particles of the touch: their index in it and number.
    fn loose(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        (0..self.touch.count)
            .filter(|&k| !self.rigid[k])
            .map(|k| (k, self.touch.particles[k] as usize))
    }

    /// The relative velocity of its two sides (m/s).
    fn relative(&self, velocity: &[Vec3], motion: &[Option<Motion>]) -> Vec3 {
        let loose: Vec3 = self
            .loose()
            .map(|(k, p)| self.touch.weights[k] * velocity[p])
            .sum();
        let rigid: Vec3 = self
            .shares
            .iter()
            .flatten()
            .filter_map(|s| motion[s.body].map(|m| m.velocity_of(s.weight, s.arm)))
            .sum();
        loose + rigid
    }

    /// The inverse effective mass (1/kg) of the touch along `along`.
    fn inverse_mass(&self, along: Vec3, inverse_mass: &[Real], motion: &[Option<Motion>]) -> Real {
        let loose: Real = self
            .loose()
            .map(|(k, p)| self.touch.weights[k].powi(2) * inverse_mass[p])
            .sum();
        let rigid: Real = self
            .shares
            .iter()
            .flatten()
            .filter_map(|s| motion[s.body].map(|m| m.inverse_mass_of(s.weight, s.arm, along)))
            .sum();
        loose + rigid
    }

    /// Apply `impulse` (N·s): the first side takes it, the second the
    /// opposite, shared by the weights; a rigid body's share through its
    /// motion; the loose particles move by their velocity change times
    /// `dt` (s).
    fn kick(
        &self,
        impulse: Vec3,
        (position, velocity, inverse_mass): (&mut [Vec3], &mut [Vec3], &[Real]),
        motion: &mut [Option<Motion>],
        dt: Real,
    ) {
        for (k, p) in self.loose() {
            let change = self.touch.weights[k] * inverse_mass[p] * impulse;
            velocity[p] += change;
            position[p] += change * dt;
        }
        for share in self.shares.iter().flatten() {
            if let Some(m) = &mut motion[share.body] {
                m.kick_shared(share.weight, share.arm, impulse);
            }
        }
    }

    /// One pass of sequential impulses: the normal speed back to what the
    /// forces left, by a normal impulse that takes back at most their own
    /// push over the step (`f_n dt`: the sum never pulls); then the sliding
    /// stopped by at most `μ f_n dt` in all (`friction_step` = `μ dt`, s).
    fn pass(
        &mut self,
        friction_step: Real,
        loose: (&mut [Vec3], &mut [Vec3], &[Real]),
        motion: &mut [Option<Motion>],
        dt: Real,
    ) {
        if self.push == 0.0 {
            return;
        }
        let (position, velocity, inverse_mass) = loose;
        let normal = self.touch.normal;
        let along_normal = self.inverse_mass(normal, inverse_mass, motion);
        if along_normal > 0.0 {
            let speed = self.relative(velocity, motion).dot(normal);
            let wanted = (self.normal_speed - speed) / along_normal;
            let total = (self.pushed + wanted).max(-self.push * dt);
            let impulse = (total - self.pushed) * normal;
            self.pushed = total;
            self.kick(impulse, (position, velocity, inverse_mass), motion, dt);
        }
        let now = self.relative(velocity, motion);
        let sliding = now - now.dot(normal) * normal;
        let speed = sliding.length();
        if speed == 0.0 {
            return;
        }
        let along = sliding / speed;
        let inverse_effective_mass = self.inverse_mass(along, inverse_mass, motion);
        if inverse_effective_mass <= 0.0 || inverse_effective_mass.is_nan() {
            return;
        }
        let mut total = self.rubbed - speed / inverse_effective_mass * along;
        let most = friction_step * self.push;
        if total.length() > most {
            total *= most / total.length();
        }
        let impulse = total - self.rubbed;
        self.rubbed = total;
        self.kick(impulse, (position, velocity, inverse_mass), motion, dt);
    }
}
