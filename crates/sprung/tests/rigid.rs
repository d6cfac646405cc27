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

fn angular_momentum(world: &World) -> Vec3 {
    let p = &world.particles;
    let total: Real = p.mass.iter().sum();
    let centre: Vec3 = p
        .position
        .iter()
        .zip(&p.mass)
        .map(|(&x, &m)| m * x)
        .sum::<Vec3>()
        / total;
    p.position
        .iter()
        .zip(&p.velocity)
        .zip(&p.mass)
        .map(|((&x, &v), &m)| m * (x - centre).cross(v))
        .sum()
}

#[test]
fn a_spinning_rigid_body_keeps_its_shape_and_angular_momentum() {
    // Spin about an axis that is not a principal one, plus a drift: the
    // angular velocity then wanders (the body tumbles) but L stays.
    let mut body = cube();
    let spin = Vec3::new(3.0, 1.0, -2.0);
    let drift = Vec3::new(0.5, 0.0, 0.2);
    let centre = Vec3::splat(0.1);
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
        let mut world = World::new(kind);
        world.set_gravity(Vec3::ZERO);
        world.add_body("cube", body.clone()).unwrap();
        let rest: Vec<Vec3> = world.particles.position.clone();
        let momentum = angular_momentum(&world);
        for _ in 0..2000 {
            world.step(1e-3).unwrap();
        }
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
    let lowest = body
        .position
        .iter()
        .map(|x| x.y)
        .fold(Real::INFINITY, Real::min);
    let below = body.position.iter().filter(|x| x.y < lowest + 1e-3).count();
    assert_eq!(below, 1, "it starts on one corner");
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("cube", body).unwrap();
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    let response = ContactResponse::Projection {
        restitution: 0.5,
        friction: 0.5,
    };
    world
        .colliders
        .push(Collider::new(floor, response).unwrap());
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
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    let response = ContactResponse::Projection {
        restitution: 0.3,
        friction: 0.5,
    };
    world
        .colliders
        .push(Collider::new(floor, response).unwrap());
    let thickness = world.contacts.settings.thickness;
    let mut lowest_cube: Real = Real::INFINITY;
    for _ in 0..(0.5 / 2e-4) as usize {
        world.step(2e-4).unwrap();
        let deepest = common::deepest_inside_another(&world);
        assert!(
            deepest <= thickness,
            "a particle is {deepest} m inside another body"
        );
        let cube_low = world.particles.position[world.bodies[1].particles.clone()]
            .iter()
            .map(|x| x.y)
            .fold(Real::INFINITY, Real::min);
        lowest_cube = lowest_cube.min(cube_low);
    }
    // In its first half second it lands on the ball (top at 0.81 m, reached
    // at about 0.25 s) and is held there, not passed through to the floor
    // (later it rolls off the round top, as it should).
    assert!(lowest_cube > 0.6, "the cube sank to {lowest_cube} m");
}
