//! Switching the integrator of a running world (`World::set_integrator`):
//! the state carries over with no jump in position or energy, and the
//! oscillator keeps the phase of the exact solution (docs/physics.md §6, §7).
//!
//! Notation: `ω = √(k/m)`, `h = ω dt`, `z = (u, v/ω)` the phase-space point.

mod common;

use common::{displacement, exact_oscillator, oscillator, phase_space_distance, velocity};
use sprung::{IntegratorKind, Real, World};

const MASS: Real = 1.0; // kg
const STIFFNESS: Real = 100.0; // N/m
const OMEGA: Real = 10.0; // rad/s
const H: Real = 0.01; // ω dt
const DT: Real = H / OMEGA; // s
const SEGMENT: usize = 1000; // steps per integrator: ω Δt = 10 rad

fn state(world: &World) -> (Real, Real) {
    (displacement(world), velocity(world))
}

fn norm((u, v): (Real, Real)) -> Real {
    u.hypot(v / OMEGA)
}

/// Switch `world` to `kind` and take one step; check that the position
/// continues as a Taylor step would and that the energy does not jump by
/// more than `energy_tolerance` (relative).
fn switch_and_check(world: &mut World, kind: IntegratorKind, energy_tolerance: Real) {
    let (u, v) = state(world);
    let energy = world.energies().total();
    world.set_integrator(kind);
    assert_eq!(world.integrator(), kind);
    world.step(DT).expect("stable");
    // The exact solution lies within |u'''| dt³ / 6 ≤ h³ |z| / 6 of the
    // Taylor step u + v dt + ½ a dt²; Verlet's first step is that Taylor
    // step, RK4's is within ~h⁵ |z| of the exact one, so h³ |z| bounds both.
    // A method that lost the state (zero velocity, a stale previous
    // position) is off by ~v dt = h |z|, 10⁴ times more.
    let taylor = u + v * DT - 0.5 * OMEGA * OMEGA * u * DT * DT;
    let jump = (displacement(world) - taylor).abs();
    assert!(
        jump <= H.powi(3) * norm((u, v)),
        "{kind}: first step lands {jump:.3e} m from the Taylor step"
    );
    let change = (world.energies().total() / energy - 1.0).abs();
    assert!(
        change <= energy_tolerance,
        "{kind}: energy jumped by {change:.3e} (relative) on the first step"
    );
}

/// Run `steps` steps and return the phase-space distance (m) from the exact
/// solution started at the state and time the run started from.
fn run_against_exact(world: &mut World, steps: usize) -> Real {
    let (start, t0) = (state(world), world.time());
    for _ in 0..steps {
        world.step(DT).expect("stable");
    }
    let exact = exact_oscillator(start.0, start.1, OMEGA, world.time() - t0);
    phase_space_distance(state(world), exact, OMEGA)
}

#[test]
fn switching_symplectic_euler_to_verlet_to_rk4_continues_the_state() {
    let u0 = 0.1;
    let mut world = oscillator(
        IntegratorKind::SymplecticEuler,
        MASS,
        STIFFNESS,
        0.0,
        u0,
        0.0,
    );
    for _ in 0..SEGMENT {
        world.step(DT).expect("stable");
    }

    // Into Verlet: its first step is a Taylor step (its documented
    // bootstrap): with q = u, p = v/ω, it goes to q + h p - ½ h² q and
    // p - h q, so E changes by exactly (h² p² - h³ p q + ¼ h⁴ q²) / (p² + q²)
    // relative, at most h² (1 + h).
    switch_and_check(&mut world, IntegratorKind::Verlet, H * H * (1.0 + H));
    let start = norm(state(&world));
    let error = run_against_exact(&mut world, SEGMENT - 1);
    // Verlet's phase drifts by ω Δt h²/24 and its stored velocity (central
    // difference carried one step) is off by at most ⅜ h²: together at most
    // (ω Δt / 24 + ½) h² |z|.
    let bound = (OMEGA * SEGMENT as Real * DT / 24.0 + 0.5) * H * H * start;
    assert!(
        error <= bound,
        "Verlet segment: error {error:.3e} m, bound {bound:.3e} m"
    );

    // Into RK4: its energy error per step is h⁶/72 ≈ 1e-14; 1e-12 covers the
    // round-off of the energies themselves.
    switch_and_check(&mut world, IntegratorKind::Rk4, 1e-12);
    let start = norm(state(&world));
    let error = run_against_exact(&mut world, SEGMENT - 1);
    // RK4: ω Δt h⁴ / 120 ≈ 8e-10 of |z|; we claim 1e-8 (round-off ~1e-14).
    assert!(
        error <= 1e-8 * start,
        "RK4 segment: error {error:.3e} m, of |z| = {start:.3e} m"
    );

    // Back into a fresh Verlet: nothing stale from the first one.
    switch_and_check(&mut world, IntegratorKind::Verlet, H * H * (1.0 + H));
    let start = norm(state(&world));
    let error = run_against_exact(&mut world, SEGMENT - 1);
    let bound = (OMEGA * SEGMENT as Real * DT / 24.0 + 0.5) * H * H * start;
    assert!(
        error <= bound,
        "second Verlet segment: error {error:.3e} m, bound {bound:.3e} m"
    );

    // Overall, against the exact solution from the very start: symplectic
    // Euler's orbit is tilted by up to (h/2) |z| (the first-order part of
    // its error, frozen into the state handed over), plus second-order
    // drifts ~1e-4 |z|: we claim h |z|.
    assert_eq!(world.steps(), 4 * SEGMENT as u64);
    let exact = exact_oscillator(u0, 0.0, OMEGA, world.time());
    let error = phase_space_distance(state(&world), exact, OMEGA);
    assert!(
        error <= H * u0,
        "after all switches: error {error:.3e} m, bound h u0 = {:.3e} m",
        H * u0
    );
}

#[test]
fn verlet_keeps_the_phase_across_a_change_of_time_step() {
    // Verlet re-derives its previous positions when dt changes (its doc);
    // otherwise x⁻ from the old dt would act as a velocity jump of
    // ~v (dt_old - dt_new) / dt_new, an O(1) error.
    let u0 = 0.1;
    let mut world = oscillator(IntegratorKind::Verlet, MASS, STIFFNESS, 0.0, u0, 0.0);
    for _ in 0..SEGMENT {
        world.step(DT).expect("stable");
    }
    for _ in 0..2 * SEGMENT {
        world.step(DT / 2.0).expect("stable");
    }
    let exact = exact_oscillator(u0, 0.0, OMEGA, world.time());
    let error = phase_space_distance(state(&world), exact, OMEGA);
    // Phase drift ω t h²/24 over both segments (the second at h/2), plus the
    // velocity offsets of at most ⅜ h² each: below (20/24 + 1) h² u0.
    let bound = (2.0 * OMEGA * SEGMENT as Real * DT / 24.0 + 1.0) * H * H * u0;
    assert!(error <= bound, "error {error:.3e} m, bound {bound:.3e} m");
}
