//! Springs that give way (docs/physics.md §11): a bob's spring holds below
//! its break strain and breaks at once above it; a spring stretched past
//! yield keeps the rest length `L_max / (1 + Y)` and the `plastic` term
//! closes the energy balance; a pumped balloon bursts; joins hold bodies
//! together and let go past their break strain; a resumed run goes on with
//! the same bits after a break.

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::{
    BodyData, Gas, IntegratorKind, JoinData, JoinEnd, Real, SpringData, StrainLimits, Vec3, World,
};

/// A bob of 1 kg hanging at rest from a spring of stiffness 64 N/m and
/// rest length 1 m, pinned at the origin, under `g = 8 m/s²`: it hangs in
/// equilibrium at the static strain `m g / (k L0) = 0.125`. All numbers
/// are short binary fractions, so symplectic Euler is exact to the bit.
fn bob(break_strain: Real) -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::new(0.0, -8.0, 0.0));
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(0.0, -1.125, 0.0)])
        .with_pinned(vec![0]);
    body.springs.push(SpringData {
        rest_length: Some(1.0),
        stiffness: 64.0,
        ..SpringData::between(0, 1)
    });
    body.limits.break_strain = Some(break_strain);
    world.add_body("bob", body).unwrap();
    world
}

#[test]
fn a_bob_holds_below_its_break_strain_and_falls_freely_above() {
    let dt = 1.0 / 16.0;
    // Static strain 0.125 below 0.2: the spring holds, the bob hangs still.
    let mut held = bob(0.2);
    for _ in 0..100 {
        held.step(dt).unwrap();
    }
    assert_eq!(held.limits.broken_count(), 0);
    assert_eq!(held.particles.position[1], Vec3::new(0.0, -1.125, 0.0));
    assert_eq!(held.particles.velocity[1], Vec3::ZERO);

    // Above 0.1: the first step, whose forces balance, leaves the bob where
    // it was, and the spring breaks at its end. From then on the bob falls
    // freely: after n steps in all, v = -g (n - 1) dt and
    // y = y0 - g dt² (n - 1) n / 2, exactly.
    let mut broken = bob(0.1);
    broken.step(dt).unwrap();
    assert_eq!(broken.limits.broken_count(), 1);
    assert!(broken.springs.is_broken(0));
    assert_eq!(broken.energies().get("spring"), Some(0.0));
    for _ in 1..40 {
        broken.step(dt).unwrap();
    }
    let n = 40.0;
    assert_eq!(broken.particles.velocity[1].y, -8.0 * (n - 1.0) * dt);
    assert_eq!(
        broken.particles.position[1].y,
        -1.125 - 8.0 * dt * dt * (n - 1.0) * n / 2.0
    );
    // The energy the spring held at the break, ½ k (L - L0)² = ½ 64 0.125²,
    // is the plastic term.
    assert_eq!(broken.energies().get("plastic"), Some(0.5));
}

/// A 1 kg particle on a spring of stiffness 100 N/m and rest length 1 m
/// pinned at the origin, no gravity, thrown outward at 2 m/s and sideways
/// at 0.5 m/s: elastic, it would stretch by about 0.2 m, past the yield
/// strain 0.1. The sideways motion keeps it from swinging back as far in
/// compression (its angular momentum), so it yields in tension only.
fn yielding(kind: IntegratorKind) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]).with_pinned(vec![0]);
    body.velocity = vec![Vec3::ZERO, Vec3::new(2.0, 0.5, 0.0)];
    body.springs.push(SpringData {
        stiffness: 100.0,
        ..SpringData::between(0, 1)
    });
    body.limits.yield_strain = Some(0.1);
    world.add_body("bob", body).unwrap();
    world
}

#[test]
fn a_spring_stretched_past_yield_keeps_the_rest_length_l_max_over_1_plus_y() {
    let mut world = yielding(IntegratorKind::Rk4);
    let start = world.energies().total();
    let mut longest: Real = 0.0;
    let mut worst: Real = 0.0;
    for _ in 0..30_000 {
        world.step(1e-4).unwrap();
        let x = &world.particles.position;
        longest = longest.max(x[0].distance(x[1]));
        worst = worst.max((world.energies().total() - start).abs() / start);
    }
    let rest = world.springs.rest_length[0];
    // The rest length moved (it started at 1 m) and is the longest length
    // over 1 + Y, to the rounding of that one division.
    assert!(rest > 1.05, "{rest}");
    assert!(
        (rest - longest / 1.1).abs() <= 2.0 * Real::EPSILON * rest,
        "{rest} {longest}"
    );
    assert!(world.energies().get("plastic").unwrap() > 0.1);
    // Kinetic + spring + plastic stays what it was: RK4 at ω dt = 1e-3
    // keeps the energy to about (ω dt)⁴ per period, far below 1e-6.
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn hardening_raises_the_yield_strain_by_h_times_the_relative_move() {
    let mut world = yielding(IntegratorKind::Rk4);
    world.limits = sprung::tearing::SpringLimits::default();
    let limits = StrainLimits {
        yield_strain: Some(0.1),
        hardening: 2.0,
        ..StrainLimits::default()
    };
    world.limits.set(&world.springs, 0..1, limits);
    for _ in 0..30_000 {
        world.step(1e-4).unwrap();
    }
    // Each yield moves the rest length from L0 to L0' and raises Y by
    // 2 |L0' - L0| / L0: summed, the yield strain ends above 0.1 by at least
    // 2 (L0_end - 1) / L0_end (each move is relative to a rest length at
    // most L0_end).
    let rest = world.springs.rest_length[0];
    let yield_now = world.limits.yield_strain(0);
    assert!(rest > 1.0);
    assert!(
        yield_now >= 0.1 + 2.0 * (rest - 1.0) / rest * (1.0 - 1e-12),
        "{yield_now}"
    );
    assert!(
        yield_now <= 0.1 + 2.0 * (rest - 1.0) * (1.0 + 1e-12),
        "{yield_now}"
    );
}

/// A balloon: an icosphere of radius 0.2 m whose gas is pumped to
/// `nrt` J over 1 s, with surface springs breaking past `break_strain`.
fn balloon(nrt: Real, break_strain: Real) -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    let mut ball = build::icosphere(0.2, 2, SurfaceSprings::default())
        .unwrap()
        .with_total_mass(0.1)
        .with_stiffness(400.0)
        .with_damping(0.05);
    ball.gas = Some(Gas::new(nrt, 1.0));
    ball.limits.break_strain = Some(break_strain);
    world.add_body("balloon", ball).unwrap();
    world
}

#[test]
fn a_balloon_pumped_past_its_break_strain_bursts() {
    let dt = 2e-4;
    // Pumped gently, the balloon holds: nothing breaks, it keeps its gas.
    let mut gentle = balloon(20.0, 0.3);
    for _ in 0..10_000 {
        gentle.step(dt).unwrap();
    }
    assert_eq!(gentle.limits.broken_count(), 0);
    assert!(gentle.pressure(0).unwrap() > 100.0);
    // Pumped hard, it bursts: springs break, its surface opens and the
    // pressure reads 0 from then on.
    let mut hard = balloon(400.0, 0.3);
    let mut burst_at = None;
    for step in 0..10_000 {
        hard.step(dt).unwrap();
        let pressure = hard.pressure(0).unwrap();
        match burst_at {
            None if hard.limits.broken_count() > 0 => {
                burst_at = Some(step);
                assert!(!hard.bodies[0].closed);
                assert_eq!(pressure, 0.0);
            }
            Some(_) => assert_eq!(pressure, 0.0, "step {step}"),
            None => assert!(pressure > 0.0),
        }
    }
    assert!(burst_at.is_some());
    assert!(hard.bodies[0].faces.len() < 320);
    assert_eq!(hard.volume(0), None);
}

/// Two single particles 1 m apart joined by a spring of 50 N/m, thrown
/// apart at 1 m/s and 3 m/s (no gravity).
fn joined(break_strain: Option<Real>) -> World {
    let mut world = World::new(IntegratorKind::Rk4);
    world.set_gravity(Vec3::ZERO);
    let a = BodyData::from_positions(vec![Vec3::ZERO])
        .with_mass(2.0)
        .with_velocity(Vec3::new(-1.0, 0.5, 0.0));
    let b = BodyData::from_positions(vec![Vec3::X])
        .with_mass(1.0)
        .with_velocity(Vec3::new(3.0, 0.0, 0.2));
    world.add_body("a", a).unwrap();
    world.add_body("b", b).unwrap();
    let mut join = JoinData::between(JoinEnd::new("a", 0), JoinEnd::new("b", 0));
    join.stiffness = 50.0;
    join.break_strain = break_strain;
    world.add_join(join).unwrap();
    world
}

#[test]
fn a_join_holds_two_bodies_together_and_conserves_momentum() {
    let mut world = joined(None);
    let p0 = world.linear_momentum();
    let mut farthest: Real = 0.0;
    for _ in 0..5000 {
        world.step(1e-3).unwrap();
        let x = &world.particles.position;
        farthest = farthest.max(x[0].distance(x[1]));
        // The spring's equal and opposite pulls: momentum to round-off.
        assert!((world.linear_momentum() - p0).length() <= 1e-12 * p0.length());
    }
    // Held: relative speed 4 m/s, reduced mass 2/3 kg, k = 50 N/m: it
    // stretches by v sqrt(mu / k) ≈ 0.46 m at most, never flies apart.
    assert!(farthest < 1.5, "{farthest}");
    assert_eq!(world.limits.broken_count(), 0);
}

#[test]
fn a_join_lets_go_past_its_break_strain() {
    let mut world = joined(Some(0.2));
    let p0 = world.linear_momentum();
    for _ in 0..5000 {
        world.step(1e-3).unwrap();
    }
    assert!(world.join_broken(0));
    assert_eq!(world.limits.broken_count(), 1);
    // Apart: each flies on at its own constant velocity, the momentum the
    // same.
    let v = world.particles.velocity.clone();
    world.step(1e-3).unwrap();
    assert_eq!(world.particles.velocity, v);
    assert!((world.linear_momentum() - p0).length() <= 1e-12 * p0.length());
    let x = &world.particles.position;
    assert!(x[0].distance(x[1]) > 5.0);
}

#[test]
fn joins_refuse_unknown_bodies_particles_out_of_range_and_bad_strains() {
    let mut world = joined(None);
    let end = |body: &str, particle| JoinEnd::new(body, particle);
    let refused = |world: &mut World, join: JoinData| world.add_join(join).unwrap_err().to_string();
    let message = refused(&mut world, JoinData::between(end("a", 0), end("c", 0)));
    assert!(message.contains("join `b` names body \"c\""), "{message}");
    let message = refused(&mut world, JoinData::between(end("a", 1), end("b", 0)));
    assert!(
        message.contains("join `a` = [\"a\", 1]: particle index out of range"),
        "{message}"
    );
    let mut join = JoinData::between(end("a", 0), end("b", 0));
    join.break_strain = Some(-0.1);
    let message = refused(&mut world, join.clone());
    assert!(message.starts_with("`break_strain` = -0.1"), "{message}");
    join.break_strain = Some(0.1);
    join.rod = true;
    let message = refused(&mut world, join);
    assert!(message.contains("needs a spring join"), "{message}");
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    body.limits = StrainLimits {
        break_strain: Some(0.2),
        yield_strain: Some(0.2),
        hardening: 0.0,
    };
    let message = world.add_body("c", body).unwrap_err().to_string();
    assert!(
        message.starts_with("`yield_strain` = 0.2: must be below `break_strain`"),
        "{message}"
    );
    // A muscle's drive would undo every yield of its spring.
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    body.springs.push(SpringData::between(0, 1));
    body.muscles.push(sprung::MuscleData {
        spring: 0,
        drive: sprung::MuscleDrive::Sine {
            amplitude: 0.1,
            period: 1.0,
            phase: 0.0,
        },
    });
    body.limits.yield_strain = Some(0.1);
    let message = world.add_body("d", body).unwrap_err().to_string();
    assert!(
        message.contains("cannot be combined with `muscles`"),
        "{message}"
    );
    assert_eq!(world.joins.len(), 1);
}

/// A cloth pinned along its top edge, pulled down hard at its bottom
/// corners (their masses 2000 times the others), so that it tears; its
/// springs break past 30 % strain.
fn tearing() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let mut cloth = build::cloth(12, 12, 1.0, 1.0, ClothSprings::default())
        .unwrap()
        .with_total_mass(0.2)
        .with_stiffness(300.0)
        .with_damping(0.02)
        .with_pinned((0..12).collect());
    cloth.mass[132] *= 2000.0;
    cloth.mass[143] *= 2000.0;
    cloth.limits.break_strain = Some(0.3);
    cloth.contact.self_collision = true;
    world.add_body("cloth", cloth).unwrap();
    world
}

#[test]
fn a_tearing_cloth_resumes_with_the_same_bits_after_a_break() {
    let dt = 5e-4;
    let mut run = tearing();
    let mut steps = 0;
    while run.limits.broken_count() == 0 {
        run.step(dt).unwrap();
        steps += 1;
        assert!(steps < 20_000, "the cloth never tore");
    }
    for _ in 0..50 {
        run.step(dt).unwrap();
    }
    let saved = run.save_state();
    let faces = run.bodies[0].faces.len();
    for _ in 0..400 {
        run.step(dt).unwrap();
    }
    let mut resumed = tearing();
    resumed.restore_state(&saved).unwrap();
    assert_eq!(resumed.bodies[0].faces.len(), faces);
    for _ in 0..400 {
        resumed.step(dt).unwrap();
    }
    assert_eq!(resumed.particles.position, run.particles.position);
    assert_eq!(resumed.particles.velocity, run.particles.velocity);
    assert_eq!(resumed.limits.broken_count(), run.limits.broken_count());
    assert_eq!(resumed.springs.rest_length, run.springs.rest_length);
    assert_eq!(resumed.bodies[0].faces, run.bodies[0].faces);
    assert_eq!(
        resumed.energies().get("plastic"),
        run.energies().get("plastic")
    );
    // A state saved before any break is refused by the torn world: a
    // broken spring cannot be mended.
    let mut fresh = tearing();
    let before = fresh.save_state();
    assert!(run.restore_state(&before).is_err());
    fresh.step(dt).unwrap();
}

#[test]
fn a_flag_hangs_from_a_thrown_rigid_pole_by_rods() {
    // A rigid pole of 5 particles (0.4 m) thrown up and spinning, a 4 × 4
    // cloth hung from it by rod joins at two of its corners: the rods and
    // the pole's shape matching take turns in the constrain stage, so the
    // rods hold their lengths at every step and the pole stays rigid,
    // while the flag swings behind it.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let pole = BodyData::from_positions(
        (0..5)
            .map(|k| Vec3::new(0.1 * k as Real, 1.0, 0.0))
            .collect(),
    )
    .with_total_mass(1.0)
    .with_velocity(Vec3::new(0.5, 3.0, 0.0))
    .with_spin(Vec3::new(0.0, 0.0, 2.0));
    let pole = BodyData {
        rigid: true,
        ..pole
    };
    world.add_body("pole", pole).unwrap();
    let flag = build::cloth(4, 4, 0.4, 0.3, ClothSprings::default())
        .unwrap()
        .with_total_mass(0.05)
        .with_stiffness(200.0)
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.65, 0.0));
    world.add_body("flag", flag).unwrap();
    for (pole_end, flag_corner) in [(0, 12), (4, 15)] {
        let mut join = JoinData::between(
            JoinEnd::new("pole", pole_end),
            JoinEnd::new("flag", flag_corner),
        );
        join.rod = true;
        world.add_join(join).unwrap();
    }
    let lengths = world.rods.length.clone();
    assert!(
        lengths.iter().all(|&l| (l - 0.05).abs() < 1e-12),
        "{lengths:?}"
    );
    let shape = |w: &World| w.particles.position[0].distance(w.particles.position[4]);
    let span = shape(&world);
    for _ in 0..2000 {
        world.step(2.5e-4).unwrap();
        let x = &world.particles.position;
        for r in 0..world.rods.len() {
            let (a, b) = (world.rods.first[r] as usize, world.rods.second[r] as usize);
            let error = (x[a].distance(x[b]) - world.rods.length[r]).abs() / world.rods.length[r];
            // The constrain stage's tolerance (1e-9, relative) it stops
            // at, with a rounding's room.
            assert!(error <= 1.01e-9, "rod {r} off by {error:e}");
        }
        assert!((shape(&world) - span).abs() < 1e-9);
    }
    // It flew: thrown up at 3 m/s, after 0.5 s its centre is near
    // 1 + 3 · 0.5 - 9.81 · 0.5² / 2 = 1.27 m (less for the flag it lifts).
    assert!(
        world.particles.position[2].y > 1.15,
        "{}",
        world.particles.position[2].y
    );
}

#[test]
fn the_movement_budget_gives_what_a_search_every_step_gives() {
    // The same tearing cloth twice: once as it runs (a full search only
    // when the particles have moved far enough for a spring to reach its
    // limit), once with a search forced every step (refreshing no spring
    // drops the budget). Both break the same springs at the same steps:
    // the same bits every step.
    let dt = 5e-4;
    let (mut budget, mut every) = (tearing(), tearing());
    let steps = 1_500;
    let mut before_tear = None;
    for step in 0..steps {
        budget.step(dt).unwrap();
        every.limits.refresh(&every.springs, 0..0);
        every.step(dt).unwrap();
        assert_eq!(
            budget.particles.position, every.particles.position,
            "step {step}"
        );
        assert_eq!(budget.limits.broken_count(), every.limits.broken_count());
        if budget.limits.broken_count() > 0 && before_tear.is_none() {
            before_tear = Some((step, budget.limits.searches()));
        }
    }
    assert_eq!(every.limits.searches(), steps);
    // While the cloth stretched towards the tear, the budget skipped at
    // least nine searches in ten.
    let (step, searches) = before_tear.expect("the cloth never tore");
    assert!(searches * 10 < step, "{searches} searches in {step} steps");
}

#[test]
fn a_particle_moved_by_hand_is_seen_by_the_next_search() {
    let dt = 1.0 / 16.0;
    // The bob hangs still at strain 0.125, 0.075 m from its break length:
    // after the first search nothing moves and no pass searches again.
    let mut world = bob(0.2);
    for _ in 0..100 {
        world.step(dt).unwrap();
    }
    assert_eq!(world.limits.searches(), 1);
    // Moved by hand to strain 0.5: the next step's pass measures the move,
    // searches and breaks the spring.
    world.particles.position[1].y = -1.5;
    world.step(dt).unwrap();
    assert_eq!(world.limits.searches(), 2);
    assert_eq!(world.limits.broken_count(), 1);
}
