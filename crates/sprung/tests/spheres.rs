//! Sphere colliders and moving (kinematic) colliders (docs/physics.md §5).
//!
//! Projection form: a drop onto the top of a sphere bounces to `e² h`; a
//! frictionless elastic sphere scatters a point by `χ = 2 arccos(b / r)`;
//! an oblique contact obeys Newton's restitution and Coulomb's impulse
//! bound at the contact normal; a moving sphere gives a resting particle its
//! own normal velocity, and a moving floor drags a resting particle up to
//! its speed in `u / (μ g)`. Penalty form: the rest depth `m g / k_c`, on a
//! static sphere and on a rising one (damping acts on the *relative*
//! velocity), and the contact energy `½ k_c depth²`. A cloth dropped on a
//! sphere: never inside a projection sphere, resting on its top, and
//! within the impact depth of a penalty sphere.

mod common;

use common::assert_penalty_rest;
use sprung::collide::{self, Path};
use sprung::{
    build, BodyData, BuildError, Collider, ContactResponse, IntegratorKind, Real, Shape, Vec3,
    World,
};

const G: Real = 9.81; // m/s²

/// A world with gravity `gravity` (m/s²), one collider, and free particles
/// of mass `mass` (kg) at `position` (m) with `velocity` (m/s), no springs.
fn particles_and(
    kind: IntegratorKind,
    gravity: Vec3,
    mass: Real,
    position: Vec<Vec3>,
    velocity: Vec<Vec3>,
    collider: Collider,
) -> World {
    let mut world = World::new(kind);
    world.set_gravity(gravity);
    world.colliders.push(collider);
    let mut body = BodyData::from_positions(position).with_mass(mass);
    body.velocity = velocity;
    world.add_body("points", body).expect("valid points");
    world
}

fn projection(restitution: Real, friction: Real) -> ContactResponse {
    ContactResponse::Projection {
        restitution,
        friction,
    }
}

fn sphere(centre: Vec3, radius: Real) -> Shape {
    Shape::sphere(centre, radius).expect("valid sphere")
}

/// A path moving at constant velocity `velocity` (m/s) from time 0 to far
/// beyond the end of any test here (100 s), displacement zero at time 0.
fn steady(velocity: Vec3) -> Path {
    Path::new(vec![(0.0, Vec3::ZERO), (100.0, 100.0 * velocity)]).expect("valid path")
}

/// Signed distance (m) of every particle from `world`'s first collider where
/// it is now, and the outward normals.
fn distances(world: &World) -> Vec<(Real, Vec3)> {
    let shape = world.colliders[0].shape_at(world.time());
    world
        .particles
        .position
        .iter()
        .map(|&x| shape.distance_and_normal(x))
        .collect()
}

/// The deepest penetration (m, positive inside) of any particle into the
/// first collider.
fn deepest(world: &World) -> Real {
    distances(world)
        .iter()
        .fold(Real::NEG_INFINITY, |deepest, &(d, _)| deepest.max(-d))
}

/// Angle between `a` and `b` (rad), well conditioned near 0 and π.
fn angle(a: Vec3, b: Vec3) -> Real {
    a.cross(b).length().atan2(a.dot(b))
}

/// How far a discrete contact tilts the normal: a point approaching a
/// sphere of radius `radius` (m) along an axis at impact parameter `b` (m)
/// is found inside up to `lag` (m) deep and projected radially, so the
/// normal's sine to the axis is `s = b / ρ` with `ρ ∈ [radius - lag,
/// radius]` instead of `b / radius`. Returns `(Δs, s_max)`, the largest
/// change of `s` and the largest `s`.
fn normal_tilt(b: Real, radius: Real, lag: Real) -> (Real, Real) {
    let s_max = b / (radius - lag);
    (s_max - b / radius, s_max)
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

/// Step `world` by `dt` and check that no particle is inside its collider:
/// projection is exact to round-off (~1e-16 m for coordinates of order
/// 1 m); we claim 1e-12 m.
fn step_outside(world: &mut World, dt: Real) {
    world.step(dt).expect("stable");
    let depth = deepest(world);
    assert!(
        depth <= 1e-12,
        "{depth:.3e} m inside at t = {} s",
        world.time()
    );
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
    collide::penalty_force(&moving, time, &moved, &velocity, &mut force);
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
        collide::penalty_force(
            collider,
            world.time(),
            position,
            velocity,
            &mut contact_force,
        );
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
