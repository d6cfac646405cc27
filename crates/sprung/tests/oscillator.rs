//! The single oscillator (docs/physics.md §7): one pinned and one free particle,
//! no gravity, `T = 2π √(m/k)`; with damping the amplitude decays as
//! `exp(-c t / 2m)`. Claims: each integrator's period error is the one its
//! amplification factor predicts, each converges at its stated order, and
//! the damped decay rate is `c / 2m`.
//!
//! Notation: `ω = √(k/m)`, `h = ω dt` (the step in radians of phase).

mod common;

use std::f64::consts::TAU;

use common::{
    displacement, exact_oscillator, mean_period, oscillator, peaks, phase_space_distance, velocity,
};
use sprung::{IntegratorKind, Real};

const MASS: Real = 1.0; // kg
const STIFFNESS: Real = 100.0; // N/m, so ω = 10 rad/s and T = 0.628 s
const OMEGA: Real = 10.0; // √(k/m), rad/s

/// Relative period error `T_measured / T - 1` predicted for each method at
/// phase step `h`, from the argument of its amplification factor on the
/// harmonic oscillator (the numerical angular frequency is `arg R / dt`):
///
/// - explicit Euler: `R = 1 - ih`, `arg R = atan h ≈ h - h³/3`: the period
///   is *longer* by `h²/3`;
/// - symplectic Euler and position Verlet: both produce positions obeying
///   `u⁺ = (2 - h²) u - u⁻`, so `cos θ = 1 - h²/2`, `θ ≈ h + h³/24`: the
///   period is *shorter* by `h²/24`;
/// - midpoint: `R = 1 - ih - h²/2`, `arg R ≈ h + h³/6`: shorter by `h²/6`;
/// - RK4: `R = e^{-ih} + O(h⁵)` with `arg R ≈ h - h⁵/120`: longer by `h⁴/120`;
/// - implicit Euler: `R = 1 / (1 + ih)`, `arg R = atan h`: longer by `h²/3`,
///   like explicit Euler (the two are each other's time reverse). The
///   projective solver is the same method, and on a spring moving along its
///   axis its first iteration is already exact (the spring force plus
///   `k x` is the constant `k L0`).
///
/// These are within the bound each method's order predicts (`C hᵖ` with
/// `p` = 1, 1, 2, 4, 2); for the two Euler methods the phase error is even
/// one order better than the global error, whose first-order part is the
/// amplitude growth (Euler) or a bounded tilt of the orbit (symplectic).
/// The adaptive `rk45` has no step of its own: its error is set by its
/// tolerance (see `tests/adaptive.rs`), so it has no entry here.
fn predicted_period_error(kind: IntegratorKind, h: Real) -> Option<Real> {
    Some(match kind {
        IntegratorKind::Euler | IntegratorKind::ImplicitEuler | IntegratorKind::Projective => {
            h * h / 3.0
        }
        IntegratorKind::SymplecticEuler | IntegratorKind::Verlet => -h * h / 24.0,
        IntegratorKind::Midpoint => -h * h / 6.0,
        IntegratorKind::Rk4 => h.powi(4) / 120.0,
        IntegratorKind::Rk45 => return None,
    })
}

#[test]
fn period_error_of_each_integrator_is_its_leading_term() {
    let h = 0.1;
    let dt = h / OMEGA;
    let period = TAU / OMEGA;
    // 20 periods: explicit Euler's amplitude grows by (1 + h²)^(n/2) ≈ e^6.4
    // ≈ 600 over them, so the 1 mm start stays below the 1 m rest length
    // (the spring stays linear).
    let steps = (20.5 * period / dt).ceil() as usize;
    for kind in IntegratorKind::ALL {
        let Some(predicted) = predicted_period_error(kind, h) else {
            continue;
        };
        let mut world = oscillator(kind, MASS, STIFFNESS, 0.0, 1e-3, 0.0);
        let mut samples = vec![displacement(&world)];
        for _ in 0..steps {
            world.step(dt).expect("stable at h = 0.1");
            samples.push(displacement(&world));
        }
        let measured = mean_period(&samples, dt) / period - 1.0;
        // Tolerance 2 % of the predicted error: the leading term differs from
        // the exact `h / arg R - 1` by a relative O(h²) (at most 0.5 %, for
        // midpoint, at h = 0.1), and locating the crossings on a cubic adds
        // at most ~0.04 h⁵ rad per crossing, spread over 20 periods: < 0.7 %
        // of RK4's tiny h⁴/120 and negligible for the others.
        assert!(
            (measured - predicted).abs() <= 0.02 * predicted.abs(),
            "{kind}: period error {measured:.6e}, predicted {predicted:.6e}"
        );
    }
}

/// Phase-space error `|(u, v/ω) - exact| / u0` of `kind` after `steps` steps
/// of `duration / steps`, from `u = u0, v = 0`.
fn error_at(kind: IntegratorKind, duration: Real, steps: usize) -> Real {
    let u0 = 0.1;
    let dt = duration / steps as Real;
    let mut world = oscillator(kind, MASS, STIFFNESS, 0.0, u0, 0.0);
    for _ in 0..steps {
        world.step(dt).expect("stable");
    }
    let exact = exact_oscillator(u0, 0.0, OMEGA, world.time());
    phase_space_distance((displacement(&world), velocity(&world)), exact, OMEGA) / u0
}

#[test]
fn each_integrator_converges_at_its_order() {
    // The error is measured at t = 1.25 T, where sin(ω t) = 1: symplectic
    // Euler's first-order error is a phase lead `(h/2) u0 sin(ω t)` that
    // vanishes at whole periods.
    let duration = 1.25 * TAU / OMEGA;
    // Per method, a step `h` small enough that the leading error term
    // dominates: the next term, relative to the leading one, is about
    // `ω t h / 4` for Euler (its amplitude error is e^(ω t h / 2) - 1),
    // `ω t h / 12` for symplectic Euler, and O(h²) for the others: every
    // one moves the measured order by < 0.05. RK4 at h = 0.1 and 0.05 has
    // errors ~6e-6 and ~4e-7, far above round-off (~1e-14).
    let cases = [
        (IntegratorKind::Euler, 0.02, 1.0),
        (IntegratorKind::SymplecticEuler, 0.02, 1.0),
        (IntegratorKind::Midpoint, 0.05, 2.0),
        (IntegratorKind::Rk4, 0.1, 4.0),
        (IntegratorKind::Verlet, 0.05, 2.0),
        // Backward Euler's first-order error is its amplitude decay,
        // e^(-ω t h / 2) - 1, whose next term moves the order by < 0.05
        // at h = 0.02, as for explicit Euler.
        (IntegratorKind::ImplicitEuler, 0.02, 1.0),
        (IntegratorKind::Projective, 0.02, 1.0),
    ];
    for (kind, h, order) in cases {
        assert_eq!(kind.order() as Real, order, "{kind}: documented order");
        let steps = (OMEGA * duration / h).round() as usize;
        let coarse = error_at(kind, duration, steps);
        let fine = error_at(kind, duration, 2 * steps);
        let measured = (coarse / fine).log2();
        // ±0.2: the band, well above the < 0.05 shift computed above.
        assert!(
            (measured - order).abs() <= 0.2,
            "{kind}: measured order {measured:.3} (errors {coarse:.3e}, {fine:.3e}), expected {order}"
        );
    }
}

/// Decay rate (1/s) of the displacement peaks of a damped oscillator run
/// with `kind` at step `dt` for `duration` seconds.
fn measured_decay_rate(kind: IntegratorKind, damping: Real, dt: Real, duration: Real) -> Real {
    let mut world = oscillator(kind, MASS, STIFFNESS, damping, 0.1, 0.0);
    let mut samples = vec![displacement(&world)];
    for _ in 0..(duration / dt).round() as usize {
        world.step(dt).expect("stable");
        samples.push(displacement(&world));
    }
    // The maxima of `A e^{-γt} cos(ω_d t + φ)` are exactly one damped period
    // apart and each is `e^{-γ T_d}` times the one before.
    let found = peaks(&samples, dt);
    assert!(found.len() >= 5, "{kind}: only {} peaks", found.len());
    let ((t0, p0), (t1, p1)) = (found[0], found[found.len() - 1]);
    (p0 / p1).ln() / (t1 - t0)
}

#[test]
fn damped_amplitude_decays_at_c_over_2m_with_rk4() {
    let damping = 1.0; // N·s/m: c² = 1 < 4km = 400, underdamped
    let expected = damping / (2.0 * MASS);
    let rate = measured_decay_rate(IntegratorKind::Rk4, damping, 1e-3, 5.0);
    // The issue asks for 1 %. The numerical error is far smaller: RK4 at
    // h = 0.01 shifts the eigenvalue by ~ω h⁴/120, i.e. γ by ~1e-9
    // relative; the parabola through three samples misplaces a peak value
    // by ~h⁴/24 ≈ 4e-10 relative, spread over ln(p0/p1) ≈ 2. We claim 1e-4.
    assert!(
        (rate / expected - 1.0).abs() <= 1e-4,
        "decay rate {rate:.8} 1/s, expected c/2m = {expected}"
    );
}

#[test]
fn damped_amplitude_decays_at_c_over_2m_with_verlet() {
    // Verlet's damping needs a true velocity: the textbook loop computes it
    // after shifting the positions and always gets zero, which would leave
    // this oscillator undamped (docs/physics.md §6).
    let damping = 1.0;
    let expected = damping / (2.0 * MASS);
    let h: Real = 0.01;
    let rate = measured_decay_rate(IntegratorKind::Verlet, damping, h / OMEGA, 5.0);
    // Verlet is second order: the decay rate is off by a relative O(h²)
    // (about h²/2 for this light damping); 10 h² = 1e-3 leaves room for the
    // constant, while the textbook bug (no damping) is a 100 % error.
    assert!(
        (rate / expected - 1.0).abs() <= 10.0 * h * h,
        "decay rate {rate:.8} 1/s, expected c/2m = {expected}"
    );
}

#[test]
fn implicit_euler_takes_exactly_one_over_one_plus_h_squared_of_the_energy_per_step() {
    // Backward Euler on `u'' = -ω² u`: `(u, v/ω)` is multiplied per step by
    // a rotation scaled by `1 / √(1 + h²)`, so the energy ½ k u² + ½ m v²
    // by exactly `1 / (1 + h²)`. The spring moves along its axis, where its
    // force is linear, so one Newton iteration (the default) is exact, and
    // one conjugate-gradient iteration solves the one-dimensional system;
    // the projective solver's first iteration is exact too (see the period
    // test). The displacement is read as `x - L0` with `x` near 1 m, so
    // its round-off is ~1e-16 m: the steps stop while the amplitude is
    // above 1e-5 m, where that is < 1e-11 of the energy, and we claim 1e-9,
    // at a step far beyond the explicit limit (h = 3) and at small ones.
    for kind in [IntegratorKind::ImplicitEuler, IntegratorKind::Projective] {
        for h in [3.0, 0.5, 0.01] {
            let dt = h / OMEGA;
            let (u0, v0) = (0.1, 0.3);
            let mut world = oscillator(kind, MASS, STIFFNESS, 0.0, u0, v0);
            let ratio = 1.0 / (1.0 + h * h);
            let amplitude = (u0 * u0 + (v0 / OMEGA).powi(2)).sqrt();
            let steps = ((amplitude / 1e-5).ln() / (1.0 + h * h).sqrt().ln()).min(50.0) as usize;
            let mut energy = world.energies().total();
            for step in 1..=steps {
                world
                    .step(dt)
                    .expect("backward Euler is stable at any step");
                let next = world.energies().total();
                assert!(
                    (next / energy / ratio - 1.0).abs() <= 1e-9,
                    "{kind}, h = {h}, step {step}: energy ratio {}, expected 1/(1+h²) = {ratio}",
                    next / energy
                );
                energy = next;
            }
        }
    }
}

#[test]
fn the_implicit_period_tends_to_the_exact_one_as_dt_goes_to_zero() {
    // Backward Euler's numerical frequency is atan(h) / dt: the period is
    // longer by h²/3 + O(h⁴). Halving h must quarter the error and the
    // error must match h²/3 within the O(h²) relative correction (h²/5 of
    // it, < 1 % at h = 0.2) plus the cubic crossing location (< 0.1 %):
    // we claim 2 %. Five periods keep the decaying amplitude (by
    // (1 + h²)^(-n/2)) far above round-off.
    let period = TAU / OMEGA;
    for kind in [IntegratorKind::ImplicitEuler, IntegratorKind::Projective] {
        let mut previous: Option<Real> = None;
        for h in [0.2, 0.1, 0.05] {
            let dt = h / OMEGA;
            let mut world = oscillator(kind, MASS, STIFFNESS, 0.0, 1e-3, 0.0);
            let mut samples = vec![displacement(&world)];
            for _ in 0..(5.5 * period / dt).ceil() as usize {
                world.step(dt).expect("stable");
                samples.push(displacement(&world));
            }
            let error = mean_period(&samples, dt) / period - 1.0;
            let predicted = h * h / 3.0;
            assert!(
                (error / predicted - 1.0).abs() <= 0.02,
                "{kind}, h = {h}: period error {error:.4e}, predicted h²/3 = {predicted:.4e}"
            );
            if let Some(coarse) = previous {
                assert!(
                    (coarse / error - 4.0).abs() <= 0.1,
                    "{kind}: halving h divided the period error by {}",
                    coarse / error
                );
            }
            previous = Some(error);
        }
    }
}
