//! Projection colliders inside an implicit step: velocity constraints.
//!
//! At a time step far above the explicit limit a particle can travel deep
//! into a collider within one step. Moving it back out afterwards (the
//! projection stage) then squeezes the springs and the gas between it and
//! its neighbours, and at a large step that stored energy comes back as a
//! bounce far higher than the drop. So the implicit integrators treat the
//! projection colliders the way Baraff and Witkin treat contacts ("Large
//! steps in cloth simulation", SIGGRAPH 1998, §5.3): every particle that
//! touches a collider (`d ≤ 0`) or would reach it during the step at its
//! present velocity (`d + dt v_n < 0`) has its velocity along the normal,
//! relative to the surface, prescribed in the linear solve, and the rest
//! of its body answers through the springs within the same solve.
//!
//! The prescribed relative normal speed at the end of the step is
//! `-d/dt` without restitution: reach the surface exactly (from a distance
//! `d`, negative inside, which pushes the particle out). With restitution
//! `e` it is `max(-d/dt, e v)`, `v` the approach speed: the particle leaves
//! at `e` times the speed it came with. Backward Euler moves it by
//! `dt` times its end velocity, so a particle that would have reached the
//! surface during the step bounces from where the step found it, at most
//! one step's travel above the surface, rather than landing in one step
//! and losing its speed to the landing.
//!
//! A contact can only push. The solver measures the impulse each constraint
//! needed and releases those that pulled (a particle its springs lift off
//! the floor), then solves again without them. Coulomb friction then slows
//! the relative tangential velocity by `μ` times the normal impulse over
//! the mass ([`ContactConstraint::normal_change`]; `g dt` for a particle at
//! rest on a floor), as the projection stage does.

use std::ops::Range;

use super::{Collider, ContactResponse};
use crate::units::{Real, Vec3};

/// A particle's contact with a projection collider over one implicit step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactConstraint {
    /// The particle.
    pub particle: usize,
    /// Outward unit normal of the surface.
    pub normal: Vec3,
    /// Velocity of the surface at the end of the step (m/s).
    pub surface_velocity: Vec3,
    /// Normal velocity relative to the surface at the end of the step
    /// (m/s, positive away from the surface).
    pub normal_speed: Real,
    /// The normal impulse the contact gave, over the particle's mass (m/s),
    /// filled in by the solver: `μ` times it is taken from the tangential
    /// speed.
    pub normal_change: Real,
    /// Coulomb friction coefficient `μ`.
    pub friction: Real,
}

impl ContactConstraint {
    /// The velocity (m/s) the constraint prescribes along its normal, for a
    /// particle whose velocity is `velocity`: the component of `velocity`
    /// along the normal is replaced.
    pub fn normal_velocity(&self) -> Real {
        self.surface_velocity.dot(self.normal) + self.normal_speed
    }

    /// Apply Coulomb friction to `velocity` (m/s) after the solve.
    pub fn apply_friction(&self, velocity: &mut Vec3) {
        let relative = *velocity - self.surface_velocity;
        let normal = relative.dot(self.normal) * self.normal;
        let kept = coulomb(
            relative - normal,
            self.friction * self.normal_change.max(0.0),
        );
        *velocity = self.surface_velocity + normal + kept;
    }
}

/// The tangential velocity `tangential` (m/s) slowed by `slowdown` (m/s)
/// along itself, never past zero (Coulomb friction over one impulse).
pub(super) fn coulomb(tangential: Vec3, slowdown: Real) -> Vec3 {
    let speed = tangential.length();
    if speed > slowdown {
        tangential * (1.0 - slowdown / speed)
    } else {
        Vec3::ZERO
    }
}

/// Add to `out` the constraints of the movable particles of `particles` (`inverse_mass >
/// 0`) that touch `collider`, or would reach it at their present velocity,
/// during a step of `dt` (s) ending at `end_time` (s), from their position
/// (m) and velocity (m/s) at its start. Only projection colliders give
/// constraints; a particle already constrained by an earlier collider is
/// left to it.
#[allow(clippy::too_many_arguments)]
pub fn add_contact_constraints(
    collider: &Collider,
    end_time: Real,
    dt: Real,
    particles: Range<usize>,
    position: &[Vec3],
    velocity: &[Vec3],
    inverse_mass: &[Real],
    out: &mut Vec<ContactConstraint>,
) {
    let ContactResponse::Projection {
        restitution,
        friction,
    } = collider.response
    else {
        return;
    };
    let shape = collider.shape_at(end_time);
    let surface_velocity = collider.velocity_at(end_time);
    let already = out.len();
    for i in particles {
        if inverse_mass[i] == 0.0 {
            continue;
        }
        let (distance, normal) = shape.distance_and_normal(position[i]);
        let approach = (velocity[i] - surface_velocity).dot(normal);
        if distance > 0.0 && distance + dt * approach >= 0.0 {
            continue;
        }
        if out[..already].iter().any(|c| c.particle == i) {
            continue;
        }
        let land = -distance / dt;
        let bounce = restitution * (-approach).max(0.0);
        out.push(ContactConstraint {
            particle: i,
            normal,
            surface_velocity,
            normal_speed: if bounce > 0.0 { land.max(bounce) } else { land },
            normal_change: 0.0,
            friction,
        });
    }
}
