//! Rigid bodies of particles, by shape matching (Müller et al. 2005) with
//! stiffness one.
//!
//! **Method.** After the step, each rigid body's particles are put on
//! their rest shape, turned by the rotation that best fits where the
//! particles went and placed at their centre of mass: `x_i = c + R q_i`,
//! with `q_i` the rest offsets from the centre of mass and `R` the
//! rotation part of `Σ m_i (x_i - c) q_iᵀ`, found by the quaternion
//! iteration of Müller et al. (2016), started from the last rotation
//! (robust for flat and straight bodies, where the matrix is singular).
//! The velocities become those of a rigid body, `v_i = V + ω × (x_i - c)`,
//! with `V` the centre of mass's velocity and `ω = I⁻¹ L` from the
//! particles' angular momentum `L` about it: momentum and angular momentum
//! are kept exactly, so a collider's or a contact's impulse on one particle
//! moves and turns the whole body, and a body in free flight keeps its
//! spin. Every pairwise distance holds to rounding.
//!
//! **Colliders.** A rigid body meets the projection colliders as a body,
//! not particle by particle (a particle's reflection would be averaged
//! away by the projection, and the body would land as if inelastic): it
//! is moved out by its deepest particle, then each touching particle that
//! approaches the surface takes an impulse with the body's effective mass
//! there, `1/k = 1/M + n·((I⁻¹ (r × n)) × r)`, so that it leaves at the
//! restitution times its approach speed, with a Coulomb friction impulse
//! of at most the friction coefficient times the normal one (a few passes
//! over the touching particles, as sequential impulses); the body then
//! moves along the surface by the impulses' change of its drift times the
//! step, as if they had acted from the start of the step (and out again
//! where a curved surface took it in), so a body at rest on a slope stays
//! put. Below
//! `rest_speed` (the speed gravity gives in two steps, at least
//! [`crate::world::RESTING_SPEED`]) a contact is treated as resting: no
//! restitution, so a body at rest does not rock.
//!
//! Shape matching was chosen over rods between every pair of particles:
//! its cost is linear in the particles, it needs no iterations to converge,
//! and it never leaves a body slightly bent.

use std::ops::Range;

use glam::{DMat3, DQuat};

use crate::colliders::{Collider, ContactResponse};
use crate::units::{Real, Vec3};

/// One rigid body: its particles, rest shape and last rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// The world's particles of the body.
    pub particles: Range<usize>,
    /// Rest offsets `q_i` from the centre of mass (m), one per particle.
    pub rest: Vec<Vec3>,
    /// Rotation from the rest shape at the end of the last step.
    pub rotation: DQuat,
    /// The motion of the last projection: centre of mass (m), its velocity
    /// (m/s), the spin (rad/s), the total mass (kg) and the inverse inertia
    /// (1/(kg·m²)) about the centre.
    motion: Motion,
    /// Per particle, this step's normal impulse (N·s), approach speed
    /// (m/s) and friction impulse (N·s) against a collider (scratch).
    pushed: Vec<Real>,
    approach: Vec<Real>,
    rubbed: Vec<Vec3>,
}

/// A rigid body's motion: centre of mass (m), its velocity `drift` (m/s),
/// the `spin` (rad/s), the total mass (kg) and the inverse inertia
/// (1/(kg·m²)) about the centre.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(crate) struct Motion {
    pub centre: Vec3,
    pub drift: Vec3,
    pub spin: Vec3,
    pub mass: Real,
    pub inverse_inertia: DMat3,
}

impl Motion {
    /// The motion of the particles `x` (m) with velocities `v` (m/s) and
    /// masses `m` (kg) as one rigid body: the momentum and the angular
    /// momentum about their centre of mass that the projection
    /// ([`RigidBody::project`]) keeps, with the inertia of where they are.
    pub fn of(x: &[Vec3], v: &[Vec3], m: &[Real]) -> Motion {
        let (centre, total) = centre_of_mass(x, m);
        let mut momentum = Vec3::ZERO;
        let mut angular = Vec3::ZERO;
        let mut inertia = DMat3::ZERO;
        for ((&x, &v), &m) in x.iter().zip(v).zip(m) {
            let arm = x - centre;
            momentum += m * v;
            angular += m * arm.cross(v);
            inertia += point_inertia(m, arm);
        }
        let inverse_inertia = inverse_inertia(inertia);
        Motion {
            centre,
            drift: momentum / total,
            spin: inverse_inertia * angular,
            mass: total,
            inverse_inertia,
        }
    }

    /// Velocity (m/s) of the body's point at `x` (m).
    pub fn velocity_at(&self, x: Vec3) -> Vec3 {
        self.velocity_of(1.0, x - self.centre)
    }

    /// `Σ wᵢ vᵢ` over points of the body with weights `wᵢ` summing to
    /// `weight`, and weighted arms `Σ wᵢ (xᵢ - c)` summing to `arm` (m):
    /// their weighted velocity (m/s).
    pub fn velocity_of(&self, weight: Real, arm: Vec3) -> Vec3 {
        weight * self.drift + self.spin.cross(arm)
    }

    /// The inverse effective mass (1/kg) along `along` of points of the
    /// body taken with weights summing to `weight` and weighted arms
    /// summing to `arm` (m), as [`Motion::velocity_of`]: `weight² / M +
    /// (arm × t)·I⁻¹ (arm × t)`.
    pub fn inverse_mass_of(&self, weight: Real, arm: Vec3, along: Vec3) -> Real {
        let turn = arm.cross(along);
        weight * weight / self.mass + turn.dot(self.inverse_inertia * turn)
    }

    /// Apply `impulse` (N·s) shared by points of the body with weights
    /// summing to `weight` and weighted arms summing to `arm` (m).
    pub fn kick_shared(&mut self, weight: Real, arm: Vec3, impulse: Vec3) {
        self.drift += weight * impulse / self.mass;
        self.spin += self.inverse_inertia * arm.cross(impulse);
    }

    /// Apply `impulse` (N·s) at the point `x` (m).
    fn kick(&mut self, x: Vec3, impulse: Vec3) {
        self.kick_shared(1.0, x - self.centre, impulse);
    }

    /// `1/k`: the effective inverse mass (1/kg) at `x` (m) along `n`.
    fn inverse_mass_along(&self, x: Vec3, n: Vec3) -> Real {
        let r = x - self.centre;
        1.0 / self.mass + n.dot((self.inverse_inertia * r.cross(n)).cross(r))
    }
}

/// Passes of sequential impulses over a rigid body's touching particles.
const IMPULSE_PASSES: usize = 16;

/// The world's rigid bodies.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct RigidBodies {
    /// Every rigid body.
    pub list: Vec<RigidBody>,
}

/// Iterations of the rotation fit; each is cheap, and it starts from the
/// last step's rotation, a few degrees away at most.
const ROTATION_ITERATIONS: usize = 30;

impl RigidBody {
    /// A rigid body of the particles `particles` at `position` (m) with
    /// `mass` (kg): its rest shape is the one it has now.
    pub fn new(particles: Range<usize>, position: &[Vec3], mass: &[Real]) -> Self {
        let (centre, _) = centre_of_mass(&position[particles.clone()], &mass[particles.clone()]);
        let rest = position[particles.clone()]
            .iter()
            .map(|&x| x - centre)
            .collect();
        RigidBody {
            particles,
            rest,
            rotation: DQuat::IDENTITY,
            motion: Motion::default(),
            pushed: Vec::new(),
            approach: Vec::new(),
            rubbed: Vec::new(),
        }
    }

    /// Put the body's particles on its rest shape (see the module docs).
    pub fn project(&mut self, position: &mut [Vec3], velocity: &mut [Vec3], mass: &[Real]) {
        let range = self.particles.clone();
        let (x, v, m) = (
            &mut position[range.clone()],
            &mut velocity[range.clone()],
            &mass[range],
        );
        let (centre, total) = centre_of_mass(x, m);
        let momentum: Vec3 = v.iter().zip(m).map(|(&v, &m)| m * v).sum();
        let angular: Vec3 = x
            .iter()
            .zip(v.iter())
            .zip(m)
            .map(|((&x, &v), &m)| m * (x - centre).cross(v))
            .sum();
        let fit = x
            .iter()
            .zip(&self.rest)
            .zip(m)
            .fold(DMat3::ZERO, |a, ((&x, &q), &m)| {
                a + m * outer(x - centre, q)
            });
        self.rotation = best_rotation(fit, self.rotation);
        let r = self.rotation;
        let mut inertia = DMat3::ZERO;
        for ((x, &q), &m) in x.iter_mut().zip(&self.rest).zip(m) {
            let arm = r * q;
            *x = centre + arm;
            inertia += point_inertia(m, arm);
        }
        let inverse_inertia = inverse_inertia(inertia);
        self.motion = Motion {
            centre,
            drift: momentum / total,
            spin: inverse_inertia * angular,
            mass: total,
            inverse_inertia,
        };
        for (v, x) in v.iter_mut().zip(x.iter()) {
            *v = self.motion.velocity_at(*x);
        }
    }

    /// Meet the projection colliders at `time` (s), the end of a step of
    /// `dt` (s), as a body (see the module docs), after
    /// [`RigidBody::project`]. Particles within `rest_speed · dt` of the
    /// surface (a resting contact's motion in a step) count as touching,
    /// so a body lying on a face holds on all its corners at once.
    pub fn collide(
        &mut self,
        colliders: &[Collider],
        time: Real,
        dt: Real,
        rest_speed: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
    ) {
        let range = self.particles.clone();
        let (x, v) = (&mut position[range.clone()], &mut velocity[range]);
        let mut touched = false;
        for collider in colliders {
            let ContactResponse::Projection {
                restitution,
                friction,
            } = collider.response
            else {
                continue;
            };
            let shape = collider.shape_at(time);
            let surface_velocity = collider.velocity_at(time);
            let deepest = x
                .iter()
                .map(|&p| shape.distance_and_normal(p))
                .fold((0.0, Vec3::ZERO), |a, b| if b.0 < a.0 { b } else { a });
            if deepest.0 >= 0.0 {
                continue;
            }
            touched = true;
            let shift = -deepest.0 * deepest.1;
            x.iter_mut().for_each(|p| *p += shift);
            self.motion.centre += shift;
            // The approach speed of each touching particle before any
            // impulse, for its restitution.
            let touching = |p: Vec3| {
                let (distance, normal) = shape.distance_and_normal(p);
                (distance <= rest_speed * dt + 1e-9 * (1.0 + p.length())).then_some(normal)
            };
            let motion = &mut self.motion;
            let start = *motion;
            self.pushed.clear();
            self.pushed.resize(x.len(), 0.0);
            self.rubbed.clear();
            self.rubbed.resize(x.len(), Vec3::ZERO);
            self.approach.clear();
            self.approach.extend(x.iter().map(|&p| {
                touching(p).map_or(0.0, |n| {
                    (motion.velocity_at(p) - surface_velocity).dot(n).min(0.0)
                })
            }));
            for _ in 0..IMPULSE_PASSES {
                for (k, &p) in x.iter().enumerate() {
                    let Some(n) = touching(p) else { continue };
                    let relative = motion.velocity_at(p) - surface_velocity;
                    let bounce = if -self.approach[k] > rest_speed {
                        restitution
                    } else {
                        0.0
                    };
                    let target = -bounce * self.approach[k];
                    let normal_speed = relative.dot(n);
                    // The accumulated normal impulse stays pushing (≥ 0).
                    let wanted = (target - normal_speed) / motion.inverse_mass_along(p, n);
                    let total = (self.pushed[k] + wanted).max(0.0);
                    motion.kick(p, (total - self.pushed[k]) * n);
                    self.pushed[k] = total;
                    // Friction: the accumulated tangential impulse that
                    // stops the sliding, at most μ times the push (Coulomb).
                    let relative = motion.velocity_at(p) - surface_velocity;
                    let sliding = relative - relative.dot(n) * n;
                    let speed = sliding.length();
                    if speed > 0.0 && friction > 0.0 {
                        let t = sliding / speed;
                        let stop = -speed / motion.inverse_mass_along(p, t) * t;
                        let mut rubbed = self.rubbed[k] + stop;
                        let most = friction * self.pushed[k];
                        if rubbed.length() > most {
                            rubbed *= most / rubbed.length();
                        }
                        motion.kick(p, rubbed - self.rubbed[k]);
                        self.rubbed[k] = rubbed;
                    }
                }
            }
            // The body moves by the impulses' change of its drift times
            // `dt`, along the surface, as if they had acted from the start
            // of the step (the shift out took care of the normal part):
            // otherwise each step's sliding, taken before friction stops
            // it, adds up to a creep (`g sin θ dt` per second on a slope)
            // of a body at rest. Not turned: a turn about the centre would
            // drive other corners into the surface.
            let normal = deepest.1;
            let along = motion.drift - start.drift;
            let step = (along - along.dot(normal) * normal) * dt;
            x.iter_mut().for_each(|p| *p += step);
            motion.centre += step;
            // Along a curved surface (a sphere) that move may take a
            // particle a little inside: out again.
            let deepest = x
                .iter()
                .map(|&p| shape.distance_and_normal(p))
                .fold((0.0, Vec3::ZERO), |a, b| if b.0 < a.0 { b } else { a });
            if deepest.0 < 0.0 {
                let shift = -deepest.0 * deepest.1;
                x.iter_mut().for_each(|p| *p += shift);
                motion.centre += shift;
            }
        }
        if touched {
            for (v, p) in v.iter_mut().zip(x.iter()) {
                *v = self.motion.velocity_at(*p);
            }
        }
    }
}

impl RigidBodies {
    /// Put every rigid body on its rest shape, then let it meet the
    /// projection `colliders` at `time` (s), the end of a step of `dt` (s);
    /// contacts slower than `rest_speed` (m/s) rest rather than bounce.
    #[allow(clippy::too_many_arguments)]
    pub fn project(
        &mut self,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        mass: &[Real],
        colliders: &[Collider],
        time: Real,
        dt: Real,
        rest_speed: Real,
    ) {
        for body in &mut self.list {
            body.project(position, velocity, mass);
            body.collide(colliders, time, dt, rest_speed, position, velocity);
        }
    }
}

/// Centre of mass (m) and total mass (kg).
fn centre_of_mass(x: &[Vec3], m: &[Real]) -> (Vec3, Real) {
    let total: Real = m.iter().sum();
    let moment: Vec3 = x.iter().zip(m).map(|(&x, &m)| m * x).sum();
    (moment / total, total)
}

/// The inertia (kg·m²) of a mass `m` (kg) at `arm` (m) from the centre.
fn point_inertia(m: Real, arm: Vec3) -> DMat3 {
    m * (DMat3::from_diagonal(Vec3::splat(arm.length_squared())) - outer(arm, arm))
}

/// `a bᵀ`.
fn outer(a: Vec3, b: Vec3) -> DMat3 {
    DMat3::from_cols(a * b.x, a * b.y, a * b.z)
}

/// The rotation nearest to `a` (the one maximising `trace(Rᵀ a)`), by
/// Müller et al.'s quaternion iteration from `start`.
fn best_rotation(a: DMat3, start: DQuat) -> DQuat {
    let scale = a.x_axis.length() + a.y_axis.length() + a.z_axis.length();
    if scale == 0.0 || !scale.is_finite() {
        return start;
    }
    let mut q = start;
    for _ in 0..ROTATION_ITERATIONS {
        let r = DMat3::from_quat(q);
        let torque = r.x_axis.cross(a.x_axis) + r.y_axis.cross(a.y_axis) + r.z_axis.cross(a.z_axis);
        let alignment = r.x_axis.dot(a.x_axis) + r.y_axis.dot(a.y_axis) + r.z_axis.dot(a.z_axis);
        let omega = torque / (alignment.abs() + 1e-12 * scale);
        let angle = omega.length();
        if angle < 1e-15 {
            break;
        }
        q = (DQuat::from_axis_angle(omega / angle, angle) * q).normalize();
    }
    q
}

/// `I⁻¹`; for a body on a line (`I` singular along it) the moment about
/// the line is regularised, so the spin about it stays zero.
fn inverse_inertia(inertia: DMat3) -> DMat3 {
    let size = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    if size == 0.0 {
        return DMat3::ZERO;
    }
    if inertia.determinant().abs() > 1e-12 * size.powi(3) {
        inertia.inverse()
    } else {
        (inertia + DMat3::from_diagonal(Vec3::splat(1e-9 * size))).inverse()
    }
}
