//! The springs' force (docs/physics.md §1) as the engine computes it, in
//! runs of springs read as slices and in springs gathered one by one,
//! against each spring's pull summed directly.

mod common;

use common::Rng;
use sprung::{BodyData, IntegratorKind, Real, SpringData, Vec3, World};

/// Every spring's pull `s t` with `s = k (d - L0) + c Δv·t`, added to its
/// particles (a one-sided spring's to its second only), spring by spring.
fn summed_directly(world: &World) -> Vec<Vec3> {
    let (x, v) = (&world.particles.position, &world.particles.velocity);
    let springs = &world.springs;
    let mut force = vec![Vec3::ZERO; x.len()];
    for s in 0..springs.len() {
        let [i, j] = springs.endpoints(s).map(|p| p as usize);
        let delta = x[i] - x[j];
        let axis = delta / delta.length();
        let tension = springs.stiffness[s] * (delta.length() - springs.rest_length[s])
            + springs.damping[s] * (v[i] - v[j]).dot(axis);
        if !springs.one_sided[s] {
            force[i] -= tension * axis;
        }
        force[j] += tension * axis;
    }
    force
}

/// The largest pull of any spring on each particle (N): the scale of the
/// round-off in its summed force.
fn largest_pulls(world: &World) -> Vec<Real> {
    let (x, v, springs) = (
        &world.particles.position,
        &world.particles.velocity,
        &world.springs,
    );
    let mut largest = vec![0.0; x.len()];
    for s in 0..springs.len() {
        let [i, j] = springs.endpoints(s).map(|q| q as usize);
        let length = (x[i] - x[j]).length();
        let pull = springs.stiffness[s] * (length - springs.rest_length[s]).abs()
            + springs.damping[s] * (v[i] - v[j]).length();
        for p in [i, j] {
            largest[p] = Real::max(largest[p], pull);
        }
    }
    largest
}

/// Check the world's spring force against [`summed_directly`].
fn assert_force_is_each_spring_summed(world: &mut World) {
    world.evaluate_forces();
    let expected = summed_directly(world);
    let largest = largest_pulls(world);
    for (p, (f, e)) in world.particles.force.iter().zip(&expected).enumerate() {
        // The same pulls added in another order, each computed as `(s/d) Δx`
        // rather than `s (Δx/d)`: a few roundings of the largest pull at
        // the particle, summed over its dozen springs (1e-13 relative).
        let tolerance = 1e-13 * largest[p];
        assert!(
            (*f - *e).abs().max_element() <= tolerance,
            "particle {p}: {f} against {e}"
        );
    }
}

/// A spring between `first` and `second` with random rest length (m),
/// stiffness (N/m) and damping (N·s/m).
fn random_spring(first: usize, second: usize, one_sided: bool, rng: &mut Rng) -> SpringData {
    SpringData {
        first,
        second,
        rest_length: Some(0.5 + 0.4 * rng.symmetric()),
        stiffness: 100.0 * (1.5 + rng.symmetric()),
        damping: 0.5 * (1.5 + rng.symmetric()),
        one_sided,
    }
}

#[test]
fn springs_in_runs_and_scattered_pull_as_each_spring_summed() {
    // 60 particles at random places and velocities; springs [p, p + 1] and
    // [p, p + 7] along them (runs, the first one-sided), and 40 springs
    // between random particles (scattered), with random stiffness, damping
    // and rest lengths.
    let mut rng = Rng::new(9);
    let n = 60;
    let position: Vec<Vec3> = (0..n).map(|_| rng.vector(1.0)).collect();
    let mut body = BodyData::from_positions(position);
    body.velocity = (0..n).map(|_| rng.vector(2.0)).collect();
    let spring = random_spring;
    for p in 0..n - 1 {
        body.springs.push(spring(p, p + 1, true, &mut rng));
    }
    for p in 0..n - 7 {
        body.springs.push(spring(p, p + 7, false, &mut rng));
    }
    let mut joined = std::collections::HashSet::new();
    while joined.len() < 40 {
        let a = ((rng.symmetric() + 1.0) * 0.5 * n as Real) as usize % n;
        let b = ((rng.symmetric() + 1.0) * 0.5 * n as Real) as usize % n;
        let gap = a.abs_diff(b);
        if gap > 1 && gap != 7 && joined.insert((a.min(b), a.max(b))) {
            body.springs.push(spring(a, b, false, &mut rng));
        }
    }
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("random", body).expect("valid body");
    // The runs are stored first, in order: the force reads them as slices.
    let stored = |s: usize| world.springs.endpoints(s);
    assert!((0..n - 1).all(|p| stored(p) == [p as u32, p as u32 + 1]));
    assert!((0..n - 7).all(|p| stored(n - 1 + p) == [p as u32, p as u32 + 7]));
    assert_force_is_each_spring_summed(&mut world);
}

#[test]
fn a_large_grid_of_runs_in_blocks_pulls_as_each_spring_summed() {
    // 130 × 130 particles (more than the schedule's blocks of 4096, so it
    // cuts them by neighbourhood and permutes the springs into blocks):
    // a cloth's families of springs, each a run longer than a batch, one
    // of them one-sided and one stored backwards ([p + 131, p]), and short
    // random springs between them, at random places and velocities.
    let side = 130;
    let mut rng = Rng::new(17);
    let position: Vec<Vec3> = (0..side * side)
        .map(|p| Vec3::new((p % side) as Real, (p / side) as Real, 0.0) + rng.vector(0.2))
        .collect();
    let mut body = BodyData::from_positions(position);
    body.velocity = (0..side * side).map(|_| rng.vector(1.0)).collect();
    for row in 0..side {
        for column in 0..side {
            let p = row * side + column;
            if column + 1 < side {
                body.springs.push(random_spring(p, p + 1, false, &mut rng));
            }
            if column + 2 < side {
                body.springs.push(random_spring(p, p + 2, true, &mut rng));
            }
            if row + 1 < side {
                body.springs
                    .push(random_spring(p, p + side, false, &mut rng));
                if column + 1 < side {
                    body.springs
                        .push(random_spring(p + side + 1, p, false, &mut rng));
                }
            }
        }
    }
    let mut joined = std::collections::HashSet::new();
    while joined.len() < 500 {
        let a = ((rng.symmetric() + 1.0) * 0.5 * (side * side) as Real) as usize % (side * side);
        let b = (a + 3 * side + ((rng.symmetric() + 1.0) * 100.0) as usize) % (side * side);
        if a.abs_diff(b) < 4 * side && joined.insert((a.min(b), a.max(b))) {
            body.springs.push(random_spring(a, b, false, &mut rng));
        }
    }
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("grid", body).expect("valid body");
    assert_force_is_each_spring_summed(&mut world);
}

#[test]
fn a_cloth_of_a_few_thousand_particles_steps_alike_on_one_two_and_three_threads() {
    // 48² particles, over 8192 springs: under a chunk of particles, so its
    // springs are cut into the schedule's finer blocks, two phases of
    // blocks run side by side, and each integrator's per-particle loops
    // are cut into pieces of two such blocks (`parallel::particle_span`).
    // Each particle still takes its springs in the same order and each
    // update writes its own particle: the same bits on any number of
    // threads, under every explicit integrator.
    let run = |kind, threads| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("a thread pool");
        let cloth = sprung::build::cloth(48, 48, 1.0, 1.0, Default::default())
            .expect("valid cloth")
            .with_mass(1e-3)
            .with_stiffness(100.0)
            .with_pinned(vec![0, 47]);
        let mut world = World::new(kind);
        world.add_body("cloth", cloth).expect("valid body");
        assert!(world.springs.len() >= 8192, "enough springs to cut finer");
        let span = sprung::parallel::particle_span(world.springs.len(), world.particles.len());
        assert_eq!(span, 2 * 48 * 48 / 8, "loops in pieces of two fine blocks");
        world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
        let start = world.particles.position.clone();
        let dt = 0.5 * world.stable_time_step();
        pool.install(|| {
            for _ in 0..50 {
                world.step(dt).expect("stable");
            }
        });
        assert_ne!(world.particles.position, start, "the cloth moved");
        (world.particles.position, world.particles.velocity)
    };
    for kind in [
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Euler,
        IntegratorKind::Midpoint,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
    ] {
        let one = run(kind, 1);
        assert!(one == run(kind, 2), "{kind:?}: 2 threads");
        assert!(one == run(kind, 3), "{kind:?}: 3 threads");
    }
}
