//! Implicit Euler's preconditioners (docs/simulation.md "Stiff materials:
//! the implicit integrators"). Claims: the stiffness factor is the Newton matrix of a world
//! of springs, so each solve takes one iteration; it reaches the step the
//! diagonal reaches; the default, auto, is Jacobi bit for bit where Jacobi
//! converges within its budget, takes the factor where it would not, names
//! its choice in the step's report, keeps the factor across steps (made
//! again only when it stops paying) and across a saved state, and gives
//! the same bits on 1, 2 and 3 threads; a cloth at rest takes no
//! iterations; and a step with the factor allocates nothing.
//!
//! The stiff cloths are those of `sprung bench`'s stiff group and of issue
//! 35: 1 m square, springs of 2·10⁴ N/m, hanging from the two corners of
//! their top edge, laid flat first so they swing down, stepped at the frame
//! rate.

mod common;

use common::wind::largest_distance;
use sprung::build::{self, ClothSprings};
use sprung::integrate::Preconditioner;
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

const FRAME: Real = 1.0 / 60.0; // s

/// An `n × n` cloth of 1 m square weighing `total_mass` (kg) with springs
/// of `stiffness` (N/m) and damping 0.5 N·s/m, laid flat and hanging from
/// two corners, stepped by implicit Euler with `preconditioner`.
fn cloth(n: usize, total_mass: Real, stiffness: Real, preconditioner: Preconditioner) -> World {
    damped_cloth(n, total_mass, (stiffness, 0.5), preconditioner)
}

/// [`cloth`] with springs of `(stiffness, damping)` (N/m, N·s/m).
fn damped_cloth(
    n: usize,
    total_mass: Real,
    (stiffness, damping): (Real, Real),
    preconditioner: Preconditioner,
) -> World {
    let body = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_mass(total_mass / (n * n) as Real)
        .with_stiffness(stiffness)
        .with_damping(damping)
        .with_pinned(vec![n * (n - 1), n * n - 1])
        .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.add_body("cloth", body).expect("valid body");
    world.settings.solver.preconditioner = preconditioner;
    world
}

/// The light cloth: 0.2 kg, where `dt² k / m` is about 3·10⁴ at
/// 16²: Jacobi needs hundreds of iterations a step.
fn light_cloth(preconditioner: Preconditioner) -> World {
    cloth(16, 0.2, 2e4, preconditioner)
}

#[test]
fn the_stiffness_factor_is_the_springs_newton_matrix() {
    // Springs and gravity alone: gravity has no Jacobian, so the factor of
    // the springs' M - dt D - dt² K is the solve's very matrix, and
    // conjugate gradients end after one iteration at the rounding of the
    // back-substitution (the factor's condition, about dt² k / m = 3·10⁴,
    // times 1e-16, well under the asked 1e-9).
    let mut world = light_cloth(Preconditioner::Stiffness);
    world.settings.solver.tolerance = 1e-9;
    for step in 1..=30 {
        let report = world.step(FRAME).expect("stable");
        assert_eq!(report.iterations, Some(1), "step {step}");
        assert!(report.residual.is_some_and(|r| r <= 1e-9), "step {step}");
        assert_eq!(report.preconditioner, Some(Preconditioner::Stiffness));
    }
}

#[test]
fn the_stiffness_factor_and_jacobi_reach_the_same_step() {
    // The preconditioner changes the path, not the system: solved to a
    // relative residual of 1e-12, the velocities agree to the residual
    // times the system's condition number (below dt² k / m · 12 springs a
    // particle ≈ 4·10⁵ here): we claim 1e-6 of the largest speed.
    let run = |preconditioner| {
        let mut world = light_cloth(preconditioner);
        world.settings.solver.tolerance = 1e-12;
        world.settings.solver.max_iterations = 100_000;
        for _ in 0..5 {
            let report = world.step(FRAME).expect("stable");
            assert!(!report.unconverged);
        }
        world
    };
    let (jacobi, factored) = (run(Preconditioner::Jacobi), run(Preconditioner::Stiffness));
    let velocity = &jacobi.particles.velocity;
    let speed = velocity.iter().map(|v| v.length()).fold(0.0, Real::max);
    let gap = largest_distance(velocity, &factored.particles.velocity);
    assert!(speed > 0.1, "the cloth swings: {speed} m/s");
    assert!(gap <= 1e-6 * speed, "{gap} m/s apart");
}

#[test]
fn auto_is_jacobi_bit_for_bit_where_jacobi_is_cheaper() {
    // A soft, lightly damped cloth (10 N/m, 0.01 N·s/m, particles of 2 g):
    // Jacobi converges in under 32 iterations a step (measured), below the
    // factor's budget for 16² (about 40), so auto never factors and its
    // steps are Jacobi's to the bit.
    let run = |preconditioner| {
        let mut world = damped_cloth(16, 0.512, (10.0, 0.01), preconditioner);
        let mut chosen = Vec::new();
        for _ in 0..30 {
            chosen.push(world.step(FRAME).expect("stable").preconditioner);
        }
        (world, chosen)
    };
    let (auto, chosen) = run(Preconditioner::Auto);
    let (jacobi, _) = run(Preconditioner::Jacobi);
    assert!(chosen.iter().all(|&c| c == Some(Preconditioner::Jacobi)));
    assert_eq!(auto.particles.position, jacobi.particles.position);
    assert_eq!(auto.particles.velocity, jacobi.particles.velocity);
    assert_eq!(auto.solver_stats().unconverged_steps, 0);
}

#[test]
fn auto_takes_the_factor_where_jacobi_would_cost_more_and_keeps_it() {
    // The light cloth: Jacobi's iterations pass the factor's budget within
    // a few steps (a step's solve is then done again with the factor);
    // from then on every step takes the factor, one iteration each, and
    // no step is left unconverged.
    let mut world = light_cloth(Preconditioner::Auto);
    let chosen: Vec<_> = (0..30)
        .map(|_| world.step(FRAME).expect("stable"))
        .collect();
    let first = chosen
        .iter()
        .position(|r| r.preconditioner == Some(Preconditioner::Stiffness))
        .expect("auto takes the factor");
    assert!(first < 10, "took it at step {}", first + 1);
    // Swinging, its springs turn enough that the kept factor does not
    // converge within the few iterations a new factor costs at 16²: each
    // step then factors at most once, and with a new factor converges in
    // one iteration, after at most one trial of the kept one.
    for report in &chosen[first + 1..] {
        assert_eq!(report.preconditioner, Some(Preconditioner::Stiffness));
        assert_eq!(report.refactorings, Some(1));
        assert!(report.iterations.is_some_and(|i| i <= 3));
    }
    assert_eq!(world.solver_stats().unconverged_steps, 0);
}

#[test]
fn a_resumed_run_keeps_autos_choice() {
    // Saved after auto took the factor, a run resumed in a fresh world goes
    // on with it (made again at the positions it was made at), step by step
    // with the same reports, and ends on the bits of the run that was not
    // stopped.
    let mut whole = light_cloth(Preconditioner::Auto);
    let mut first = light_cloth(Preconditioner::Auto);
    for _ in 0..15 {
        whole.step(FRAME).expect("stable");
        first.step(FRAME).expect("stable");
    }
    let saved = first.save_state();
    let mut resumed = light_cloth(Preconditioner::Auto);
    resumed.restore_state(&saved).expect("same scene");
    for _ in 0..15 {
        let report = whole.step(FRAME).expect("stable");
        assert_eq!(report.preconditioner, Some(Preconditioner::Stiffness));
        let again = resumed.step(FRAME).expect("stable");
        assert_eq!(again, report, "the same choices, no Jacobi trial again");
    }
    assert_eq!(whole.particles.position, resumed.particles.position);
    assert_eq!(whole.particles.velocity, resumed.particles.velocity);
}

#[test]
fn the_factored_steps_are_the_same_on_any_number_of_threads() {
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let mut world = cloth(24, 0.2, 2e4, Preconditioner::Auto);
        pool.install(|| {
            for _ in 0..10 {
                world.step(FRAME).expect("stable");
            }
        });
        world.particles.position
    };
    let one = run(1);
    assert_eq!(one, run(2));
    assert_eq!(one, run(3));
}

#[test]
fn the_laplacian_factors_steps_are_the_same_on_any_number_of_threads() {
    // At 64² the factor of M + dt² L has about 2.6·10⁵ values, enough for
    // its substitutions to cut the elimination tree and solve the parts
    // side by side: the projective solver and the Laplacian
    // preconditioner still give the same bits on 1, 2 and 3 threads.
    let run = |threads, kind| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let mut world = cloth(64, 0.2, 2e4, Preconditioner::Laplacian);
        world.set_integrator(kind);
        pool.install(|| {
            for _ in 0..3 {
                world.step(FRAME).expect("stable");
            }
        });
        world.particles.position
    };
    for kind in [IntegratorKind::Projective, IntegratorKind::ImplicitEuler] {
        let one = run(1, kind);
        assert_eq!(one, run(2, kind), "{kind}");
        assert_eq!(one, run(3, kind), "{kind}");
    }
}

#[test]
fn worlds_with_nothing_to_factor_step_under_every_preconditioner() {
    // Every particle pinned (an empty matrix) and a particle with no
    // springs (the factor is the mass alone): each preconditioner
    // steps them, the free particle falling as gravity says (a world
    // without springs has a linear system that every preconditioner solves
    // in at most one iteration).
    for preconditioner in [
        Preconditioner::Auto,
        Preconditioner::Jacobi,
        Preconditioner::Laplacian,
        Preconditioner::Stiffness,
    ] {
        let mut pinned = World::new(IntegratorKind::ImplicitEuler);
        pinned
            .add_body("cloth", cloth_body(4).with_pinned((0..16).collect()))
            .expect("valid body");
        let mut alone = World::new(IntegratorKind::ImplicitEuler);
        alone
            .add_body("point", BodyData::from_positions(vec![Vec3::ZERO]))
            .expect("valid body");
        for world in [&mut pinned, &mut alone] {
            world.settings.solver.preconditioner = preconditioner;
            for _ in 0..3 {
                let report = world.step(FRAME).expect("steps");
                assert!(report.iterations.is_some_and(|i| i <= 1));
                assert!(!report.unconverged);
            }
        }
        assert!(pinned.particles.velocity.iter().all(|v| *v == Vec3::ZERO));
        // Backward Euler from rest under g: v_n = -n g dt, x_3 = -6 g dt².
        let fallen = alone.particles.position[0].y;
        let expected = 6.0 * sprung::world::DEFAULT_GRAVITY.y * FRAME * FRAME;
        assert!(
            (fallen - expected).abs() < 1e-12,
            "{preconditioner:?}: {fallen}"
        );
    }
}

/// A 1 m square `n × n` cloth of 1 g particles and 100 N/m springs.
fn cloth_body(n: usize) -> BodyData {
    build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_mass(0.001)
        .with_stiffness(100.0)
}

/// The light cloth hung in its plane from the two corners of its top edge
/// (not laid flat first): it settles within a second.
fn hung_cloth(n: usize) -> World {
    let body = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_mass(0.2 / (n * n) as Real)
        .with_stiffness(2e4)
        .with_damping(0.5)
        .with_pinned(vec![n * (n - 1), n * n - 1]);
    let mut world = World::new(IntegratorKind::ImplicitEuler);
    world.add_body("cloth", body).expect("valid body");
    world
}

#[test]
fn a_cloth_at_rest_takes_no_iterations() {
    // Settled to a tolerance far below the default (Newton to 1e-12), the
    // hung cloth's right side is the rounding of forces that balance: its
    // norm is far below 1e-6 of the step's gravity impulse |dt g M|, the
    // default solve's floor, so the default solve takes no iterations,
    // step after step (measured against |b| alone it would chase the
    // rounding for hundreds of iterations). The auto preconditioner then
    // keeps the factor it took: no refactorings either.
    let mut world = hung_cloth(16);
    world.settings.solver.tolerance = 1e-12;
    world.settings.solver.newton_iterations = 4;
    for _ in 0..240 {
        world.step(FRAME).expect("stable");
    }
    world.settings.solver = sprung::integrate::SolverSettings::default();
    for step in 0..60 {
        let report = world.step(FRAME).expect("stable");
        assert_eq!(report.iterations, Some(0), "step {step}");
        assert_eq!(report.refactorings, Some(0), "step {step}");
    }
}

#[test]
fn the_kept_factor_serves_a_cloth_hung_in_its_plane() {
    // Hung in its plane the springs turn little from step to step: the
    // factor taken at the first step preconditions every later one within
    // its refactoring threshold (1 to 2 iterations measured), so it is
    // never made again, and no step is left unconverged.
    let mut world = hung_cloth(16);
    let first = world.step(FRAME).expect("stable");
    assert_eq!(first.preconditioner, Some(Preconditioner::Stiffness));
    for step in 1..120 {
        let report = world.step(FRAME).expect("stable");
        assert_eq!(report.refactorings, Some(0), "step {step}");
        assert!(report.iterations.is_some_and(|i| i <= 2), "step {step}");
    }
    assert_eq!(world.solver_stats().unconverged_steps, 0);
}

#[test]
fn a_resumed_run_remakes_the_kept_factor_with_the_springs_it_was_made_with() {
    // The hung cloth keeps its first factor. Its springs' rest lengths
    // change after it was made (as a muscle's or a yielding spring's do),
    // so a resumed run must make it again from the saved rest lengths, not
    // the springs' present ones, to take the same steps to the bit.
    let shorten = |world: &mut World| {
        for rest in &mut world.springs.rest_length {
            *rest *= 0.999;
        }
    };
    let mut whole = hung_cloth(16);
    let mut first = hung_cloth(16);
    for step in 0..15 {
        if step == 5 {
            shorten(&mut whole);
            shorten(&mut first);
        }
        whole.step(FRAME).expect("stable");
        first.step(FRAME).expect("stable");
    }
    let saved = first.save_state();
    let mut resumed = hung_cloth(16);
    shorten(&mut resumed);
    resumed.restore_state(&saved).expect("same scene");
    for _ in 0..15 {
        let report = whole.step(FRAME).expect("stable");
        assert_eq!(report.refactorings, Some(0), "the first factor is kept");
        assert_eq!(resumed.step(FRAME).expect("stable"), report);
    }
    assert_eq!(whole.particles.position, resumed.particles.position);
    assert_eq!(whole.particles.velocity, resumed.particles.velocity);
}

/// The sag (m: how far the lowest particle hangs below the pins) and the
/// largest strain of `world`'s springs (|length / rest − 1|).
fn sag_and_strain(world: &World) -> (Real, Real) {
    let x = &world.particles.position;
    let top = x.iter().map(|p| p.y).fold(Real::MIN, Real::max);
    let lowest = x.iter().map(|p| p.y).fold(Real::MAX, Real::min);
    let springs = &world.springs;
    let strain = (0..springs.len())
        .map(|s| {
            let (i, j) = (springs.first()[s] as usize, springs.second()[s] as usize);
            ((x[i] - x[j]).length() / springs.rest_length[s] - 1.0).abs()
        })
        .fold(0.0, Real::max);
    (top - lowest, strain)
}

#[test]
fn each_solver_at_its_defaults_hangs_the_cloth_as_newton_does() {
    // Issue 51's quality claim on the hung cloth, where Newton converges:
    // after 3 s (settled within one) the sag and the largest strain under
    // implicit Euler and projective at their defaults are within 1 % of
    // implicit Euler with Newton to convergence (8 iterations a step, each
    // solve to 1e-12 with the step's own factor). The default solves stop
    // at 1e-6 of the step's gravity impulse and projective takes 10
    // iterations a step, so at rest each is a force balance far inside
    // 1 %; a solver that lost the stiffness or the weight would be off by
    // its order.
    let settle = |world: &mut World| {
        for _ in 0..180 {
            world.step(FRAME).expect("stable");
        }
        sag_and_strain(world)
    };
    let mut newton = hung_cloth(16);
    newton.settings.solver.newton_iterations = 8;
    newton.settings.solver.tolerance = 1e-12;
    newton.settings.solver.preconditioner = Preconditioner::Stiffness;
    let (sag, strain) = settle(&mut newton);
    assert!(
        sag > 0.9 && strain > 1e-4,
        "it hangs: {sag} m, strain {strain}"
    );
    let mut projective = hung_cloth(16);
    projective.set_integrator(IntegratorKind::Projective);
    for (name, mut world) in [
        ("implicit_euler", hung_cloth(16)),
        ("projective", projective),
    ] {
        let (s, e) = settle(&mut world);
        assert!(
            (s / sag - 1.0).abs() <= 0.01,
            "{name}: sag {s} m against {sag}"
        );
        assert!(
            (e / strain - 1.0).abs() <= 0.01,
            "{name}: strain {e} against {strain}"
        );
    }
}
