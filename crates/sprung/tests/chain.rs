//! Chains of masses and springs (docs/physics.md §7): the static stretch of a
//! hanging chain, with two-sided and one-sided springs, and the normal-mode
//! frequencies of a chain pinned at both ends.

mod common;

use std::f64::consts::{PI, TAU};

use common::{fixed_fixed_chain, mean_period, rope};
use sprung::{IntegratorKind, Real, Vec3, World};

const G: Real = 9.81; // m/s²
const FREE: usize = 10; // free masses below the pinned top
const MASS: Real = 0.1; // kg
const STIFFNESS: Real = 1000.0; // N/m: √(k/m) = 100 rad/s
const SPACING: Real = 0.1; // m

/// Hang a rope of [`FREE`] masses from its pinned top and let air drag
/// settle it; returns the stretch `d - L0` (m) of each spring, top first.
fn settled_stretches(one_sided: bool) -> Vec<Real> {
    let body = rope(FREE, MASS, STIFFNESS, SPACING).with_one_sided(one_sided);
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::new(0.0, -G, 0.0));
    // Air drag damps every mode without moving the equilibrium (v = 0).
    // Two-sided springs: the slowest mode of a fixed-free chain of N masses
    // has ω₁ = 2 √(k/m) sin(π / (2 (2N + 1))) ≈ 15 rad/s; drag c = 2 m ω₁
    // damps it critically and every other mode at the rate ω₁.
    // One-sided springs: the chain is a cascade of oscillators that all have
    // ω = √(k/m) = 100 rad/s, each driven at resonance by its parent, so a
    // lightly damped cascade amplifies the start-up transient by about
    // (ω/γ)ʲ at spring j. With γ = 15/s that is far more than the 0.1 m
    // spacing: the particles pass through one another and settle in the
    // other equilibrium, child above parent on a compressed spring. Drag
    // c = 2 m √(k/m) damps each stage critically instead.
    let omega = if one_sided {
        (STIFFNESS / MASS).sqrt()
    } else {
        2.0 * (STIFFNESS / MASS).sqrt() * (PI / (2.0 * (2 * FREE + 1) as Real)).sin()
    };
    world.set_air_drag(2.0 * MASS * omega);
    world.add_body("rope", body).expect("valid rope");
    // dt = 1 ms is a tenth of the stable step 1/√(k/m) = 10 ms. After 4 s the
    // initial offset (the total sag, ~0.05 m) has decayed by at least
    // (1 + ω t) e^{-ω t} ≈ 1e-24 (with one-sided springs, the cascade's
    // (ω t)^N / N! e^{-ω t} at ω t = 400 is smaller still): the state is the
    // static equilibrium to round-off (~1e-16 m, i.e. ~1e-13 of the smallest
    // stretch, 1 mm).
    for _ in 0..4000 {
        world.step(1e-3).expect("stable");
    }
    let x = &world.particles.position;
    (0..world.springs.len())
        .map(|s| {
            let (i, j) = (
                world.springs.first()[s] as usize,
                world.springs.second()[s] as usize,
            );
            x[i].distance(x[j]) - world.springs.rest_length[s]
        })
        .collect()
}

#[test]
fn hanging_chain_spring_s_carries_the_weight_below_it() {
    let stretches = settled_stretches(false);
    assert_eq!(stretches.len(), FREE);
    for (index, &stretch) in stretches.iter().enumerate() {
        let s = index + 1; // counted from the top, 1-based
        let expected = (FREE - s + 1) as Real * MASS * G / STIFFNESS;
        // 1e-6 relative: the residual motion and round-off are below 1e-12
        // relative (see `settled_stretches`).
        assert!(
            (stretch / expected - 1.0).abs() <= 1e-6,
            "spring {s}: stretch {stretch:.9e} m, expected (N - s + 1) m g / k = {expected:.9e} m"
        );
    }
}

#[test]
fn hanging_chain_of_one_sided_springs_stretches_evenly() {
    // A one-sided spring pulls only its child (the particle below), so each
    // spring holds exactly one mass: every stretch is m g / k.
    let expected = MASS * G / STIFFNESS;
    for (index, stretch) in settled_stretches(true).into_iter().enumerate() {
        // 1e-6 relative, as for the two-sided chain.
        assert!(
            (stretch / expected - 1.0).abs() <= 1e-6,
            "spring {}: stretch {stretch:.9e} m, expected m g / k = {expected:.9e} m",
            index + 1
        );
    }
}

/// Angular frequency (rad/s) of mode `n` measured on a fixed-fixed chain of
/// `free` masses excited in exactly that mode.
fn measured_mode_frequency(free: usize, n: usize, mass: Real, stiffness: Real) -> Real {
    let spacing = 0.1;
    let shape: Vec<Real> = (1..=free)
        .map(|j| (n as Real * j as Real * PI / (free + 1) as Real).sin())
        .collect();
    let mut world = fixed_fixed_chain(IntegratorKind::Rk4, free, mass, stiffness, spacing);
    // Longitudinal displacements (along the chain, 1 % of the spacing: no
    // particles cross, so the forces are exactly linear) in the mode shape.
    for (j, &a) in shape.iter().enumerate() {
        world.particles.position[j + 1].x += 1e-3 * a;
    }
    let omega =
        2.0 * (stiffness / mass).sqrt() * (n as Real * PI / (2.0 * (free + 1) as Real)).sin();
    // RK4 with h = ω_n dt = 0.05: period error h⁴/120 ≈ 5e-8.
    let dt = 0.05 / omega;
    // The projection of the displacements on the mode shape, sampled every
    // step for 10 periods.
    let projection = |world: &World| -> Real {
        shape
            .iter()
            .enumerate()
            .map(|(j, &a)| a * (world.particles.position[j + 1].x - spacing * (j + 1) as Real))
            .sum()
    };
    let steps = (10.5 * TAU / omega / dt).ceil() as usize;
    let mut samples = vec![projection(&world)];
    for _ in 0..steps {
        world.step(dt).expect("stable");
        samples.push(projection(&world));
    }
    TAU / mean_period(&samples, dt)
}

#[test]
fn fixed_fixed_chain_modes_have_the_exact_frequencies() {
    let (free, mass, stiffness): (usize, Real, Real) = (8, 1.0, 100.0);
    for n in [1, 3] {
        let expected =
            2.0 * (stiffness / mass).sqrt() * (n as Real * PI / (2.0 * (free + 1) as Real)).sin();
        let measured = measured_mode_frequency(free, n, mass, stiffness);
        // The issue asks for 0.5 %. The modes of the discrete chain are exact
        // and stay decoupled (RK4's update is a polynomial in the stiffness
        // matrix, so it shares its eigenvectors); the only errors are RK4's
        // h⁴/120 ≈ 5e-8 and the crossing interpolation (< 1e-8). We claim
        // 1e-5: a wrong formula (e.g. N instead of N + 1) is off by ~10 %.
        assert!(
            (measured / expected - 1.0).abs() <= 1e-5,
            "mode {n}: ω = {measured:.8} rad/s, expected 2√(k/m) sin(nπ/(2(N+1))) = {expected:.8}"
        );
    }
}
