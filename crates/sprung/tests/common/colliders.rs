//! Helpers of the collider tests (`sphere_colliders.rs`,
//! `moving_colliders.rs`, `sphere_cloth.rs`): free particles and a
//! collider, its shapes and responses, and how deep particles are inside it.

use sprung::colliders::Path;
use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Real, Shape, Vec3, World};

pub const G: Real = 9.81; // m/s²

/// A world with gravity `gravity` (m/s²), one collider, and free particles
/// of mass `mass` (kg) at `position` (m) with `velocity` (m/s), no springs.
pub fn particles_and(
    kind: IntegratorKind,
    gravity: Vec3,
    mass: Real,
    position: Vec<Vec3>,
    velocity: Vec<Vec3>,
    collider: Collider,
) -> World {
    let mut world = World::new(kind);
    world.set_gravity(gravity);
    world.colliders.push(collider);
    let mut body = BodyData::from_positions(position).with_mass(mass);
    body.velocity = velocity;
    world.add_body("points", body).expect("valid points");
    world
}

pub fn projection(restitution: Real, friction: Real) -> ContactResponse {
    ContactResponse::Projection {
        restitution,
        friction,
    }
}

pub fn sphere(centre: Vec3, radius: Real) -> Shape {
    Shape::sphere(centre, radius).expect("valid sphere")
}

/// A path moving at constant velocity `velocity` (m/s) from time 0 to far
/// beyond the end of any test here (100 s), displacement zero at time 0.
pub fn steady(velocity: Vec3) -> Path {
    Path::new(vec![(0.0, Vec3::ZERO), (100.0, 100.0 * velocity)]).expect("valid path")
}

/// Signed distance (m) of every particle from `world`'s first collider where
/// it is now, and the outward normals.
pub fn distances(world: &World) -> Vec<(Real, Vec3)> {
    let shape = world.colliders[0].shape_at(world.time());
    world
        .particles
        .position
        .iter()
        .map(|&x| shape.distance_and_normal(x))
        .collect()
}

/// The deepest penetration (m, positive inside) of any particle into the
/// first collider.
pub fn deepest(world: &World) -> Real {
    distances(world)
        .iter()
        .fold(Real::NEG_INFINITY, |deepest, &(d, _)| deepest.max(-d))
}

/// How far a discrete contact tilts the normal: a point approaching a
/// sphere of radius `radius` (m) along an axis at impact parameter `b` (m)
/// is found inside up to `lag` (m) deep and projected radially, so the
/// normal's sine to the axis is `s = b / ρ` with `ρ ∈ [radius - lag,
/// radius]` instead of `b / radius`. Returns `(Δs, s_max)`, the largest
/// change of `s` and the largest `s`.
pub fn normal_tilt(b: Real, radius: Real, lag: Real) -> (Real, Real) {
    let s_max = b / (radius - lag);
    (s_max - b / radius, s_max)
}

/// Step `world` by `dt` and check that no particle is inside its collider:
/// projection is exact to round-off (~1e-16 m for coordinates of order
/// 1 m); we claim 1e-12 m.
pub fn step_outside(world: &mut World, dt: Real) {
    world.step(dt).expect("stable");
    let depth = deepest(world);
    assert!(
        depth <= 1e-12,
        "{depth:.3e} m inside at t = {} s",
        world.time()
    );
}
