//! Helpers of the gas tests (`gas_rings.rs`, `gas_conservation.rs`,
//! `gas_bodies.rs`): a world without gravity, running it for a time, and
//! the gas pressure force alone.

use sprung::forces::{Force, GasPressure};
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

/// A world without gravity holding `body` as body 0.
pub fn weightless(kind: IntegratorKind, body: BodyData) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("body", body).expect("valid body");
    world
}

/// Step `world` by `dt` until its time reaches `until` (s).
pub fn run_until(world: &mut World, dt: Real, until: Real) {
    while world.time() < until - 0.5 * dt {
        world.step(dt).expect("stable");
    }
}

/// The gas pressure force alone at the world's state (N per particle).
pub fn gas_force(world: &World) -> Vec<Vec3> {
    let context = world.force_context();
    let mut force = vec![Vec3::ZERO; world.particles.len()];
    GasPressure::new().accumulate(&context, &mut force);
    force
}
