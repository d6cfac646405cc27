//! The forces' Jacobian products (docs/physics.md §6, the implicit solvers):
//! each force's `∂f/∂x·p` and `∂f/∂v·p` against central differences of its
//! own force, where they are meant to be exact; the documented
//! approximations where they are not (compressed springs made definite,
//! the gas's volume stiffness); and, for every force, the symmetry and the
//! diagonal the conjugate-gradient solver relies on.
//!
//! Central differences with a step `ε = 1e-6` (positions of order 1 m,
//! velocities of order 1 m/s) have a truncation error `~ε² |f'''|` and a
//! round-off `~1e-16 |f| / ε = 1e-10 |f|`: the exact Jacobians are checked
//! to 1e-6 of the largest difference.

mod common;

use common::Rng;
use sprung::build::{self, ClothSprings};
use sprung::forces::ColliderContacts;
use sprung::forces::{
    AirDrag, Force, ForceContext, GasPressure, JacobianScale, MouseSpring, SpringForce,
};
use sprung::{Collider, ContactResponse, Gas, IntegratorKind, Real, Shape, Vec3, World};

const EPSILON: Real = 1e-6;
const POSITION: JacobianScale = JacobianScale {
    position: 1.0,
    velocity: 0.0,
};
const VELOCITY: JacobianScale = JacobianScale {
    position: 0.0,
    velocity: 1.0,
};

/// The force context of `world` with other positions or velocities.
fn context<'a>(world: &'a World, position: &'a [Vec3], velocity: &'a [Vec3]) -> ForceContext<'a> {
    ForceContext {
        position,
        velocity,
        ..world.force_context()
    }
}

/// `force` alone at a context (N per particle).
fn force_at(force: &mut dyn Force, context: &ForceContext) -> Vec<Vec3> {
    let mut out = vec![Vec3::ZERO; context.position.len()];
    force.accumulate(context, &mut out);
    out
}

/// The product of `force`'s Jacobian (`scale`) with `p`, linearised at the
/// world's state.
fn product(force: &mut dyn Force, world: &World, scale: JacobianScale, p: &[Vec3]) -> Vec<Vec3> {
    let context = world.force_context();
    force.linearize(&context);
    let mut out = vec![Vec3::ZERO; p.len()];
    force.add_jacobian_products(&context, scale, p, &mut out);
    out
}

/// Central difference of `force` along `p`, in positions (`scale` =
/// [`POSITION`]) or velocities ([`VELOCITY`]).
fn difference(force: &mut dyn Force, world: &World, scale: JacobianScale, p: &[Vec3]) -> Vec<Vec3> {
    let shifted = |sign: Real, base: &[Vec3], weight: Real| -> Vec<Vec3> {
        base.iter()
            .zip(p)
            .map(|(x, p)| *x + sign * weight * EPSILON * *p)
            .collect()
    };
    let (x, v) = (&world.particles.position, &world.particles.velocity);
    let (xp, xm) = (
        shifted(1.0, x, scale.position),
        shifted(-1.0, x, scale.position),
    );
    let (vp, vm) = (
        shifted(1.0, v, scale.velocity),
        shifted(-1.0, v, scale.velocity),
    );
    let plus = force_at(force, &context(world, &xp, &vp));
    let minus = force_at(force, &context(world, &xm, &vm));
    plus.iter()
        .zip(&minus)
        .map(|(a, b)| (*a - *b) / (2.0 * EPSILON))
        .collect()
}

/// Largest difference between two particle vectors over the largest entry
/// of the second.
fn relative_gap(a: &[Vec3], b: &[Vec3]) -> Real {
    let gap = a
        .iter()
        .zip(b)
        .map(|(a, b)| (*a - *b).length())
        .fold(0.0, Real::max);
    let size = b.iter().map(|b| b.length()).fold(0.0, Real::max);
    gap / size
}

fn dot(a: &[Vec3], b: &[Vec3]) -> Real {
    a.iter().zip(b).map(|(a, b)| a.dot(*b)).sum()
}

/// A 4 × 3 cloth stretched (`scale` > 1) or squeezed (< 1) by `scale` from
/// its rest shape and crumpled a little out of its plane, with random
/// velocities, springs of 100 N/m and `damping`, no gravity.
fn crumpled_cloth(scale: Real, damping: Real, rng: &mut Rng) -> World {
    let mut body = build::cloth(4, 3, 1.0, 0.6, ClothSprings::default())
        .expect("valid cloth")
        .with_stiffness(100.0)
        .with_damping(damping);
    for s in &mut body.springs {
        s.rest_length = Some(body.position[s.first].distance(body.position[s.second]) / scale);
    }
    for x in &mut body.position {
        x.z += 0.05 * rng.symmetric();
    }
    body.velocity = (0..body.particle_count())
        .map(|_| rng.vector(1.0))
        .collect();
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("cloth", body).expect("valid body");
    world
}

fn random(n: usize, rng: &mut Rng) -> Vec<Vec3> {
    (0..n).map(|_| rng.vector(1.0)).collect()
}

#[test]
fn stretched_springs_have_their_exact_jacobians() {
    let mut rng = Rng::new(3);
    // No damping for the position Jacobian (the dashpot's turning axis is
    // left out, documented); with damping for the velocity Jacobian,
    // `-c t tᵀ`, which is exact.
    let still = crumpled_cloth(1.1, 0.0, &mut rng);
    let damped = crumpled_cloth(1.1, 0.7, &mut rng);
    for (world, scale, what) in [(&still, POSITION, "∂f/∂x"), (&damped, VELOCITY, "∂f/∂v")]
    {
        let p = random(world.particles.len(), &mut rng);
        let mut springs = SpringForce::new();
        let analytic = product(&mut springs, world, scale, &p);
        let numeric = difference(&mut springs, world, scale, &p);
        let gap = relative_gap(&analytic, &numeric);
        assert!(gap <= 1e-6, "springs {what}: {gap:.3e}");
    }
}

#[test]
fn compressed_springs_give_a_definite_approximation() {
    // Squeezed, a spring's transverse stiffness k (1 - L0/d) is negative
    // (it buckles): the product clamps it at 0, so `-p·J p ≥ 0` for every
    // p, while the exact Jacobian is indefinite somewhere.
    let mut rng = Rng::new(5);
    let world = crumpled_cloth(0.9, 0.0, &mut rng);
    let mut springs = SpringForce::new();
    let mut indefinite = false;
    for trial in 0..50 {
        // Half the trials move the particles out of the cloth's plane only,
        // across its springs, where squeezed springs buckle.
        let mut p = random(world.particles.len(), &mut rng);
        if trial % 2 == 0 {
            p.iter_mut().for_each(|p| *p = Vec3::new(0.0, 0.0, p.z));
        }
        let analytic = product(&mut springs, &world, POSITION, &p);
        assert!(-dot(&p, &analytic) >= 0.0, "not definite along a random p");
        let numeric = difference(&mut springs, &world, POSITION, &p);
        indefinite |= -dot(&p, &numeric) < 0.0;
        // The clamped part only ever adds stiffness: the approximation is
        // at least as stiff as the exact Jacobian.
        assert!(-dot(&p, &analytic) >= -dot(&p, &numeric) - 1e-6 * dot(&p, &p));
    }
    assert!(
        indefinite,
        "the squeezed cloth should have a buckling direction"
    );
}

#[test]
fn drag_the_hand_and_a_penalty_floor_have_their_exact_jacobians() {
    let mut rng = Rng::new(7);
    let mut world = crumpled_cloth(1.0, 0.0, &mut rng);
    // Sink the cloth 0.1 m into a penalty floor, well inside, moving
    // slowly enough that the damped normal force still pushes.
    for (x, v) in world
        .particles
        .position
        .iter_mut()
        .zip(&mut world.particles.velocity)
    {
        x.y = -0.1 - 0.05 * rng.symmetric().abs();
        *v *= 0.01;
    }
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let penalty = ContactResponse::Penalty {
        stiffness: 1e4,
        damping: 5.0,
        friction: 0.0,
    };
    world
        .colliders
        .push(Collider::new(floor, penalty).expect("valid response"));
    let mut forces: Vec<(Box<dyn Force>, &str)> = vec![
        (Box::new(AirDrag { coefficient: 0.3 }), "drag"),
        (
            Box::new(MouseSpring {
                particle: 4,
                target: Vec3::new(0.3, 0.2, 0.1),
                stiffness: 50.0,
                damping: 2.0,
            }),
            "hand",
        ),
        (Box::new(ColliderContacts::new()), "penalty floor"),
    ];
    for (force, what) in &mut forces {
        for scale in [POSITION, VELOCITY] {
            let p = random(world.particles.len(), &mut rng);
            let analytic = product(force.as_mut(), &world, scale, &p);
            let numeric = difference(force.as_mut(), &world, scale, &p);
            if numeric.iter().all(|v| *v == Vec3::ZERO) {
                assert!(analytic.iter().all(|v| *v == Vec3::ZERO), "{what}");
                continue;
            }
            let gap = relative_gap(&analytic, &numeric);
            assert!(gap <= 1e-6, "{what}, {scale:?}: {gap:.3e}");
        }
    }
}

#[test]
fn the_gas_jacobian_is_its_exact_volume_stiffness() {
    // The gas force is F = P g with g = ∂V/∂x and P = nRT / V. Its exact
    // Jacobian is P ∂g/∂x - (nRT / V²) g gᵀ; the product keeps the second
    // term, the stiffness against a change of volume. So the product must
    // equal the central difference of F minus P times that of g (= F / P).
    let mut rng = Rng::new(11);
    let mut ball = build::icosphere(0.5, 1, build::SurfaceSprings::default())
        .expect("valid sphere")
        .with_stiffness(10.0);
    for x in &mut ball.position {
        *x *= 1.0 + 0.05 * rng.symmetric();
    }
    ball.gas = Some(Gas::new(300.0, 0.0));
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("ball", ball).expect("valid body");
    let mut gas = GasPressure::new();
    let p = random(world.particles.len(), &mut rng);
    let analytic = product(&mut gas, &world, POSITION, &p);
    let force_difference = difference(&mut gas, &world, POSITION, &p);
    let pressure = world.pressure(0).expect("a gas");
    let x = &world.particles.position;
    let gradient_at = |sign: Real| -> Vec<Vec3> {
        let moved: Vec<Vec3> = x
            .iter()
            .zip(&p)
            .map(|(x, p)| *x + sign * EPSILON * *p)
            .collect();
        let at = context(&world, &moved, &world.particles.velocity);
        let body = &world.bodies[0];
        let volume = body.enclosed_volume(&moved).expect("closed");
        let scale = 300.0 / volume;
        force_at(&mut GasPressure::new(), &at)
            .into_iter()
            .map(|f| f / scale)
            .collect()
    };
    let (plus, minus) = (gradient_at(1.0), gradient_at(-1.0));
    let expected: Vec<Vec3> = force_difference
        .iter()
        .zip(plus.iter().zip(&minus))
        .map(|(df, (a, b))| *df - pressure * (*a - *b) / (2.0 * EPSILON))
        .collect();
    let gap = relative_gap(&analytic, &expected);
    assert!(gap <= 1e-6, "gas volume stiffness: {gap:.3e}");
}

#[test]
fn every_jacobian_is_symmetric_with_the_diagonal_it_reports() {
    // Conjugate gradients need a symmetric matrix and the preconditioner its
    // diagonal: for every force, p·(J q) = q·(J p) and the reported
    // diagonal is (J e)·e for each unit vector e. One-sided springs keep
    // only their child's own block, which keeps them symmetric.
    let mut rng = Rng::new(13);
    let mut world = crumpled_cloth(0.95, 0.4, &mut rng);
    world.springs.one_sided[3] = true;
    world.springs.one_sided[8] = true;
    let n = world.particles.len();
    let mut forces: Vec<Box<dyn Force>> = vec![
        Box::new(SpringForce::new()),
        Box::new(AirDrag { coefficient: 0.3 }),
        Box::new(MouseSpring {
            particle: 2,
            target: Vec3::ONE,
            stiffness: 50.0,
            damping: 2.0,
        }),
    ];
    let scale = JacobianScale {
        position: 0.3,
        velocity: 0.7,
    };
    for force in &mut forces {
        let context = world.force_context();
        force.linearize(&context);
        let apply = |force: &dyn Force, p: &[Vec3]| {
            let mut out = vec![Vec3::ZERO; n];
            force.add_jacobian_products(&context, scale, p, &mut out);
            out
        };
        let (p, q) = (random(n, &mut rng), random(n, &mut rng));
        let (jp, jq) = (apply(force.as_ref(), &p), apply(force.as_ref(), &q));
        let (a, b) = (dot(&p, &jq), dot(&q, &jp));
        assert!(
            (a - b).abs() <= 1e-12 * (a.abs() + b.abs()),
            "{}: p·Jq = {a}, q·Jp = {b}",
            force.name()
        );
        let mut diagonal = vec![Vec3::ZERO; n];
        force.add_jacobian_diagonal(&context, scale, &mut diagonal);
        for i in 0..n {
            for axis in 0..3 {
                let mut e = vec![Vec3::ZERO; n];
                e[i][axis] = 1.0;
                let entry = apply(force.as_ref(), &e)[i][axis];
                assert!(
                    (entry - diagonal[i][axis]).abs() <= 1e-12 * entry.abs().max(1.0),
                    "{}: diagonal ({i}, {axis}) = {}, product gives {entry}",
                    force.name(),
                    diagonal[i][axis]
                );
            }
        }
    }
}

/// A world of one loose particle of 1 kg at the origin and another
/// `gap` m from it along `(1, 1, 1)`, each a body without surfaces (so
/// they meet particle to particle), with velocities `velocity`, no
/// gravity; its contact pairs found by a step too short to move them
/// (1e-12 s: the pushes move them by ~1e-20 m).
fn two_loose_particles(gap: Real, velocity: [Vec3; 2]) -> World {
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.set_gravity(Vec3::ZERO);
    let axis = Vec3::ONE.normalize();
    for (name, x, v) in [
        ("a", Vec3::ZERO, velocity[0]),
        ("b", gap * axis, velocity[1]),
    ] {
        let mut body = sprung::BodyData::from_positions(vec![x]);
        body.velocity = vec![v];
        world.add_body(name, body).expect("valid particle");
    }
    world.step(1e-12).expect("a step");
    world
}

#[test]
fn the_body_contact_velocity_jacobian_is_exact() {
    // The contact's damping -c (u·n) n on the relative velocity u of the
    // closest points is linear in the velocities: its Jacobian -c n nᵀ
    // (shared by the closest-point weights) is exact, for particle pairs
    // and for a particle over a triangle alike.
    let mut rng = Rng::new(17);
    let pair = two_loose_particles(0.006, [Vec3::new(0.1, 0.0, 0.0), Vec3::ZERO]);
    let mut over = World::new(IntegratorKind::ImplicitEuler);
    over.set_gravity(Vec3::ZERO);
    let mut sheet = sprung::BodyData::from_positions(vec![
        Vec3::new(-1.0, -1.0, 0.0),
        Vec3::new(2.0, -1.0, 0.0),
        Vec3::new(-1.0, 2.0, 0.0),
    ]);
    sheet.faces = vec![[0, 1, 2]];
    over.add_body("sheet", sheet).expect("valid triangle");
    let mut bead = sprung::BodyData::from_positions(vec![Vec3::new(0.2, 0.3, 0.004)]);
    bead.velocity = vec![Vec3::new(0.05, 0.0, -0.02)];
    over.add_body("bead", bead).expect("valid particle");
    over.step(1e-12).expect("a step");
    for (world, what) in [
        (&pair, "particle pair"),
        (&over, "particle over a triangle"),
    ] {
        assert_eq!(world.active_contacts(), 1, "{what}");
        let mut force = sprung::forces::BodyContacts::new();
        let p = random(world.particles.len(), &mut rng);
        let analytic = product(&mut force, world, VELOCITY, &p);
        let numeric = difference(&mut force, world, VELOCITY, &p);
        // Central differences of a force linear in v: round-off only.
        let gap = relative_gap(&analytic, &numeric);
        assert!(gap <= 1e-6, "{what}, ∂f/∂v: {gap:.3e}");
    }
}

#[test]
fn the_body_contact_position_jacobian_leaves_out_only_the_normals_turning() {
    // Two particles d apart within the thickness h push with f = k (h - d) n,
    // n = (x_a - x_b) / d. Its exact Jacobian on the relative motion q is
    // -k n nᵀ q + k (h - d) / d (q - (n·q) n): the product keeps the first
    // term (definite), and leaves out the second, the normal's turning.
    // So the central difference equals the product plus that term, on `a`,
    // and minus it on `b`, for any motion (at rest: no damping term).
    let mut rng = Rng::new(19);
    let world = two_loose_particles(0.006, [Vec3::ZERO; 2]);
    assert_eq!(world.active_contacts(), 1);
    let thickness = world.contacts.settings.thickness;
    let x = &world.particles.position;
    let distance = x[0].distance(x[1]);
    let normal = (x[0] - x[1]) / distance;
    // The default stiffness, m (v_ref / h)² for the pair's reduced mass
    // (½ kg), docs/physics.md §8.
    let k = 0.5 * (sprung::contact::REFERENCE_SPEED / thickness).powi(2);
    let mut force = sprung::forces::BodyContacts::new();
    for _ in 0..3 {
        let p = random(2, &mut rng);
        let analytic = product(&mut force, &world, POSITION, &p);
        let numeric = difference(&mut force, &world, POSITION, &p);
        let q = p[0] - p[1];
        let turning = k * (thickness - distance) / distance * (q - normal.dot(q) * normal);
        let expected = [analytic[0] + turning, analytic[1] - turning];
        // Truncation ~ε² |f'''| ~ k h / d³ ε², round-off ~1e-16 |f| / ε:
        // both far below 1e-6 of the difference (~k |q|).
        let gap = relative_gap(&expected, &numeric);
        assert!(gap <= 1e-6, "∂f/∂x with the turning added back: {gap:.3e}");
        // And the part along the normal alone is exact without it.
        let along = [normal.dot(p[0]) * normal, normal.dot(p[1]) * normal];
        let analytic = product(&mut force, &world, POSITION, &along);
        let numeric = difference(&mut force, &world, POSITION, &along);
        let gap = relative_gap(&analytic, &numeric);
        assert!(gap <= 1e-6, "∂f/∂x along the normal: {gap:.3e}");
    }
}
