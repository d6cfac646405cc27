//! A stop asked for from outside the engine (`sprung::interrupt`, as
//! `sprung run` asks on SIGINT) ends the step under way as soon as it
//! validly can: the CCD takes its fail-safe (the colliding bodies
//! end the step where they started it, which had no crossing) and an
//! implicit solve stops after its first iteration. The flag is the
//! process's, so this file holds one test, which sets it in turn.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use sprung::build::{self, ClothSprings};
use sprung::{IntegratorKind, Vec3, World};

/// Two 8×8 cloths of 1 m, 2 cm apart, thrown at each other at 2 m/s each
/// along their normal: in a step of 10 ms each would pass the other's
/// plane halfway through.
fn crossing_cloths() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    for (name, z, speed) in [("up", -0.01, 2.0), ("down", 0.01, -2.0)] {
        let cloth = build::cloth(8, 8, 1.0, 1.0, ClothSprings::default())
            .expect("a cloth")
            .with_stiffness(100.0)
            .with_velocity(Vec3::new(0.0, 0.0, speed))
            .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.0, z));
        world.add_body(name, cloth).expect("added");
    }
    world
}

/// A stiff hanging cloth under implicit Euler, which takes several
/// iterations a step.
fn stiff_cloth() -> World {
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    let cloth = build::cloth(16, 16, 1.0, 1.0, ClothSprings::default())
        .expect("a cloth")
        .with_stiffness(2e4)
        .with_pinned(vec![240, 255]);
    world.add_body("cloth", cloth).expect("added");
    world
}

#[test]
fn a_stop_ends_the_step_under_way_as_soon_as_it_validly_can() {
    let flag = Arc::new(AtomicBool::new(false));
    assert!(sprung::interrupt::watch(Arc::clone(&flag)));
    let dt = 1e-2;

    // Unasked, the CCD parts the cloths that would pass through.
    let mut world = crossing_cloths();
    assert!(world.is_guarded());
    let start = world.particles.position.clone();
    world.step(dt).expect("a step");
    assert!(world.last_ccd_report().impulses > 0, "they collide");
    assert_ne!(world.particles.position, start);

    // Asked, every particle of the colliding bodies ends the step where it
    // started it, to the bit, its velocity losing the step's motion
    // (`v + (x₀ - (x₀ + v dt)) / dt`: zero but for rounding, 1e-15 m/s at
    // 2 m/s).
    let mut world = crossing_cloths();
    let start = world.particles.position.clone();
    flag.store(true, Ordering::Relaxed);
    world.step(dt).expect("a step, taken");
    flag.store(false, Ordering::Relaxed);
    assert_eq!(world.particles.position, start);
    for v in &world.particles.velocity {
        assert!(v.length() < 1e-12, "{v}");
    }
    // The world steps on as before.
    world.step(dt).expect("the next step");

    // An implicit solve stops after its first iteration, counted as a
    // solve short of its tolerance.
    let mut world = stiff_cloth();
    world.step(1.0 / 60.0).expect("a step");
    let unasked = world.last_step_report().iterations.expect("iterations");
    assert!(unasked > 1, "{unasked}");
    let mut world = stiff_cloth();
    flag.store(true, Ordering::Relaxed);
    world.step(1.0 / 60.0).expect("a step, taken");
    flag.store(false, Ordering::Relaxed);
    // The auto preconditioner's trial of Jacobi, cut short, is not taken
    // as a verdict on Jacobi (it would have factored the springs for the
    // rest of the run).
    let report = world.last_step_report();
    assert_eq!(report.iterations, Some(1), "{unasked} unasked");
    assert!(report.unconverged);
    assert_eq!(world.solver_stats().unconverged_steps, 1);
}
