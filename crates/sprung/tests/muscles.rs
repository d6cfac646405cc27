//! Muscles: springs whose rest length is `L0 s(t)`.

use std::sync::Arc;

use sprung::{
    BodyData, Collider, ContactResponse, IntegratorKind, MuscleData, MuscleDrive, Real, Shape,
    SpringData, Vec3, World,
};

/// Three particles in a row, springs listed out of the order the world
/// stores them in (by lowest particle): [2–1, 0–1]; the muscle drives the
/// scene's spring 0, the 2–1 one.
fn worm(drive: MuscleDrive) -> World {
    let mut body = BodyData::from_positions(vec![
        Vec3::ZERO,
        Vec3::new(0.5, 0.0, 0.0),
        Vec3::new(1.2, 0.0, 0.0),
    ])
    .with_mass(0.1);
    body.springs = vec![SpringData::between(2, 1), SpringData::between(0, 1)];
    let mut body = body.with_stiffness(100.0).with_damping(0.1);
    body.muscles.push(MuscleData { spring: 0, drive });
    let mut world = World::new(IntegratorKind::Rk4);
    world.set_gravity(Vec3::ZERO);
    world.add_body("worm", body).unwrap();
    world
}

#[test]
fn a_muscle_follows_its_formula_at_every_step() {
    let (amplitude, period, phase) = (0.3, 0.7, 1.1);
    let mut world = worm(MuscleDrive::Sine {
        amplitude,
        period,
        phase,
    });
    let muscle = &world.muscles.list[0];
    let spring = muscle.spring;
    // The scene's spring 0 joins particles 2 and 1, wherever it is stored.
    let ends = world.springs.endpoints(spring);
    assert!(
        ends == [2, 1] || ends == [1, 2],
        "the muscle drives {ends:?}"
    );
    let rest = 0.7; // |x2 - x1| at creation (m)
    assert!((muscle.rest_length - rest).abs() < 1e-15);
    let dt = 1e-3;
    for _ in 0..2000 {
        // Set at the start of each step, for every force evaluation in it.
        let t = world.time();
        world.step(dt).unwrap();
        let expected =
            rest * (1.0 + amplitude * (std::f64::consts::TAU * t / period + phase).sin());
        let found = world.springs.rest_length[spring];
        // The same arithmetic: equal to the last bit or two.
        assert!(
            (found - expected).abs() <= 4.0 * Real::EPSILON * expected,
            "at t = {t} s: {found} m, formula {expected} m"
        );
    }
    // The other spring is not a muscle: its rest length never changed.
    let other = 1 - spring;
    assert!((world.springs.rest_length[other] - 0.5).abs() < 1e-15);
}

#[test]
fn a_muscle_takes_any_function_of_time_and_refuses_a_bad_one() {
    let mut world = worm(MuscleDrive::Function(Arc::new(|t: Real| 1.0 + t)));
    for _ in 0..100 {
        world.step(0.01).unwrap();
    }
    let spring = world.muscles.list[0].spring;
    // Set at the start of the last step, t = 0.99 s.
    assert!((world.springs.rest_length[spring] - 0.7 * 1.99).abs() < 1e-12);
    let mut world = worm(MuscleDrive::Function(Arc::new(|t: Real| 1.0 - t)));
    let error = (0..200).find_map(|_| world.step(0.01).err());
    let message = error
        .expect("a factor reaching zero is refused")
        .to_string();
    assert!(message.contains("muscles"), "{message}");
}

/// The walker: two feet and a heavy body on three springs, all muscles
/// (period 1 s). The feet's spring (amplitude 0.3) lengthens while the
/// legs (amplitude 0.15, a quarter period either side) lean the body over
/// one foot, which then carries the weight and grips while the other
/// slides; half a period later the other way round. It hops as it goes,
/// its body never touching the floor. On a floor at y = 0 with friction
/// `friction`.
fn walker(friction: Real) -> World {
    let mut body = BodyData::from_positions(vec![
        Vec3::ZERO,
        Vec3::new(0.4, 0.0, 0.0),
        Vec3::new(0.2, 0.25, 0.0),
    ]);
    body.mass = vec![0.1, 0.1, 1.0];
    body.springs = vec![
        SpringData::between(0, 1),
        SpringData::between(0, 2),
        SpringData::between(1, 2),
    ];
    let mut body = body.with_stiffness(3000.0).with_damping(10.0);
    let sine = |amplitude, phase| MuscleDrive::Sine {
        amplitude,
        period: 1.0,
        phase,
    };
    let quarter = std::f64::consts::FRAC_PI_2;
    body.muscles = vec![
        MuscleData {
            spring: 0,
            drive: sine(0.3, 0.0),
        },
        MuscleData {
            spring: 1,
            drive: sine(0.15, -quarter),
        },
        MuscleData {
            spring: 2,
            drive: sine(0.15, quarter),
        },
    ];
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("walker", body).unwrap();
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    let response = ContactResponse::Projection {
        restitution: 0.0,
        friction,
    };
    world
        .colliders
        .push(Collider::new(floor, response).unwrap());
    world
}

/// Horizontal position (m) of the walker's centre of mass.
fn centroid_x(world: &World) -> Real {
    let p = &world.particles;
    let moment: Real = p.position.iter().zip(&p.mass).map(|(x, m)| m * x.x).sum();
    moment / p.mass.iter().sum::<Real>()
}

#[test]
fn the_walker_walks_on_a_rough_floor_and_stays_put_on_ice() {
    let dt = 1e-4;
    let length = 0.4; // between its feet (m)
    let mut rough = walker(0.8);
    let mut ice = walker(0.0);
    let (start, start_ice) = (centroid_x(&rough), centroid_x(&ice));
    for _ in 0..(10.0 / dt) as usize {
        rough.step(dt).unwrap();
        ice.step(dt).unwrap();
        // It walks upright: the body stays above its feet.
        let body = rough.particles.position[2].y;
        assert!(body > 0.1, "the walker fell over (body at {body} m)");
    }
    let walked = centroid_x(&rough) - start;
    assert!(
        walked > length,
        "it walked {walked} m in 10 s, less than its length"
    );
    // No horizontal force on ice: the centre of mass stays where it was,
    // to the rounding of 1e5 steps (1e-12 m).
    let drift = centroid_x(&ice) - start_ice;
    assert!(drift.abs() < 1e-12, "on ice it drifted {drift} m");
}
