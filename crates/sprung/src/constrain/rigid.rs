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
//! Shape matching was chosen over rods between every pair of particles:
//! its cost is linear in the particles, it needs no iterations to converge,
//! and it never leaves a body slightly bent.

use std::ops::Range;

use glam::{DMat3, DQuat};

use crate::{Real, Vec3};

/// One rigid body: its particles, rest shape and last rotation.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidBody {
    /// The world's particles of the body.
    pub particles: Range<usize>,
    /// Rest offsets `q_i` from the centre of mass (m), one per particle.
    pub rest: Vec<Vec3>,
    /// Rotation from the rest shape at the end of the last step.
    pub rotation: DQuat,
}

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
            inertia +=
                m * (DMat3::from_diagonal(Vec3::splat(arm.length_squared())) - outer(arm, arm));
        }
        let spin = solve_inertia(inertia, angular);
        let drift = momentum / total;
        for (v, x) in v.iter_mut().zip(x.iter()) {
            *v = drift + spin.cross(*x - centre);
        }
    }
}

impl RigidBodies {
    /// Put every rigid body on its rest shape.
    pub fn project(&mut self, position: &mut [Vec3], velocity: &mut [Vec3], mass: &[Real]) {
        for body in &mut self.list {
            body.project(position, velocity, mass);
        }
    }
}

/// Centre of mass (m) and total mass (kg).
fn centre_of_mass(x: &[Vec3], m: &[Real]) -> (Vec3, Real) {
    let total: Real = m.iter().sum();
    let moment: Vec3 = x.iter().zip(m).map(|(&x, &m)| m * x).sum();
    (moment / total, total)
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

/// `ω` with `I ω = L`; for a body on a line (`I` singular along it) the
/// spin about the line is zero.
fn solve_inertia(inertia: DMat3, angular: Vec3) -> Vec3 {
    let size = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    if size == 0.0 {
        return Vec3::ZERO;
    }
    if inertia.determinant().abs() > 1e-12 * size.powi(3) {
        inertia.inverse() * angular
    } else {
        // A straight body: regularise the zero moment about its axis.
        (inertia + DMat3::from_diagonal(Vec3::splat(1e-9 * size))).inverse() * angular
    }
}
