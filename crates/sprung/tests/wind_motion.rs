//! What the wind does to surfaces over time (docs/physics.md §3). The
//! claims:
//!
//! 1. a free flat patch approaches the wind's normal speed as
//!    `w_n (1 - exp(-λ t))`, `λ = c / m` (simple) or `ρ A / 3m` (area);
//! 2. a sheet pinned on all four sides billows downwind, the more so the
//!    stronger the wind, and its steady shape depends on `ρ w` only; a slack
//!    membrane's deflection grows as the cube root of the load;
//! 3. a flag in a steady wind flutters for 30 s without blowing up, its
//!    energy below what the wind could have put in.
//!
//! Unless a test says otherwise, gravity is off and the world holds
//! nothing but the bodies and the wind. The forces themselves are checked
//! in `wind_forces.rs`.

mod common;

use common::wind::{
    flat_cloth, frame, largest_distance, triangle, windy_world, AREA, RHO, TRIANGLE_AREA,
};
use sprung::build::{self, ClothSprings};
use sprung::forces::{Wind, WindField, WindModel};
use sprung::{IntegratorKind, Real, StepError, Vec3, World};

// ----------------------------------------------------- a free patch speeds up

/// Largest error allowed on the speed of a patch relaxing to the wind's
/// normal speed `w_n` at rate `λ`, stepped by RK4 at `h = λ dt` (m/s).
///
/// With `e = w_n - v`, `e' = -λ e`, RK4 multiplies `e` by
/// `R(h) = 1 - h + h²/2 - h³/6 + h⁴/24 = e^{-h} (1 - h⁵/120 + O(h⁶))` per
/// step, so after `n` steps (`λ t = n h`) `e` is off by
/// `w_n e^{-λt} λt h⁴/120 ≤ w_n h⁴ / (120 e)`. Twice that covers the O(h)
/// relative next term; `1e-12 w_n` covers rounding (a few ulps per step
/// over at most 1000 steps).
fn rk4_speed_tolerance(w_n: Real, h: Real) -> Real {
    w_n * (2.0 * h.powi(4) / (120.0 * std::f64::consts::E) + 1e-12)
}

/// Step `world` (whose `moving` particles all move as one along `n` from
/// rest at its initial position) for `duration` seconds at `dt` and check,
/// at every step, that their velocity is `w_n (1 - e^{-λt}) n` and their
/// displacement `w_n (t - (1 - e^{-λt}) / λ) n`; and that the rate read
/// back from the velocity, `-ln(1 - v/w_n) / t`, is `λ`.
fn check_relaxation(mut world: World, n: Vec3, w_n: Real, rate: Real, dt: Real, duration: Real) {
    let start = world.particles.position.clone();
    let h = rate * dt;
    let speed_tolerance = rk4_speed_tolerance(w_n, h);
    // The displacement error is the integral of the speed error,
    // `∫ w_n e^{-λs} λs h⁴/120 ds ≤ w_n h⁴ / (120 λ)`, doubled as above,
    // plus rounding of positions of order 1 m.
    let position_tolerance = w_n * 2.0 * h.powi(4) / (120.0 * rate) + 1e-12;
    let steps = (duration / dt).round() as usize;
    for step in 1..=steps {
        world.step(dt).expect("stable");
        let t = world.time();
        let decay = (-rate * t).exp();
        let speed = w_n * (1.0 - decay);
        let travelled = w_n * (t - (1.0 - decay) / rate);
        for (i, (&x, &v)) in world
            .particles
            .position
            .iter()
            .zip(&world.particles.velocity)
            .enumerate()
        {
            assert!(
                (v - speed * n).length() <= speed_tolerance,
                "step {step}, particle {i}: v = {v:?}, expected {:?}",
                speed * n
            );
            assert!(
                (x - start[i] - travelled * n).length() <= position_tolerance,
                "step {step}, particle {i}: moved {:?}, expected {:?}",
                x - start[i],
                travelled * n
            );
        }
        // The rate itself: -ln(1 - v/w_n)/t is off by δv / (w_n e^{-λt} t)
        // for a speed error δv.
        if step % (steps / 5) == 0 {
            let v = world.particles.velocity[0].dot(n);
            let measured = -(1.0 - v / w_n).ln() / t;
            let allowed = speed_tolerance / (w_n * decay * t);
            assert!(
                (measured - rate).abs() <= allowed,
                "t = {t}: rate {measured}, expected {rate} ± {allowed:.1e}"
            );
        }
    }
}

#[test]
fn a_free_patch_approaches_the_wind_speed_at_the_simple_models_rate() {
    // A springless flat cloth: every particle feels c (w_z - v_z) z, the
    // same for all, so the patch stays flat and moves as a whole, its normal
    // stays z and m v_z' = c (w_z - v_z): v_z = w_z (1 - e^{-ct/m}). The
    // in-plane part of the oblique wind pushes nothing.
    let (c, mass) = (0.5, 0.1); // N·s/m, kg: λ = 5 /s
    let w = Vec3::new(2.0, 1.0, 6.0);
    let world = windy_world(
        IntegratorKind::Rk4,
        flat_cloth(4, 3, 1.0, 0.5, mass),
        WindField::uniform(w),
        WindModel::Simple { coefficient: c },
    );
    // h = λ dt = 0.01, over 5 time constants.
    check_relaxation(world, Vec3::Z, w.z, c / mass, 2e-3, 1.0);
}

#[test]
fn a_free_triangle_approaches_the_wind_speed_at_the_area_models_rate() {
    // One springless triangle: each vertex feels a third of
    // ρ A (w - v)·n n with v the common velocity, so it moves as a whole,
    // and m v_n' = ρ A (w_n - v_n) / 3: λ = ρ A / (3 m).
    let (n, e1, _) = frame();
    let mass = 0.2;
    let w = 6.0 * n + 3.0 * e1;
    let world = windy_world(
        IntegratorKind::Rk4,
        triangle(mass),
        WindField::uniform(w),
        AREA,
    );
    let rate = RHO * TRIANGLE_AREA / (3.0 * mass); // 1.8 /s
    check_relaxation(world, n, 6.0, rate, 0.01 / rate, 3.0);
}

// ------------------------------------------------------- the billowing sheet

/// A settled run of [`billowing_sheet`].
struct Sheet {
    /// Air density (kg/m³).
    air_density: Real,
    /// Wind speed (m/s).
    speed: Real,
    /// Positions at the end (m).
    position: Vec<Vec3>,
    /// Largest move of any particle over the last second (m).
    moved: Real,
}

/// Particles along each side of the square sheet.
const SHEET_N: usize = 9;

/// A 1 m square `SHEET_N × SHEET_N` cloth of 0.1 kg, springs of 1000 N/m
/// and 0.01 N·s/m, pinned on all four sides, in the plane z = 0, in a wind
/// `(0, 0, speed)` through the area model with `air_density`, no gravity,
/// global air drag 0.025 N·s/m (20 /s over the particle mass, so every
/// mode settles within a few seconds; drag vanishes at rest and leaves the
/// steady shape alone). Stepped by symplectic Euler at 0.9 of the stable
/// step, whose fixed points are exactly the states where the forces
/// balance (`v` stays 0 iff `a = 0`).
fn billowing_sheet(air_density: Real, speed: Real, duration: Real) -> Sheet {
    let n = SHEET_N;
    let pinned = (0..n * n)
        .filter(|i| {
            let (x, y) = (i % n, i / n);
            x == 0 || y == 0 || x == n - 1 || y == n - 1
        })
        .collect();
    let sheet = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_total_mass(0.1)
        .with_stiffness(1000.0)
        .with_damping(0.01)
        .with_pinned(pinned);
    let mut world = windy_world(
        IntegratorKind::SymplecticEuler,
        sheet,
        WindField::uniform(Vec3::new(0.0, 0.0, speed)),
        WindModel::Area {
            air_density,
            lift: 0.0,
        },
    );
    world.set_air_drag(0.025);
    let dt = 0.9 * world.stable_time_step();
    let steps = (duration / dt).round() as usize;
    let last_second = (1.0 / dt).round() as usize;
    let mut earlier = Vec::new();
    for step in 1..=steps {
        world.step(dt).expect("stable below the stable step");
        if step == steps - last_second {
            earlier = world.particles.position.clone();
        }
    }
    let position = world.particles.position.clone();
    Sheet {
        air_density,
        speed,
        moved: largest_distance(&position, &earlier),
        position,
    }
}

/// The centre particle of the sheet.
const CENTRE: usize = (SHEET_N / 2) * SHEET_N + SHEET_N / 2;

#[test]
fn a_sheet_pinned_on_four_sides_billows_downwind_and_depends_on_rho_w_only() {
    let duration = 6.0;
    // (ρ, w) pairs: four speeds at 1.2 kg/m³, and double the density at 4.
    let runs: Vec<Sheet> = [(1.2, 1.0), (1.2, 2.0), (1.2, 4.0), (1.2, 8.0), (2.4, 4.0)]
        .into_iter()
        .map(|(rho, w)| billowing_sheet(rho, w, duration))
        .collect();
    // How settled each run is: the largest move of any particle over its
    // last second. Every mode decays exponentially: the in-plane ones
    // (ω ~ √(k/m) ~ 900 rad/s) and the out-of-plane ones (the slowest, the
    // fundamental `π √2 √(N/σ)` of a membrane of tension N ≳ p a²/(8 u)
    // ≈ 8 N/m at the lightest load and σ = 0.1 kg/m², ~40 rad/s) are all
    // underdamped by the drag alone and decay at ≥ c_air/2m = 10 /s. So
    // what is left to settle after the last second is `δ e^{-γ}/(1 -
    // e^{-γ}) ≤ δ`, the move `δ` during it. A run still visibly moving
    // fails here rather than in a comparison.
    for run in &runs {
        let (rho, w, moved) = (run.air_density, run.speed, run.moved);
        assert!(
            moved <= 1e-9,
            "ρ = {rho}, w = {w}: moved {moved:.2e} m in the last second, not settled"
        );
    }
    let deflection: Vec<Real> = runs.iter().map(|run| run.position[CENTRE].z).collect();
    // Downwind (+z), and growing with the wind speed 1, 2, 4, 8 m/s.
    assert!(deflection[0] > 0.0, "centre at z = {}", deflection[0]);
    for pair in deflection[..4].windows(2) {
        assert!(
            pair[1] > pair[0],
            "deflection does not grow with the wind: {deflection:?}"
        );
    }
    // Same ρ w (1.2 × 8 = 2.4 × 4): the same steady shape, to within what
    // both runs have left to settle plus rounding. The rounding: a spring
    // force k (d - L0) with d ~ 0.1 m rounded at ~1e-17 m is off by ~1e-14
    // N; over the out-of-plane stiffness of the taut sheet (≳ 10 N/m per
    // particle) that moves the equilibrium by ~1e-15 m. 1e-12 m covers it.
    let (same_a, same_b) = (&runs[3], &runs[4]);
    let apart = largest_distance(&same_a.position, &same_b.position);
    let allowed = same_a.moved + same_b.moved + 1e-12;
    assert!(
        apart <= allowed,
        "(ρ, 2w) and (2ρ, w) settle {apart:.2e} m apart, allowed {allowed:.2e} m"
    );
    // Twice the density at the same wind: more deflection.
    assert!(
        deflection[4] > deflection[2],
        "2ρ: {} m, ρ: {} m",
        deflection[4],
        deflection[2]
    );
    // The cube-root law. Every spring of the flat sheet is at its rest
    // length, so the unloaded sheet is slack: with the out-of-plane
    // deflection of order u and the in-plane displacements of order u²,
    // every spring stretches by O(u²) (`Δx + Δz²/2L0`), its tension is
    // O(u²), and the out-of-plane part of its pull O(u³). The load (ρ w
    // times the area, linear in w) is balanced by a force homogeneous of
    // degree 3 in u, so u ∝ load^(1/3): 8 times the load (w = 8 against
    // w = 1) doubles the deflection. The law holds up to relative
    // corrections of the order of the square of the sheet's slope s: the
    // z-part of the follower load (ρ A w n_z², 1 - s² at slope s), the
    // tilt of the pull (Δz/d against Δz/L0, s²/2), the next term of the
    // stretch, the in-plane push of the tilted load. They enter the ratio
    // as C s_8² (1 - 1/4), C of order 1: the ratio is held to 2 (1 ± s_8²),
    // s_8 the steepest slope of the w = 8 sheet.
    let sheet = &runs[3].position;
    let spacing = 1.0 / (SHEET_N - 1) as Real;
    let at = |x: usize, y: usize| sheet[y * SHEET_N + x].z;
    let steepest = (0..SHEET_N)
        .flat_map(|a| (0..SHEET_N - 1).map(move |b| (a, b)))
        .map(|(a, b)| {
            let along_x = (at(b + 1, a) - at(b, a)).abs();
            let along_y = (at(a, b + 1) - at(a, b)).abs();
            along_x.max(along_y) / spacing
        })
        .fold(0.0, Real::max);
    let ratio = deflection[3] / deflection[0];
    assert!(
        (ratio / 2.0 - 1.0).abs() <= steepest * steepest,
        "8 times the load: deflection × {ratio}, expected 2 (cube root) within ± {:.2e}",
        2.0 * steepest * steepest
    );
    // The slope is small enough for the bound to mean something: ± s² is
    // far from 8 (a taut, linear membrane) or 8^(1/2).
    assert!(steepest < 0.5, "steepest slope {steepest}");
}

// ------------------------------------------------------------------ the flag

#[test]
fn a_flag_in_a_steady_wind_keeps_fluttering_with_bounded_energy() {
    // scenes/flag.toml at 12 × 8 particles instead of 30 × 20: the same
    // 3 m × 2 m cloth of 0.6 kg, springs of 800 N/m and 0.02 N·s/m (for a
    // square grid the membrane's stiffness, k per unit strain and width,
    // does not depend on the spacing), the x = 0 column pinned, turned 10°
    // about the pole, in a uniform 8 m/s wind along x with gravity. The
    // simple model's coefficient is per particle: the scene's 0.02 N·s/m on
    // 600 particles, 12 N·s/m in all, is shared among the 96 here, so the
    // wind acts on each kilogram of flag as in the scene (c/m = 20 /s).
    let (nx, ny) = (12, 8);
    let count = (nx * ny) as Real;
    let coefficient = 0.02 * 600.0 / count;
    let speed = 8.0;
    let flag = build::cloth(nx, ny, 3.0, 2.0, ClothSprings::default())
        .expect("valid cloth")
        .with_total_mass(0.6)
        .with_stiffness(800.0)
        .with_damping(0.02)
        .with_pinned((0..ny).map(|y| y * nx).collect())
        .placed(1.0, Vec3::new(0.0, 10.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("flag", flag).expect("valid flag");
    let wind = Wind::new(
        WindField::uniform(Vec3::new(speed, 0.0, 0.0)),
        WindModel::Simple { coefficient },
    )
    .expect("valid wind");
    world.forces.push(Box::new(wind));
    // Half the stable step (symplectic Euler is stable below it; the half
    // is a margin for what the estimate leaves out: the wind's own damping
    // of normal motion, c/m = 20 /s, and the geometric stiffness T/L of
    // the stretched springs, both small beside √(k/m) ~ 700 rad/s).
    let dt = 0.5 * world.stable_time_step();
    let duration = 30.0;
    let steps = (duration / dt).round() as usize;

    // The energy bound. Gravity and the springs are in the total energy E,
    // the spring dampers only take energy out, so E grows at most at the
    // wind's power Σ c ((w - v)·n)(v·n) = Σ c (a - b) b with a = w·n,
    // b = v·n: at most c a²/4 ≤ c |w|²/4 per free particle. So
    // E(t) ≤ E(0) + P t with P = c N_free |w|²/4 (176 W here). Symplectic
    // Euler adds no drift, only a bounded error, at most h/2 of the
    // oscillating (kinetic and elastic) energy of each mode, h = ω dt ≤ 1
    // at half the stable step: a few joules at most, below the
    // P × 0.1 s = 17.6 J the bound has grown by at the first check.
    let free = ((nx - 1) * ny) as Real; // all but the pole's column
    let power = coefficient * free * speed * speed / 4.0;
    let initial = world.energies().total();
    let check_every = (0.1 / dt).round() as usize;

    // What "moving" means, over the last 10 s: the kinetic energy never
    // falls below 1 % of ½ M |w|² (19.2 J, the flag carried along by the
    // wind), which a flag coming to rest would (with the wind relaxing its
    // normal motion at c/m = 20 /s, its kinetic energy would fall by many
    // orders of magnitude in 10 s); and each free corner swings from one
    // side of the plane of pole and wind (z = 0) to the other and back
    // (at least two changes of sign of z), over more than a tenth of the
    // flag's width (0.3 m).
    let floor = 0.01 * 0.5 * 0.6 * speed * speed;
    let corners = [nx - 1, nx * ny - 1];
    let watch_from = duration - 10.0;
    let mut lowest_kinetic = Real::INFINITY;
    let mut sign_changes = [0usize; 2];
    let mut last_sign = [0.0; 2];
    let mut range = [(Real::INFINITY, Real::NEG_INFINITY); 2];
    for step in 1..=steps {
        world
            .step(dt)
            .unwrap_or_else(|error: StepError| panic!("the flag blew up: {error}"));
        if step % check_every == 0 {
            let energy = world.energies().total();
            let bound = initial + power * world.time();
            assert!(
                energy <= bound,
                "t = {:.2} s: energy {energy:.3} J above the wind's bound {bound:.3} J",
                world.time()
            );
        }
        if world.time() >= watch_from {
            let kinetic: Real = world
                .particles
                .velocity
                .iter()
                .zip(&world.particles.mass)
                .map(|(v, m)| 0.5 * m * v.length_squared())
                .sum();
            lowest_kinetic = lowest_kinetic.min(kinetic);
            for (k, &corner) in corners.iter().enumerate() {
                let z = world.particles.position[corner].z;
                let sign = z.signum();
                if last_sign[k] != 0.0 && sign != last_sign[k] {
                    sign_changes[k] += 1;
                }
                last_sign[k] = sign;
                range[k] = (range[k].0.min(z), range[k].1.max(z));
            }
        }
    }
    assert!(
        lowest_kinetic >= floor,
        "kinetic energy fell to {lowest_kinetic:.3e} J in the last 10 s (floor {floor} J)"
    );
    for (k, &corner) in corners.iter().enumerate() {
        let (low, high) = range[k];
        assert!(
            sign_changes[k] >= 2 && high - low > 0.3,
            "corner {corner}: {} changes of side, z in [{low:.3}, {high:.3}] m over the last 10 s",
            sign_changes[k]
        );
    }
}
