//! Moving (kinematic) colliders (docs/physics.md §5): a moving sphere
//! gives a resting particle its own normal velocity, and a moving floor
//! drags a resting particle up to its speed in `u / (μ g)`; paths
//! interpolate between their keyframes and hold outside them; bad paths,
//! spheres and penalty coefficients are refused.

mod common;

use common::colliders::{
    distances, normal_tilt, particles_and, projection, sphere, steady, step_outside, G,
};
use sprung::colliders::Path;
use sprung::{BuildError, Collider, ContactResponse, IntegratorKind, Real, Shape, Vec3, World};

// ------------------------------------------------------- moving colliders

#[test]
fn a_moving_sphere_pushes_resting_particles_off_along_the_contact_normal() {
    // A frictionless (μ = 0), perfectly inelastic (e = 0) sphere moving at
    // u along x meets particles at rest at impact parameters b. At contact
    // the relative normal velocity is removed and the tangential velocity
    // (zero) kept, so a particle leaves with the sphere's normal velocity,
    // (u·n) n = u √(1 - b²/r²) n, n = (√(1 - b²/r²), b/r): in the sphere's
    // frame it then moves along the tangent, outside the sphere for good.
    // The particle on the centre line (b = 0) is pushed along at u; those
    // with b > r are never touched.
    let (radius, speed, dt) = (0.5, 1.0, 1e-4);
    let u = Vec3::new(speed, 0.0, 0.0);
    let offsets = [
        Vec3::ZERO,
        Vec3::new(0.0, 0.1, 0.0),
        Vec3::new(0.0, 0.0, -0.2),
        Vec3::new(0.0, -0.18, 0.24), // b = 0.3
        Vec3::new(0.0, 0.4, 0.0),
        Vec3::new(0.0, 0.6, 0.0),  // misses
        Vec3::new(0.0, 0.0, -0.7), // misses
    ];
    let position: Vec<Vec3> = offsets.to_vec();
    let collider = Collider::new(
        sphere(Vec3::new(-1.0, 0.0, 0.0), radius),
        projection(0.0, 0.0),
    )
    .expect("valid response")
    .with_path(steady(u));
    let mut world = particles_and(
        IntegratorKind::SymplecticEuler,
        Vec3::ZERO,
        1.0,
        position.clone(),
        vec![],
        collider,
    );
    // 3 s: the sphere's centre goes from x = -1 to x = 2, past every particle.
    let mut before = world.particles.velocity.clone();
    for step in 1..=30_000 {
        step_outside(&mut world, dt);
        for (i, (distance, normal)) in distances(&world).into_iter().enumerate() {
            // No force acts but the contact, so a change of velocity is a
            // contact: the particle is then on the surface, and moves on
            // with zero normal velocity relative to it (e = 0), so it does
            // not lag inside. Round-off: ~1e-16 m and m/s.
            let v = world.particles.velocity[i];
            if v != before[i] {
                let relative = (v - u).dot(normal);
                assert!(
                    distance.abs() <= 1e-12 && relative.abs() <= 1e-12,
                    "particle {i} at step {step}: distance {distance:.3e} m, relative normal velocity {relative:.3e} m/s"
                );
            }
            before[i] = v;
        }
    }
    for (i, offset) in offsets.iter().enumerate() {
        let v = world.particles.velocity[i];
        let b = offset.length();
        if b >= radius {
            assert_eq!(v, Vec3::ZERO, "particle {i} (b = {b}) was touched");
            assert_eq!(world.particles.position[i], position[i]);
            continue;
        }
        let along = (1.0 - (b / radius).powi(2)).sqrt();
        let normal = Vec3::new(along, 0.0, 0.0) + *offset / radius;
        let expected = speed * along * normal;
        // The contact is found up to u dt deep; the particle is projected
        // radially, so the normal's sine is s = b / ρ, ρ ∈ [r - u dt, r].
        // The leaving velocity u (√(1 - s²) n_x, √(1 - s²) s) has
        // |d/ds| = u / √(1 - s²). Round-off adds ~1e-16 m/s.
        let (tilt, s_max) = normal_tilt(b, radius, speed * dt);
        let bound = speed * tilt / (1.0 - s_max * s_max).sqrt() + 1e-12;
        assert!(
            (v - expected).length() <= bound,
            "particle {i} (b = {b}): leaves at {v} m/s, expected (u·n) n = {expected} (±{bound:.1e})"
        );
    }
    // The centre-line particle rides on the sphere's front point, pushed
    // back whenever it lags inside. Moving at u like the sphere, it can only
    // drift ahead by round-off: each step's `x += v dt` rounds by at most
    // ε |x| (|x| < 3 m), over 30 000 steps.
    let front = world.colliders[0].shape_at(world.time());
    let Shape::Sphere { centre, .. } = front else {
        unreachable!("a sphere")
    };
    let gap = (world.particles.position[0] - (centre + Vec3::new(radius, 0.0, 0.0))).length();
    let drift = 30_000.0 * Real::EPSILON * 3.0;
    assert!(
        gap <= drift,
        "the centre-line particle is {gap:.3e} m from the sphere's front (round-off allows {drift:.1e} m)"
    );
}

/// A 1 kg particle resting at the origin on the floor y = 0 moving along x
/// at `speed` (m/s), friction `friction`, restitution 0, stepped `steps`
/// times with `dt` by symplectic Euler. `check` sees the world after each
/// step.
fn on_moving_floor(
    speed: Real,
    friction: Real,
    dt: Real,
    steps: usize,
    mut check: impl FnMut(&World),
) -> World {
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let collider = Collider::new(floor, projection(0.0, friction))
        .expect("valid response")
        .with_path(steady(Vec3::new(speed, 0.0, 0.0)));
    let mut world = particles_and(
        IntegratorKind::SymplecticEuler,
        Vec3::new(0.0, -G, 0.0),
        1.0,
        vec![Vec3::ZERO],
        vec![],
        collider,
    );
    for _ in 0..steps {
        world.step(dt).expect("stable");
        check(&world);
    }
    world
}

#[test]
fn a_moving_floor_drags_a_resting_particle_up_to_its_speed_in_u_over_mu_g() {
    // Coulomb friction on a floor moving at u: relative to the floor the
    // particle slides back at u, and kinetic friction μ m g slows that
    // sliding at μ g; so the particle speeds up at μ g and moves with the
    // floor after u / (μ g), having fallen behind by u² / (2 μ g) (the slide
    // of the static-floor test, seen from the floor). The projection scheme
    // does exactly this: each step gravity drives the particle g dt² into
    // the floor, the projection removes the relative normal speed g dt and
    // μ g dt of the relative tangential speed.
    let (speed, mu, dt) = (2.0, 0.5, 1e-4);
    let catch_up = speed / (mu * G);
    let mut caught = None;
    let world = on_moving_floor(speed, mu, dt, 10_000, |world| {
        let (t, v) = (world.time(), world.particles.velocity[0]);
        assert_eq!(world.particles.position[0].y, 0.0, "left the floor");
        if caught.is_none() && v.x == speed {
            caught = Some(t);
        }
        if caught.is_none() {
            // Exactly μ g dt per step: round-off only (~1e-13 m/s over
            // the 4000 steps); we claim 1e-9.
            assert!(
                (v.x - mu * G * t).abs() <= 1e-9,
                "speed {} m/s at t = {t:.4} s, expected μ g t = {}",
                v.x,
                mu * G * t
            );
        } else {
            // Carried: the relative velocity is zero, exactly.
            assert_eq!(v, Vec3::new(speed, 0.0, 0.0), "slipped at t = {t:.4} s");
        }
    });
    let caught = caught.expect("the particle catches up with the floor");
    // It moves with the floor on the first step that would take the
    // relative speed below zero.
    assert!(
        (caught - catch_up).abs() <= 2.0 * dt,
        "caught up at {caught:.6} s, expected u/(μ g) = {catch_up:.6} s"
    );
    // The lag is the left Riemann sum of the relative speed u - μ g t: it
    // exceeds u²/(2 μ g) by at most u dt, a relative μ g dt / u ≈ 2.5e-4 (as
    // in the static-floor slide). We claim 1e-3.
    let lag = speed * world.time() - world.particles.position[0].x;
    let expected = speed * speed / (2.0 * mu * G);
    assert!(
        (lag / expected - 1.0).abs() <= 1e-3,
        "fell behind the floor by {lag:.6} m, expected u²/(2 μ g) = {expected:.6} m"
    );
}

#[test]
fn a_frictionless_moving_floor_slides_under_a_resting_particle() {
    // μ = 0: the floor exerts no tangential force, so the particle stays
    // where it is; the projection only removes the normal velocity that
    // gravity gives it each step, and the tangential relative velocity -u
    // is kept, exactly: the particle's velocity stays zero.
    let world = on_moving_floor(2.0, 0.0, 1e-4, 10_000, |world| {
        assert_eq!(world.particles.velocity[0], Vec3::ZERO);
        assert_eq!(world.particles.position[0], Vec3::ZERO);
    });
    assert!((world.time() - 1.0).abs() <= 1e-12);
}

// ------------------------------------------------------- paths and checks

#[test]
fn paths_interpolate_linearly_and_hold_outside_their_keyframes() {
    let path = Path::new(vec![
        (1.0, Vec3::ZERO),
        (3.0, Vec3::new(2.0, 4.0, -2.0)),
        (4.0, Vec3::new(2.0, 4.0, 1.0)),
    ])
    .expect("valid path");
    // Every value here is a short binary fraction: the interpolation is
    // exact, so the comparisons are exact.
    let offsets = [
        (0.0, Vec3::ZERO), // held before the first keyframe
        (1.0, Vec3::ZERO),
        (2.0, Vec3::new(1.0, 2.0, -1.0)),
        (3.0, Vec3::new(2.0, 4.0, -2.0)),
        (3.5, Vec3::new(2.0, 4.0, -0.5)),
        (4.0, Vec3::new(2.0, 4.0, 1.0)),
        (10.0, Vec3::new(2.0, 4.0, 1.0)), // held after the last
    ];
    for (t, expected) in offsets {
        assert_eq!(path.offset_at(t), expected, "offset at t = {t} s");
    }
    // The slope of the segment holding t (a segment includes its start);
    // zero outside.
    let velocities = [
        (0.0, Vec3::ZERO),
        (1.0, Vec3::new(1.0, 2.0, -1.0)),
        (2.0, Vec3::new(1.0, 2.0, -1.0)),
        (3.0, Vec3::new(0.0, 0.0, 3.0)),
        (3.5, Vec3::new(0.0, 0.0, 3.0)),
        (4.0, Vec3::ZERO),
        (10.0, Vec3::ZERO),
    ];
    for (t, expected) in velocities {
        assert_eq!(path.velocity_at(t), expected, "velocity at t = {t} s");
    }
    // One keyframe: a fixed displacement.
    let fixed = Path::new(vec![(2.0, Vec3::new(0.0, 1.0, 0.0))]).expect("valid path");
    for t in [0.0, 2.0, 5.0] {
        assert_eq!(fixed.offset_at(t), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(fixed.velocity_at(t), Vec3::ZERO);
    }
    // A collider follows its path: its shape is translated by the offset,
    // its surface velocity is the path's.
    let centre = Vec3::new(0.5, 0.5, 0.5);
    let collider = Collider::new(sphere(centre, 1.0), projection(0.0, 0.0))
        .expect("valid response")
        .with_path(path);
    assert_eq!(
        collider.shape_at(2.0),
        Shape::Sphere {
            centre: centre + Vec3::new(1.0, 2.0, -1.0),
            radius: 1.0
        }
    );
    assert_eq!(collider.velocity_at(2.0), Vec3::new(1.0, 2.0, -1.0));
    let plane = Collider::new(
        Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane"),
        projection(0.0, 0.0),
    )
    .expect("valid response")
    .with_path(fixed);
    assert_eq!(
        plane.shape_at(7.0),
        Shape::Plane {
            point: Vec3::new(0.0, 1.0, 0.0),
            normal: Vec3::Y
        }
    );
}

/// The error's message names the scene key `field`.
fn assert_names(error: &BuildError, field: &str) {
    let message = error.to_string();
    assert!(
        message.contains(&format!("`{field}`")),
        "message does not name `{field}`: {message}"
    );
}

#[test]
fn bad_paths_spheres_and_penalty_coefficients_are_refused() {
    let error = Path::new(vec![]).expect_err("no keyframe");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "path", .. }),
        "{error:?}"
    );
    assert_names(&error, "path");
    let error = Path::new(vec![(0.0, Vec3::ZERO), (Real::NAN, Vec3::X)]).expect_err("NaN time");
    assert!(
        matches!(error, BuildError::NotFinite { field: "path", index: 1, value } if value.is_nan()),
        "{error:?}"
    );
    let error = Path::new(vec![(0.0, Vec3::new(0.0, Real::INFINITY, 0.0))])
        .expect_err("infinite displacement");
    assert!(
        matches!(error, BuildError::NotFinite { field: "path", index: 0, value } if value == Real::INFINITY),
        "{error:?}"
    );
    for times in [[0.0, 1.0, 1.0], [0.0, 2.0, 1.0]] {
        let keyframes = times.iter().map(|&t| (t, Vec3::ZERO)).collect();
        let error = Path::new(keyframes).expect_err("times not increasing");
        assert!(
            matches!(error, BuildError::OutOfRange { field: "path", value, .. } if value == times[2]),
            "{times:?}: {error:?}"
        );
        assert_names(&error, "path");
    }

    for radius in [0.0, -1.0, Real::NAN, Real::INFINITY] {
        let error = Shape::sphere(Vec3::ZERO, radius).expect_err("bad radius");
        assert!(
            matches!(
                error,
                BuildError::OutOfRange {
                    field: "sphere.radius",
                    ..
                }
            ),
            "radius {radius}: {error:?}"
        );
        assert_names(&error, "sphere.radius");
    }
    let error = Shape::sphere(Vec3::new(0.0, 0.0, Real::NAN), 1.0).expect_err("NaN centre");
    assert!(
        matches!(
            error,
            BuildError::NotFinite {
                field: "sphere.centre",
                index: 2,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "sphere.centre");

    let response = ContactResponse::Penalty {
        stiffness: 0.0,
        damping: 1.0,
        friction: 0.0,
    };
    let error = Collider::new(sphere(Vec3::ZERO, 1.0), response).expect_err("k_c = 0");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "penalty_stiffness", value, .. } if value == 0.0),
        "{error:?}"
    );
    assert_names(&error, "penalty_stiffness");
}
