//! The gas of a body among others, and bad gas parameters (docs/physics.md
//! §4): a body's pressure goes to its own particles wherever they start in
//! the world and however its particle range reads; bad parameters are
//! refused.

mod common;

use common::gas::gas_force;
use sprung::build::{self, SurfaceSprings};
use sprung::{BuildError, Gas, IntegratorKind, Real, Vec3, World};

// ------------------------------------------------------ bad input

#[test]
fn bad_gas_parameters_are_refused() {
    let cases: Vec<(Gas, &str)> = vec![
        (Gas::new(-1.0, 0.0), "gas.nrt"),
        (Gas::new(Real::NAN, 0.0), "gas.nrt"),
        (Gas::new(1.0, -0.5), "gas.ramp_time"),
        (
            Gas {
                leak_rate: -0.1,
                ..Gas::new(1.0, 0.0)
            },
            "gas.leak_rate",
        ),
        // A keyframe during the ramp, at its end, or not after the previous.
        (
            Gas {
                keyframes: vec![(0.5, 2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(1.0, 2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(2.0, 2.0), (2.0, 3.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(3.0, 2.0), (2.5, 3.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(2.0, -2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
    ];
    for (gas, field) in cases {
        let mut ring = build::ring(8, 1.0)
            .expect("valid ring")
            .with_stiffness(10.0);
        ring.gas = Some(gas.clone());
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        let error = world.add_body("ring", ring).expect_err("must be refused");
        assert!(world.bodies.is_empty() && world.particles.is_empty());
        assert!(
            matches!(error, BuildError::OutOfRange { field: f, .. } if f == field),
            "{gas:?}: {error:?}"
        );
        assert!(error.to_string().contains(&format!("`{field}`")), "{error}");
    }
}

#[test]
fn a_gas_ball_after_other_bodies_feels_the_same_pressure() {
    // Claim: a body's pressure goes to its own particles wherever they
    // start in the world (small surfaces are added into the body's own
    // entries). The same ball alone and after a rope far away (its
    // particles first in the world) moves to the same bits.
    let ball = || {
        let mut ball = build::icosphere(0.5, 2, SurfaceSprings::default())
            .expect("icosphere")
            .with_total_mass(1.0)
            .with_stiffness(500.0)
            .with_damping(0.1);
        ball.gas = Some(Gas::new(50.0, 0.0));
        ball
    };
    let run = |others: bool| {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        if others {
            let rope = build::rope(7, 1.0).expect("rope").placed(
                1.0,
                Vec3::ZERO,
                Vec3::new(50.0, 0.0, 0.0),
            );
            world.add_body("rope", rope).expect("rope");
        }
        let id = world.add_body("ball", ball()).expect("ball");
        for _ in 0..50 {
            world.step(1e-3).expect("steps");
        }
        world.particles.position[world.bodies[id].particles.clone()].to_vec()
    };
    let (alone, after) = (run(false), run(true));
    assert_eq!(alone, after);
    // And the gas did push: the ball grew from its rest radius.
    let centre = alone.iter().sum::<Vec3>() / alone.len() as f64;
    assert!(
        alone.iter().all(|p| p.distance(centre) > 0.5),
        "the gas pushed out"
    );
}

#[test]
fn body_ranges_changed_by_hand_take_the_world_wide_path_to_the_same_forces() {
    // Claim: a body's pressure forces do not depend on how the bodies'
    // particle ranges read, as long as the faces are right. Two gas balls,
    // their ranges then edited by hand (public fields) so that they
    // overlap, and so that one runs beyond the world's particles: no
    // panic, and the same forces to the bit as with the ranges the world
    // gave (each particle still gets its own body's faces, in order).
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    for (name, x) in [("left", -1.0), ("right", 1.0)] {
        let mut ball = build::icosphere(0.5, 2, SurfaceSprings::default())
            .expect("icosphere")
            .placed(1.0, Vec3::ZERO, Vec3::new(x, 0.0, 0.0));
        ball.gas = Some(Gas::new(50.0, 0.0));
        world.add_body(name, ball).expect("ball");
    }
    let expected = gas_force(&world);
    assert!(expected.iter().any(|f| f.length() > 0.0));
    let given = world.bodies[1].particles.clone();
    world.bodies[1].particles = given.start - 10..given.end;
    assert_eq!(gas_force(&world), expected, "overlapping ranges");
    world.bodies[1].particles = given.start..given.end + 10;
    assert_eq!(gas_force(&world), expected, "a range beyond the particles");
}
