//! Conservation laws (docs/physics.md §1, §6): springs conserve linear momentum
//! with every integrator; on the undamped oscillator explicit Euler's energy
//! grows by exactly `(1 + h²)` per step while symplectic Euler and Verlet
//! keep it in a band of known width forever.
//!
//! Notation: `ω = √(k/m)`, `h = ω dt`.

mod common;

use std::f64::consts::TAU;

use common::{oscillator, Rng};
use sprung::build::{self, ClothSprings};
use sprung::{BodyData, IntegratorKind, Real, SpringData, Vec3, World};

/// A world with `body` (given random velocities around a common drift),
/// no gravity and no colliders: only springs act.
fn springs_only(kind: IntegratorKind, body: BodyData, seed: u64) -> World {
    let mut rng = Rng::new(seed);
    let drift = Vec3::new(0.3, -0.2, 0.1);
    let mut body = body;
    body.velocity = (0..body.particle_count())
        .map(|_| drift + rng.vector(1.0))
        .collect();
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("body", body).expect("valid body");
    world
}

/// Run `world` for `steps` steps at a quarter of its stable step and check
/// that the total momentum did not change while the velocities did.
fn check_momentum_conserved(mut world: World, steps: usize, what: &str) {
    let kind = world.integrator();
    let before = world.linear_momentum();
    let scale: Real = world
        .particles
        .velocity
        .iter()
        .zip(&world.particles.mass)
        .map(|(v, &m)| m * v.length())
        .sum();
    let initial_velocity = world.particles.velocity.clone();
    // Implicit Euler's linear solve leaves a residual `r`, and since the
    // Jacobian products of internal forces sum to zero over the particles,
    // each step changes the momentum by exactly `-Σ r`: ask the solver for
    // a residual far below the bound below.
    world.settings.solver.tolerance = 1e-12;
    let dt = 0.25 * world.stable_time_step();
    for _ in 0..steps {
        world
            .step(dt)
            .expect("stable at a quarter of the stable step");
    }
    let change = (world.linear_momentum() - before).length() / scale;
    // 1e-10 of Σ m |v|: springs act in equal and opposite pairs and every
    // integrator here is a linear combination of force evaluations, so the
    // momentum is exact up to round-off: ~1e-16 per force addition, and for
    // Verlet, whose velocity is a difference of positions divided by 2 dt,
    // ε |x| / (|v| dt) ≈ 1e-13.
    assert!(
        change <= 1e-10,
        "{what}, {kind}: momentum changed by {change:.3e} of Σ m|v|"
    );
    // The test means something only if the springs did act.
    let stirred = world
        .particles
        .velocity
        .iter()
        .zip(&initial_velocity)
        .map(|(v, v0)| (*v - *v0).length())
        .fold(0.0, Real::max);
    assert!(
        stirred > 0.1,
        "{what}, {kind}: velocities hardly changed ({stirred})"
    );
}

#[test]
fn springs_conserve_momentum_on_a_cloth() {
    for kind in IntegratorKind::ALL {
        let cloth = build::cloth(6, 5, 1.0, 0.8, ClothSprings::default())
            .expect("valid cloth")
            .with_mass(0.1)
            .with_stiffness(100.0)
            .with_damping(0.5);
        check_momentum_conserved(springs_only(kind, cloth, 7), 1000, "cloth");
    }
}

#[test]
fn springs_conserve_momentum_in_a_lattice() {
    for kind in IntegratorKind::ALL {
        let lattice = build::lattice(3, 3, 3, 0.2)
            .expect("valid lattice")
            .with_mass(0.05)
            .with_stiffness(200.0)
            .with_damping(0.2);
        check_momentum_conserved(springs_only(kind, lattice, 11), 1000, "lattice");
    }
}

#[test]
fn one_sided_springs_do_not_conserve_momentum() {
    // docs/physics.md §1: a one-sided spring pulls only its child, so the total
    // momentum changes by the child's impulse: the control for the checks
    // above. Two free particles 1.1 m apart on a spring of rest length 1 m
    // and stiffness k: one step of symplectic Euler from rest changes the
    // momentum by k (1.1 - 1) dt towards the parent with a one-sided spring,
    // and by nothing with a two-sided one.
    let (stiffness, dt) = (100.0, 1e-3);
    for one_sided in [false, true] {
        let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(1.1, 0.0, 0.0)]);
        body.springs.push(SpringData {
            rest_length: Some(1.0),
            stiffness,
            one_sided,
            ..SpringData::between(0, 1)
        });
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        world.add_body("pair", body).expect("valid pair");
        world.step(dt).expect("stable");
        let expected = if one_sided {
            Vec3::new(-stiffness * 0.1 * dt, 0.0, 0.0)
        } else {
            Vec3::ZERO
        };
        // 1e-12 kg·m/s: the stretch 1.1 - 1 is exact to ~1e-16 m.
        let momentum = world.linear_momentum();
        assert!(
            (momentum - expected).length() <= 1e-12,
            "one_sided = {one_sided}: momentum {momentum} after one step, expected {expected}"
        );
    }
}

const MASS: Real = 1.0; // kg
const STIFFNESS: Real = 100.0; // N/m: ω = 10 rad/s
const OMEGA: Real = 10.0;

/// Energy `E_n / E_0` after each step of the undamped oscillator started at
/// `u = 0.1 m`, `v = 0`, stepped with `kind` at phase step `h` for `periods`
/// periods.
fn energy_ratios(kind: IntegratorKind, h: Real, periods: Real) -> Vec<Real> {
    let mut world = oscillator(kind, MASS, STIFFNESS, 0.0, 0.1, 0.0);
    let initial = world.energies().total();
    let dt = h / OMEGA;
    let steps = (periods * TAU / h).round() as usize;
    (0..steps)
        .map(|_| {
            world.step(dt).expect("stable");
            world.energies().total() / initial
        })
        .collect()
}

#[test]
fn explicit_euler_gains_energy_by_exactly_one_plus_h_squared_per_step() {
    // Euler on u'' = -ω² u: (u, v/ω) ← (u + h v/ω, v/ω - h u), which
    // multiplies u² + (v/ω)², i.e. the energy, by exactly 1 + h² per step.
    let h = 0.05;
    let ratios = energy_ratios(IntegratorKind::Euler, h, 10.0);
    let mut previous = 1.0;
    for (n, &ratio) in ratios.iter().enumerate() {
        let expected = (1.0 + h * h).powi(n as i32 + 1);
        // 1e-9: the formula is exact; round-off grows to ~1e-13 over the
        // 1257 steps.
        assert!(
            (ratio / expected - 1.0).abs() <= 1e-9,
            "step {}: E/E0 = {ratio:.12}, expected (1 + h²)^n = {expected:.12}",
            n + 1
        );
        assert!(ratio > previous, "step {}: energy did not grow", n + 1);
        previous = ratio;
    }
    // Over 10 periods that is e^(2π · 10 · h) ≈ 23 times the energy: clearly
    // more than the 10 %.
    assert!(previous > 1.1);
}

#[test]
fn verlet_energy_stays_in_its_band_over_1000_periods() {
    // Position Verlet from (u0, 0) follows u_n = u0 cos(n θ) exactly, with
    // cos θ = 1 - h²/2 (its Taylor start is exact for v0 = 0). The engine's
    // velocity after step n+1 is the central difference at n carried one
    // step, (u_{n+1} - u_{n-1}) / (2 dt) + a_n dt; expanding, the energy is
    //   E_{n+1} / E_0 = 1 + ¾ h² sin²(n θ) + O(h⁴):
    // a band [0, ¾ h²] above the initial energy, with no drift.
    let h: Real = 0.1;
    let ratios = energy_ratios(IntegratorKind::Verlet, h, 1000.0);
    let band = 0.75 * h * h;
    let (low, high) = ratios.iter().fold((Real::MAX, Real::MIN), |(lo, hi), &r| {
        (lo.min(r - 1.0), hi.max(r - 1.0))
    });
    // The O(h⁴) terms are at most ~h⁴/8 (i.e. band · h²/6) in size: the band
    // edges get a margin of band · h².
    assert!(
        low >= -band * h * h,
        "energy fell to {low:.3e} below E0, band [0, {band:.3e}]"
    );
    assert!(
        high <= band * (1.0 + h * h),
        "energy rose to {high:.3e} above E0, band [0, {band:.3e}]"
    );
    // And the band is the one predicted, not a narrower one: over 1000
    // periods n θ sweeps every phase, so sin² comes within (h/2)² of 1.
    assert!(
        high >= band * (1.0 - h * h),
        "energy only rose to {high:.3e} above E0, band [0, {band:.3e}]"
    );
}

#[test]
fn symplectic_euler_energy_stays_in_its_band_over_1000_periods() {
    // Symplectic Euler on the oscillator conserves exactly the modified
    // energy Q = u² + (v/ω)² - h u (v/ω). Since |u v/ω| ≤ (u² + (v/ω)²)/2,
    // the true energy E satisfies E (1 - h/2) ≤ Q ≤ E (1 + h/2); from
    // (u0, 0), Q = E_0, so E / E_0 ∈ [1 / (1 + h/2), 1 / (1 - h/2)].
    let h: Real = 0.1;
    let ratios = energy_ratios(IntegratorKind::SymplecticEuler, h, 1000.0);
    let (low, high) = ratios.iter().fold((Real::MAX, Real::MIN), |(lo, hi), &r| {
        (lo.min(r), hi.max(r))
    });
    // The bounds are exact; 1e-12 covers round-off.
    let (floor, ceiling) = (1.0 / (1.0 + h / 2.0), 1.0 / (1.0 - h / 2.0));
    assert!(low >= floor - 1e-12, "E/E0 fell to {low}, bound {floor}");
    assert!(
        high <= ceiling + 1e-12,
        "E/E0 rose to {high}, bound {ceiling}"
    );
    // The bounds are reached where |u| = |v/ω|, which the orbit passes
    // every quarter period, to within a step: the band is not narrower than
    // 90 % of the predicted one.
    assert!(
        high - 1.0 >= 0.9 * (ceiling - 1.0),
        "E/E0 only rose to {high}"
    );
    assert!(1.0 - low >= 0.9 * (1.0 - floor), "E/E0 only fell to {low}");
}
