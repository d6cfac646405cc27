//! A world's saved state put into a second world built the same way makes
//! it step on with the same bits; a state that does not fit is refused and
//! changes nothing.

use sprung::{build, IntegratorKind, StateError, Vec3, World};

/// A swinging rope of 12 particles, pinned at one end.
fn rope_world(integrator: IntegratorKind) -> World {
    let mut world = World::new(integrator);
    let rope = build::rope(12, 1.2)
        .expect("valid rope")
        .with_stiffness(400.0)
        .with_pinned(vec![0]);
    world.add_body("rope", rope).expect("valid body");
    world.particles.velocity[11] = Vec3::new(0.0, 0.0, 1.0);
    world
}

#[test]
fn a_restored_world_steps_on_with_the_same_bits() {
    for integrator in IntegratorKind::ALL {
        let mut whole = rope_world(integrator);
        for _ in 0..40 {
            whole.step(1e-3).expect("stable");
        }
        let saved = whole.save_state();
        let mut resumed = rope_world(integrator);
        resumed.restore_state(&saved).expect("same scene");
        assert_eq!(resumed.steps(), 40);
        assert_eq!(resumed.time().to_bits(), whole.time().to_bits());
        for _ in 0..40 {
            whole.step(1e-3).expect("stable");
            resumed.step(1e-3).expect("stable");
        }
        assert_eq!(
            whole.particles.position, resumed.particles.position,
            "{integrator:?}"
        );
        assert_eq!(whole.particles.velocity, resumed.particles.velocity);
    }
}

#[test]
fn a_state_that_does_not_fit_is_refused_and_changes_nothing() {
    let mut world = rope_world(IntegratorKind::Verlet);
    world.step(1e-3).expect("stable");
    let mut saved = world.save_state();
    let mut other = World::new(IntegratorKind::Verlet);
    let short = build::rope(5, 1.0).expect("valid rope");
    other.add_body("rope", short).expect("valid body");
    let before = other.particles.position.clone();
    assert!(matches!(
        other.restore_state(&saved),
        Err(StateError::Length { ref name, expected: 15, found: 36 }) if name == "verlet.previous_position"
    ));
    assert_eq!(other.particles.position, before);
    assert_eq!(other.steps(), 0);
    saved.put("time", vec![f64::NAN, 0.0]);
    assert!(matches!(
        world.restore_state(&saved),
        Err(StateError::BadValue { ref name, .. }) if name == "time"
    ));
    assert_eq!(world.steps(), 1);
}
