//! Bodies: what the builders lay out (exact spring and face counts), what
//! placement does, that a 26-neighbour lattice holds its shape, and that bad
//! input is refused with an error naming the field (a clear error, never a panic).

use sprung::build::{self, ClothSprings};
use sprung::{
    BodyData, BuildError, Collider, ContactResponse, IntegratorKind, Real, Shape, SpringData, Vec3,
    World,
};

// ---------------------------------------------------------------- bad input

/// Two particles 1 m apart joined by one spring of stiffness 10 N/m.
fn pair() -> BodyData {
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    body.springs.push(SpringData::between(0, 1));
    body.with_stiffness(10.0)
}

/// Add `body` to an empty world; it must be refused.
fn refused(body: BodyData) -> BuildError {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("body", body).expect_err("must be refused")
}

/// The error's message must name `field` (in backquotes, as the scene key).
fn assert_names(error: &BuildError, field: &str) {
    let message = error.to_string();
    assert!(
        message.contains(&format!("`{field}`")),
        "message does not name `{field}`: {message}"
    );
}

#[test]
fn negative_mass_is_refused() {
    let error = refused(pair().with_mass(-1.0));
    assert!(
        matches!(error, BuildError::BadMass { field: "masses", index: 0, value } if value == -1.0),
        "{error:?}"
    );
    assert_names(&error, "masses");
}

#[test]
fn zero_mass_is_refused() {
    let mut body = pair();
    body.mass[1] = 0.0;
    let error = refused(body);
    assert!(
        matches!(error, BuildError::BadMass { field: "masses", index: 1, value } if value == 0.0),
        "{error:?}"
    );
    assert_names(&error, "masses");
}

#[test]
fn non_finite_position_is_refused() {
    let mut body = pair();
    body.position[1].y = Real::NAN;
    let error = refused(body);
    assert!(
        matches!(
            error,
            BuildError::NotFinite {
                field: "particles",
                index: 1,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "particles");
}

#[test]
fn spring_index_out_of_range_is_refused() {
    let mut body = pair();
    body.springs.push(SpringData::between(0, 5));
    let error = refused(body.with_stiffness(10.0));
    assert!(
        matches!(
            error,
            BuildError::SpringIndexOutOfRange {
                spring: 1,
                bad: 5,
                particles: 2,
                ..
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "springs");
}

#[test]
fn spring_from_a_particle_to_itself_is_refused() {
    let mut body = pair();
    body.springs.push(SpringData::between(1, 1));
    let error = refused(body.with_stiffness(10.0));
    assert!(
        matches!(
            error,
            BuildError::SelfSpring {
                spring: 1,
                particle: 1
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "springs");
}

#[test]
fn duplicate_spring_is_refused_even_reversed() {
    let mut body = pair();
    body.springs.push(SpringData::between(1, 0));
    let error = refused(body.with_stiffness(10.0));
    assert!(
        matches!(
            error,
            BuildError::DuplicateSpring {
                spring: 1,
                earlier: 0,
                first: 1,
                second: 0
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "springs");
}

#[test]
fn zero_length_spring_is_refused() {
    let mut body = BodyData::from_positions(vec![Vec3::ONE, Vec3::ONE]);
    body.springs.push(SpringData::between(0, 1));
    let error = refused(body.with_stiffness(10.0));
    assert!(
        matches!(error, BuildError::ZeroLengthSpring { spring: 0, length, .. } if length == 0.0),
        "{error:?}"
    );
    assert_names(&error, "springs");
}

#[test]
fn negative_stiffness_is_refused() {
    let error = refused(pair().with_stiffness(-5.0));
    assert!(
        matches!(error, BuildError::NegativeSpringCoefficient { field: "stiffness", value, .. } if value == -5.0),
        "{error:?}"
    );
    assert_names(&error, "stiffness");
}

#[test]
fn pinned_index_out_of_range_is_refused() {
    let error = refused(pair().with_pinned(vec![0, 7]));
    assert!(
        matches!(
            error,
            BuildError::PinnedOutOfRange {
                entry: 1,
                index: 7,
                particles: 2
            }
        ),
        "{error:?}"
    );
    assert_names(&error, "pinned");
}

#[test]
fn a_refused_body_leaves_the_world_unchanged() {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world
        .add_body(
            "rope",
            build::rope(5, 1.0).expect("valid").with_stiffness(10.0),
        )
        .expect("valid rope");
    let (particles, springs, bodies) = (
        world.particles.len(),
        world.springs.len(),
        world.bodies.len(),
    );
    // Valid up to its last spring, which joins a particle to itself.
    let mut body = build::cloth(3, 3, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_stiffness(10.0);
    body.springs.push(SpringData::between(4, 4));
    world.add_body("cloth", body).expect_err("refused");
    assert_eq!(world.particles.len(), particles);
    assert_eq!(world.springs.len(), springs);
    assert_eq!(world.bodies.len(), bodies);
    assert_eq!(world.particles.velocity.len(), particles);
    assert_eq!(world.particles.inverse_mass.len(), particles);
    assert!(world.body("cloth").is_none());
}

#[test]
fn duplicate_body_name_is_refused_and_changes_nothing() {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("jelly", pair()).expect("first is fine");
    let (particles, springs) = (world.particles.len(), world.springs.len());
    let error = world.add_body("jelly", pair()).expect_err("same name");
    assert_eq!(error, BuildError::DuplicateName("jelly".to_string()));
    assert!(error.to_string().contains("\"jelly\""), "{error}");
    assert_eq!(world.particles.len(), particles);
    assert_eq!(world.springs.len(), springs);
    assert_eq!(world.bodies.len(), 1);
}

#[test]
fn rope_with_one_particle_is_refused() {
    let error = build::rope(1, 1.0).expect_err("one particle");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "rope.particles", value, .. } if value == 1.0),
        "{error:?}"
    );
    assert_names(&error, "rope.particles");
}

#[test]
fn cloth_with_negative_width_is_refused() {
    let error = build::cloth(3, 3, -1.0, 1.0, ClothSprings::default()).expect_err("width < 0");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "cloth.width", value, .. } if value == -1.0),
        "{error:?}"
    );
    assert_names(&error, "cloth.width");
}

#[test]
fn lattice_with_zero_spacing_is_refused() {
    let error = build::lattice(2, 2, 2, 0.0).expect_err("spacing 0");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "lattice.spacing", value, .. } if value == 0.0),
        "{error:?}"
    );
    assert_names(&error, "lattice.spacing");
}

#[test]
fn plane_with_zero_normal_is_refused() {
    let error = Shape::plane(Vec3::ZERO, Vec3::ZERO).expect_err("zero normal");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "plane.normal", value, .. } if value == 0.0),
        "{error:?}"
    );
    assert_names(&error, "plane.normal");
}

#[test]
fn restitution_above_one_is_refused() {
    let plane = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let response = ContactResponse::Projection {
        restitution: 1.5,
        friction: 0.0,
    };
    let error = Collider::new(plane, response).expect_err("e > 1");
    assert!(
        matches!(error, BuildError::OutOfRange { field: "restitution", value, .. } if value == 1.5),
        "{error:?}"
    );
    assert_names(&error, "restitution");
}

// ----------------------------------------------------------------- builders

#[test]
fn cloth_has_the_exact_spring_and_face_counts() {
    for (nx, ny) in [(5, 4), (2, 2), (2, 7), (3, 3)] {
        // Structural: (nx - 1) per row times ny rows, plus nx (ny - 1)
        // columns. Shear: two diagonals per cell. Bending: pairs two apart
        // along x, (nx - 2) per row, and along y, nx (ny - 2).
        let structural = (nx - 1) * ny + nx * (ny - 1);
        let shear = 2 * (nx - 1) * (ny - 1);
        let bending = (nx - 2) * ny + nx * (ny - 2);
        for family in 0..8 {
            let springs = ClothSprings {
                structural: family & 1 != 0,
                shear: family & 2 != 0,
                bending: family & 4 != 0,
            };
            let (width, height) = (1.2, 0.9);
            let cloth = build::cloth(nx, ny, width, height, springs).expect("valid cloth");
            let expected = [
                (springs.structural, structural),
                (springs.shear, shear),
                (springs.bending, bending),
            ]
            .iter()
            .filter(|(on, _)| *on)
            .map(|(_, count)| count)
            .sum::<usize>();
            assert_eq!(cloth.springs.len(), expected, "{nx}×{ny}, {springs:?}");
            assert_eq!(cloth.particle_count(), nx * ny);
            assert_eq!(
                cloth.faces.len(),
                2 * (nx - 1) * (ny - 1),
                "{nx}×{ny} faces"
            );
            // Every spring has the length of its family.
            let (dx, dy) = (width / (nx - 1) as Real, height / (ny - 1) as Real);
            let lengths = [dx, dy, dx.hypot(dy), 2.0 * dx, 2.0 * dy];
            for s in &cloth.springs {
                let length = cloth.rest_length(s);
                assert!(
                    lengths.iter().any(|l| (length - l).abs() <= 1e-12),
                    "{nx}×{ny}: spring {s:?} has length {length}"
                );
            }
            // And the world accepts it: no duplicate or degenerate spring
            // (with no springs at all it is still a valid body).
            let mut world = World::new(IntegratorKind::SymplecticEuler);
            world.add_body("cloth", cloth).expect("valid body");
        }
    }
}

#[test]
fn cloth_faces_are_counter_clockwise_seen_from_plus_z() {
    let cloth = build::cloth(4, 3, 1.0, 1.0, ClothSprings::default()).expect("valid cloth");
    for face in &cloth.faces {
        let [a, b, c] = face.map(|i| cloth.position[i]);
        let normal = (b - a).cross(c - a);
        assert!(normal.z > 0.0, "face {face:?} has normal {normal}");
    }
}

#[test]
fn lattice_has_the_exact_26_neighbour_spring_count() {
    // Each unordered neighbour pair is one of 13 directions (d ≠ 0 with
    // components in {-1, 0, 1}, up to sign). Direction d fits
    // Π_a (n_a - |d_a|) times. Faces (3 axes), face diagonals (2 per plane,
    // 3 planes) and body diagonals (4):
    let count = |nx: usize, ny: usize, nz: usize| {
        let edges = (nx - 1) * ny * nz + nx * (ny - 1) * nz + nx * ny * (nz - 1);
        let face_diagonals =
            2 * ((nx - 1) * (ny - 1) * nz + (nx - 1) * ny * (nz - 1) + nx * (ny - 1) * (nz - 1));
        let body_diagonals = 4 * (nx - 1) * (ny - 1) * (nz - 1);
        edges + face_diagonals + body_diagonals
    };
    // A single cell: every one of the 8 corners neighbours every other,
    // so the count is C(8, 2) = 28.
    assert_eq!(count(2, 2, 2), 28);
    for (nx, ny, nz) in [(2, 2, 2), (3, 4, 5), (3, 3, 3), (2, 3, 2)] {
        let spacing = 0.1;
        let lattice = build::lattice(nx, ny, nz, spacing).expect("valid lattice");
        assert_eq!(lattice.particle_count(), nx * ny * nz);
        assert_eq!(lattice.springs.len(), count(nx, ny, nz), "{nx}×{ny}×{nz}");
        // Every spring joins neighbours: length s, s√2 or s√3.
        for s in &lattice.springs {
            let ratio = lattice.rest_length(s) / spacing;
            assert!(
                [1.0, Real::sqrt(2.0), Real::sqrt(3.0)]
                    .iter()
                    .any(|r| (ratio - r).abs() <= 1e-12),
                "{nx}×{ny}×{nz}: spring {s:?} is {ratio} spacings long"
            );
        }
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world
            .add_body("jelly", lattice)
            .expect("no duplicate springs");
    }
}

#[test]
fn rope_pins_its_top_and_has_n_minus_1_springs() {
    let (n, length) = (7, 3.0);
    let rope = build::rope(n, length).expect("valid rope");
    assert_eq!(rope.particle_count(), n);
    assert_eq!(rope.pinned, vec![0]);
    assert_eq!(rope.springs.len(), n - 1);
    for (i, s) in rope.springs.iter().enumerate() {
        // Parent above child: one-sided springs pull the lower particle.
        assert_eq!((s.first, s.second), (i, i + 1));
        assert!((rope.rest_length(s) - length / (n - 1) as Real).abs() <= 1e-12);
    }
    assert_eq!(rope.position[0], Vec3::ZERO);
    assert!((rope.position[n - 1] - Vec3::new(0.0, -length, 0.0)).length() <= 1e-12);
}

/// Drop a 3×3×3 lattice, sliding sideways, onto a floor with friction, and
/// return its height (m) after it settles. With `only_edges`, keep only
/// the 6-neighbour springs along the cell edges.
fn dropped_lattice_height(only_edges: bool) -> (Real, Real) {
    let spacing = 0.1;
    let (mass, stiffness) = (0.01, 100.0);
    let mut body = build::lattice(3, 3, 3, spacing)
        .expect("valid lattice")
        .with_mass(mass)
        .with_stiffness(stiffness)
        .with_damping(0.05);
    if only_edges {
        let position = body.position.clone();
        body.springs
            .retain(|s| (position[s.first].distance(position[s.second]) - spacing).abs() < 1e-9);
        assert_eq!(body.springs.len(), 3 * 2 * 3 * 3);
    }
    let body = body
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.3, 0.0))
        .with_velocity(Vec3::new(1.0, 0.0, 0.0));
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_air_drag(0.01);
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let response = ContactResponse::Projection {
        restitution: 0.0,
        friction: 0.5,
    };
    world
        .colliders
        .push(Collider::new(floor, response).expect("valid floor"));
    world.add_body("jelly", body).expect("valid lattice");
    // dt = 1 ms is a third of the stable step (~2.8 ms for 26 springs of
    // 100 N/m on 10 g); 3 s is enough for the drag and spring damping to
    // remove all but ~1e-8 J of the landing's kinetic energy.
    for _ in 0..3000 {
        world.step(1e-3).expect("stable");
    }
    let heights = world.particles.position.iter().map(|x| x.y);
    let top = heights.clone().fold(Real::MIN, Real::max);
    let bottom = heights.fold(Real::MAX, Real::min);
    (top - bottom, 2.0 * spacing)
}

#[test]
fn a_dropped_26_neighbour_lattice_holds_its_shape() {
    let (height, rest) = dropped_lattice_height(false);
    // Static bound: even if the 9 vertical springs of a layer carried all
    // the weight above them alone, the lower layer would shorten by
    // 18 m g / (9 k) and the upper one by 9 m g / (9 k): 3 m g / k ≈ 3 mm,
    // 1.5 % of the 0.2 m height; the diagonals only stiffen it. We claim
    // 95 %, leaving room for friction-held lateral strain.
    assert!(
        height >= 0.95 * rest,
        "settled height {height:.4} m of {rest} m: the lattice collapsed"
    );
}

#[test]
fn a_dropped_6_neighbour_lattice_collapses() {
    // The control for the test above: with springs only along the cell
    // edges the lattice has no shear stiffness (docs/physics.md §2). Friction
    // shears it as it lands sliding, and gravity then folds it flat.
    let (height, rest) = dropped_lattice_height(true);
    assert!(
        height < 0.5 * rest,
        "settled height {height:.4} m of {rest} m: the 6-neighbour lattice held"
    );
}

// ---------------------------------------------------------------- placement

#[test]
fn placement_scales_then_rotates_about_x_y_z_then_translates() {
    let mut body = BodyData::from_positions(vec![Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO]);
    body.velocity = vec![Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO];
    body.springs.push(SpringData {
        rest_length: Some(0.5),
        ..SpringData::between(0, 1)
    });
    let placed = body.placed(2.0, Vec3::new(90.0, 90.0, 90.0), Vec3::new(1.0, 2.0, 3.0));
    // By hand, right-handed rotations by 90°: R_x (x, y, z) = (x, -z, y),
    // R_y (x, y, z) = (z, y, -x), R_z (x, y, z) = (-y, x, z).
    // (0, 1, 0) · 2 = (0, 2, 0) → R_x → (0, 0, 2) → R_y → (2, 0, 0)
    // → R_z → (0, 2, 0) → + (1, 2, 3) = (1, 4, 3).
    // (The reverse order z, y, x would give (0, -2, 0) + (1, 2, 3).)
    // 1e-12: the rotations are exact up to sin/cos(π/2) round-off.
    let expected = Vec3::new(1.0, 4.0, 3.0);
    assert!(
        (placed.position[0] - expected).length() <= 1e-12,
        "placed at {}, expected {expected}",
        placed.position[0]
    );
    // The origin only moves by the translation.
    assert!((placed.position[1] - Vec3::new(1.0, 2.0, 3.0)).length() <= 1e-12);
    // Velocities turn with the rotation but are not scaled or translated:
    // (0, 1, 0) → (0, 0, 1) → (1, 0, 0) → (0, 1, 0).
    assert!(
        (placed.velocity[0] - Vec3::new(0.0, 1.0, 0.0)).length() <= 1e-12,
        "velocity {}",
        placed.velocity[0]
    );
    // An explicit rest length scales with the body.
    assert_eq!(placed.springs[0].rest_length, Some(1.0));
}

#[test]
fn placement_rotations_one_axis_at_a_time() {
    // Each rotation alone, on a point off its axis: a sign or axis mix-up in
    // any one of them shows here.
    let p = Vec3::new(1.0, 2.0, 3.0);
    let cases = [
        (Vec3::new(90.0, 0.0, 0.0), Vec3::new(1.0, -3.0, 2.0)),
        (Vec3::new(0.0, 90.0, 0.0), Vec3::new(3.0, 2.0, -1.0)),
        (Vec3::new(0.0, 0.0, 90.0), Vec3::new(-2.0, 1.0, 3.0)),
        (Vec3::new(0.0, 0.0, 180.0), Vec3::new(-1.0, -2.0, 3.0)),
    ];
    for (degrees, expected) in cases {
        let placed = BodyData::from_positions(vec![p]).placed(1.0, degrees, Vec3::ZERO);
        assert!(
            (placed.position[0] - expected).length() <= 1e-12,
            "rotate {degrees}: {} instead of {expected}",
            placed.position[0]
        );
    }
}

#[test]
fn absurd_builder_sizes_are_refused_not_allocated() {
    // 1e11 particles would need terabytes: refused by the size check
    // before any allocation (the test would abort otherwise).
    let error = build::rope(100_000_000_000, 1.0).expect_err("too many");
    assert!(
        matches!(
            error,
            BuildError::OutOfRange {
                field: "rope.particles",
                ..
            }
        ),
        "{error:?}"
    );
    let error = build::lattice(1 << 32, 1 << 32, 2, 1.0).expect_err("overflows");
    assert!(
        matches!(
            error,
            BuildError::OutOfRange {
                field: "lattice.nx",
                ..
            }
        ),
        "{error:?}"
    );
    let error =
        build::cloth(5_000, 5_000, 1.0, 1.0, ClothSprings::default()).expect_err("25 million");
    assert!(
        matches!(
            error,
            BuildError::OutOfRange {
                field: "cloth.nx",
                ..
            }
        ),
        "{error:?}"
    );
}

#[test]
fn body_names_that_would_break_the_diagnostics_columns_are_refused() {
    for name in ["", "a,b", "say \"hi\"", "two\nlines"] {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        let error = world.add_body(name, pair()).expect_err(name);
        assert_eq!(error, BuildError::BadName(name.to_string()));
        assert!(world.bodies.is_empty());
    }
}
