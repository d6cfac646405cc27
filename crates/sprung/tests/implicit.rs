//! The implicit integrators (docs/physics.md §6): backward Euler by Newton's
//! method and conjugate gradients (`implicit_euler`) and by the local/global
//! iterations of the fast mass-spring solver (`projective`). Claims: both
//! hold a stiff cloth at a frame-sized step where every explicit method
//! blows up, dissipating; both converge to the RK4 motion as the step
//! shrinks and to each other as they iterate; the linear solves reach their
//! tolerance or say so; projection colliders hold inside the solves.
//!
//! The stiff cloth is the one of the issue that asked for these solvers: 16
//! × 16 particles of 2 g, 1 m square, springs of 2·10⁴ N/m, hanging from
//! two corners, stepped at dt = 1/60 s.

mod common;

use sprung::build::{self, ClothSprings};
use sprung::integrate::Preconditioner;
use sprung::{
    BodyData, Collider, ContactResponse, IntegratorKind, Real, Shape, SpringData, Vec3, World,
};

const FRAME: Real = 1.0 / 60.0; // s
const IMPLICIT: [IntegratorKind; 2] = [IntegratorKind::ImplicitEuler, IntegratorKind::Projective];

/// An `n × n` cloth of 1 m × 1 m, particles of `mass` (kg), springs of
/// `stiffness` (N/m), hanging from the two corners of its top edge; laid
/// flat first (`horizontal`), it swings down, else it hangs in its plane.
fn cloth(kind: IntegratorKind, n: usize, mass: Real, stiffness: Real, horizontal: bool) -> World {
    let mut body = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_mass(mass)
        .with_stiffness(stiffness)
        .with_pinned(vec![n * (n - 1), n * n - 1]);
    if horizontal {
        body = body.placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
    }
    let mut world = World::new(kind);
    world.add_body("cloth", body).expect("valid body");
    world
}

fn stiff_cloth(kind: IntegratorKind, horizontal: bool) -> World {
    cloth(kind, 16, 0.002, 2e4, horizontal)
}

/// Largest distance (m) between the particles of two runs.
fn largest_distance(a: &World, b: &World) -> Real {
    a.particles
        .position
        .iter()
        .zip(&b.particles.position)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, Real::max)
}

#[test]
fn the_stiff_cloth_needs_a_hundred_times_smaller_steps_explicitly() {
    let world = stiff_cloth(IntegratorKind::SymplecticEuler, true);
    let ratio = FRAME / world.stable_time_step();
    assert!(ratio > 100.0, "dt / stable dt = {ratio}");
    for kind in [
        IntegratorKind::Euler,
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Midpoint,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
    ] {
        let mut world = stiff_cloth(kind, true);
        let blew_up = (0..600).any(|_| world.step(FRAME).is_err());
        assert!(blew_up, "{kind} survived 10 s at dt = 1/60 s");
    }
}

#[test]
fn implicit_euler_holds_the_swinging_stiff_cloth_for_a_minute_and_only_dissipates() {
    // Laid flat, the cloth swings down and comes to rest. Backward Euler on
    // springs and gravity takes energy out at every step (its matrix is
    // made definite, so each step is the exact solution of a dissipative
    // linearisation). The total is a sum of ~3000 terms of up to a few J:
    // its round-off is ~1e-13 J, and we allow 1e-12 J per step.
    let mut world = stiff_cloth(IntegratorKind::ImplicitEuler, true);
    let start = world.energies().total();
    let mut previous = start;
    for step in 1..=3600 {
        world
            .step(FRAME)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        let energy = world.energies().total();
        assert!(
            energy <= previous + 1e-12,
            "step {step}: energy grew from {previous} J to {energy} J"
        );
        previous = energy;
    }
    // It swung down and came to rest: the potential fell by about m g Δh
    // (half the cloth's 0.512 kg falling about 0.5 m: -2.5 J).
    assert!(previous < start - 2.0, "energy {start} J -> {previous} J");
    assert!(world.energies().kinetic < 1e-6);
}

#[test]
fn projective_holds_the_swinging_stiff_cloth_for_a_minute_below_its_starting_energy() {
    // With its 10 iterations per step the local/global iteration is not
    // converged on the swinging cloth (its slowest modes, the cloth's
    // bending, converge by about 0.5 % per iteration), so the energy
    // wanders from step to step; it never rises above where it started,
    // and the cloth stays whole.
    let mut world = stiff_cloth(IntegratorKind::Projective, true);
    let start = world.energies().total();
    for step in 1..=3600 {
        world
            .step(FRAME)
            .unwrap_or_else(|e| panic!("step {step}: {e}"));
        let energy = world.energies().total();
        assert!(
            energy <= start + 1e-12,
            "step {step}: {energy} J > {start} J"
        );
    }
    let stretch = (0..world.springs.len())
        .map(|s| {
            let (i, j) = (
                world.springs.first()[s] as usize,
                world.springs.second()[s] as usize,
            );
            world.particles.position[i].distance(world.particles.position[j])
                / world.springs.rest_length[s]
        })
        .fold(0.0, Real::max);
    assert!(
        stretch < 1.01,
        "a spring is stretched {stretch} times its rest length"
    );
}

#[test]
fn both_only_dissipate_on_the_hanging_stiff_cloth_once_converged() {
    // Hanging in its plane from the start, the cloth sags under gravity.
    // Converged (projective with 50 iterations; implicit Euler converges
    // each linear solve), each step is dissipative: we allow the 1e-12 J
    // round-off of the energy sum per step, for a minute.
    for kind in IMPLICIT {
        let mut world = stiff_cloth(kind, false);
        world.settings.solver.iterations = 50;
        let mut previous = world.energies().total();
        for step in 1..=3600 {
            world
                .step(FRAME)
                .unwrap_or_else(|e| panic!("{kind}, step {step}: {e}"));
            let energy = world.energies().total();
            assert!(
                energy <= previous + 1e-12,
                "{kind}, step {step}: energy grew from {previous} J to {energy} J"
            );
            previous = energy;
        }
    }
}

#[test]
fn both_converge_to_the_rk4_motion_of_a_hanging_cloth() {
    // An 8 × 8 cloth, 10 g particles, 500 N/m springs, hanging from two
    // corners and sagging for 1 s. RK4 at 1.25e-4 s is the reference (its
    // error, ~dt⁴, is below 1e-10 m). Both implicit methods are first
    // order: their error after T = 1 s is about that of Euler's free fall,
    // ½ g T dt; we allow twice that, g T dt (2.5 mm at dt = 2.5e-4 s), and
    // halving dt must divide the error by about 2 (at these steps the
    // damping of the fastest modes, ω dt ≈ 0.3, still adds higher-order
    // terms: between 1.5 and 2.5).
    let run = |kind: IntegratorKind, dt: Real| {
        let mut world = cloth(kind, 8, 0.01, 500.0, false);
        for _ in 0..(1.0 / dt).round() as usize {
            world.step(dt).expect("stable");
        }
        world
    };
    let reference = run(IntegratorKind::Rk4, 1.25e-4);
    for kind in IMPLICIT {
        let coarse = largest_distance(&run(kind, 5e-4), &reference);
        let fine = largest_distance(&run(kind, 2.5e-4), &reference);
        assert!(fine <= 9.81 * 1.0 * 2.5e-4, "{kind}: {fine} m from RK4");
        let ratio = coarse / fine;
        assert!(
            (1.5..=2.5).contains(&ratio),
            "{kind}: halving dt divided the error by {ratio} ({coarse} m, {fine} m)"
        );
    }
}

#[test]
fn projective_iterated_to_convergence_is_implicit_euler_with_newton() {
    // Both solve the same backward-Euler equations
    // `M (x - x_n - dt v_n) = dt² f(x, (x - x_n)/dt)`; iterated to a relative
    // residual of 1e-12 (Newton: 8 iterations; projective: 200) they must
    // give the same positions. The step's matrix has a condition number
    // below 1 + 16 dt² k / m ≈ 5e4, so residuals of 1e-12 leave each
    // position within ~1e-10 m of the exact solution; we claim 1e-9 m, on
    // the soft hanging cloth at a small step and on the stiff one at the
    // frame step.
    for (n, mass, stiffness, dt, steps) in
        [(8, 0.01, 500.0, 1e-3, 1000), (8, 0.002, 2e4, FRAME, 60)]
    {
        let mut newton = cloth(IntegratorKind::ImplicitEuler, n, mass, stiffness, false);
        newton.settings.solver.newton_iterations = 8;
        newton.settings.solver.tolerance = 1e-12;
        let mut projective = cloth(IntegratorKind::Projective, n, mass, stiffness, false);
        projective.settings.solver.iterations = 200;
        projective.settings.solver.tolerance = 1e-12;
        for _ in 0..steps {
            newton.step(dt).expect("stable");
            projective.step(dt).expect("stable");
        }
        let apart = largest_distance(&newton, &projective);
        assert!(apart <= 1e-9, "k = {stiffness}, dt = {dt}: {apart} m apart");
    }
}

#[test]
fn the_linear_solves_reach_their_tolerance_or_say_so() {
    let mut world = stiff_cloth(IntegratorKind::ImplicitEuler, true);
    world.settings.solver.tolerance = 1e-8;
    // Jacobi, which needs dozens of iterations here (auto would take the
    // stiffness factor, which needs one).
    world.settings.solver.preconditioner = Preconditioner::Jacobi;
    for step in 1..=30 {
        let report = world.step(FRAME).expect("stable");
        let residual = report
            .residual
            .expect("implicit Euler reports its residual");
        assert!(
            residual <= 1e-8 && !report.unconverged,
            "step {step}: residual {residual}"
        );
        assert!(report.iterations.is_some_and(|i| i > 0));
    }
    assert_eq!(world.solver_stats().unconverged_steps, 0);
    // Three iterations cannot solve the swinging cloth's system to 1e-8
    // (the 30 steps above took dozens each).
    world.settings.solver.max_iterations = 3;
    for _ in 0..10 {
        let report = world.step(FRAME).expect("stable");
        assert!(report.unconverged);
        assert_eq!(report.iterations, Some(3));
    }
    let stats = world.solver_stats();
    assert_eq!(stats.unconverged_steps, 10);
    let (step, residual) = stats.first_unconverged.expect("the first is recorded");
    assert_eq!(step, 31);
    assert!(residual > 1e-8, "first residual {residual}");
    // The explicit integrators report no solve.
    let mut world = stiff_cloth(IntegratorKind::Rk4, true);
    let report = world.step(1e-5).expect("stable");
    assert_eq!((report.iterations, report.residual), (None, None));
}

/// One particle of 1 kg, `height` m above a projection floor.
fn point_over_floor(kind: IntegratorKind, height: Real, restitution: Real) -> World {
    let mut world = World::new(kind);
    world
        .add_body(
            "point",
            BodyData::from_positions(vec![Vec3::new(0.0, height, 0.0)]),
        )
        .expect("valid point");
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let response = ContactResponse::Projection {
        restitution,
        friction: 0.0,
    };
    world
        .colliders
        .push(Collider::new(floor, response).expect("valid response"));
    world
}

#[test]
fn a_point_leaves_the_floor_at_e_times_the_speed_it_came_with() {
    // The contact's prescribed normal velocity is max(-d/dt, e v): the step
    // that reaches the floor turns the approach speed v into e v exactly
    // (one conjugate-gradient iteration solves the one-particle system).
    for kind in IMPLICIT {
        let mut world = point_over_floor(kind, 1.0, 0.5);
        let mut approach = 0.0;
        let mut bounced = None;
        for _ in 0..120 {
            let before = world.particles.velocity[0].y;
            world.step(FRAME).expect("stable");
            let after = world.particles.velocity[0].y;
            assert!(
                world.particles.position[0].y >= -1e-15,
                "{kind}: inside the floor"
            );
            if after > 0.0 {
                approach = -before;
                bounced = Some(after);
                break;
            }
        }
        let speed = bounced.unwrap_or_else(|| panic!("{kind}: never bounced"));
        assert!(
            (speed / (0.5 * approach) - 1.0).abs() <= 1e-12,
            "{kind}: left at {speed} m/s after coming at {approach} m/s"
        );
    }
}

#[test]
fn a_stiff_lattice_lands_and_rests_on_a_floor_at_the_frame_step() {
    // A 3 × 3 × 3 lattice (26-neighbour springs of 2·10⁴ N/m, 30 g
    // particles), dropped 0.2 m onto a floor without restitution. Moving
    // penetrating particles out after the step would squeeze the stiff
    // springs and throw the lattice up; inside the solve, the contacts stop
    // it: it never goes higher than it started, no particle is inside the
    // floor after a step (beyond round-off), the lattice keeps its shape
    // (every spring within 1 % of its rest length once it rests) and it
    // comes to rest.
    for kind in IMPLICIT {
        let lattice = build::lattice(3, 3, 3, 0.25)
            .expect("valid lattice")
            .with_mass(0.03)
            .with_stiffness(2e4)
            .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.2, 0.0));
        let mut world = World::new(kind);
        world.add_body("jelly", lattice).expect("valid body");
        let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
        let response = ContactResponse::Projection {
            restitution: 0.0,
            friction: 0.5,
        };
        world
            .colliders
            .push(Collider::new(floor, response).expect("valid response"));
        let start = world.centroid(0).expect("a body").y;
        // 4 s: implicit Euler stops within a step of landing; the projective
        // solver, unconverged at 10 iterations, jiggles for about 3 s.
        for step in 1..=240 {
            world.step(FRAME).expect("stable");
            let lowest = world
                .particles
                .position
                .iter()
                .map(|x| x.y)
                .fold(Real::INFINITY, Real::min);
            assert!(
                lowest >= -1e-12,
                "{kind}, step {step}: {lowest} m inside the floor"
            );
            let height = world.centroid(0).expect("a body").y;
            assert!(
                height <= start + 1e-12,
                "{kind}, step {step}: rose to {height} m"
            );
        }
        for s in 0..world.springs.len() {
            let (i, j) = (
                world.springs.first()[s] as usize,
                world.springs.second()[s] as usize,
            );
            let length = world.particles.position[i].distance(world.particles.position[j]);
            let strain = length / world.springs.rest_length[s] - 1.0;
            assert!(strain.abs() < 0.01, "{kind}: spring {s} strained {strain}");
        }
        assert!(world.energies().kinetic < 1e-6, "{kind}: still moving");
    }
}

#[test]
fn a_contact_that_would_pull_lets_go() {
    // A particle of 1 kg rests on the floor under a spring to a pinned point
    // 1 m above, stretched by 0.5 m at 100 N/m: it pulls with 50 N against
    // 9.81 N of weight. Held at zero normal velocity, the contact would
    // need to pull it down: it is released and the particle rises.
    for kind in IMPLICIT {
        let mut body = BodyData::from_positions(vec![Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO])
            .with_pinned(vec![0]);
        body.springs.push(SpringData {
            rest_length: Some(0.5),
            stiffness: 100.0,
            ..SpringData::between(0, 1)
        });
        let mut world = World::new(kind);
        world.add_body("lifted", body).expect("valid body");
        let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
        let response = ContactResponse::Projection {
            restitution: 0.0,
            friction: 0.0,
        };
        world
            .colliders
            .push(Collider::new(floor, response).expect("valid response"));
        world.step(FRAME).expect("stable");
        assert!(
            world.particles.velocity[1].y > 0.0,
            "{kind}: held on the floor"
        );
        // Free, it oscillates (ω = 10 rad/s) about 1 - 0.5 - g m/k = 0.4019 m
        // with that amplitude: backward Euler shrinks the amplitude by
        // (1 + ω² dt²)^(-1/2) per step, 0.772 over the half period (18.8
        // steps), so it must rise above 0.4019 (1 + 0.772) = 0.712 m less
        // the longer numerical period's small phase lag: we ask 0.65 m.
        let mut highest: Real = 0.0;
        for _ in 0..30 {
            world.step(FRAME).expect("stable");
            highest = highest.max(world.particles.position[1].y);
        }
        assert!(highest > 0.65, "{kind}: rose to {highest} m");
    }
}

#[test]
fn both_preconditioners_reach_the_same_step_and_the_laplacian_takes_fewer_iterations_in_plane() {
    // The preconditioner changes the path of conjugate gradients, not the
    // linear system: at a relative residual of 1e-12 both give the same
    // velocities (the system's condition number, < 5e4, turns the
    // residuals into a relative velocity error below ~1e-7; we claim 1e-6
    // of the largest speed). On the stiff cloth hanging in its plane the
    // springs' Laplacian captures the stiff directions and needs fewer than
    // half the diagonal's iterations (about a third, measured). The cloth is thrown
    // sideways in its plane at 1 m/s, against its two pinned corners: it
    // stretches, and backward Euler damps that stiff motion within a few
    // steps, so the comparison takes three.
    let run = |preconditioner: Preconditioner| {
        let mut world = stiff_cloth(IntegratorKind::ImplicitEuler, false);
        world
            .particles
            .velocity
            .iter_mut()
            .zip(&world.particles.inverse_mass)
            .filter(|(_, &w)| w > 0.0)
            .for_each(|(v, _)| *v = Vec3::X);
        world.settings.solver.tolerance = 1e-12;
        world.settings.solver.preconditioner = preconditioner;
        let mut iterations = 0;
        for _ in 0..3 {
            iterations += world.step(FRAME).expect("stable").iterations.unwrap_or(0);
        }
        (world, iterations)
    };
    let (jacobi, jacobi_iterations) = run(Preconditioner::Jacobi);
    let (laplacian, laplacian_iterations) = run(Preconditioner::Laplacian);
    let velocity = &jacobi.particles.velocity;
    let speed = velocity.iter().map(|v| v.length()).fold(0.0, Real::max);
    let gap = common::wind::largest_distance(velocity, &laplacian.particles.velocity);
    assert!(
        gap <= 1e-6 * speed,
        "velocities {gap} m/s apart (speeds up to {speed})"
    );
    assert!(
        2 * laplacian_iterations < jacobi_iterations,
        "laplacian {laplacian_iterations} iterations, jacobi {jacobi_iterations}"
    );
}
