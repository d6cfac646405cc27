//! Plane colliders (docs/physics.md §5): the projection form's restitution
//! (a drop from `h` bounces to `e² h`) and Coulomb friction (a slide
//! decelerates at `μ g`), and the penalty form's static depth `m g / k_c`.

mod common;

use common::assert_penalty_rest;
use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Real, Shape, Vec3, World};

const G: Real = 9.81; // m/s²

/// A world with one free particle of mass `mass` (kg) at `position`, with
/// `velocity`, above the floor y = 0 answering with `response`.
fn particle_over_floor(
    kind: IntegratorKind,
    mass: Real,
    position: Vec3,
    velocity: Vec3,
    response: ContactResponse,
) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::new(0.0, -G, 0.0));
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    world
        .colliders
        .push(Collider::new(floor, response).expect("valid response"));
    let body = BodyData::from_positions(vec![position])
        .with_mass(mass)
        .with_velocity(velocity);
    world.add_body("point", body).expect("valid point");
    world
}

#[test]
fn a_drop_from_h_bounces_to_e_squared_h_with_every_integrator() {
    let (height, restitution) = (1.0, 0.8);
    let expected = restitution * restitution * height;
    let dt = 1e-4;
    for kind in IntegratorKind::ALL {
        let response = ContactResponse::Projection {
            restitution,
            friction: 0.0,
        };
        let mut world =
            particle_over_floor(kind, 1.0, Vec3::new(0.0, height, 0.0), Vec3::ZERO, response);
        // Fall until the first contact reverses the velocity, then rise to
        // the apex (the step where the vertical velocity turns negative).
        let mut bounced = false;
        let mut apex: Real = 0.0;
        for _ in 0..20_000 {
            world.step(dt).expect("stable");
            let (y, vy) = (world.particles.position[0].y, world.particles.velocity[0].y);
            if vy > 0.0 {
                bounced = true;
            }
            if bounced {
                apex = apex.max(y);
                if vy < 0.0 {
                    break;
                }
            }
        }
        assert!(bounced, "{kind}: never bounced");
        // 1 %: the contact is found at the end of a step, up to v dt = 4.4e-4 m
        // below the plane, with the speed of that depth (a relative excess of
        // at most 4.4e-4 in height); the free flight of the first-order
        // methods is off by g t dt / 2 ≈ 2e-4 m per leg; sampling the apex
        // misses at most g dt² / 2. The budget is ~2e-3 of e² h.
        assert!(
            (apex / expected - 1.0).abs() <= 0.01,
            "{kind}: bounced to {apex:.6} m, expected e² h = {expected} m"
        );
    }
}

/// Slide a point along the floor (restitution 0, friction `friction`) at
/// `speed` m/s with symplectic Euler; returns the world after `duration` s
/// and the time (s) at which it stopped, if it did.
fn slide(friction: Real, speed: Real, dt: Real, duration: Real) -> (World, Option<Real>) {
    let response = ContactResponse::Projection {
        restitution: 0.0,
        friction,
    };
    let mut world = particle_over_floor(
        IntegratorKind::SymplecticEuler,
        1.0,
        Vec3::ZERO,
        Vec3::new(speed, 0.0, 0.0),
        response,
    );
    let mut stopped = None;
    for _ in 0..(duration / dt).round() as usize {
        world.step(dt).expect("stable");
        if stopped.is_none() && world.particles.velocity[0].x == 0.0 {
            stopped = Some(world.time());
        }
    }
    (world, stopped)
}

#[test]
fn friction_stops_a_slide_after_v0_squared_over_2_mu_g() {
    let (mu, v0, dt) = (0.5, 2.0, 1e-4);
    let expected_distance = v0 * v0 / (2.0 * mu * G);
    let expected_time = v0 / (mu * G);
    let (world, stopped) = slide(mu, v0, dt, 1.5 * expected_time);
    let distance = world.particles.position[0].x;
    // Each step gravity drives the point g dt² into the floor; the projection
    // removes the normal speed g dt and μ g dt of the tangential speed, so
    // the speed falls by exactly μ g dt per step. The position advances with
    // the speed before the friction of its step, so the distance is the
    // left Riemann sum of v0 - μ g t: larger than v0²/(2 μ g) by at most
    // v0 dt, i.e. a relative μ g dt / v0 ≈ 2.5e-4 (with v0 dt / 2 being the
    // leading part). We claim 1e-3 (the issue asks for 1 %).
    assert!(
        (distance / expected_distance - 1.0).abs() <= 1e-3,
        "slid {distance:.6} m, expected v0²/(2 μ g) = {expected_distance:.6} m"
    );
    let stopped = stopped.expect("the slide stops");
    // It stops on the first step that would take the speed below zero.
    assert!(
        (stopped - expected_time).abs() <= 2.0 * dt,
        "stopped at {stopped:.6} s, expected v0/(μ g) = {expected_time:.6} s"
    );
    // And it stays stopped, on the floor.
    assert_eq!(world.particles.velocity[0], Vec3::ZERO);
    assert_eq!(world.particles.position[0].y, 0.0);
}

#[test]
fn friction_decelerates_at_mu_g() {
    // Speed at half the stopping time: v0 / 2, to within one step's μ g dt.
    let (mu, v0, dt) = (0.3, 3.0, 1e-4);
    let half_time = 0.5 * v0 / (mu * G);
    let (world, _) = slide(mu, v0, dt, half_time);
    let speed = world.particles.velocity[0].length();
    let expected = v0 - mu * G * world.time();
    // The engine takes exactly μ g dt off the speed each step: the only
    // difference is round-off (~1e-13 m/s over the 5000 steps).
    assert!(
        (speed - expected).abs() <= 1e-9,
        "speed {speed:.9} m/s at t = {:.6} s, expected v0 - μ g t = {expected:.9}",
        world.time()
    );
}

#[test]
fn without_friction_a_slide_keeps_its_speed() {
    let (v0, dt) = (2.0, 1e-4);
    let (world, stopped) = slide(0.0, v0, dt, 1.0);
    assert!(stopped.is_none());
    // μ = 0: the projection only removes the normal velocity; the
    // tangential one is untouched, exactly.
    assert_eq!(world.particles.velocity[0], Vec3::new(v0, 0.0, 0.0));
    let travelled = world.particles.position[0].x;
    assert!(
        (travelled / (v0 * world.time()) - 1.0).abs() <= 1e-12,
        "travelled {travelled} m in {} s at {v0} m/s",
        world.time()
    );
}

#[test]
fn a_particle_rests_on_a_penalty_floor_at_depth_m_g_over_k() {
    let (mass, stiffness): (Real, Real) = (1.0, 1e4); // ω = √(k_c/m) = 100 rad/s
    let damping = 2.0 * (stiffness * mass).sqrt(); // critical: no bounce
    let expected = mass * G / stiffness;
    for kind in IntegratorKind::ALL {
        let response = ContactResponse::Penalty {
            stiffness,
            damping,
            friction: 0.0,
        };
        let mut world = particle_over_floor(kind, mass, Vec3::ZERO, Vec3::ZERO, response);
        // The implicit solves stop within their tolerance of the step's
        // gravity impulse m g dt: at rest, a force balance to that share of
        // the weight. 1e-12 puts it below the 1e-9 claimed here.
        world.settings.solver.tolerance = 1e-12;
        // dt = 1e-4 s: ω dt = 0.01, and c dt / m = 0.02, far inside every
        // method's stability region. After 0.5 s the critically damped
        // approach has left (1 + ω t) e^{-ω t} ≈ 1e-20 of the initial offset.
        for _ in 0..5000 {
            world.step(1e-4).expect("stable");
        }
        let depth = -world.particles.position[0].y;
        // The penalty spring's energy is reported as contact energy.
        assert_penalty_rest(
            kind.name(),
            depth,
            expected,
            world.energies().get("contact").expect("a standard term"),
            stiffness,
        );
    }
}

#[test]
fn penalty_friction_decelerates_a_slide_at_mu_g() {
    // A 1 kg point resting in a critically damped penalty floor (k_c = 1e5
    // N/m, depth m g / k_c ≈ 0.1 mm) slides at 2 m/s with μ = 0.4. Once the
    // normal oscillation has died out, f_n = m g and the regularised
    // Coulomb force is μ m g · v / √(v² + v_ε²), within (v_ε / v)² / 2 <
    // 2e-5 of μ m g while v > 1.5 m/s. The deceleration measured between
    // two instants is μ g to that, plus symplectic Euler's O(dt) error in a
    // smooth motion: 0.5 % covers both with a wide margin.
    let (mass, g, mu, stiffness): (Real, Real, Real, Real) = (1.0, 9.81, 0.4, 1e5);
    let damping = 2.0 * (stiffness * mass).sqrt();
    let depth = mass * g / stiffness;
    let sliding = |friction: Real| {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::new(0.0, -g, 0.0));
        let point = BodyData::from_positions(vec![Vec3::new(0.0, -depth, 0.0)])
            .with_mass(mass)
            .with_velocity(Vec3::new(2.0, 0.0, 0.0));
        world.add_body("point", point).expect("valid");
        let plane = Shape::plane(Vec3::ZERO, Vec3::Y).expect("plane");
        let response = ContactResponse::Penalty {
            stiffness,
            damping,
            friction,
        };
        world
            .colliders
            .push(Collider::new(plane, response).expect("collider"));
        world
    };
    let dt = 1e-4;
    let speed_after = |world: &mut World, steps: usize| {
        for _ in 0..steps {
            world.step(dt).expect("stable");
        }
        world.particles.velocity[0].x
    };
    let mut world = sliding(mu);
    let v1 = speed_after(&mut world, 100);
    let v2 = speed_after(&mut world, 1000);
    let deceleration = (v1 - v2) / (1000.0 * dt);
    assert!(v2 > 1.5, "still sliding fast: {v2}");
    assert!(
        (deceleration - mu * g).abs() < 5e-3 * mu * g,
        "deceleration {deceleration} vs μg {}",
        mu * g
    );
    // Without friction the same slide keeps its speed (no tangential force).
    assert_eq!(speed_after(&mut sliding(0.0), 1100), 2.0);
}
