//! Rigid bodies of particles (shape matching): free flight keeps every
//! distance and the angular momentum; a cube dropped on its corner bounces
//! and comes to rest on a face.

mod common;

use sprung::build;
use sprung::{BodyData, Collider, ContactResponse, IntegratorKind, Real, Shape, Vec3, World};

/// A 3×3×3 lattice cube of side 0.2 m and 1 kg, rigid, its springs left as
/// the builder made them (they stay at rest length).
fn cube() -> BodyData {
    let mut cube = build::lattice(3, 3, 3, 0.1)
        .unwrap()
        .with_total_mass(1.0)
        .with_stiffness(500.0)
        .with_damping(0.1);
    cube.rigid = true;
    cube
}

/// The centre of mass (m) of the world's particles.
fn centre_of_mass(world: &World) -> Vec3 {
    let p = &world.particles;
    let total: Real = p.mass.iter().sum();
    p.position
        .iter()
        .zip(&p.mass)
        .map(|(&x, &m)| m * x)
        .sum::<Vec3>()
        / total
}

/// Angular momentum (kg·m²/s) of the world's particles about their centre
/// of mass.
fn angular_momentum(world: &World) -> Vec3 {
    let p = &world.particles;
    let centre = centre_of_mass(world);
    p.position
        .iter()
        .zip(&p.velocity)
        .zip(&p.mass)
        .map(|((&x, &v), &m)| m * (x - centre).cross(v))
        .sum()
}

/// The lowest height (m, y) of `positions`.
fn lowest_height(positions: &[Vec3]) -> Real {
    positions
        .iter()
        .map(|x| x.y)
        .fold(Real::INFINITY, Real::min)
}

/// The angular velocity (rad/s) of a rigid world's one body, `ω = I⁻¹ L`
/// with the inertia of its particles about their centre of mass.
fn spin_of(world: &World) -> Vec3 {
    let p = &world.particles;
    let centre = centre_of_mass(world);
    let mut inertia = glam::DMat3::ZERO;
    for (&x, &m) in p.position.iter().zip(&p.mass) {
        let r = x - centre;
        inertia += m
            * (glam::DMat3::from_diagonal(Vec3::splat(r.length_squared()))
                - glam::DMat3::from_cols(r * r.x, r * r.y, r * r.z));
    }
    inertia.inverse() * angular_momentum(world)
}

#[test]
fn a_spinning_rigid_body_keeps_its_shape_and_angular_momentum() {
    // A 4×3×2 brick (three different moments of inertia) spun about an
    // axis that is not a principal one, plus a drift: its angular velocity
    // wanders (it tumbles) while L stays.
    let mut body = build::lattice(4, 3, 2, 0.1)
        .unwrap()
        .with_total_mass(1.0)
        .with_stiffness(500.0);
    body.rigid = true;
    let spin = Vec3::new(3.0, 1.0, -2.0);
    let drift = Vec3::new(0.5, 0.0, 0.2);
    let centre = Vec3::new(0.15, 0.1, 0.05);
    body.velocity = body
        .position
        .iter()
        .map(|&x| drift + spin.cross(x - centre))
        .collect();
    for kind in [
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
    ] {
        let mut world = common::weightless(kind, "brick", body.clone());
        let rest: Vec<Vec3> = world.particles.position.clone();
        let momentum = angular_momentum(&world);
        for _ in 0..2000 {
            world.step(1e-3).unwrap();
        }
        // ω = I⁻¹ L has moved away from its start (by more than a tenth of
        // its size): the body tumbles, so keeping L is not keeping ω.
        let turned = spin_of(&world);
        assert!(
            (turned - spin).length() > 0.1 * spin.length(),
            "{}: ω stayed at {turned}",
            kind.name()
        );
        let x = &world.particles.position;
        // Every pairwise distance to rounding: the positions are the rest
        // shape turned by a unit quaternion, 1e-9 relative is a million
        // times its rounding.
        for i in 0..x.len() {
            for j in i + 1..x.len() {
                let (now, then) = (x[i].distance(x[j]), rest[i].distance(rest[j]));
                assert!(
                    (now - then).abs() <= 1e-9 * then,
                    "{}: distance {i}–{j} is {now} m, was {then} m",
                    kind.name()
                );
            }
        }
        // The projection rebuilds the velocities from L itself, so L is kept
        // to rounding; 1e-6 relative is the bound.
        let now = angular_momentum(&world);
        assert!(
            (now - momentum).length() <= 1e-6 * momentum.length(),
            "{}: L went from {momentum} to {now}",
            kind.name()
        );
    }
}

#[test]
fn a_rigid_cube_dropped_on_its_corner_bounces_and_rests_on_a_face() {
    // Turn the cube so a corner points down, a few degrees off the
    // symmetric pose (45° about x, 35.26° about z puts a diagonal
    // vertical; exactly so, it would land on an edge and balance there),
    // 0.5 m above a floor with restitution 0.5 and friction 0.5.
    let body = cube().placed(1.0, Vec3::new(40.0, 5.0, 30.0), Vec3::new(0.0, 0.5, 0.0));
    let lowest = lowest_height(&body.position);
    let below = body.position.iter().filter(|x| x.y < lowest + 1e-3).count();
    assert_eq!(below, 1, "it starts on one corner");
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("cube", body).unwrap();
    add_floor(&mut world, 0.5, 0.5);
    let mut bounced = false;
    let mut was_falling = false;
    for _ in 0..(6.0 / 1e-3) as usize {
        world.step(1e-3).unwrap();
        let vy = world.particles.velocity.iter().map(|v| v.y).sum::<Real>() / 27.0;
        if vy < -0.5 {
            was_falling = true;
        }
        if was_falling && vy > 0.2 {
            bounced = true;
        }
    }
    assert!(bounced, "the cube never bounced");
    // At rest on a face: nine particles (a face of the 3×3×3 lattice) on
    // the floor, the rest above by a spacing or more, and no motion left.
    let x = &world.particles.position;
    let on_floor = x.iter().filter(|x| x.y.abs() < 1e-3).count();
    assert_eq!(
        on_floor,
        9,
        "heights: {:?}",
        x.iter().map(|x| x.y).collect::<Vec<_>>()
    );
    let fastest = world
        .particles
        .velocity
        .iter()
        .map(|v| v.length())
        .fold(0.0, Real::max);
    assert!(fastest < 1e-2, "still moving at {fastest} m/s");
}

#[test]
fn a_rigid_cube_lands_on_a_gas_ball_without_entering_it() {
    // The cube's particles (a lattice: no faces) meet the ball's triangles
    // as balls of the contact thickness; the penalty pushes them, the
    // shape matching carries the push to the whole cube. The contact
    // stiffness stops a particle arriving at 10 m/s within the thickness
    // (1 cm); the cube lands at about 2.4 m/s, so no particle gets inside.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let mut ball = build::icosphere(0.4, 2, build::SurfaceSprings::default())
        .unwrap()
        .with_total_mass(1.0)
        .with_stiffness(300.0)
        .with_damping(0.1)
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.41, 0.0));
    ball.gas = Some(sprung::Gas::new(120.0, 0.0));
    world.add_body("ball", ball).unwrap();
    world
        .add_body(
            "cube",
            cube().placed(1.0, Vec3::new(10.0, 20.0, 0.0), Vec3::new(-0.1, 1.1, -0.1)),
        )
        .unwrap();
    add_floor(&mut world, 0.3, 0.5);
    let thickness = world.contacts.settings.thickness;
    let mut lowest_cube: Real = Real::INFINITY;
    for _ in 0..(0.5 / 2e-4) as usize {
        world.step(2e-4).unwrap();
        let deepest = common::deepest_inside_another(&world);
        assert!(
            deepest <= thickness,
            "a particle is {deepest} m inside another body"
        );
        let cube_low = lowest_height(&world.particles.position[world.bodies[1].particles.clone()]);
        lowest_cube = lowest_cube.min(cube_low);
    }
    // In its first half second it lands on the ball (top at 0.81 m, reached
    // at about 0.25 s) and is held there, not passed through to the floor
    // (later it rolls off the round top, as it should).
    assert!(lowest_cube > 0.6, "the cube sank to {lowest_cube} m");
}

/// A rigid cube on a floor (restitution `restitution`, friction
/// `friction`) under `kind`, its lowest face at `height` (m), moving at
/// `velocity` (m/s).
fn cube_over_floor(
    kind: IntegratorKind,
    height: Real,
    velocity: Vec3,
    restitution: Real,
    friction: Real,
) -> World {
    let mut body = cube().placed(1.0, Vec3::ZERO, Vec3::new(0.0, height, 0.0));
    body.velocity = vec![velocity; body.position.len()];
    let mut world = World::new(kind);
    world.add_body("cube", body).unwrap();
    add_floor(&mut world, restitution, friction);
    world
}

/// Add the floor y = 0 to `world`: a projection collider with
/// `restitution` and Coulomb `friction`.
fn add_floor(world: &mut World, restitution: Real, friction: Real) {
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    let response = ContactResponse::Projection {
        restitution,
        friction,
    };
    world
        .colliders
        .push(Collider::new(floor, response).unwrap());
}

#[test]
fn a_rigid_cube_bounces_with_its_restitution_under_every_integrator() {
    // Dropped flat from 0.5 m with restitution 0.8: it leaves the floor at
    // 0.8 of its landing speed, so it rises to 0.8² × 0.5 = 0.32 m. One
    // step of landing (the impulse comes at the end of the step that
    // reaches the floor) costs up to g dt² ~ 1e-5 m here; 3 % allows for
    // the landing step's own error in height, dt v / h = 1e-3 · 3 / 0.1.
    for kind in [
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
        IntegratorKind::ImplicitEuler,
        IntegratorKind::Projective,
    ] {
        let mut world = cube_over_floor(kind, 0.5, Vec3::ZERO, 0.8, 0.0);
        let (mut landed, mut highest) = (false, 0.0);
        for _ in 0..1200 {
            world.step(1e-3).unwrap();
            let low = lowest_height(&world.particles.position);
            let rising = world.particles.velocity[0].y > 0.0;
            landed |= rising;
            if landed {
                highest = Real::max(highest, low);
            }
        }
        assert!(
            (highest - 0.32).abs() <= 0.03 * 0.32,
            "{}: rebounded to {highest} m, expected 0.32 m",
            kind.name()
        );
    }
}

#[test]
fn a_sliding_rigid_cube_stops_where_coulomb_friction_says() {
    // Sliding at 2 m/s on a floor with μ = 0.5: it decelerates at μ g and
    // stops after v / (μ g) = 0.408 s, having slid v² / (2 μ g) = 0.408 m,
    // at any step size (within one step's travel, 2e-3 m at 1e-3 s).
    let (speed, mu, g) = (2.0, 0.5, 9.81);
    let expected = speed * speed / (2.0 * mu * g);
    for dt in [1e-3, 1e-4] {
        let mut world = cube_over_floor(
            IntegratorKind::SymplecticEuler,
            0.0,
            Vec3::new(speed, 0.0, 0.0),
            0.0,
            mu,
        );
        let start = centre_of_mass(&world);
        for _ in 0..(1.0 / dt) as usize {
            world.step(dt).unwrap();
        }
        let slid = centre_of_mass(&world).x - start.x;
        assert!(
            (slid - expected).abs() <= 2.0 * speed * dt + 1e-3 * expected,
            "dt = {dt}: slid {slid} m, Coulomb says {expected} m"
        );
    }
}

#[test]
fn a_rigid_cube_rests_on_a_slope_below_the_friction_angle_and_slides_above() {
    // Gravity tilted by θ onto a floor with μ = 0.5 (friction angle
    // 26.6°), the cube resting on a face. At 20° friction holds it: over
    // 2 s its centre moves less than 1e-7 m, a quarter of one step's fall
    // g dt² = 4e-7 m (it settles by some 1e-9 m); before, each step's
    // sliding, taken before friction stopped it, crept on at g sin θ dt =
    // 0.67 mm/s, 1.3 mm in the 2 s. At 35° it slides at g (sin θ - μ cos θ) = 1.609 m/s²:
    // s = a t² / 2 after 1 s, to 0.1 % (symplectic Euler's s differs from
    // a t² / 2 by a dt / 2 t, 1e-4 relative at dt = 2e-4 s).
    let (mu, g, dt): (Real, Real, Real) = (0.5, 9.81, 2e-4);
    for degrees in [20.0, 35.0] {
        let theta = Real::to_radians(degrees);
        let mut world = cube_over_floor(IntegratorKind::SymplecticEuler, 0.0, Vec3::ZERO, 0.0, mu);
        world.set_gravity(g * Vec3::new(theta.sin(), -theta.cos(), 0.0));
        let start = centre_of_mass(&world);
        let seconds = if degrees < 26.0 { 2.0 } else { 1.0 };
        for _ in 0..(seconds / dt).round() as usize {
            world.step(dt).unwrap();
        }
        let moved = centre_of_mass(&world) - start;
        if degrees < 26.0 {
            assert!(moved.length() < 1e-7, "{degrees}°: moved {moved} m");
        } else {
            let expected = 0.5 * g * (theta.sin() - mu * theta.cos()) * seconds * seconds;
            assert!(
                (moved.x - expected).abs() <= 1e-3 * expected,
                "{degrees}°: slid {} m, Coulomb says {expected} m",
                moved.x
            );
        }
    }
}

#[test]
fn a_tilted_rigid_rod_landing_with_friction_never_ends_a_step_inside_the_floor() {
    // A rigid lattice rod (9 × 2 × 2 particles, 0.8 m long, 1 kg) tilted
    // 20° and thrown down at 3 m/s onto a floor with μ = 0.5 and no bounce:
    // it lands on one end and slaps down, its friction and normal impulses
    // spinning it. Claim: after every step no particle is below the floor
    // (beyond rounding, 1e-12 m). Moving the body afterwards by the
    // impulses' change of its motion must not turn it into the floor, as a
    // turn about its centre did (0.83 mm inside).
    let mut rod = build::lattice(9, 2, 2, 0.1)
        .unwrap()
        .with_total_mass(1.0)
        .with_stiffness(500.0)
        .placed(1.0, Vec3::new(0.0, 0.0, 20.0), Vec3::new(0.0, 0.5, 0.0));
    rod.rigid = true;
    rod.velocity = vec![Vec3::new(0.0, -3.0, 0.0); rod.position.len()];
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("rod", rod).unwrap();
    add_floor(&mut world, 0.0, 0.5);
    for step in 1..=1000 {
        world.step(1e-3).unwrap();
        let lowest = lowest_height(&world.particles.position);
        assert!(lowest >= -1e-12, "step {step}: {lowest} m below the floor");
    }
}

#[test]
fn a_rigid_cloth_folded_on_itself_does_not_rub_on_itself() {
    // A 10 × 10 cloth (0.45 m, 1 kg) folded in two, its upper half 6 mm
    // above the lower (within the 10 mm contact thickness), rigid and
    // self-colliding with friction 0.5, spun about the fold's own axis
    // so that the two layers move apart at a few cm/s where they face
    // each other. Its self-contacts push (they are internal, so the
    // projection averages them away), but a body does not rub on itself:
    // no friction brakes its spin, and its angular momentum stays, as in
    // free flight (1e-9 relative, a million times its rounding; friction
    // at the touches, sized to stop the layers' relative sliding, would
    // take a part in every step).
    let n = 10;
    let mut cloth = build::cloth(n, n, 0.45, 0.45, build::ClothSprings::default())
        .unwrap()
        .with_total_mass(1.0)
        .with_stiffness(500.0);
    let fold = 0.45 * 4.5 / 9.0;
    for x in &mut cloth.position {
        if x.y > fold {
            *x = Vec3::new(x.x, 2.0 * fold - x.y, 0.006);
        }
    }
    cloth.rigid = true;
    cloth.contact.self_collision = true;
    let spin = Vec3::new(2.0, 0.0, 0.0);
    cloth.velocity = cloth.position.iter().map(|&x| spin.cross(x)).collect();
    let mut world = common::weightless(IntegratorKind::SymplecticEuler, "cloth", cloth);
    world.contacts.settings.friction = 0.5;
    let start = angular_momentum(&world);
    let mut touched = 0;
    for _ in 0..200 {
        world.step(2e-4).unwrap();
        touched = touched.max(world.active_contacts());
    }
    assert!(touched > 0, "the layers never touched");
    let change = (angular_momentum(&world) - start).length() / start.length();
    assert!(
        change < 1e-9,
        "angular momentum changed by {change:e} of itself"
    );
}
