//! Gusts and turbulence of the wind (docs/physics.md §3): they repeat
//! exactly for a seed, stay in their bounds, average out and are smooth.

mod common;

use common::wind::{largest_distance, windy_world, RHO};
use common::Rng;
use sprung::build::{self, ClothSprings};
use sprung::forces::{Gusts, Turbulence, WindField, WindModel};
use sprung::{IntegratorKind, Real, Vec3};

// ------------------------------------------------------ gusts and turbulence

const GUSTS: Gusts = Gusts {
    amplitude: 0.4,
    period: 2.0, // s
};
const TURBULENCE: Turbulence = Turbulence {
    amplitude: 1.5,    // m/s
    length_scale: 0.5, // m
    time_scale: 0.3,   // s
};

/// Positions after 1 s of a 6 × 5 cloth hanging from its top row, with
/// gravity, in an 8 m/s wind along z with gusts and turbulence drawn from
/// `seed`, through the area model with lift.
fn gusty_run(seed: u64) -> Vec<Vec3> {
    let (nx, ny) = (6, 5);
    let cloth = build::cloth(nx, ny, 1.0, 0.8, ClothSprings::default())
        .expect("valid cloth")
        .with_total_mass(0.2)
        .with_stiffness(500.0)
        .with_damping(0.01)
        .with_pinned(((ny - 1) * nx..ny * nx).collect());
    let field = WindField::varying(
        Vec3::new(0.0, 0.0, 8.0),
        Some(GUSTS),
        Some(TURBULENCE),
        seed,
    );
    let model = WindModel::Area {
        air_density: RHO,
        lift: 0.3,
    };
    let mut world = windy_world(IntegratorKind::SymplecticEuler, cloth, field, model);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    let dt = 0.5 * world.stable_time_step();
    for _ in 0..(1.0 / dt).round() as usize {
        world.step(dt).expect("stable");
    }
    world.particles.position.clone()
}

#[test]
fn the_same_seed_repeats_a_gusty_run_bit_for_bit() {
    let first = gusty_run(7);
    let again = gusty_run(7);
    // Exactly: the same seed gives the same sinusoids, and the run does the
    // same operations in the same order.
    assert!(first == again, "two runs with seed 7 differ");
    // Another seed draws other frequencies, directions and phases: the
    // cloth ends elsewhere (the wind's fluctuations are of order 1 m/s on
    // a 1 m cloth for 1 s: centimetres, not ulps).
    let other = gusty_run(8);
    let apart = largest_distance(&first, &other);
    assert!(apart > 1e-6, "seeds 7 and 8 end {apart:.2e} m apart");
}

#[test]
fn a_different_seed_gives_a_different_field() {
    let w = Vec3::new(5.0, 0.0, 0.0);
    let a = WindField::varying(w, Some(GUSTS), Some(TURBULENCE), 1);
    let b = WindField::varying(w, Some(GUSTS), Some(TURBULENCE), 2);
    let same = WindField::varying(w, Some(GUSTS), Some(TURBULENCE), 1);
    let mut rng = Rng::new(11);
    let mut largest: Real = 0.0;
    for _ in 0..100 {
        let (x, t) = (rng.vector(2.0), 5.0 * (rng.symmetric() + 1.0));
        assert_eq!(a.velocity_at(x, t), same.velocity_at(x, t));
        largest = largest.max((a.velocity_at(x, t) - b.velocity_at(x, t)).length());
    }
    // Two independent fields differ by ~√2 × 1.5 m/s RMS in turbulence
    // alone; over 100 points the largest difference is far above 0.1 m/s.
    assert!(
        largest > 0.1,
        "seeds 1 and 2: largest difference {largest} m/s"
    );
}

#[test]
fn gusts_keep_the_wind_speed_within_one_plus_or_minus_the_amplitude() {
    // Gusts multiply the mean wind by 1 + a g(t), g the mean of three
    // sines, |g| ≤ 1: the wind keeps its direction and its speed stays in
    // [(1 - a)|w|, (1 + a)|w|]. 1e-12 relative covers rounding.
    let w = Vec3::new(3.0, -4.0, 1.0);
    let speed = w.length();
    let a = GUSTS.amplitude;
    let field = WindField::varying(w, Some(GUSTS), None, 3);
    let (mut slowest, mut fastest) = (Real::INFINITY, Real::NEG_INFINITY);
    let x = Vec3::new(0.3, 2.0, -1.0);
    for i in 0..100_000 {
        // 1000 s, 500 mean gust periods, sampled every 0.01 s.
        let t = 0.01 * i as Real;
        let v = field.velocity_at(x, t);
        assert!(
            v.cross(w).length() <= 1e-12 * speed * v.length(),
            "t = {t}: wind {v:?} turned away from {w:?}"
        );
        let s = v.length();
        assert!(
            s >= (1.0 - a) * speed * (1.0 - 1e-12) && s <= (1.0 + a) * speed * (1.0 + 1e-12),
            "t = {t}: speed {s}, allowed [{}, {}]",
            (1.0 - a) * speed,
            (1.0 + a) * speed
        );
        slowest = slowest.min(s);
        fastest = fastest.max(s);
    }
    // And it does gust: g averages to zero over long times and is not
    // identically zero, so over 500 periods it takes both signs.
    assert!(
        slowest < speed && fastest > speed,
        "speed in [{slowest}, {fastest}], mean {speed}"
    );
    // A gust-free wind (amplitude 0) is the mean exactly, and so is a
    // turbulence of amplitude 0: 1 + 0·g is exactly 1, and 0·cos exactly 0.
    let calm_gusts = WindField::varying(
        w,
        Some(Gusts {
            amplitude: 0.0,
            ..GUSTS
        }),
        None,
        3,
    );
    let calm_turbulence = WindField::varying(
        w,
        None,
        Some(Turbulence {
            amplitude: 0.0,
            ..TURBULENCE
        }),
        3,
    );
    let mut rng = Rng::new(5);
    for _ in 0..1000 {
        let (x, t) = (rng.vector(10.0), 100.0 * (rng.symmetric() + 1.0));
        assert_eq!(calm_gusts.velocity_at(x, t), w, "gusts of amplitude 0");
        assert_eq!(
            calm_turbulence.velocity_at(x, t),
            w,
            "turbulence of amplitude 0"
        );
    }
}

#[test]
fn turbulence_averages_out_over_space_and_time() {
    // The turbulent part is Σ_k s cos(k_k·x - ω_k t + φ_k) d_k over 8 modes,
    // s = A √(2/8) (so its mean square is 8 s²/2 = A²), |k_k| ∈ [0.5, 2]/ℓ,
    // ω_k ∈ [0.5, 1.5]/τ. Its mean over random points of a box of side
    // L = 200 ℓ and times in [0, T], T = 2000 τ:
    // - bias: each cosine's mean over the time interval alone is at most
    //   2/(ω T) ≤ 4τ/T = 0.002, so each component's exact mean is at most
    //   8 s × 0.002 = 0.008 A;
    // - sampling: a component is Σ_k s d_kj cos_k, and N independent
    //   samples of a cosine (variance ≤ ½) have a mean of standard
    //   deviation ≤ √(1/2N); the modes' cosines at one point need not be
    //   independent, so their deviations add at worst (Cauchy-Schwarz):
    //   ≤ Σ_k s |d_kj| √(1/2N) ≤ 8 s √(1/2N) = 2√2 A/√N = 0.0045 A for
    //   N = 4·10⁵.
    // Allowed: bias + 5 standard deviations ≈ 0.03 A per component (by
    // the central limit theorem a spurious failure about once in 10⁶
    // seeds), against fluctuations of RMS A.
    let w = Vec3::new(4.0, 0.0, 0.0);
    let a = TURBULENCE.amplitude;
    let (l, tau) = (TURBULENCE.length_scale, TURBULENCE.time_scale);
    let field = WindField::varying(w, None, Some(TURBULENCE), 21);
    let mut rng = Rng::new(99);
    let samples = 400_000;
    let mut sum = Vec3::ZERO;
    for _ in 0..samples {
        let x = rng.vector(100.0 * l);
        let t = 1000.0 * tau * (rng.symmetric() + 1.0);
        sum += field.velocity_at(x, t) - w;
    }
    let mean = sum / samples as Real;
    let allowed = 0.008 * a + 5.0 * 2.0 * Real::sqrt(2.0) * a / (samples as Real).sqrt();
    assert!(
        mean.abs().max_element() <= allowed,
        "mean turbulence {mean:?} m/s, allowed ± {allowed:.4} m/s per component"
    );
}

#[test]
fn turbulence_is_smooth() {
    // Each mode is s cos(k·x - ω t + φ) d: its gradient is at most s |k|
    // ≤ 2s/ℓ and its second derivative along a unit vector at most
    // s |k|² ≤ 4s/ℓ² (in time: s ω ≤ 1.5 s/τ and s ω² ≤ 2.25 s/τ²).
    // Summed over 8 modes with s = A/2, the field's difference over a step
    // h is at most D1 h, D1 = 8 A/ℓ (Lipschitz: linear in h), and the
    // difference over h differs from twice the one over h/2 by at most
    // (h²/2 + h²/4) D2 by Taylor's theorem, D2 = 16 A/ℓ²: the differences
    // scale linearly as h → 0. Rounding: the phases reach ~30 rad here and
    // are rounded at ~1e-14 rad, so each evaluation is off by ~1e-14 A:
    // 1e-13 A covers three.
    let w = Vec3::new(4.0, 1.0, 0.0);
    let a = TURBULENCE.amplitude;
    let (l, tau) = (TURBULENCE.length_scale, TURBULENCE.time_scale);
    let field = WindField::varying(w, None, Some(TURBULENCE), 5);
    let rounding = 1e-13 * a;
    let mut rng = Rng::new(17);
    for _ in 0..1000 {
        let (x, t) = (rng.vector(5.0 * l), 10.0 * tau * (rng.symmetric() + 1.0));
        let along = rng.vector(1.0).normalize();
        // In space.
        let h = 1e-3 * l;
        let (d1, d2) = (8.0 * a / l, 16.0 * a / (l * l));
        let full = field.velocity_at(x + h * along, t) - field.velocity_at(x, t);
        let half = field.velocity_at(x + 0.5 * h * along, t) - field.velocity_at(x, t);
        assert!(
            full.length() <= d1 * h + rounding,
            "space step {h}: {full:?}"
        );
        assert!(
            (full - 2.0 * half).length() <= 0.75 * h * h * d2 + rounding,
            "space: difference over h {full:?}, over h/2 {half:?}"
        );
        // In time.
        let h = 1e-3 * tau;
        let (d1, d2) = (
            8.0 * 1.5 * a / (2.0 * tau),
            8.0 * 2.25 * a / (2.0 * tau * tau),
        );
        let full = field.velocity_at(x, t + h) - field.velocity_at(x, t);
        let half = field.velocity_at(x, t + 0.5 * h) - field.velocity_at(x, t);
        assert!(
            full.length() <= d1 * h + rounding,
            "time step {h}: {full:?}"
        );
        assert!(
            (full - 2.0 * half).length() <= 0.75 * h * h * d2 + rounding,
            "time: difference over h {full:?}, over h/2 {half:?}"
        );
    }
}
