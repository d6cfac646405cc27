//! Sphere colliders (docs/physics.md §5).
//!
//! Projection form: a drop onto the top of a sphere bounces to `e² h`; a
//! frictionless elastic sphere scatters a point by `χ = 2 arccos(b / r)`;
//! an oblique contact obeys Newton's restitution and Coulomb's impulse
//! bound at the contact normal. Penalty form: the rest depth `m g / k_c`,
//! on a static sphere and on a rising one (damping acts on the *relative*
//! velocity), and the contact energy `½ k_c depth²`. Moving colliders are
//! in `moving_colliders.rs`, a cloth dropped on a sphere in
//! `sphere_cloth.rs`.

mod common;

use common::assert_penalty_rest;
use common::colliders::{normal_tilt, particles_and, projection, sphere, steady, step_outside, G};
use sprung::colliders::Path;
use sprung::{Collider, ContactResponse, IntegratorKind, Real, Vec3, World};

/// Angle between `a` and `b` (rad), well conditioned near 0 and π.
fn angle(a: Vec3, b: Vec3) -> Real {
    a.cross(b).length().atan2(a.dot(b))
}

// ----------------------------------------------------- static sphere, projection

#[test]
fn a_drop_onto_the_top_of_a_sphere_bounces_to_e_squared_h_with_every_integrator() {
    let (radius, height, restitution) = (1.0, 1.0, 0.8);
    let centre = Vec3::new(0.5, -1.0, 0.25); // the top is at y = 0
    let expected = restitution * restitution * height;
    let dt = 1e-4;
    for kind in IntegratorKind::ALL {
        let collider = Collider::new(sphere(centre, radius), projection(restitution, 0.0))
            .expect("valid response");
        let start = centre + Vec3::new(0.0, radius + height, 0.0);
        let mut world = particles_and(
            kind,
            Vec3::new(0.0, -G, 0.0),
            1.0,
            vec![start],
            vec![],
            collider,
        );
        let mut bounced = false;
        let mut apex: Real = 0.0;
        for _ in 0..20_000 {
            step_outside(&mut world, dt);
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
        // Straight above the centre the particle's x and z offsets are
        // exactly zero, so the normal is exactly +y: the contact is the plane
        // contact at the top, with the budget of the plane test (~2e-3 of
        // e² h from the contact depth v dt, the first-order free flights and
        // the apex sampling). We claim 1 %.
        assert!(
            (apex / expected - 1.0).abs() <= 0.01,
            "{kind}: bounced to {apex:.6} m above the top, expected e² h = {expected} m"
        );
    }
}

/// One free particle of 1 kg (no gravity) at `start` (m) with velocity
/// `v0` (m/s), and a sphere of radius `radius` (m) about the origin
/// answering with `response`.
fn particle_and_sphere(radius: Real, start: Vec3, v0: Vec3, response: ContactResponse) -> World {
    let collider = Collider::new(sphere(Vec3::ZERO, radius), response).expect("valid response");
    particles_and(
        IntegratorKind::SymplecticEuler,
        Vec3::ZERO,
        1.0,
        vec![start],
        vec![v0],
        collider,
    )
}

/// Fire a particle as in [`particle_and_sphere`] and step it `steps`
/// times with `dt`. Returns the world and whether its velocity ever
/// changed: with no force the free flight keeps the velocity bit for bit,
/// so a change is a contact.
fn fire_at_sphere(
    radius: Real,
    start: Vec3,
    v0: Vec3,
    response: ContactResponse,
    dt: Real,
    steps: usize,
) -> (World, bool) {
    let mut world = particle_and_sphere(radius, start, v0, response);
    let mut hit = false;
    for _ in 0..steps {
        step_outside(&mut world, dt);
        hit |= world.particles.velocity[0] != v0;
    }
    (world, hit)
}

#[test]
fn a_frictionless_elastic_sphere_scatters_by_twice_arccos_b_over_r() {
    // Hard-sphere scattering: a point at impact parameter b reflects
    // specularly off the normal n at the contact, sin(angle of n to the
    // approach axis) = b / r, and is deflected by χ = 2 arccos(b / r),
    // keeping its speed.
    let (radius, speed, dt) = (1.0, 1.0, 1e-4);
    let offsets = [
        Vec3::ZERO,
        Vec3::new(0.0, 0.3, 0.0),
        Vec3::new(0.0, 0.0, -0.6),
        Vec3::new(0.0, 0.48, 0.64), // b = 0.8
    ];
    for offset in offsets {
        let b = offset.length();
        let v0 = Vec3::new(speed, 0.0, 0.0);
        let start = Vec3::new(-2.0, 0.0, 0.0) + offset;
        let (world, contact) = fire_at_sphere(radius, start, v0, projection(1.0, 0.0), dt, 40_000);
        assert!(contact, "b = {b}: never hit");
        let v = world.particles.velocity[0];
        // Reflection about a unit normal keeps the speed, up to round-off.
        assert!(
            (v.length() / speed - 1.0).abs() <= 1e-12,
            "b = {b}: speed {} m/s after an elastic contact, expected {speed}",
            v.length()
        );
        // The contact is found at the end of a step, up to v dt inside; the
        // point is projected radially from there, so the normal's sine is
        // b / ρ with ρ ∈ [r - v dt, r], and χ = 2 arccos(b / ρ) moves by at
        // most 2 Δs / √(1 - s_max²) (arccos' grows with its argument).
        // Round-off adds ~1e-15 rad.
        let expected = 2.0 * (b / radius).acos();
        let (tilt, s_max) = normal_tilt(b, radius, speed * dt);
        let bound = 2.0 * tilt / (1.0 - s_max * s_max).sqrt() + 1e-12;
        let chi = angle(v0, v);
        assert!(
            (chi - expected).abs() <= bound,
            "b = {b}: deflected by {chi:.9} rad, expected 2 arccos(b/r) = {expected:.9} (±{bound:.1e})"
        );
    }
    // A point that misses (b > r) is not touched at all.
    let v0 = Vec3::new(speed, 0.0, 0.0);
    let (world, contact) = fire_at_sphere(
        radius,
        Vec3::new(-2.0, 1.2, 0.0),
        v0,
        projection(1.0, 0.0),
        dt,
        40_000,
    );
    assert!(!contact, "b = 1.2 > r was touched");
    assert_eq!(world.particles.velocity[0], v0);
}

#[test]
fn an_oblique_impact_obeys_restitution_and_coulomb_friction_at_the_contact_normal() {
    // Newton's law of restitution at the contact normal n, v'·n = -e v·n,
    // and Coulomb's law for the impulse: the tangential impulse is at most μ
    // times the normal one, m (1 + e) |v·n|, and opposes the tangential
    // velocity; what it cannot remove is kept (sliding), else the
    // tangential velocity stops (sticking).
    let (radius, dt) = (1.0, 1e-4);
    let start = Vec3::new(-2.0, 0.4, 0.3);
    let v0 = Vec3::new(1.0, 0.2, -0.1); // passes 0.79 m from the centre: a hit
    for (restitution, friction) in [(1.0, 0.0), (0.5, 0.2), (0.0, 0.3), (0.3, 10.0)] {
        let mut world = particle_and_sphere(radius, start, v0, projection(restitution, friction));
        // Step to the contact (the first change of velocity: free flight
        // keeps it bit for bit), and stop there.
        let mut steps = 0;
        while world.particles.velocity[0] == v0 {
            step_outside(&mut world, dt);
            steps += 1;
            assert!(
                steps < 40_000,
                "e = {restitution}, μ = {friction}: never hit"
            );
        }
        let x = world.particles.position[0];
        // It is on the surface (round-off, ~1e-16 m), and the contact
        // normal is the radial direction there.
        assert!((x.length() - radius).abs() <= 1e-12, "not on the surface");
        let n = x / x.length();
        let v = world.particles.velocity[0];
        let (vn0, vn) = (v0.dot(n), v.dot(n));
        assert!(vn0 < 0.0, "the contact approaches");
        // Round-off: the components are of order 1 m/s, products ~1e-16.
        assert!(
            (vn + restitution * vn0).abs() <= 1e-12,
            "e = {restitution}: normal velocity {vn} after {vn0}, expected -e v·n"
        );
        let (t0, t) = (v0 - vn0 * n, v - vn * n);
        let removable = friction * (1.0 + restitution) * -vn0;
        let expected = t0 * (1.0 - removable / t0.length()).max(0.0);
        assert!(
            (t - expected).length() <= 1e-12,
            "e = {restitution}, μ = {friction}: tangential velocity {t}, expected {expected}"
        );
        // After the contact it leaves (or sticks, e = 0 and μ large) and is
        // never found inside again.
        for _ in 0..20_000 {
            step_outside(&mut world, dt);
        }
    }
}

// -------------------------------------------------------- penalty spheres

#[test]
fn a_particle_rests_on_top_of_a_penalty_sphere_at_depth_m_g_over_k() {
    let (mass, stiffness, radius): (Real, Real, Real) = (1.0, 1e4, 1.0); // ω = 100 rad/s
    let damping = 2.0 * (stiffness * mass).sqrt(); // critical: no bounce
    let centre = Vec3::new(0.5, -1.0, 0.25);
    let expected = mass * G / stiffness;
    for kind in IntegratorKind::ALL {
        let response = ContactResponse::Penalty {
            stiffness,
            damping,
            friction: 0.0,
        };
        let collider = Collider::new(sphere(centre, radius), response).expect("valid response");
        let top = centre + Vec3::new(0.0, radius, 0.0);
        let mut world = particles_and(
            kind,
            Vec3::new(0.0, -G, 0.0),
            mass,
            vec![top],
            vec![],
            collider,
        );
        // As for the penalty floor: a force balance to 1e-12 of the weight
        // (the implicit solves' floor), below the claim.
        world.settings.solver.tolerance = 1e-12;
        // As for the penalty floor: ω dt = 0.01 and c dt / m = 0.02 are deep
        // inside every method's stability region, and after 0.5 s the
        // critically damped approach has left (1 + ω t) e^{-ω t} ≈ 1e-20.
        for _ in 0..5000 {
            world.step(1e-4).expect("stable");
        }
        let x = world.particles.position[0];
        let depth = radius - (x - centre).length();
        // Straight above the centre the normal is exactly +y, so the floor's
        // force balance holds as it is.
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
fn a_rising_penalty_sphere_carries_a_particle_at_depth_m_g_over_k() {
    // The sphere rises at u. Carried along at u, the particle's velocity
    // relative to the surface is zero, so the penalty damping, which acts on
    // the relative normal velocity, is silent and the depth is m g / k_c,
    // as at rest. (Damping on the absolute velocity would hold it at
    // (m g + c u) / k_c, 11 times deeper here.)
    let (mass, stiffness, radius, rise): (Real, Real, Real, Real) = (1.0, 1e4, 1.0, 0.5);
    let damping = 2.0 * (stiffness * mass).sqrt();
    let centre = Vec3::new(0.5, -1.0, 0.25);
    let expected = mass * G / stiffness;
    for kind in IntegratorKind::ALL {
        let response = ContactResponse::Penalty {
            stiffness,
            damping,
            friction: 0.0,
        };
        let collider = Collider::new(sphere(centre, radius), response)
            .expect("valid response")
            .with_path(steady(Vec3::new(0.0, rise, 0.0)));
        let top = centre + Vec3::new(0.0, radius, 0.0);
        let mut world = particles_and(
            kind,
            Vec3::new(0.0, -G, 0.0),
            mass,
            vec![top],
            vec![],
            collider,
        );
        // As for the penalty floor: a force balance to 1e-12 of the weight
        // (the implicit solves' floor), below the claim.
        world.settings.solver.tolerance = 1e-12;
        // The particle starts at rest on a surface moving at u: a step in
        // the relative velocity, which decays critically, as
        // (1 + ω t) e^{-ω t} ≈ 1e-20 after 0.5 s (ω = 100 rad/s).
        for _ in 0..5000 {
            world.step(1e-4).expect("stable");
        }
        let now = world.colliders[0].shape_at(world.time());
        let (distance, normal) = now.distance_and_normal(world.particles.position[0]);
        assert_eq!(normal, Vec3::Y, "{kind}: left the axis");
        // Moving at constant velocity under zero net force is an exact
        // solution of every method, so the fixed point is exact to
        // round-off (~1e-13 relative); we claim 1e-9.
        assert!(
            (-distance / expected - 1.0).abs() <= 1e-9,
            "{kind}: depth {:.9e} m, expected m g / k_c = {expected:.9e} m",
            -distance
        );
        let vy = world.particles.velocity[0].y;
        assert!(
            (vy / rise - 1.0).abs() <= 1e-9,
            "{kind}: rises at {vy} m/s, expected the sphere's {rise} m/s"
        );
    }
}

#[test]
fn penalty_sphere_contact_energy_is_half_k_depth_squared() {
    let (radius, stiffness) = (0.5, 2000.0);
    let centre = Vec3::new(1.0, 2.0, 3.0);
    let response = ContactResponse::Penalty {
        stiffness,
        damping: 0.0,
        friction: 0.0,
    };
    let collider = Collider::new(sphere(centre, radius), response).expect("valid response");
    // Particles at known depths along assorted directions, and two outside.
    let inside = [
        (Vec3::new(1.0, 0.0, 0.0), 0.01),
        (Vec3::new(0.0, -3.0, 4.0) / 5.0, 0.1),
        (Vec3::new(2.0, 1.0, -2.0) / 3.0, 0.4),
    ];
    let mut position: Vec<Vec3> = inside
        .iter()
        .map(|&(n, depth)| centre + (radius - depth) * n)
        .collect();
    position.push(centre + Vec3::new(0.0, radius + 0.1, 0.0));
    position.push(centre + Vec3::new(-radius - 1e-3, 0.0, 0.0));
    let expected: Real = inside.iter().map(|&(_, d)| 0.5 * stiffness * d * d).sum();
    // Round-off: depths are differences of numbers of order 1 m (~1e-16 m
    // absolute, 1e-14 relative to the smallest depth).
    let energy = collider.contact_energy(0.0, &position);
    assert!(
        (energy / expected - 1.0).abs() <= 1e-12,
        "contact energy {energy} J, expected Σ ½ k d² = {expected} J"
    );
    // The world reports the same as its contact energy.
    let world = particles_and(
        IntegratorKind::SymplecticEuler,
        Vec3::ZERO,
        1.0,
        position.clone(),
        vec![],
        collider.clone(),
    );
    assert_eq!(
        world.energies().get("contact").expect("a standard term"),
        energy
    );

    // A moving sphere: at time t the energy is measured against the centre
    // translated by the path's offset.
    let path =
        Path::new(vec![(0.0, Vec3::ZERO), (2.0, Vec3::new(0.0, 0.0, 0.2))]).expect("valid path");
    let moving = collider.clone().with_path(path);
    let (time, offset) = (1.5, Vec3::new(0.0, 0.0, 0.15));
    let moved: Vec<Vec3> = position.iter().map(|&x| x + offset).collect();
    let energy_moved = moving.contact_energy(time, &moved);
    assert!(
        (energy_moved / expected - 1.0).abs() <= 1e-12,
        "moving sphere: {energy_moved} J at t = {time} s, expected {expected} J"
    );

    // The penalty force (without damping) is minus the gradient of that
    // energy: central differences with h = 1e-6 m have a truncation error
    // h² |E'''| / 6 ~ 1e-12 of the force and a round-off error
    // ε E / h ~ 1e-10 N; we claim 1e-6 relative.
    let h = 1e-6;
    let velocity = vec![Vec3::ZERO; moved.len()];
    let mut force = vec![Vec3::ZERO; moved.len()];
    moving.penalty_force(time, &moved, &velocity, &mut force);
    for i in 0..moved.len() {
        let mut gradient = Vec3::ZERO;
        for axis in 0..3 {
            let (mut plus, mut minus) = (moved.clone(), moved.clone());
            plus[i][axis] += h;
            minus[i][axis] -= h;
            gradient[axis] = (moving.contact_energy(time, &plus)
                - moving.contact_energy(time, &minus))
                / (2.0 * h);
        }
        let scale = force[i].length().max(1.0);
        assert!(
            (force[i] + gradient).length() <= 1e-6 * scale,
            "particle {i}: penalty force {} N, -∇E = {} N",
            force[i],
            -gradient
        );
    }

    // The projection form stores no energy.
    let projecting =
        Collider::new(sphere(centre, radius), projection(0.5, 0.1)).expect("valid response");
    assert_eq!(projecting.contact_energy(0.0, &position), 0.0);
}
