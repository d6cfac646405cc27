//! Enclosed volume and area (docs/physics.md §4 "Volume"): the divergence-theorem
//! sums are exact for polygons and polyhedra, the textbook's 2D formula is
//! not, the builders' rings and icospheres converge to the circle and the
//! sphere at the predicted rates, the cruder volume models give the box and
//! ellipsoid volumes exactly, and a gas is refused on anything that does not
//! enclose a volume.
//!
//! Round-off: a sum of `n` terms each within a few ε (2.2e-16) of exact is
//! within about `n ε` of the sum of their magnitudes; every exact claim here
//! uses 1e-12 relative, far above that for the sizes used (n ≤ 1000) and far
//! below any modelling error the tests look for.

mod common;

use std::f64::consts::{PI, TAU};

use common::{box_surface, faces_u32, segments_u32};
use sprung::build::{self, Internal, SurfaceSprings};
use sprung::surface::{self, SurfaceProblem};
use sprung::{BodyData, BuildError, Gas, IntegratorKind, Real, Vec3, VolumeModel, World};

/// Tolerance of the exact identities (see the module comment).
const EXACT: Real = 1e-12;

fn assert_close(value: Real, expected: Real, relative: Real, what: &str) {
    assert!(
        (value - expected).abs() <= relative * expected.abs(),
        "{what}: {value:.17e}, expected {expected:.17e} (relative error {:.3e}, allowed {relative:.1e})",
        (value / expected - 1.0).abs()
    );
}

/// A world (no gravity) holding `body` as body 0.
fn world_with(body: BodyData) -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("body", body).expect("valid body");
    world
}

/// Area of the regular N-gon of circumradius `r`: N triangles of apex angle
/// 2π/N, each ½ r² sin(2π/N).
fn polygon_area(n: usize, r: Real) -> Real {
    0.5 * n as Real * r * r * (TAU / n as Real).sin()
}

/// The builder's ring: positions and `u32` segments.
fn ring_points(n: usize, r: Real) -> (Vec<Vec3>, Vec<[u32; 2]>) {
    let ring = build::ring(n, r).expect("valid ring");
    let segments = segments_u32(&ring.segments);
    (ring.position, segments)
}

// ------------------------------------------------------------- 2D: area

#[test]
fn regular_polygon_area_is_exact() {
    for n in [3, 4, 5, 7, 12, 17, 100, 1000] {
        for (r, centre) in [(1.0, Vec3::ZERO), (1.5, Vec3::new(3.0, -2.0, 0.0))] {
            let (mut position, segments) = ring_points(n, r);
            position.iter_mut().for_each(|p| *p += centre);
            // Shoelace = divergence theorem: exact for any polygon, and
            // translation-invariant (Σ Δy = 0 around a closed loop).
            assert_close(
                surface::enclosed_area(&position, &segments),
                polygon_area(n, r),
                EXACT,
                &format!("area of the {n}-gon of radius {r} at {centre}"),
            );
        }
    }
}

#[test]
fn ring_area_converges_to_the_circle_at_the_predicted_rate() {
    // With u = 2π/N, A_N = ½ N R² sin u = π R² (sin u)/u, and
    // sin u / u = 1 - u²/6 + u⁴/120 - ..., an alternating series with
    // decreasing terms for u < √20, so its partial sums bracket it:
    //   π R² (u²/6 - u⁴/120) ≤ π R² - A_N ≤ π R² u²/6 = (2π³/3) R²/N².
    // The ratio of the deficit to (2π³/3) R²/N² therefore lies in
    // [1 - u²/20, 1]: the error falls as 1/N² with exactly that constant.
    let r = 1.3;
    let circle = PI * r * r;
    let mut previous = 0.0;
    for n in [17, 32, 64, 128, 256, 512] {
        let (position, segments) = ring_points(n, r);
        let area = surface::enclosed_area(&position, &segments);
        assert!(
            area < circle,
            "N = {n}: area {area} not below π R² = {circle}"
        );
        assert!(area > previous, "N = {n}: area {area} did not grow");
        previous = area;
        let u = TAU / n as Real;
        let predicted = 2.0 * PI.powi(3) / 3.0 * r * r / (n * n) as Real;
        let ratio = (circle - area) / predicted;
        // Round-off: the area carries an absolute error of at most
        // (N + 8) ε π R² (N terms, and the vertices' sines and cosines),
        // which the difference divides by the deficit.
        let slack = (n + 8) as Real * Real::EPSILON * circle / predicted;
        assert!(
            ratio >= 1.0 - u * u / 20.0 - slack && ratio <= 1.0 + slack,
            "N = {n}: (π R² - A_N) / ((2π³/3) R²/N²) = {ratio:.12}, expected in [{:.12}, 1]",
            1.0 - u * u / 20.0
        );
    }
}

/// The textbook's sum `Σ ½ |Δx| |Δy|` for the builder's regular N-gon
/// (vertex k at angle 2πk/N). Edge k runs from angle θ_k to θ_k + 2π/N, so
/// `Δx = -2R sin(π/N) sin φ_k`, `Δy = 2R sin(π/N) cos φ_k` with
/// `φ_k = (2k+1)π/N`, and the term is `R² sin²(π/N) |sin 2φ_k|`. The angles
/// `2φ_k = (2k+1) 2π/N` reduced mod π give, with
/// `Σ_{j<M} sin(jπ/M) = cot(π/2M)` and
/// `Σ_{i<M/2} sin((2i+1)π/M) = 1/sin(π/M)`:
///   - N odd:      each multiple of π/N once:  Σ = cot(π/2N),
///     so the sum is `R² sin(π/N) (1 + cos(π/N))`;
///   - N ≡ 2 (4):  each multiple of 2π/N twice: Σ = 2 cot(π/N),
///     so the sum is `R² sin(2π/N)`;
///   - N ≡ 0 (4):  odd multiples of 2π/N, four times: Σ = 4/sin(2π/N),
///     so the sum is `2 R² tan(π/N)`.
fn textbook_closed_form(n: usize, r: Real) -> Real {
    let v = PI / n as Real;
    r * r
        * match n % 4 {
            0 => 2.0 * v.tan(),
            2 => (2.0 * v).sin(),
            _ => v.sin() * (1.0 + v.cos()),
        }
}

#[test]
fn textbook_segment_formula_gives_about_2_pi_r_squared_over_n() {
    let r = 1.2;
    for n in [3, 4, 5, 6, 7, 8, 12, 17, 30, 64, 101] {
        let (position, segments) = ring_points(n, r);
        let textbook = surface::textbook_segment_area(&position, &segments);
        assert_close(
            textbook,
            textbook_closed_form(n, r),
            EXACT,
            &format!("textbook sum for the {n}-gon"),
        );
        // Expanding the closed forms in v = π/N: (sin v)/v · (1 + cos v)/2,
        // (sin 2v)/(2v) and (tan v)/v are 1 - 5v²/12, 1 - 2v²/3 and
        // 1 + v²/3 to leading order, and within 2v²/3 of 1 for all N ≥ 3
        // (alternating series for the first two; tan v / v - 1 ≤ 2v²/3 for
        // v ≤ π/4). So the textbook sum is 2πR²/N to within 2π²/(3N²).
        let about = TAU * r * r / n as Real;
        let bound = 2.0 * PI * PI / (3.0 * (n * n) as Real);
        assert!(
            (textbook / about - 1.0).abs() <= bound,
            "N = {n}: textbook {textbook} vs 2πR²/N = {about}: off by more than {bound:.3e}"
        );
        // It is not the area: it coincides with it for the triangle and the
        // diamond (N = 3, 4 in this orientation) and is off by a factor of
        // about N/2 from there on (already 2.2 at N = 5).
        let area = polygon_area(n, r);
        if n >= 5 {
            assert!(
                textbook < 0.5 * area,
                "N = {n}: textbook {textbook} vs area {area}"
            );
        } else {
            assert_close(textbook, area, EXACT, "triangle or diamond");
        }
    }
}

#[test]
fn axis_aligned_square_textbook_area_is_zero_exact_area_is_side_squared() {
    let side = 2.5;
    let low = Vec3::new(1.0, -3.0, 0.0);
    let position = vec![
        low,
        low + Vec3::new(side, 0.0, 0.0),
        low + Vec3::new(side, side, 0.0),
        low + Vec3::new(0.0, side, 0.0),
    ];
    let segments = [[0, 1], [1, 2], [2, 3], [3, 0]];
    // Every edge has Δx = 0 or Δy = 0: each textbook term is exactly 0.
    assert_eq!(surface::textbook_segment_area(&position, &segments), 0.0);
    assert_close(
        surface::enclosed_area(&position, &segments),
        side * side,
        EXACT,
        "square",
    );
    // Clockwise, the same loop encloses minus the area.
    let reversed: Vec<[u32; 2]> = segments.iter().map(|&[a, b]| [b, a]).collect();
    assert_close(
        surface::enclosed_area(&position, &reversed),
        -side * side,
        EXACT,
        "clockwise square",
    );
}

#[test]
fn clockwise_ring_is_turned_outward_by_add_body() {
    let (n, r) = (9, 0.7);
    let mut ring = build::ring(n, r).expect("valid ring");
    ring.segments.iter_mut().for_each(|s| s.reverse());
    let raw = surface::enclosed_area(&ring.position, &segments_u32(&ring.segments));
    assert_close(raw, -polygon_area(n, r), EXACT, "clockwise ring as given");
    let world = world_with(ring);
    let area = world.volume(0).expect("a ring is closed");
    assert_close(area, polygon_area(n, r), EXACT, "ring after add_body");
}

// ------------------------------------------------------------- 3D: volume

#[test]
fn cube_of_side_two_has_volume_eight() {
    let (position, faces) = box_surface(Vec3::splat(-1.0), Vec3::splat(2.0));
    assert_eq!(faces.len(), 12);
    surface::check_closed_faces(&faces).expect("the box is closed and consistently oriented");
    assert_close(
        surface::enclosed_volume(&position, &faces_u32(&faces)),
        8.0,
        EXACT,
        "cube",
    );
    // Moved and turned, still 8 (and World::volume agrees).
    let body = build::surface(position.clone(), faces.clone(), SurfaceSprings::default())
        .expect("valid surface")
        .placed(1.0, Vec3::new(30.0, 40.0, 50.0), Vec3::new(3.7, -1.2, 5.1));
    let moved = surface::enclosed_volume(&body.position, &faces_u32(&body.faces));
    assert_close(moved, 8.0, EXACT, "cube turned and translated");
    let world = world_with(body);
    assert_close(
        world.volume(0).expect("closed"),
        8.0,
        EXACT,
        "World::volume",
    );
    // Faces all reversed: the same sum gives -8, and add_body turns them.
    let inward: Vec<[usize; 3]> = faces.iter().map(|&[a, b, c]| [a, c, b]).collect();
    assert_close(
        surface::enclosed_volume(&position, &faces_u32(&inward)),
        -8.0,
        EXACT,
        "cube with faces reversed",
    );
    let body = build::surface(position, inward, SurfaceSprings::default()).expect("valid");
    let world = world_with(body);
    assert_close(
        world.volume(0).expect("closed"),
        8.0,
        EXACT,
        "reversed cube after add_body",
    );
    // And its faces now point out: each face's normal agrees with the
    // direction from the cube's centre (the origin) to the face's centre.
    let x = &world.particles.position;
    for &[a, b, c] in &world.bodies[0].faces {
        let (a, b, c) = (x[a as usize], x[b as usize], x[c as usize]);
        assert!((b - a).cross(c - a).dot(a + b + c) > 0.0);
    }
}

#[test]
fn icosphere_has_the_exact_vertex_face_and_edge_counts() {
    let edges_only = SurfaceSprings {
        bending: false,
        internal: Internal::None,
    };
    for s in 0..=5 {
        let sphere = build::icosphere(1.0, s, edges_only).expect("valid icosphere");
        let power = 4usize.pow(s as u32);
        assert_eq!(sphere.position.len(), 10 * power + 2, "s = {s}: vertices");
        assert_eq!(sphere.faces.len(), 20 * power, "s = {s}: faces");
        // Euler: V - E + F = 2, so E = (10·4ˢ + 2) + 20·4ˢ - 2 = 30·4ˢ, and
        // there is one spring per edge.
        assert_eq!(sphere.springs.len(), 30 * power, "s = {s}: edges");
        surface::check_closed_faces(&sphere.faces).expect("closed and oriented");
    }
}

#[test]
fn icosahedron_volume_is_the_exact_regular_icosahedron_volume() {
    // A regular icosahedron of edge a has circumradius a sin(2π/5)
    // (= (a/4) √(10 + 2√5)) and volume 5 (3 + √5) a³ / 12.
    let r: Real = 1.7;
    let ico = build::icosphere(r, 0, SurfaceSprings::default()).expect("valid");
    let a = r / (TAU / 5.0).sin();
    let expected = 5.0 * (3.0 + 5.0_f64.sqrt()) * a.powi(3) / 12.0;
    // The builder's faces are outward as built (no reorientation needed).
    let volume = surface::enclosed_volume(&ico.position, &faces_u32(&ico.faces));
    assert_close(volume, expected, EXACT, "icosahedron");
    // And every edge has that length a.
    for &[i, j] in &surface::unique_edges(&ico.faces) {
        assert_close(ico.position[i].distance(ico.position[j]), a, EXACT, "edge");
    }
}

#[test]
fn icosphere_volume_approaches_the_sphere_from_below_at_second_order() {
    // Every vertex lies on the sphere and the polyhedron is convex, so it is
    // inside the ball: V_s < 4/3 π R³. The gap is a sum over faces of thin
    // caps of height ∝ h²/R on faces of edge h, so it falls as h², i.e. by
    // 4 per subdivision. Demanding a ratio in (3, 5) pins the order p of
    // 2^p to (1.58, 2.32): second order, not first (2) nor third (8).
    let r: Real = 0.8;
    let sphere = 4.0 / 3.0 * PI * r.powi(3);
    let gaps: Vec<Real> = (0..=5)
        .map(|s| {
            let body = build::icosphere(r, s, SurfaceSprings::default()).expect("valid");
            for p in &body.position {
                assert_close(p.length(), r, EXACT, "vertex on the sphere");
            }
            let volume = surface::enclosed_volume(&body.position, &faces_u32(&body.faces));
            assert!(volume < sphere, "s = {s}: V = {volume} not below {sphere}");
            sphere - volume
        })
        .collect();
    for s in 1..gaps.len() {
        assert!(gaps[s] < gaps[s - 1], "s = {s}: the gap did not shrink");
        let ratio = gaps[s - 1] / gaps[s];
        if s >= 2 {
            assert!(
                (3.0..5.0).contains(&ratio),
                "s = {}→{s}: gap ratio {ratio}, expected about 4",
                s - 1
            );
        }
    }
}

// ------------------------------------------------------------- volume models

/// The three models' volumes of body 0 of `world`.
fn model_volumes(world: &World) -> [Real; 3] {
    let body = &world.bodies[0];
    let x = &world.particles.position;
    [
        body.gas_volume(VolumeModel::Exact, x),
        body.gas_volume(VolumeModel::BoundingBox, x),
        body.gas_volume(VolumeModel::BoundingEllipsoid, x),
    ]
}

#[test]
fn volume_models_give_the_box_and_ellipsoid_volumes() {
    // A 2 × 3 × 0.5 box: exact = box = 3 m³, inscribed ellipsoid
    // (4/3) π (w/2)(h/2)(d/2) = π/6 · 3.
    let (position, faces) = box_surface(Vec3::new(-0.5, 1.0, 2.0), Vec3::new(2.0, 3.0, 0.5));
    let body = build::surface(position, faces, SurfaceSprings::default()).expect("valid");
    let [exact, boxed, ellipsoid] = model_volumes(&world_with(body));
    assert_close(exact, 3.0, EXACT, "box, exact");
    assert_close(boxed, 3.0, EXACT, "box, bounding box");
    assert_close(ellipsoid, PI / 6.0 * 3.0, EXACT, "box, ellipsoid");

    // The icosahedron of circumradius R: its vertices are (0, ±1, ±φ) and
    // cyclic, over √(1 + φ²), so its bounding box is a cube of side
    // 2 R φ / √(1 + φ²).
    let r: Real = 1.1;
    let phi = (1.0 + 5.0_f64.sqrt()) / 2.0;
    let side = 2.0 * r * phi / (1.0 + phi * phi).sqrt();
    let ico = build::icosphere(r, 0, SurfaceSprings::default()).expect("valid");
    let [exact, boxed, ellipsoid] = model_volumes(&world_with(ico));
    let a = r / (TAU / 5.0).sin();
    assert_close(
        exact,
        5.0 * (3.0 + 5.0_f64.sqrt()) * a.powi(3) / 12.0,
        EXACT,
        "icosahedron, exact",
    );
    assert_close(boxed, side.powi(3), EXACT, "icosahedron, bounding box");
    assert_close(
        ellipsoid,
        PI / 6.0 * side.powi(3),
        EXACT,
        "icosahedron, ellipsoid",
    );

    // A 16-gon has vertices on both axes: bounding square (2R)², inscribed
    // circle π R² (π/4 of the square). Stretched ×2 along x: 4R × 2R and the
    // ellipse π (2R) R; the exact area doubles too.
    let (n, r) = (16, 1.5);
    for stretch in [1.0, 2.0] {
        let mut ring = build::ring(n, r).expect("valid ring");
        ring.position.iter_mut().for_each(|p| p.x *= stretch);
        let [exact, boxed, ellipse] = model_volumes(&world_with(ring));
        let what = format!("16-gon stretched ×{stretch}");
        assert_close(exact, stretch * polygon_area(n, r), EXACT, &what);
        assert_close(boxed, stretch * 4.0 * r * r, EXACT, &what);
        assert_close(ellipse, stretch * PI * r * r, EXACT, &what);
    }
}

#[test]
fn volume_models_give_zero_for_a_body_that_is_not_closed() {
    // Body::gas_volume's contract: "0 for a body that is not closed",
    // for every model (a box with its top missing has a bounding box of
    // 1 m³, but encloses nothing).
    let (position, mut faces) = box_surface(Vec3::ZERO, Vec3::ONE);
    faces.truncate(10);
    let body = build::surface(position, faces, SurfaceSprings::default()).expect("valid");
    let world = world_with(body);
    assert_eq!(world.volume(0), None);
    assert_eq!(model_volumes(&world), [0.0; 3]);
}

#[test]
fn pressure_uses_the_chosen_volume_model() {
    // P = nRT / V with V from the model: for the 16-gon of radius R,
    // nRT/(½ N R² sin(2π/N)), nRT/(4R²), nRT/(π R²).
    let (n, r, nrt) = (16, 1.5, 7.0);
    for (model, volume) in [
        (VolumeModel::Exact, polygon_area(n, r)),
        (VolumeModel::BoundingBox, 4.0 * r * r),
        (VolumeModel::BoundingEllipsoid, PI * r * r),
    ] {
        let mut ring = build::ring(n, r).expect("valid ring");
        ring.gas = Some(Gas {
            volume_model: model,
            ..Gas::new(nrt, 0.0)
        });
        let world = world_with(ring);
        let pressure = world.pressure(0).expect("a gas");
        assert_close(pressure, nrt / volume, EXACT, model.name());
        assert_eq!(VolumeModel::from_name(model.name()), Some(model));
    }
}

// ------------------------------------------------------------- bad input

/// Add `body` to an empty world; it must be refused, leaving it empty.
fn refused(body: BodyData) -> BuildError {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let error = world.add_body("body", body).expect_err("must be refused");
    assert!(world.bodies.is_empty() && world.particles.is_empty());
    error
}

/// The error's message must name `key` (in backquotes, as the scene key).
fn assert_names(error: &BuildError, key: &str) {
    let message = error.to_string();
    assert!(
        message.contains(&format!("`{key}`")),
        "message does not name `{key}`: {message}"
    );
}

/// A box of side 1 with springs on its edges, its gas and faces as given.
fn gas_box(faces: Vec<[usize; 3]>) -> BodyData {
    let (position, _) = box_surface(Vec3::ZERO, Vec3::ONE);
    let mut body = build::surface(position, faces, SurfaceSprings::default())
        .expect("valid surface")
        .with_stiffness(100.0);
    body.gas = Some(Gas::new(1.0, 0.0));
    body
}

/// The edges `[lower, higher]` around the quad split into `triangles`
/// (the edges used by one of them only: the diagonal is used by both).
fn quad_outline(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    let all: Vec<[usize; 2]> = triangles
        .iter()
        .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
        .map(|[u, v]| [u.min(v), u.max(v)])
        .collect();
    all.iter()
        .copied()
        .filter(|e| all.iter().filter(|f| *f == e).count() == 1)
        .collect()
}

#[test]
fn gas_without_faces_or_segments_is_refused() {
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z]);
    body.gas = Some(Gas::new(1.0, 0.0));
    let error = refused(body);
    assert_eq!(error, BuildError::GasWithoutSurface);
    assert_names(&error, "gas");
}

#[test]
fn gas_in_a_single_triangle_is_refused_naming_a_boundary_edge() {
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    body.faces = vec![[0, 1, 2]];
    body.gas = Some(Gas::new(1.0, 0.0));
    let error = refused(body);
    let BuildError::OpenSurface {
        problem: SurfaceProblem::Boundary(edge),
    } = error
    else {
        panic!("expected a boundary edge, got {error:?}");
    };
    assert!([[0, 1], [1, 2], [0, 2]].contains(&edge), "{edge:?}");
    assert_names(&error, "gas");
    assert!(
        error.to_string().contains(&format!(
            "edge {}-{} belongs to one face only",
            edge[0], edge[1]
        )),
        "{error}"
    );
}

#[test]
fn gas_in_a_box_with_a_face_missing_is_refused_naming_an_edge_of_the_hole() {
    let (_, mut faces) = box_surface(Vec3::ZERO, Vec3::ONE);
    // Faces 10 and 11 are the two triangles of the top (z = 1) face.
    let hole: Vec<[usize; 3]> = faces.drain(10..12).collect();
    let outline = quad_outline(&hole);
    assert_eq!(outline.len(), 4);
    let error = refused(gas_box(faces.clone()));
    assert!(
        matches!(&error, BuildError::OpenSurface { problem: SurfaceProblem::Boundary(edge) } if outline.contains(edge)),
        "expected a boundary edge among {outline:?}, got {error:?}"
    );
    // Without a gas the open box is a valid body that encloses nothing.
    let mut open = gas_box(faces);
    open.gas = None;
    assert_eq!(world_with(open).volume(0), None);
}

#[test]
fn misoriented_faces_are_refused() {
    // Two triangles traversing the edge 0→1 in the same direction.
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z]);
    body.faces = vec![[0, 1, 2], [0, 1, 3]];
    body.gas = Some(Gas::new(1.0, 0.0));
    assert_eq!(
        refused(body),
        BuildError::OpenSurface {
            problem: SurfaceProblem::Misoriented([0, 1])
        }
    );
    // A closed box with the two triangles of one face turned inside: their
    // outline edges run the same way as their neighbours'.
    let (_, mut faces) = box_surface(Vec3::ZERO, Vec3::ONE);
    faces[10..12].iter_mut().for_each(|f| f.swap(1, 2));
    let outline = quad_outline(&faces[10..12]);
    let error = refused(gas_box(faces));
    assert!(
        matches!(&error, BuildError::OpenSurface { problem: SurfaceProblem::Misoriented(edge) } if outline.contains(edge)),
        "expected a misoriented edge among {outline:?}, got {error:?}"
    );
    assert!(error.to_string().contains("same direction"), "{error}");
}

#[test]
fn gas_in_a_broken_loop_is_refused() {
    let mut ring = build::ring(6, 1.0).expect("valid ring");
    ring.segments.remove(2); // [2, 3]: particle 2 has no way out, 3 no way in
    ring.gas = Some(Gas::new(1.0, 0.0));
    assert_eq!(
        refused(ring),
        BuildError::OpenSurface {
            problem: SurfaceProblem::BrokenLoop(2)
        }
    );
}

#[test]
fn bad_ring_and_icosphere_parameters_are_refused() {
    let cases = [
        (
            build::ring(2, 1.0).expect_err("2 particles"),
            "ring.particles",
        ),
        (build::ring(8, 0.0).expect_err("radius 0"), "ring.radius"),
        (
            build::icosphere(1.0, build::MAX_SUBDIVISIONS + 1, SurfaceSprings::default())
                .expect_err("8 subdivisions"),
            "sphere.subdivisions",
        ),
        (
            build::icosphere(0.0, 1, SurfaceSprings::default()).expect_err("radius 0"),
            "sphere.radius",
        ),
    ];
    assert_eq!(build::MAX_SUBDIVISIONS, 7);
    for (error, field) in cases {
        assert!(
            matches!(error, BuildError::OutOfRange { field: f, .. } if f == field),
            "{error:?}"
        );
        assert_names(&error, field);
    }
}
