//! The integrate stage is a function of the model, the state, the forces
//! and `dt` (`sprung::model`): a world stepped by hand through its parts
//! (`World::parts_mut`, `Dynamics::new(model, forces)` and an integrator
//! of its own) takes the same bits as `World::step`, under every
//! integrator, in 2D and in 3D, with gas, wind, gravity, drag and a
//! controller's applied forces (the controls) in the force list.

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::forces::{AppliedForces, Wind, WindField, WindModel};
use sprung::integrate::{Dynamics, IntegratorKind};
use sprung::{BodyData, Gas, Vec3, World};

/// Steps compared; each one's time is the world's before it.
const STEPS: usize = 8;
/// The step (s): below the scenes' stable steps for the explicit methods.
const DT: f64 = 2e-4;

/// `body` filled with `nrt` (J) of gas from the start.
fn with_gas(body: BodyData, nrt: f64) -> BodyData {
    BodyData {
        gas: Some(Gas::new(nrt, 0.0)),
        ..body
    }
}

/// A gas ball in the wind beside a cloth pinned at two corners, pushed
/// sideways by a controller (3D).
fn scene_3d(kind: IntegratorKind) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    world.set_air_drag(0.01);
    let ball = build::icosphere(0.3, 1, SurfaceSprings::default())
        .unwrap()
        .with_stiffness(500.0)
        .with_damping(0.2);
    world.add_body("ball", with_gas(ball, 50.0)).unwrap();
    let cloth = build::cloth(6, 5, 1.0, 0.8, ClothSprings::default())
        .unwrap()
        .with_stiffness(800.0)
        .with_pinned(vec![0, 5])
        .placed(1.0, Vec3::ZERO, Vec3::new(1.5, 0.5, 0.0));
    world.add_body("cloth", cloth).unwrap();
    let wind = Wind::new(
        WindField::uniform(Vec3::new(3.0, 0.0, 1.0)),
        WindModel::Simple { coefficient: 0.5 },
    )
    .unwrap();
    world.forces.push(Box::new(wind));
    let push: Vec<Vec3> = (0..world.particles.len())
        .map(|i| Vec3::new(0.01 * i as f64, 0.0, -0.02))
        .collect();
    world.forces.set(AppliedForces { force: push });
    world
}

/// A gas ring under gravity (2D).
fn scene_2d(kind: IntegratorKind) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    let ring = build::ring(24, 0.5)
        .unwrap()
        .with_stiffness(300.0)
        .with_damping(0.1);
    world
        .add_body(
            "ring",
            with_gas(ring, 5.0).with_velocity(Vec3::new(0.5, 0.0, 0.0)),
        )
        .unwrap();
    world
}

/// Step `world` by `World::step` and a copy built by `build` by hand,
/// and require the same bits after every step.
fn same_as_step(name: &str, kind: IntegratorKind, build: fn(IntegratorKind) -> World) {
    let (mut world, mut by_hand) = (build(kind), build(kind));
    let start = world.particles.position.clone();
    let mut integrator = kind.create();
    let solver = by_hand.settings.solver;
    for step in 0..STEPS {
        let time = world.time();
        world.step(DT).unwrap();
        // The model, the forces and the state, borrowed apart.
        let (model, forces, position, velocity) = by_hand.parts_mut();
        let mut dynamics = Dynamics::new(model, forces);
        integrator
            .step(time, DT, position, velocity, &mut dynamics, &solver)
            .unwrap();
        assert!(
            by_hand.particles.position == world.particles.position
                && by_hand.particles.velocity == world.particles.velocity,
            "{name}, {kind:?}: step {step} by hand differs from World::step"
        );
    }
    // The comparison is of a motion, not of a world at rest.
    assert_ne!(
        world.particles.position, start,
        "{name}, {kind:?}: nothing moved"
    );
}

#[test]
fn the_integrate_stage_is_a_function_of_model_state_forces_and_dt() {
    for kind in IntegratorKind::ALL {
        same_as_step("3D", kind, scene_3d);
        same_as_step("2D", kind, scene_2d);
    }
}
