//! `sprung study stability` on the one-particle oscillator, whose exact
//! discrete solutions give every integrator's largest stable step, and the
//! contract of the command: its files, and bad input refused with nothing
//! written.
//!
//! With h = ω dt, each linear method multiplies the state (x, v/ω) by a
//! fixed matrix per step, so the energy E_n after n steps is known exactly:
//!
//! - explicit Euler: E_n = (1 + h²)ⁿ E₀;
//! - explicit midpoint: |R|² = (1 − h²/2)² + h² = 1 + h⁴/4, E_n = (1 + h⁴/4)ⁿ E₀;
//! - RK4: |R|² = 1 − h⁶/72 + h⁸/576, below 1 for h < 2√2 (the energy decays);
//! - symplectic Euler keeps x² + (v/ω)² − h x v/ω fixed, so from rest the
//!   energy stays in a band whose top is E₀ / (1 − h/2), unbounded at h = 2;
//! - position Verlet (as sprung reports its velocity, v_{n+1} = central
//!   difference + a_n dt) has x_n = x₀ cos nθ, cos θ = 1 − h²/2, and the
//!   top of its band is the largest eigenvalue of
//!   [[1 + h⁴/4, h³s/2], [h³s/2, (1 − h²/4)(1 + h²)]], s = √(1 − h²/4),
//!   which stays below 5 up to h = 2;
//! - implicit Euler divides the energy by 1 + h² per step and projective is
//!   backward Euler too: stable at every step.
//!
//! A trial of T seconds takes N = ⌈T/dt⌉ steps and is unstable when
//! max_n E_n > (1 + M) E₀ (M the margin; the energy scale is E₀, the only
//! non-zero term at the start).

mod common;

use std::collections::HashMap;
use std::f64::consts::{PI, SQRT_2};
use std::path::Path;

use common::{assert_no_partial_files, png_size, sprung, text, write};

/// ω = 2π /s: k = 4π² N/m on 1 kg. The spring is 100 m long and displaced
/// 0.2 m, so that it stays linear (the particle never reaches the pin) in
/// every trial: a trial stops at the first step past the margin, and the
/// farthest any gets is about 20 m (Verlet's second step at h = 4).
const OSCILLATOR: &str = r#"[sim]
dt = 0.01
gravity = [0.0, 0.0, 0.0]
duration = 20.0

[[body]]
name = "oscillator"
particles = [[0.0, 0.0], [100.2, 0.0]]
mass = 1.0
springs = [[0, 1]]
rest_lengths = [100.0]
stiffness = 39.47841760435743   # 4π² N/m
pinned = [0]
"#;

const OMEGA: f64 = 2.0 * PI;

/// The bisection's stopping ratio: the smallest unstable step tried is
/// less than this factor above the reported stable one.
const BRACKET: f64 = 1.02;

/// A row of stability.csv.
#[derive(Debug)]
struct Row {
    dt: Option<f64>,
    capped: bool,
    estimate: f64,
    cost: Option<f64>,
    steps_per_second: Option<f64>,
    energy_criterion: bool,
}

/// stability.csv by integrator, checking the header.
fn read_csv(path: &Path) -> HashMap<String, Row> {
    let content = std::fs::read_to_string(path).expect("stability.csv");
    let mut lines = content.lines();
    assert_eq!(
        lines.next(),
        Some("integrator,largest_stable_dt,capped,stable_estimate,cost_per_simulated_second,steps_per_second,energy_criterion")
    );
    let number = |cell: &str| (!cell.is_empty()).then(|| cell.parse::<f64>().expect("number"));
    lines
        .map(|line| {
            let cells: Vec<&str> = line.split(',').collect();
            assert_eq!(cells.len(), 7, "{line}");
            let flag = |cell: &str| match cell {
                "true" => true,
                "false" => false,
                other => panic!("not a flag: {other}"),
            };
            let row = Row {
                dt: number(cells[1]),
                capped: flag(cells[2]),
                estimate: number(cells[3]).expect("estimate"),
                cost: number(cells[4]),
                steps_per_second: number(cells[5]),
                energy_criterion: flag(cells[6]),
            };
            (cells[0].to_string(), row)
        })
        .collect()
}

/// The root of the increasing function `f` between `lo` and `hi`.
fn root(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    assert!(f(lo) < 0.0 && f(hi) > 0.0);
    for _ in 0..200 {
        let middle = 0.5 * (lo + hi);
        if f(middle) > 0.0 {
            hi = middle;
        } else {
            lo = middle;
        }
    }
    lo
}

/// The bounds on the largest stable h of a method whose energy grows by
/// the factor `r(h)` (> 1, increasing, with ln r(h) / h increasing) every
/// step, over trials of `t` seconds with margin `m`. Every h above
/// `upper` fails, since N ≥ Tω/h gives N ln r ≥ (Tω/h) ln r > ln(1 + m);
/// every h below `lower` passes, since N ≤ Tω/h + 1. So the unstable step
/// the bisection stopped at is above `lower`, and the stable one it
/// reports is below `upper` and above `lower / BRACKET`.
fn growth_bounds(r: impl Fn(f64) -> f64 + Copy, t: f64, m: f64) -> (f64, f64) {
    let allowed = (1.0 + m).ln();
    let upper = root(|h| t * OMEGA / h * r(h).ln() - allowed, 1e-6, 3.0);
    let lower = root(|h| (t * OMEGA / h + 1.0) * r(h).ln() - allowed, 1e-6, 3.0);
    (lower, upper)
}

fn euler_growth(h: f64) -> f64 {
    1.0 + h * h
}

fn midpoint_growth(h: f64) -> f64 {
    1.0 + h.powi(4) / 4.0
}

fn rk4_growth(h: f64) -> f64 {
    1.0 - h.powi(6) / 72.0 + h.powi(8) / 576.0
}

/// Top of symplectic Euler's energy band over E₀.
fn symplectic_top(h: f64) -> f64 {
    1.0 / (1.0 - h / 2.0)
}

/// Top of position Verlet's energy band over E₀ (h ≤ 2).
fn verlet_top(h: f64) -> f64 {
    let s = (1.0 - h * h / 4.0).max(0.0).sqrt();
    let (a, b, c) = (
        1.0 + h.powi(4) / 4.0,
        (1.0 - h * h / 4.0) * (1.0 + h * h),
        h.powi(3) * s / 2.0,
    );
    0.5 * (a + b) + (0.25 * (a - b).powi(2) + c * c).sqrt()
}

/// Assert `found` (a step, s) lies in `[lower, upper]` (values of h).
fn assert_within(name: &str, found: Option<f64>, lower: f64, upper: f64) {
    let h = found.unwrap_or_else(|| panic!("{name}: no stable step found")) * OMEGA;
    assert!(
        lower <= h && h <= upper,
        "{name}: h = ω dt = {h} outside [{lower}, {upper}]"
    );
}

/// Run the study with `extra` options into `dir/res` and read the CSV.
fn study(dir: &Path, extra: &[&str]) -> HashMap<String, Row> {
    write(dir, "oscillator.toml", OSCILLATOR);
    let mut args = vec![
        "study",
        "stability",
        "oscillator.toml",
        "--out",
        "res",
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let output = sprung(&args, dir);
    assert!(output.status.success(), "{}", text(&output.stderr));
    assert!(
        output.stdout.is_empty() && output.stderr.is_empty(),
        "--quiet prints nothing"
    );
    assert_no_partial_files(dir);
    read_csv(&dir.join("res/stability.csv"))
}

/// Checks shared by both margins: the rows, the estimate, the implicit
/// methods and the adaptive rk45 (which divides a long step into as many
/// as its error tolerance asks) capped at the trial time, the explicit
/// fixed-step ones not.
fn check_common(rows: &HashMap<String, Row>, time: f64) {
    assert_eq!(rows.len(), 8, "one row per integrator");
    for (name, row) in rows {
        // Gershgorin with a pinned neighbour: ω_max = √(k/m) = ω, dt = 2/ω.
        assert!(
            (row.estimate - 2.0 / OMEGA).abs() < 1e-12,
            "{name}: {}",
            row.estimate
        );
        assert!(row.energy_criterion, "{name}: no driving forces");
        assert!(row.cost.is_some_and(|c| c > 0.0), "{name}: {row:?}");
        assert!(row.steps_per_second.is_some_and(|s| s > 0.0), "{name}");
        let implicit = name == "implicit_euler" || name == "projective" || name == "rk45";
        assert_eq!(row.capped, implicit, "{name}: {row:?}");
        if implicit {
            assert_eq!(row.dt, Some(time), "{name}: capped at one step of T");
        }
    }
}

/// RK4: no trial below 2√2 fails (the energy decays), so the reported
/// step is above 2√2 / BRACKET; a stable one satisfies
/// N ln|R|² ≤ ln(1 + M) with N ≥ Tω/h, which bounds it above.
fn rk4_bounds(t: f64, m: f64) -> (f64, f64) {
    let limit = 2.0 * SQRT_2;
    let allowed = (1.0 + m).ln();
    let upper = root(|h| t * OMEGA / h * rk4_growth(h).ln() - allowed, limit, 4.0);
    (limit / BRACKET, upper)
}

/// The default margin, 1 % of E₀, over trials of one period (T = 1 s).
#[test]
fn one_percent_margin_matches_the_exact_limits() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (t, m) = (1.0, 0.01);
    let rows = study(dir.path(), &["--time", "1"]);
    check_common(&rows, t);

    // Growth every step: exact bounds (h ≈ 1.6e-3 and 0.185).
    let (lower, upper) = growth_bounds(euler_growth, t, m);
    assert_within("euler", rows["euler"].dt, lower / BRACKET, upper);
    let (lower, upper) = growth_bounds(midpoint_growth, t, m);
    assert_within("midpoint", rows["midpoint"].dt, lower / BRACKET, upper);
    let (lower, upper) = rk4_bounds(t, m);
    assert_within("rk4", rows["rk4"].dt, lower, upper);

    // Bands: below the h where the band's top reaches 1 + M every trial
    // passes. The steps sample the band at phases 2θ apart (θ ≈ h over T =
    // one period, so the whole band is swept), missing its top by at most
    // (half the band's width) × (1 − cos θ): 2e-6 E₀ for symplectic Euler
    // (h ≈ 0.02, width ≈ h), 3e-5 E₀ for Verlet (h ≈ 0.115, width ≈ 3h²/4),
    // which moves the limit up by 0.02 % and 0.2 %: 0.1 % and 0.5 % allowed.
    let symplectic = 2.0 * m / (1.0 + m);
    assert!((symplectic_top(symplectic) - (1.0 + m)).abs() < 1e-12);
    assert_within(
        "symplectic_euler",
        rows["symplectic_euler"].dt,
        symplectic / BRACKET,
        symplectic * 1.001,
    );
    let verlet = root(|h| verlet_top(h) - (1.0 + m), 1e-6, 1.0);
    assert!((verlet - (4.0 * m / 3.0).sqrt()).abs() < 0.01 * verlet); // ≈ √(4M/3)
    assert_within(
        "verlet",
        rows["verlet"].dt,
        verlet / BRACKET,
        verlet * 1.005,
    );

    // The ranking the study exists to show: Euler needs by far the
    // smallest step, RK4 the largest of the explicit methods.
    let dt = |name: &str| rows[name].dt.expect("found");
    assert!(dt("euler") < dt("symplectic_euler") && dt("symplectic_euler") < dt("verlet"));
    assert!(dt("midpoint") < dt("rk4") && dt("verlet") < dt("rk4"));

    let png = dir.path().join("res/stability.png");
    assert_eq!(png_size(&png), (1000, 600));
    assert!(std::fs::metadata(&png).expect("png").len() > 1000);
}

/// A margin of 99 (the energy may grow a hundredfold) over ten periods
/// shows the limits of the methods themselves: symplectic Euler's band
/// reaches 100 E₀ at h = 1.98 (its unbounded growth starts at 2), Verlet's
/// band stays below 5 E₀ up to h = 2 and grows without bound above it.
#[test]
fn large_margin_shows_the_stability_limits() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (t, m) = (10.0, 99.0);
    let rows = study(dir.path(), &["--time", "10", "--margin", "99"]);
    check_common(&rows, t);

    let (lower, upper) = growth_bounds(euler_growth, t, m);
    assert_within("euler", rows["euler"].dt, lower / BRACKET, upper);
    let (lower, upper) = growth_bounds(midpoint_growth, t, m);
    assert_within("midpoint", rows["midpoint"].dt, lower / BRACKET, upper);
    let (lower, upper) = rk4_bounds(t, m);
    assert_within("rk4", rows["rk4"].dt, lower, upper);

    // Symplectic Euler: the band top 1/(1 − h/2) = 100 at h = 1.98. The
    // 32 steps of a trial advance the band's phase by 2θ ≡ −0.57 rad each,
    // sweeping it three times and missing the top by at most 50 E₀ ×
    // (1 − cos 0.283) = 2 E₀, which moves the limit up by 0.02 %.
    let symplectic = 2.0 * m / (1.0 + m);
    assert_within(
        "symplectic_euler",
        rows["symplectic_euler"].dt,
        symplectic / BRACKET,
        symplectic * 1.001,
    );

    // Verlet: every h ≤ 2 passes (band below 5 E₀ < 100 E₀). Above 2,
    // x_n = (−1)ⁿ x₀ cosh nβ with cosh β = h²/2 − 1: at h = 2.02 the
    // potential energy alone passes 100 E₀ well within the trial's steps,
    // so every h from 2.02 on fails.
    assert!(verlet_top(2.0) <= 5.0 + 1e-12);
    let (h, steps): (f64, f64) = (2.02, (t * OMEGA / 2.02).ceil());
    let beta = (h * h / 2.0 - 1.0).acosh();
    assert!((steps * beta).cosh().powi(2) > 100.0 * (1.0 + m));
    assert_within("verlet", rows["verlet"].dt, 2.0 / BRACKET, 2.02);
}

#[test]
fn driving_forces_turn_the_energy_criterion_off() {
    let dir = tempfile::tempdir().expect("tempdir");
    let windy = format!(
        "{OSCILLATOR}\n[wind]\nvelocity = [0.0, 1.0, 0.0]\nmodel = \"simple\"\ncoefficient = 0.01\n"
    );
    write(dir.path(), "windy.toml", &windy);
    let output = sprung(
        &[
            "study",
            "stability",
            "windy.toml",
            "--time",
            "1",
            "--integrator",
            "rk4,implicit_euler",
            "--out",
            "res",
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let stdout = text(&output.stdout);
    assert!(
        stdout.contains("energy criterion off (driving forces: wind)"),
        "{stdout}"
    );
    let rows = read_csv(&dir.path().join("res/stability.csv"));
    assert_eq!(rows.len(), 2);
    assert!(rows.values().all(|r| !r.energy_criterion));
    assert!(rows["implicit_euler"].capped);
}

#[test]
fn bad_input_exits_1_and_writes_nothing() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "oscillator.toml", OSCILLATOR);
    let cases: [(&[&str], &str); 2] = [
        (&["missing.toml"], "cannot read the scene file"),
        // 1e8 s / (2/ω) ≈ 3.1e8 steps × 2 particles: over the 1e8 limit.
        (
            &["oscillator.toml", "--time", "1e8"],
            "more than the 1e8 a trial may take",
        ),
    ];
    for (args, message) in cases {
        let mut all = vec!["study", "stability", "--out", "res"];
        all.extend_from_slice(args);
        let output = sprung(&all, dir.path());
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(!dir.path().join("res").exists(), "{args:?} wrote files");
    }
    // A malformed value is a usage error: exit 2, naming the option.
    for (args, message) in [
        (
            ["--margin", "0"],
            "'--margin <MARGIN>': 0: must be positive",
        ),
        (
            ["--margin", "-0.5"],
            "'--margin <MARGIN>': -0.5: must be positive",
        ),
        (
            ["--margin", "NaN"],
            "'--margin <MARGIN>': NaN: must be positive",
        ),
        (["--time", "0"], "'--time <TIME>': 0: must be positive"),
        (["--time", "-1"], "'--time <TIME>': -1: must be positive"),
    ] {
        let mut all = vec!["study", "stability", "oscillator.toml", "--out", "res"];
        all.extend_from_slice(&args);
        let output = sprung(&all, dir.path());
        let stderr = text(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
        assert!(!dir.path().join("res").exists(), "{args:?} wrote files");
    }
    // A malformed command line is clap's: exit 2.
    let output = sprung(
        &[
            "study",
            "stability",
            "oscillator.toml",
            "--integrator",
            "leapfrog",
        ],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(2));
    assert!(text(&output.stderr).contains("unknown integrator"));
}

/// A lone 1 kg particle falling from rest at y = 0: every energy term is
/// zero at the start, so the margin scales with the change of the gravity
/// term over the trial. Explicit Euler moves with the old velocity, so
/// after n steps v = n g dt and y = −g dt² n(n − 1)/2: the total energy is
/// ½ m g² dt² n above its start while gravity has given up
/// m g² dt² n(n − 1)/2, a ratio 1/(n − 1) that is largest at the last of
/// the N steps. With M = 0.01 a trial passes when N ≥ 102 (ratio 1/101),
/// fails when N ≤ 100, and N = 101 is a tie; so the reported step is below
/// T/100 and above T/(101 × BRACKET). Every other method is exact for a
/// constant force (midpoint, RK4, Verlet) or loses energy (symplectic and
/// implicit Euler: ½ m g² dt² n below the start): stable at every step.
/// Without springs there is no stable estimate: the search starts at the
/// scene's dt and the estimate's cell is empty.
#[test]
fn margin_of_a_fall_from_zero_energy_scales_with_the_fall() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = r#"[sim]
dt = 0.01
duration = 1.0

[[body]]
name = "stone"
particles = [[0.0, 0.0]]
mass = 1.0
"#;
    write(dir.path(), "fall.toml", scene);
    let output = sprung(
        &["study", "stability", "fall.toml", "--out", "res", "--quiet"],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let content = std::fs::read_to_string(dir.path().join("res/stability.csv")).expect("csv");
    let mut euler = None;
    for line in content.lines().skip(1) {
        let cells: Vec<&str> = line.split(',').collect();
        assert_eq!(cells[3], "", "no stable estimate: {line}");
        assert_eq!(cells[6], "true", "energy criterion on: {line}");
        if cells[0] == "euler" {
            assert_eq!(cells[2], "false", "{line}");
            euler = Some(cells[1].parse::<f64>().expect("dt"));
        } else {
            assert_eq!((cells[1], cells[2]), ("1e0", "true"), "{line}");
        }
    }
    let dt = euler.expect("an euler row");
    let t = 1.0;
    assert!(
        t / (101.0 * BRACKET) < dt && dt < t / 100.0,
        "euler: dt = {dt}"
    );
}
