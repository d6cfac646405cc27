//! The CCD's rounds against themselves.

use crate::build::{self, ClothSprings};
use crate::units::{Real, Vec3};
use crate::{IntegratorKind, World};

/// Two 12×12 cloths of 1 m in one plane, overlapping over half their
/// area, pinned all round, thrown apart along their normal at 1 m/s
/// each: where each part ends is decided pair by pair, so they interlace,
/// and their pinned edges, each across the other, hold them together:
/// they collide over the overlap at every step, through every round and
/// the impact zones (the outside battery's coplanar sheets, small).
fn interlaced() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    let border: Vec<usize> = (0..144)
        .filter(|i| i % 12 == 0 || i % 12 == 11 || *i < 12 || *i >= 132)
        .collect();
    for (name, x, speed) in [("up", 0.0, 1.0), ("down", 0.5, -1.0)] {
        let cloth = build::cloth(12, 12, 1.0, 1.0, ClothSprings::default())
            .expect("a cloth")
            .with_stiffness(150.0)
            .with_velocity(Vec3::new(0.0, 0.0, speed))
            .with_pinned(border.clone())
            .placed(1.0, Vec3::ZERO, Vec3::new(x, 0.0, 0.0));
        world.add_body(name, cloth).expect("added");
    }
    world
}

#[test]
fn a_pair_is_tested_again_only_where_the_answer_can_change() {
    // Claim: skipping the kept pairs whose earlier test this step found
    // nothing and whose particles have not moved since changes no bit of
    // the run (the test would find the same), and does skip: fewer tests
    // than testing every pair at every round.
    let dt: Real = 1e-3;
    let (mut reusing, mut retesting) = (interlaced(), interlaced());
    retesting.contacts.ccd.retest_all = true;
    let (mut tests, mut all_tests, mut zones) = (0, 0, 0);
    for step in 0..40 {
        reusing.step(dt).expect("a step");
        retesting.step(dt).expect("a step");
        tests += reusing.contacts.ccd.work;
        all_tests += retesting.contacts.ccd.work;
        zones += reusing.last_ccd_report().zones;
        assert_eq!(
            reusing.last_ccd_report(),
            retesting.last_ccd_report(),
            "step {step}"
        );
        assert_eq!(
            reusing.particles.position, retesting.particles.position,
            "step {step}"
        );
        assert_eq!(reusing.particles.velocity, retesting.particles.velocity);
    }
    assert!(zones > 0, "the rounds reach the impact zones");
    assert!(tests < all_tests, "{tests} tests against {all_tests}");
}
