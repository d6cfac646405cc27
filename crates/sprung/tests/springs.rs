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

/// The largest pull of any spring on particle `p` (N): the scale of the
/// round-off in its summed force.
fn largest_pull(world: &World, p: usize) -> Real {
    let (x, springs) = (&world.particles.position, &world.springs);
    (0..springs.len())
        .filter(|&s| springs.endpoints(s).contains(&(p as u32)))
        .map(|s| {
            let [i, j] = springs.endpoints(s).map(|q| q as usize);
            let length = (x[i] - x[j]).length();
            springs.stiffness[s] * (length - springs.rest_length[s]).abs()
                + springs.damping[s]
                    * (world.particles.velocity[i] - world.particles.velocity[j]).length()
        })
        .fold(0.0, Real::max)
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
    let spring = |first: usize, second: usize, one_sided: bool, rng: &mut Rng| SpringData {
        first,
        second,
        rest_length: Some(0.5 + 0.4 * rng.symmetric()),
        stiffness: 100.0 * (1.5 + rng.symmetric()),
        damping: 0.5 * (1.5 + rng.symmetric()),
        one_sided,
    };
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
    world.evaluate_forces();
    let expected = summed_directly(&world);
    for (p, (f, e)) in world.particles.force.iter().zip(&expected).enumerate() {
        // The same pulls added in another order, each computed as `(s/d) Δx`
        // rather than `s (Δx/d)`: a few roundings of the largest pull at
        // the particle, summed over its dozen springs (1e-13 relative).
        let tolerance = 1e-13 * largest_pull(&world, p);
        assert!(
            (*f - *e).abs().max_element() <= tolerance,
            "particle {p}: {f} against {e}"
        );
    }
}
