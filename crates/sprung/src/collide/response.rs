//! The two contact responses (PHYSICS.md §5), written against any
//! [`Shape`]'s signed distance and normal.

use super::{Collider, ContactResponse};
use crate::{Real, Vec3};

/// Projection stage: every movable particle found inside `collider` is put
/// back on its surface; the normal velocity, if it points inward, is
/// reflected and scaled by the restitution `e`; the tangential speed drops by
/// `μ (1 + e) |v_n|` (Coulomb friction: the tangential impulse is at most `μ`
/// times the normal one), never below zero. A point sliding on a plane under
/// gravity thus decelerates at `μ g` when `e = 0`.
pub fn project(
    collider: &Collider,
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
    for i in 0..position.len() {
        if inverse_mass[i] == 0.0 {
            continue;
        }
        let (distance, normal) = collider.shape.distance_and_normal(position[i]);
        if distance >= 0.0 {
            continue;
        }
        position[i] -= distance * normal;
        let normal_speed = velocity[i].dot(normal);
        if normal_speed >= 0.0 {
            continue;
        }
        let tangential = velocity[i] - normal_speed * normal;
        let tangential_speed = tangential.length();
        let slowdown = friction * (1.0 + restitution) * -normal_speed;
        let kept = if tangential_speed > slowdown {
            tangential * (1.0 - slowdown / tangential_speed)
        } else {
            Vec3::ZERO
        };
        velocity[i] = kept - restitution * normal_speed * normal;
    }
}

/// Penalty force: a virtual spring `k depth n` pushing each particle inside
/// `collider` out, with damping `-c (v·n) n` on its normal velocity.
pub fn penalty_force(
    collider: &Collider,
    position: &[Vec3],
    velocity: &[Vec3],
    force: &mut [Vec3],
) {
    let ContactResponse::Penalty { stiffness, damping } = collider.response else {
        return;
    };
    for i in 0..position.len() {
        let (distance, normal) = collider.shape.distance_and_normal(position[i]);
        if distance < 0.0 {
            force[i] += (-stiffness * distance - damping * velocity[i].dot(normal)) * normal;
        }
    }
}
