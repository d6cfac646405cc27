//! Wind on surfaces (docs/physics.md §3). The claims:
//!
//! 1. a flat patch facing the wind feels exactly each model's force: the
//!    simple model `c ((w - v)·n) n` on every particle, the area model
//!    `ρ A ((w - v)·n) n` per face, a third to each vertex; an oblique wind
//!    gives the `cos θ` of the normal part, and lift adds its share across
//!    the wind;
//! 2. wind along the patch, or a patch moving with the wind, feels nothing;
//! 3. a free flat patch approaches the wind's normal speed as
//!    `w_n (1 - exp(-λ t))`, `λ = c / m` (simple) or `ρ A / 3m` (area);
//! 4. a sheet pinned on all four sides billows downwind, the more so the
//!    stronger the wind, and its steady shape depends on `ρ w` only; a slack
//!    membrane's deflection grows as the cube root of the load;
//! 5. a flag in a steady wind flutters for 30 s without blowing up, its
//!    energy below what the wind could have put in;
//! 6. gusts and turbulence repeat exactly for a seed, stay in their bounds,
//!    average out and are smooth;
//! 7. a body's wind scale scales its force, and bad coefficients are refused.
//!
//! Unless a test says otherwise, gravity is off and the forces are read
//! with `World::evaluate_forces` on a world holding nothing but the bodies
//! and the wind.

mod common;

use common::Rng;
use sprung::build::{self, ClothSprings};
use sprung::forces::{Gusts, Turbulence, Wind, WindField, WindModel};
use sprung::{BodyData, BuildError, IntegratorKind, Real, StepError, Vec3, World};

/// Relative tolerance of the force claims: each force is a handful of
/// products and sums of numbers of order 1, so rounding leaves ~1e-15 of
/// the force; 1e-9 is the bound, far above it.
const FORCE_TOLERANCE: Real = 1e-9;

/// A world without gravity holding `body`, stepped by `kind`, with `wind`
/// (from `field`, through `model`) as its one extra force.
fn windy_world(kind: IntegratorKind, body: BodyData, field: WindField, model: WindModel) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("patch", body).expect("valid body");
    let wind = Wind::new(field, model).expect("valid wind model");
    world.forces.push(Box::new(wind));
    world
}

/// The forces (N) on every particle of `body` in a uniform wind `w` (m/s).
fn forces(body: BodyData, w: Vec3, model: WindModel) -> Vec<Vec3> {
    let mut world = windy_world(
        IntegratorKind::SymplecticEuler,
        body,
        WindField::uniform(w),
        model,
    );
    world.evaluate_forces();
    world.particles.force.clone()
}

/// Assert `found` is `expected` within `FORCE_TOLERANCE` of `scale` (N).
fn assert_force(found: Vec3, expected: Vec3, scale: Real, what: &str) {
    assert!(
        (found - expected).length() <= FORCE_TOLERANCE * scale,
        "{what}: force {found:?}, expected {expected:?}"
    );
}

// ------------------------------------------------------------- flat patches

/// A tilted triangle's frame: the unit normal `n = (1, 2, 2)/3` and two
/// unit vectors `e1 = (2, 1, -2)/3`, `e2 = (2, -2, 1)/3` in its plane (the
/// three are orthonormal: every dot product is 0 and every length 1).
fn frame() -> (Vec3, Vec3, Vec3) {
    (
        Vec3::new(1.0, 2.0, 2.0) / 3.0,
        Vec3::new(2.0, 1.0, -2.0) / 3.0,
        Vec3::new(2.0, -2.0, 1.0) / 3.0,
    )
}

/// Area of [`triangle`] (m²): in-plane corners (0, 0), (1.5, 0), (0.5, 1.2),
/// so base 1.5 m and height 1.2 m.
const TRIANGLE_AREA: Real = 0.9;

/// One springless triangle of particles of mass `mass` (kg) in the plane of
/// [`frame`], its corners at in-plane coordinates (0, 0), (1.5, 0),
/// (0.5, 1.2) from the point (0.4, -0.7, 1.3).
fn triangle(mass: Real) -> BodyData {
    let (_, e1, e2) = frame();
    let origin = Vec3::new(0.4, -0.7, 1.3);
    let corners = [(0.0, 0.0), (1.5, 0.0), (0.5, 1.2)];
    let mut body =
        BodyData::from_positions(corners.map(|(a, b)| origin + a * e1 + b * e2).to_vec())
            .with_mass(mass);
    body.faces = vec![[0, 1, 2]];
    body
}

/// A springless `nx × ny` cloth of `width × height` (m) in the plane z = 0,
/// every particle of mass `mass` (kg). Its faces are counter-clockwise seen
/// from +z: every normal is exactly (0, 0, 1).
fn flat_cloth(nx: usize, ny: usize, width: Real, height: Real, mass: Real) -> BodyData {
    let none = ClothSprings {
        structural: false,
        shear: false,
        bending: false,
    };
    build::cloth(nx, ny, width, height, none)
        .expect("valid cloth")
        .with_mass(mass)
}

/// Number of the cloth's triangles around particle `(x, y)` of an
/// `nx × ny` cloth, from the builder's split of cell `(x, y)` into
/// `(x,y) (x+1,y) (x+1,y+1)` and `(x,y) (x+1,y+1) (x,y+1)`: a particle is
/// in both triangles of the cell it is the low corner of, one of the cell
/// to its left, both of the cell below-left and one of the cell below.
fn triangles_around(x: usize, y: usize, nx: usize, ny: usize) -> usize {
    let cell = |cx: Option<usize>, cy: Option<usize>| match (cx, cy) {
        (Some(cx), Some(cy)) => cx + 1 < nx && cy + 1 < ny,
        _ => false,
    };
    let (left, below) = (x.checked_sub(1), y.checked_sub(1));
    2 * cell(Some(x), Some(y)) as usize
        + cell(left, Some(y)) as usize
        + 2 * cell(left, below) as usize
        + cell(Some(x), below) as usize
}

const SIMPLE: WindModel = WindModel::Simple { coefficient: 0.7 }; // N·s/m
const RHO: Real = 1.2; // kg/m³
const AREA: WindModel = WindModel::Area {
    air_density: RHO,
    lift: 0.0,
};

#[test]
fn a_triangle_facing_the_wind_gets_each_models_force() {
    let (n, _, _) = frame();
    let speed = 5.0; // m/s
    let w = speed * n;
    // Simple: the one face's normal is every particle's normal.
    let c = 0.7;
    for (i, f) in forces(triangle(1.0), w, SIMPLE).into_iter().enumerate() {
        let expected = c * speed * n;
        assert_force(
            f,
            expected,
            expected.length(),
            &format!("simple, particle {i}"),
        );
    }
    // Area: ρ A w n, a third to each vertex.
    for (i, f) in forces(triangle(1.0), w, AREA).into_iter().enumerate() {
        let expected = RHO * TRIANGLE_AREA * speed * n / 3.0;
        assert_force(f, expected, expected.length(), &format!("area, vertex {i}"));
    }
    // The sign of the normal does not matter: the wind from the other side
    // pushes the other way with the same strength.
    for f in forces(triangle(1.0), -w, AREA) {
        let expected = -RHO * TRIANGLE_AREA * speed * n / 3.0;
        assert_force(f, expected, expected.length(), "area, wind from behind");
    }
}

#[test]
fn an_oblique_wind_pushes_along_the_normal_with_cos_theta() {
    let (n, e1, e2) = frame();
    let speed = 5.0;
    for degrees in [0.0, 20.0, 45.0, 70.0] {
        let theta = Real::to_radians(degrees);
        // The in-plane part of the wind in a direction between e1 and e2,
        // so that no coordinate is special.
        let along = (0.6 * e1 + 0.8 * e2).normalize();
        let w = speed * (theta.cos() * n + theta.sin() * along);
        for (i, f) in forces(triangle(1.0), w, SIMPLE).into_iter().enumerate() {
            let expected = 0.7 * speed * theta.cos() * n;
            // Scale: the facing force, so that 70° is held to the same
            // absolute accuracy as 0°.
            assert_force(f, expected, 0.7 * speed, &format!("simple {degrees}°, {i}"));
        }
        for (i, f) in forces(triangle(1.0), w, AREA).into_iter().enumerate() {
            let expected = RHO * TRIANGLE_AREA * speed * theta.cos() * n / 3.0;
            let scale = RHO * TRIANGLE_AREA * speed / 3.0;
            assert_force(f, expected, scale, &format!("area {degrees}°, {i}"));
        }
    }
}

#[test]
fn lift_adds_its_share_of_the_force_across_the_wind() {
    // The code's doc: lift adds `lift` times the part of the force
    // perpendicular to the relative wind u. With u = W (cos θ n + sin θ t)
    // (t a unit vector in the plane), û = u / W and p = sin θ n - cos θ t
    // (the unit vector perpendicular to û in the plane of n and u, since
    // n = cos θ û + sin θ p), the force without lift is
    //   f0 = ρ A W cos θ n = ρ A W cos θ (cos θ û + sin θ p),
    // its part across the wind is ρ A W cos θ sin θ p, so
    //   f = ρ A W cos θ [cos θ û + (1 + lift) sin θ p]:
    // a drag ρ A W cos²θ along the wind and a lift (1 + lift) ρ A W
    // cos θ sin θ (∝ sin 2θ) across it, a third to each vertex.
    let (n, e1, _) = frame();
    let (speed, lift) = (5.0, 0.8);
    let model = WindModel::Area {
        air_density: RHO,
        lift,
    };
    let scale = RHO * TRIANGLE_AREA * speed / 3.0;
    for degrees in [0.0, 15.0, 45.0, 60.0] {
        let theta = Real::to_radians(degrees);
        let (s, c) = theta.sin_cos();
        let u_hat = c * n + s * e1;
        let p = s * n - c * e1;
        let expected = scale * c * (c * u_hat + (1.0 + lift) * s * p);
        for (i, f) in forces(triangle(1.0), speed * u_hat, model)
            .into_iter()
            .enumerate()
        {
            assert_force(f, expected, scale, &format!("lift {degrees}°, vertex {i}"));
            // Drag and lift read separately.
            let (drag_part, lift_part) = (f.dot(u_hat), f.dot(p));
            assert!(
                (drag_part - scale * c * c).abs() <= FORCE_TOLERANCE * scale
                    && (lift_part - scale * (1.0 + lift) * c * s).abs() <= FORCE_TOLERANCE * scale,
                "lift {degrees}°: drag {drag_part}, lift {lift_part}"
            );
        }
    }
}

#[test]
fn a_flat_cloth_facing_the_wind_gets_each_models_force() {
    let (nx, ny, width, height) = (5, 4, 2.0, 1.5);
    let (dx, dy) = (width / (nx - 1) as Real, height / (ny - 1) as Real);
    // Oblique: only the normal part w_z counts.
    let w = Vec3::new(1.5, -2.0, 4.0);
    let cloth = || flat_cloth(nx, ny, width, height, 0.1);
    // Simple: every particle's normal is the common face normal z.
    for (i, f) in forces(cloth(), w, SIMPLE).into_iter().enumerate() {
        let expected = Vec3::new(0.0, 0.0, 0.7 * w.z);
        assert_force(
            f,
            expected,
            expected.length(),
            &format!("simple, particle {i}"),
        );
    }
    // Area: a third of ρ (dx dy / 2) w_z per triangle around the vertex
    // (6 inside, 1 to 3 on the border), ρ w_z × the whole area in all.
    let f = forces(cloth(), w, AREA);
    for y in 0..ny {
        for x in 0..nx {
            let triangles = triangles_around(x, y, nx, ny) as Real;
            let expected = Vec3::new(0.0, 0.0, RHO * w.z * triangles * dx * dy / 6.0);
            let scale = RHO * w.z * dx * dy;
            assert_force(f[y * nx + x], expected, scale, &format!("area, ({x}, {y})"));
        }
    }
    let total: Vec3 = f.iter().sum();
    let expected = Vec3::new(0.0, 0.0, RHO * w.z * width * height);
    assert_force(total, expected, expected.length(), "area, total");
}

#[test]
fn on_a_folded_patch_the_simple_model_averages_the_face_normals() {
    // Two triangles folded along the edge 0-1 (the x axis): face [0, 1, 2]
    // with normal (1,0,0) × (0,1,0) = (0, 0, 1), face [1, 0, 3] with normal
    // (-1,0,0) × (-0.5,-0.6,0.8) = (0, 0.8, 0.6), both unit and each of
    // area ½. Particles 2 and 3 see one face each; 0 and 1 the normalised
    // average (0, 0.8, 1.6)/|·| = (0, 1, 2)/√5. In the wind w = (1, 2, 3):
    //   particle 2: c (w·n1) n1 = 3c (0, 0, 1),
    //   particle 3: c (w·n2) n2 = 3.4c (0, 0.8, 0.6),
    //   particles 0, 1: c (8/√5) (0, 1, 2)/√5 = c (0, 1.6, 3.2).
    // The area model pushes each face on its own: ρ ½ (w·n) n / 3 to each
    // of its vertices, both faces' shares to 0 and 1.
    let mut body = BodyData::from_positions(vec![
        Vec3::ZERO,
        Vec3::X,
        Vec3::Y,
        Vec3::new(0.5, -0.6, 0.8),
    ]);
    body.faces = vec![[0, 1, 2], [1, 0, 3]];
    let w = Vec3::new(1.0, 2.0, 3.0);
    let (n1, n2) = (Vec3::Z, Vec3::new(0.0, 0.8, 0.6));
    let c = 0.7;
    let on_fold = c * Vec3::new(0.0, 1.6, 3.2);
    let simple = [on_fold, on_fold, 3.0 * c * n1, 3.4 * c * n2];
    for (i, (f, expected)) in forces(body.clone(), w, SIMPLE)
        .into_iter()
        .zip(simple)
        .enumerate()
    {
        assert_force(
            f,
            expected,
            expected.length(),
            &format!("simple, particle {i}"),
        );
    }
    let (share1, share2) = (RHO * 0.5 * 3.0 * n1 / 3.0, RHO * 0.5 * 3.4 * n2 / 3.0);
    let area = [share1 + share2, share1 + share2, share1, share2];
    for (i, (f, expected)) in forces(body, w, AREA).into_iter().zip(area).enumerate() {
        assert_force(
            f,
            expected,
            expected.length(),
            &format!("area, particle {i}"),
        );
    }
}

/// Largest force (N) on any particle of `body` in wind `w`.
fn largest_force(body: BodyData, w: Vec3, model: WindModel) -> Real {
    forces(body, w, model)
        .iter()
        .map(|f| f.length())
        .fold(0.0, Real::max)
}

#[test]
fn wind_along_the_patch_gives_no_force() {
    let (_, e1, e2) = frame();
    let lifting = WindModel::Area {
        air_density: RHO,
        lift: 0.8,
    };
    // In the cloth's plane z = 0 the normal is exactly (0, 0, 1), so w·n is
    // exactly 0: the force is exactly zero.
    let w = Vec3::new(3.0, -4.0, 0.0);
    for model in [SIMPLE, AREA, lifting] {
        assert_eq!(
            largest_force(flat_cloth(5, 4, 2.0, 1.5, 0.1), w, model),
            0.0,
            "{model:?}"
        );
    }
    // The tilted triangle: its normal is rounded, so w·n is ~1e-16 w; held
    // to the force tolerance of the same wind facing it.
    let w = 5.0 * (0.6 * e1 + 0.8 * e2);
    for (model, facing) in [
        (SIMPLE, 0.7 * 5.0),
        (AREA, RHO * TRIANGLE_AREA * 5.0 / 3.0),
        (lifting, RHO * TRIANGLE_AREA * 5.0 / 3.0),
    ] {
        let largest = largest_force(triangle(1.0), w, model);
        assert!(
            largest <= FORCE_TOLERANCE * facing,
            "{model:?}: force {largest} N with the wind along the triangle"
        );
    }
}

#[test]
fn a_patch_moving_with_the_wind_feels_no_force() {
    let (n, e1, _) = frame();
    let lifting = WindModel::Area {
        air_density: RHO,
        lift: 0.8,
    };
    // An oblique wind (40° off the normal) and every particle moving with
    // it: the relative wind is zero (or, in the area model, the wind minus
    // the mean of three equal velocities, which rounds to within 1 ulp of
    // it).
    let theta = Real::to_radians(40.0);
    let w = 5.0 * (theta.cos() * n + theta.sin() * e1);
    for (model, facing) in [
        (SIMPLE, 0.7 * 5.0),
        (AREA, RHO * TRIANGLE_AREA * 5.0 / 3.0),
        (lifting, RHO * TRIANGLE_AREA * 5.0 / 3.0),
    ] {
        let largest = largest_force(triangle(1.0).with_velocity(w), w, model);
        assert!(
            largest <= FORCE_TOLERANCE * facing,
            "{model:?}: force {largest} N on a triangle moving with the wind"
        );
        let cloth = flat_cloth(5, 4, 2.0, 1.5, 0.1).with_velocity(w);
        let facing_cloth = match model {
            WindModel::Simple { coefficient } => coefficient * 5.0,
            WindModel::Area { air_density, .. } => air_density * 5.0 * 0.5 * 0.5,
        };
        let largest = largest_force(cloth, w, model);
        assert!(
            largest <= FORCE_TOLERANCE * facing_cloth,
            "{model:?}: force {largest} N on a cloth moving with the wind"
        );
    }
}

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

/// Largest distance between corresponding particles (m).
fn largest_distance(a: &[Vec3], b: &[Vec3]) -> Real {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, Real::max)
}

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

// ------------------------------------------------- body scale and refusals

#[test]
fn a_body_at_half_scale_feels_half_the_force() {
    // Two copies of the triangle, the second shifted by (4, 0, 0). Its
    // corners are not dyadic, so the copies' edge vectors can differ in the
    // last bit: the forces are compared to 1e-12 relative rather than
    // exactly (the scale itself, 0.5, is applied exactly).
    let (n, e1, _) = frame();
    let w = 5.0 * n + 2.0 * e1;
    for model in [SIMPLE, AREA] {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        world.add_body("full", triangle(1.0)).expect("valid body");
        let shifted = triangle(1.0).placed(1.0, Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0));
        world.add_body("half", shifted).expect("valid body");
        let mut wind = Wind::new(WindField::uniform(w), model).expect("valid wind");
        wind.set_body_scale(1, 0.5).expect("0.5 is a valid scale");
        world.forces.push(Box::new(wind));
        world.evaluate_forces();
        let f = &world.particles.force;
        for i in 0..3 {
            let (full, half) = (f[i], f[i + 3]);
            assert!(full.length() > 0.0, "{model:?}: no force on the full body");
            assert!(
                (half - 0.5 * full).length() <= 1e-12 * full.length(),
                "{model:?}, vertex {i}: {half:?} at scale 0.5, {full:?} at scale 1"
            );
        }
    }
}

#[test]
fn negative_or_non_finite_body_scales_are_refused() {
    let mut wind = Wind::new(WindField::uniform(Vec3::X), AREA).expect("valid wind");
    wind.set_body_scale(2, 0.25).expect("0.25 is a valid scale");
    for bad in [-0.5, Real::NAN, Real::INFINITY] {
        let error = wind.set_body_scale(2, bad).expect_err("must be refused");
        assert!(
            matches!(
                error,
                BuildError::OutOfRange {
                    field: "wind_scale",
                    ..
                }
            ),
            "{bad}: {error:?}"
        );
        assert!(error.to_string().contains("`wind_scale`"), "{error}");
    }
    // A refused scale leaves the body's scale as it was.
    assert_eq!(wind.body_scale.get(2), Some(&0.25));
    // Zero is allowed: a fully sheltered body.
    wind.set_body_scale(0, 0.0).expect("0 is a valid scale");
}

#[test]
fn bad_wind_coefficients_are_refused() {
    let cases = [
        (WindModel::Simple { coefficient: -1.0 }, "coefficient"),
        (
            WindModel::Simple {
                coefficient: Real::NAN,
            },
            "coefficient",
        ),
        (
            WindModel::Area {
                air_density: -1.2,
                lift: 0.0,
            },
            "air_density",
        ),
        (
            WindModel::Area {
                air_density: Real::INFINITY,
                lift: 0.0,
            },
            "air_density",
        ),
        (
            WindModel::Area {
                air_density: 1.2,
                lift: Real::NAN,
            },
            "lift",
        ),
    ];
    for (model, field) in cases {
        let error = model.validate().expect_err("must be refused");
        assert!(
            matches!(error, BuildError::OutOfRange { field: f, .. } if f == field),
            "{model:?}: {error:?}"
        );
        assert!(
            Wind::new(WindField::uniform(Vec3::X), model).is_err(),
            "{model:?}: Wind::new accepted it"
        );
    }
    // The edge values are fine: no wind force at all, no lift.
    for model in [
        WindModel::Simple { coefficient: 0.0 },
        WindModel::Area {
            air_density: 0.0,
            lift: 0.0,
        },
    ] {
        model.validate().expect("zero is allowed");
    }
}

#[test]
fn wind_new_refuses_bad_gusts_and_turbulence() {
    let model = WindModel::Simple { coefficient: 1.0 };
    let w = Vec3::new(5.0, 0.0, 0.0);
    let gusts = |amplitude, period| Some(Gusts { amplitude, period });
    let turbulence = |amplitude, length_scale, time_scale| {
        Some(Turbulence {
            amplitude,
            length_scale,
            time_scale,
        })
    };
    let refused = [
        WindField::varying(w, gusts(1.5, 1.0), None, 1),
        WindField::varying(w, gusts(0.5, 0.0), None, 1),
        WindField::varying(w, None, turbulence(-1.0, 1.0, 1.0), 1),
        WindField::varying(w, None, turbulence(1.0, 0.0, 1.0), 1),
        WindField::varying(w, None, turbulence(1.0, 1.0, f64::NAN), 1),
        WindField::uniform(Vec3::new(f64::INFINITY, 0.0, 0.0)),
    ];
    for field in refused {
        assert!(
            Wind::new(field.clone(), model).is_err(),
            "{field:?} was accepted"
        );
    }
    assert!(Wind::new(
        WindField::varying(w, gusts(1.0, 2.0), turbulence(0.0, 1.0, 1.0), 1),
        model
    )
    .is_ok());
}
