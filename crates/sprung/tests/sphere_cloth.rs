//! A cloth dropped on a sphere collider (docs/physics.md §5): never
//! inside a projection sphere, resting on its top, and within the impact
//! depth of a penalty sphere.

mod common;

use common::colliders::{distances, projection, sphere, step_outside};
use sprung::{build, Collider, ContactResponse, IntegratorKind, Real, Vec3, World};

// ------------------------------------------------------- cloth over a sphere

/// Particles per side of the cloth, its width (m), total mass (kg), the
/// sphere's radius (m) and the drop height above the sphere's top (m).
const CLOTH_N: usize = 15;
const CLOTH_WIDTH: Real = 1.0;
const CLOTH_MASS: Real = 0.2;
const BALL_RADIUS: Real = 0.3;
const DROP: Real = 0.05;
/// The cloth's centre particle, above the sphere's top.
const CLOTH_CENTRE: usize = (CLOTH_N / 2) * CLOTH_N + CLOTH_N / 2;
/// Time step (s): below the stable estimate, checked in the tests.
const CLOTH_DT: Real = 2e-4;

/// A horizontal 15 × 15 cloth (structural and shear springs 200 N/m, 0.02
/// N·s/m; bending springs a tenth of that, cloth folds more easily than it
/// stretches) centred `DROP` above the top of a sphere about the origin
/// answering with `response`. Air drag `5 m` per particle (N·s/m) damps
/// every motion at γ = 5 /s, so the drape settles. The grid is symmetric
/// about the x = 0 and z = 0 planes, exactly in floating point.
fn cloth_over_sphere(response: ContactResponse) -> World {
    let spacing = CLOTH_WIDTH / (CLOTH_N - 1) as Real;
    let half = (CLOTH_N / 2) as Real;
    let mut body = build::cloth(
        CLOTH_N,
        CLOTH_N,
        CLOTH_WIDTH,
        CLOTH_WIDTH,
        Default::default(),
    )
    .expect("valid cloth");
    for (i, p) in body.position.iter_mut().enumerate() {
        let (ix, iz) = ((i % CLOTH_N) as Real, (i / CLOTH_N) as Real);
        *p = Vec3::new(
            (ix - half) * spacing,
            BALL_RADIUS + DROP,
            (iz - half) * spacing,
        );
    }
    let mut body = body
        .with_total_mass(CLOTH_MASS)
        .with_stiffness(200.0)
        .with_damping(0.02);
    let position = body.position.clone();
    for spring in &mut body.springs {
        let length = position[spring.first].distance(position[spring.second]);
        if length > 1.5 * spacing {
            spring.stiffness *= 0.1;
            spring.damping *= 0.1;
        }
    }
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let mass = body.mass[0];
    world.set_air_drag(5.0 * mass);
    world
        .colliders
        .push(Collider::new(sphere(Vec3::ZERO, BALL_RADIUS), response).expect("valid response"));
    world.add_body("cloth", body).expect("valid cloth");
    assert!(
        world.stable_time_step() > 2.0 * CLOTH_DT,
        "dt = {CLOTH_DT} s is not well inside the stable estimate {} s",
        world.stable_time_step()
    );
    world
}

#[test]
fn a_cloth_dropped_on_a_projection_sphere_never_enters_it_and_rests_on_top() {
    let mut world = cloth_over_sphere(projection(0.0, 0.5));
    // 4 s: the cloth lands after 0.1 s and wraps the sphere within ~1 s.
    for _ in 0..20_000 {
        step_outside(&mut world, CLOTH_DT);
    }
    let x = world.particles.position[CLOTH_CENTRE];
    let v = world.particles.velocity[CLOTH_CENTRE];
    // The weight and the tension of the cloth wrapped over the cap press the
    // centre particle on the sphere, so each step ends with it projected
    // exactly onto the surface (round-off ~1e-16 m).
    assert!(
        (x.length() - BALL_RADIUS).abs() <= 1e-12,
        "the centre particle is {:.3e} m off the surface",
        x.length() - BALL_RADIUS
    );
    // By the mirror symmetries x → -x and z → -z the centre particle stays
    // on the vertical axis, on the sphere's top. Only round-off (~1e-16 m a
    // step) breaks the symmetry, and a drape's folds may amplify it; we
    // allow 1 µm, still 7e4 times below the cell size that a slide off the
    // top would show.
    let off_axis = Vec3::new(x.x, 0.0, x.z).length();
    assert!(
        off_axis <= 1e-6,
        "the centre particle is {off_axis:.3e} m off the top"
    );
    // Static friction: pressed on the top, where the tangential push is
    // zero by symmetry (below μ times the normal one), the particle loses
    // its whole relative velocity at each projection: it is at rest.
    assert!(
        v.length() <= 1e-12,
        "the centre particle moves at {} m/s",
        v.length()
    );
    // The whole cloth has settled: the drag damps every motion at least as
    // e^{-γ t / 2} (springs' damping, friction and e = 0 only add
    // dissipation); from speeds below √(2 g H) ≈ 4 m/s (H ≈ 0.85 m, the most
    // any particle can fall) when the wrap ends (≲ 1 s), 3 s of decay
    // leave 4 e^{-7.5} ≈ 2e-3 m/s. We claim 1e-2 m/s.
    let fastest = world
        .particles
        .velocity
        .iter()
        .map(|v| v.length())
        .fold(0.0, Real::max);
    assert!(
        fastest <= 1e-2,
        "the cloth still moves at {fastest} m/s after 4 s"
    );
}

#[test]
fn a_cloth_dropped_on_a_penalty_sphere_stays_within_the_impact_depth() {
    let mass = CLOTH_MASS / (CLOTH_N * CLOTH_N) as Real;
    let stiffness = 1000.0; // N/m: ω_c = √(k_c / m) ≈ 1060 rad/s
    let damping = 2.0 * (stiffness * mass).sqrt(); // critical, per particle
    let omega = (stiffness / mass).sqrt();
    let mut world = cloth_over_sphere(ContactResponse::Penalty {
        stiffness,
        damping,
        friction: 0.0,
    });
    let count = world.particles.len();
    // Per particle: its inward normal speed on the last step it was
    // outside (the speed it enters with), and the largest entry speed and
    // inward non-contact force (gravity, springs, drag) seen in contact.
    let mut approach = vec![0.0; count];
    let (mut entry_speed, mut load): (Real, Real) = (0.0, 0.0);
    let mut deepest_depth: Real = 0.0;
    let mut contact_force = vec![Vec3::ZERO; count];
    // 1.5 s: the impact and the wrap. A frictionless contact cannot hold
    // the symmetric drape for long (it is an unstable balance that
    // round-off eventually tips); this test is about depths.
    for _ in 0..7_500 {
        world.step(CLOTH_DT).expect("stable");
        world.evaluate_forces();
        contact_force.fill(Vec3::ZERO);
        let collider = &world.colliders[0];
        let (position, velocity) = (&world.particles.position, &world.particles.velocity);
        collider.penalty_force(world.time(), position, velocity, &mut contact_force);
        for (i, (distance, normal)) in distances(&world).into_iter().enumerate() {
            let inward_speed = -world.particles.velocity[i].dot(normal);
            if distance >= 0.0 {
                approach[i] = inward_speed.max(0.0);
                continue;
            }
            entry_speed = entry_speed.max(approach[i]);
            let other = world.particles.force[i] - contact_force[i];
            load = load.max(-other.dot(normal));
            deepest_depth = deepest_depth.max(-distance);
        }
    }
    // The normal motion of a particle in contact is a damped oscillator
    // m d'' = -k_c d - c d' + F_n - m v_t² / r, driven by the inward
    // non-contact force F_n ≤ F (the centripetal term only lifts it).
    // Energy from entry (d = 0, d' = v) to the deepest point:
    // ½ k_c d² ≤ ½ m v² + F d, so d ≤ F/k_c + √((F/k_c)² + m v² / k_c):
    // the single impact v √(m/k_c) when F → 0, and when v → 0 twice the
    // rest depth F/k_c (m g / k_c for a lone particle), the overshoot of a
    // load applied at once. A later maximum of the same contact starts from
    // d' = 0 and stays below 2 F/k_c. Discretely, the contact is found up to
    // v dt late, and symplectic Euler's amplitude error is below ω_c dt / 4:
    // we allow (1 + ω_c dt) and v dt on top.
    let static_depth = load / stiffness;
    let bound = (static_depth
        + (static_depth * static_depth + mass * entry_speed * entry_speed / stiffness).sqrt())
        * (1.0 + omega * CLOTH_DT)
        + entry_speed * CLOTH_DT;
    assert!(entry_speed > 0.0 && load > 0.0, "the cloth never hit");
    assert!(
        deepest_depth <= bound,
        "deepest {deepest_depth:.3e} m, beyond the impact bound {bound:.3e} m (v = {entry_speed:.3} m/s, F = {load:.3e} N)"
    );
    // The cloth rests on the sphere: the centre particle is pressed into it
    // on the top (on the axis, by symmetry, as in the projection test), no
    // deeper than the bound.
    let x = world.particles.position[CLOTH_CENTRE];
    let depth = BALL_RADIUS - x.length();
    assert!(
        depth > 0.0 && depth <= bound,
        "the centre particle is {depth:.3e} m deep"
    );
    assert!(
        Vec3::new(x.x, 0.0, x.z).length() <= 1e-6,
        "slid off the top"
    );
}
