//! Wind forces on surfaces (docs/physics.md §3). The claims:
//!
//! 1. a flat patch facing the wind feels exactly each model's force: the
//!    simple model `c ((w - v)·n) n` on every particle, the area model
//!    `ρ A ((w - v)·n) n` per face, a third to each vertex; an oblique wind
//!    gives the `cos θ` of the normal part, and lift adds its share across
//!    the wind;
//! 2. wind along the patch, or a patch moving with the wind, feels nothing;
//! 3. a body's wind scale scales its force, and bad coefficients are refused.
//!
//! Unless a test says otherwise, gravity is off and the forces are read
//! with `World::evaluate_forces` on a world holding nothing but the bodies
//! and the wind. What the wind does over time is in `wind_motion.rs`, its
//! gusts and turbulence in `wind_fields.rs`.

mod common;

use common::wind::{flat_cloth, frame, triangle, windy_world, AREA, RHO, TRIANGLE_AREA};
use sprung::forces::{Gusts, Turbulence, Wind, WindField, WindModel};
use sprung::{BodyData, BuildError, IntegratorKind, Real, Vec3, World};

/// Relative tolerance of the force claims: each force is a handful of
/// products and sums of numbers of order 1, so rounding leaves ~1e-15 of
/// the force; 1e-9 is the bound, far above it.
const FORCE_TOLERANCE: Real = 1e-9;

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
