//! The two contact responses (docs/physics.md §5), written against any
//! [`Shape`](super::Shape)'s signed distance and normal and the collider's
//! surface velocity, so they serve every shape, static or moving.

use super::constraint::coulomb;
use super::{Collider, ContactResponse};
use crate::units::{Real, Vec3};

/// Projection stage at `time` (s), the end of the step: every movable
/// particle found inside `collider` (where it is at `time`) is put back on
/// its surface, along the normal. With `u` the surface velocity and
/// `w = v - u` the relative velocity: the normal part of `w`, if it points
/// inward, is reflected and scaled by the restitution `e`; the tangential
/// part of `w` shrinks by `μ (1 + e) |w_n|` (Coulomb friction: the
/// tangential impulse is at most `μ` times the normal one), never below zero.
/// A point sliding on a static plane under gravity thus decelerates at
/// `μ g` when `e = 0`, and a point resting on a moving plane is dragged
/// along at `μ g` until it moves with it.
pub fn project(
    collider: &Collider,
    time: Real,
    position: &mut [Vec3],
    velocity: &mut [Vec3],
    inverse_mass: &[Real],
) {
    let ContactResponse::Projection {
        restitution,
        friction,
    } = collider.response
    else {
        return;
    };
    let shape = collider.shape_at(time);
    let surface_velocity = collider.velocity_at(time);
    for i in 0..position.len() {
        if inverse_mass[i] == 0.0 {
            continue;
        }
        let (distance, normal) = shape.distance_and_normal(position[i]);
        if distance >= 0.0 {
            continue;
        }
        position[i] -= distance * normal;
        let relative = velocity[i] - surface_velocity;
        let normal_speed = relative.dot(normal);
        if normal_speed >= 0.0 {
            continue;
        }
        let tangential = relative - normal_speed * normal;
        let kept = coulomb(tangential, friction * (1.0 + restitution) * -normal_speed);
        velocity[i] = surface_velocity + kept - restitution * normal_speed * normal;
    }
}

/// Relative tangential speed (m/s) below which penalty friction fades
/// linearly to zero, so that the force is smooth for the integrators.
pub const FRICTION_REGULARISATION: Real = 0.01;

/// Penalty force (N) at `time` (s), the integrator's trial time: a virtual
/// spring `k depth n` pushing each particle inside `collider` (where it is
/// at `time`) out, with damping `-c ((v - u)·n) n` on its normal velocity
/// relative to the surface velocity `u`, and friction
/// `-μ |f_n| v_t / √(|v_t|² + v_ε²)` against the relative tangential
/// velocity `v_t` (Coulomb's `μ |f_n|` when sliding, regularised below
/// [`FRICTION_REGULARISATION`] = `v_ε`).
pub fn penalty_force(
    collider: &Collider,
    time: Real,
    position: &[Vec3],
    velocity: &[Vec3],
    force: &mut [Vec3],
) {
    let ContactResponse::Penalty {
        stiffness,
        damping,
        friction,
    } = collider.response
    else {
        return;
    };
    let shape = collider.shape_at(time);
    let surface_velocity = collider.velocity_at(time);
    for i in 0..position.len() {
        let (distance, normal) = shape.distance_and_normal(position[i]);
        if distance < 0.0 {
            let relative = velocity[i] - surface_velocity;
            let normal_speed = relative.dot(normal);
            let push = (-stiffness * distance - damping * normal_speed).max(0.0);
            force[i] += push * normal;
            if friction > 0.0 {
                let sliding = relative - normal_speed * normal;
                let scale = (sliding.length_squared() + FRICTION_REGULARISATION.powi(2)).sqrt();
                force[i] -= friction * push * sliding / scale;
            }
        }
    }
}
