//! Bad scene files: each is refused before the run with a message naming
//! the file, the line and the key (docs/scenes.md, issue "bad input"). The line numbers asserted are those of the offending key in the
//! texts below.

use std::path::Path;

use sprung_io::{parse_scene, SceneError};

const GOOD: &str = r#"[sim]
dt = 1e-3
steps = 10

[[body]]
name = "b"
particles = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]
springs = [[0, 1], [1, 2]]
mass = 1.0
"#;

/// The scene `GOOD` with `from` replaced by `to`; panics if `from` is absent
/// so that a typo in a test cannot make it pass vacuously.
fn variant(from: &str, to: &str) -> String {
    assert!(
        GOOD.contains(from),
        "test setup: {from:?} not in the base scene"
    );
    GOOD.replacen(from, to, 1)
}

fn error_of(text: &str) -> SceneError {
    match parse_scene(text, Path::new("bad.toml")) {
        Ok(_) => panic!("scene was accepted:\n{text}"),
        Err(e) => e,
    }
}

/// Assert the error names the file, the expected line and every fragment.
fn assert_error(text: &str, line: usize, fragments: &[&str]) {
    let error = error_of(text);
    let message = error.to_string();
    assert!(
        message.starts_with(&format!("bad.toml:{line}: ")),
        "wrong place: {message}"
    );
    for fragment in fragments {
        assert!(message.contains(fragment), "{message:?} lacks {fragment:?}");
    }
}

#[test]
fn the_base_scene_is_good() {
    let scene = parse_scene(GOOD, Path::new("good.toml")).expect("valid scene");
    assert_eq!(scene.world.particles.len(), 3);
    assert_eq!(scene.world.springs.len(), 2);
    assert_eq!(scene.steps, 10);
}

#[test]
fn pinning_that_will_not_happen_as_written_is_warned_about_with_its_line() {
    // Claims: the base scene warns of nothing; a velocity given to pinned
    // particles (which the engine keeps still) is named with the
    // particles and the line of `velocity`, and the run starts with them
    // at rest; a particle pinned twice is named with the line of `pinned`.
    let scene = parse_scene(GOOD, Path::new("good.toml")).expect("valid scene");
    assert!(scene.warnings.is_empty(), "{:?}", scene.warnings);
    let moving = variant(
        "mass = 1.0\n",
        "mass = 1.0\npinned = [0, 2]\nvelocity = [1.0, 0.0, 0.0]\n",
    );
    let scene = parse_scene(&moving, Path::new("good.toml")).expect("valid scene");
    assert_eq!(
        scene.warnings,
        ["good.toml:11: body \"b\": particles 0 and 2 given a velocity are pinned: a pinned particle stays where it is, so its velocity is set to zero"]
    );
    let velocity = &scene.world.particles.velocity;
    assert_eq!(velocity[0], sprung::Vec3::ZERO);
    assert_eq!(velocity[1], sprung::Vec3::new(1.0, 0.0, 0.0));
    let twice = variant("mass = 1.0\n", "mass = 1.0\npinned = [1, 0, 1]\n");
    let scene = parse_scene(&twice, Path::new("good.toml")).expect("valid scene");
    assert_eq!(
        scene.warnings,
        ["good.toml:10: body \"b\": `pinned` lists particle 1 more than once (each is pinned once)"]
    );
}

#[test]
fn points_given_partly_in_2d_and_partly_in_3d_are_refused() {
    assert_error(
        &variant("[1.0, 0.0, 0.0], [2.0", "[1.0, 0.0], [2.0"),
        7,
        &["`particles` mixes 2D and 3D vectors: entry 0 has 3 numbers, entry 1 has 2"],
    );
    assert_error(
        &variant(
            "mass = 1.0",
            "mass = 1.0\nvelocities = [[0.0, 1.0], [0.0, 1.0], [0.0, 1.0, 0.0]]",
        ),
        10,
        &["`velocities` mixes 2D and 3D vectors: entry 0 has 2 numbers, entry 2 has 3"],
    );
    // All in 2D, or all in 3D: accepted.
    let flat = variant(
        "[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]",
        "[[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]",
    );
    assert!(parse_scene(&flat, Path::new("flat.toml")).is_ok());
}

#[test]
fn unknown_key() {
    assert_error(
        &format!("{GOOD}colour = \"red\"\n"),
        10,
        &["unknown field `colour`"],
    );
}

#[test]
fn unknown_key_in_sim() {
    assert_error(
        &variant("steps = 10", "steps = 10\ntimestep = 3"),
        4,
        &["unknown field `timestep`"],
    );
}

#[test]
fn wrong_type() {
    assert_error(
        &variant("mass = 1.0", "mass = \"heavy\""),
        9,
        &["invalid type", "string"],
    );
}

#[test]
fn negative_mass() {
    assert_error(
        &variant("mass = 1.0", "mass = -1.0"),
        9,
        &["`mass` = -1", "positive"],
    );
}

#[test]
fn zero_mass_in_list() {
    assert_error(
        &variant("mass = 1.0", "masses = [1.0, 0.0, 1.0]"),
        9,
        &["`masses`[1] = 0", "positive"],
    );
}

#[test]
fn spring_index_out_of_range() {
    assert_error(
        &variant("[1, 2]]", "[1, 5]]"),
        8,
        &["`springs`[1] = [1, 5]", "out of range", "3 particles"],
    );
}

#[test]
fn spring_to_itself() {
    assert_error(
        &variant("[1, 2]]", "[1, 1]]"),
        8,
        &["`springs`[1] = [1, 1]", "itself"],
    );
}

#[test]
fn duplicate_spring_is_refused() {
    assert_error(
        &variant("[1, 2]]", "[1, 2], [2, 1]]"),
        8,
        &["`springs`[2]", "duplicates `springs`[1]", "refused"],
    );
}

#[test]
fn zero_length_spring() {
    assert_error(
        &variant("[2.0, 0.0, 0.0]]", "[1.0, 0.0, 0.0]]"),
        8,
        &["`springs`[1] = [1, 2]", "rest length 0"],
    );
}

#[test]
fn time_step_zero_and_negative() {
    assert_error(
        &variant("dt = 1e-3", "dt = 0.0"),
        2,
        &["`dt` = 0", "positive"],
    );
    assert_error(
        &variant("dt = 1e-3", "dt = -1e-3"),
        2,
        &["`dt` = -0.001", "positive"],
    );
}

#[test]
fn non_finite_numbers() {
    assert_error(
        &variant("[2.0, 0.0, 0.0]]", "[nan, 0.0, 0.0]]"),
        7,
        &["`particles`", "finite"],
    );
    assert_error(&variant("dt = 1e-3", "dt = inf"), 2, &["`dt` = inf"]);
    assert_error(&variant("mass = 1.0", "mass = nan"), 9, &["`mass` = NaN"]);
    assert_error(
        &format!("{GOOD}stiffness = inf\n"),
        10,
        &["`stiffness`", "not a finite number"],
    );
}

#[test]
fn pinned_index_out_of_range() {
    assert_error(
        &format!("{GOOD}pinned = [7]\n"),
        10,
        &["`pinned`[0] = 7", "out of range"],
    );
}

#[test]
fn unknown_integrator() {
    assert_error(
        &variant("steps = 10", "steps = 10\nintegrator = \"leapfrog\""),
        4,
        &["unknown integrator \"leapfrog\"", "rk4"],
    );
}

#[test]
fn per_spring_list_of_the_wrong_length() {
    assert_error(
        &format!("{GOOD}stiffness = [1.0, 2.0, 3.0]\n"),
        10,
        &["`stiffness` has 3 entries", "2 springs"],
    );
}

#[test]
fn two_builders_at_once() {
    assert_error(
        &format!("{GOOD}rope = {{ particles = 3, length = 1.0 }}\n"),
        10,
        &["particles and rope", "choose one"],
    );
}

#[test]
fn bad_builder_parameters() {
    let rope =
        "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"r\"\nrope = { particles = 1, length = 1.0 }\n";
    assert_error(rope, 6, &["`rope.particles` = 1", "at least 2"]);
}

#[test]
fn duration_and_steps_together() {
    assert_error(
        &variant("steps = 10", "steps = 10\nduration = 1.0"),
        3,
        &["`duration` or `steps`, not both"],
    );
}

#[test]
fn collider_coefficients() {
    // GOOD has 9 lines, so an appended table starts on line 10.
    let plane = "[[collider]]\nplane = { point = [0.0, 0.0], normal = [0.0, 1.0] }\n";
    assert_error(
        &format!("{GOOD}{plane}restitution = 1.5\n"),
        12,
        &["`restitution` = 1.5", "[0, 1]"],
    );
    let flat = "[[collider]]\nplane = { point = [0.0, 0.0], normal = [0.0, 0.0] }\n";
    assert_error(&format!("{GOOD}{flat}"), 11, &["non-zero"]);
    assert_error(
        &format!("{GOOD}{plane}restitution = 0.5\npenalty_stiffness = 100.0\n"),
        12,
        &["`restitution` belongs to the projection form"],
    );
}

#[test]
fn sphere_colliders_and_paths() {
    // GOOD has 9 lines: `[[collider]]` is line 10, the shape line 11.
    let sphere = |radius: &str| {
        format!("{GOOD}[[collider]]\nsphere = {{ centre = [0.0, 0.0, 0.0], radius = {radius} }}\n")
    };
    assert_error(&sphere("0.0"), 11, &["`sphere.radius` = 0"]);
    assert_error(&sphere("-1.0"), 11, &["`sphere.radius` = -1"]);
    let both = format!("{GOOD}[[collider]]\nplane = {{ point = [0.0, 0.0], normal = [0.0, 1.0] }}\nsphere = {{ centre = [0.0, 0.0], radius = 1.0 }}\n");
    assert_error(&both, 12, &["a `plane` or a `sphere`, not both"]);
    let none = format!("{GOOD}[[collider]]\nfriction = 0.5\n");
    assert_error(&none, 10, &["a collider needs a shape"]);
    assert_error(
        &format!(
            "{}path = [[1.0, 0.0, 0.0], [0.5, 1.0, 0.0]]\n",
            sphere("1.0")
        ),
        12,
        &["path"],
    );
    let moving = format!("{}path = [[0.0, 0.0, 0.0, 0.0], [2.0, 4.0, 0.0, 0.0]]\npenalty_stiffness = 1000.0\nfriction = 0.3\n", sphere("1.0"));
    let scene = parse_scene(&moving, Path::new("s.toml")).unwrap_or_else(|e| panic!("{e}"));
    // Halfway along the path, the sphere has moved 2 m along x at 2 m/s.
    let collider = &scene.world.colliders[0];
    assert_eq!(
        collider.shape_at(1.0),
        sprung::Shape::Sphere {
            centre: sprung::Vec3::new(2.0, 0.0, 0.0),
            radius: 1.0
        }
    );
    assert_eq!(collider.velocity_at(1.0), sprung::Vec3::new(2.0, 0.0, 0.0));
}

#[test]
fn duplicate_body_names() {
    let second = "\n[[body]]\nname = \"b\"\nparticles = [[0.0, 5.0]]\n";
    assert_error(
        &format!("{GOOD}{second}"),
        12,
        &["named \"b\" already exists"],
    );
}

#[test]
fn missing_file_names_it() {
    let error = sprung_io::load_scene(Path::new("no/such/scene.toml")).expect_err("missing");
    let message = error.to_string();
    assert!(
        message.starts_with("no/such/scene.toml: cannot read"),
        "{message}"
    );
}

#[test]
fn two_dimensional_points_and_placement() {
    let text = "[sim]\ndt = 1e-3\n\n[[body]]\nname = \"p\"\nparticles = [[1.0, 0.0], [2.0, 0.0]]\nsprings = [[0, 1]]\nscale = 2.0\nrotate = [0.0, 0.0, 90.0]\ntranslate = [0.0, 0.0, 1.0]\n";
    let scene = parse_scene(text, Path::new("p.toml")).expect("valid");
    // (1, 0, 0) scaled to (2, 0, 0), turned 90° about z to (0, 2, 0), moved to (0, 2, 1).
    let x = scene.world.particles.position[0];
    assert!(
        (x - sprung::Vec3::new(0.0, 2.0, 1.0)).length() < 1e-12,
        "{x}"
    );
    // The rest length is the distance at creation, after placement: 2 m.
    assert!((scene.world.springs.rest_length[0] - 2.0).abs() < 1e-12);
}

#[test]
fn wind_model_that_does_not_exist() {
    let wind = "[wind]\nvelocity = [1.0, 0.0, 0.0]\nmodel = \"hurricane\"\n";
    // GOOD has 9 lines: `[wind]` is line 10, `model` line 12.
    assert_error(
        &format!("{GOOD}{wind}"),
        12,
        &["wind:", "unknown wind model \"hurricane\"", "simple, area"],
    );
}

#[test]
fn wind_with_negative_air_density() {
    let wind = "[wind]\nvelocity = [1.0, 0.0, 0.0]\nmodel = \"area\"\nair_density = -1.2\n";
    assert_error(
        &format!("{GOOD}{wind}"),
        13,
        &["`air_density` = -1.2", "not negative"],
    );
}

#[test]
fn wind_keys_of_the_other_model_and_bad_variations() {
    let base = "[wind]\nvelocity = [1.0, 0.0, 0.0]\n";
    assert_error(
        &format!("{GOOD}{base}air_density = 1.0\n"),
        12,
        &["`air_density` belongs to the \"area\" wind model"],
    );
    assert_error(
        &format!("{GOOD}{base}gust = {{ amplitude = 2.0, period = 1.0 }}\n"),
        12,
        &["`gust.amplitude` = 2", "[0, 1]"],
    );
    assert_error(
        &format!("{GOOD}{base}turbulence = {{ amplitude = 1.0, length_scale = 0.0, time_scale = 1.0 }}\n"),
        12,
        &["length scale must be positive"],
    );
    assert_error(
        &format!("{GOOD}{base}speed = 3.0\n"),
        12,
        &["unknown field `speed`"],
    );
}

#[test]
fn wind_scale_needs_wind_and_a_sensible_value() {
    assert_error(
        &format!("{GOOD}wind_scale = 0.5\n"),
        10,
        &["`wind_scale` needs a `[wind]` table"],
    );
    let wind = "[wind]\nvelocity = [1.0, 0.0, 0.0]\n";
    assert_error(
        &format!("{GOOD}wind_scale = -1.0\n{wind}"),
        10,
        &["`wind_scale` = -1", "not negative"],
    );
}

#[test]
fn a_good_wind_table_adds_one_force() {
    let wind = "[wind]\nvelocity = [1.0, 0.0, 0.0]\nmodel = \"area\"\nlift = 0.5\ngust = { amplitude = 0.3, period = 2.0 }\nturbulence = { amplitude = 1.0, length_scale = 0.5, time_scale = 0.3 }\nseed = 7\n";
    let scene = parse_scene(&format!("{GOOD}{wind}"), Path::new("w.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(scene.world.forces.get::<sprung::forces::Wind>().is_some());
}

#[test]
fn camera_table() {
    // GOOD has 9 lines: `[camera]` is line 10.
    let camera = |body: &str| format!("{GOOD}[camera]\n{body}\n");
    assert_error(
        &camera("fov = 200.0"),
        11,
        &["camera:", "`fov` = 200", "between 0 and 180"],
    );
    assert_error(
        &camera("eye = [1.0, 2.0, 3.0]\ntarget = [1.0, 2.0, 3.0]"),
        12,
        &["same point"],
    );
    assert_error(&camera("zoom = 2.0"), 11, &["unknown field `zoom`"]);
    let scene = parse_scene(
        &camera("eye = [0.0, 1.0, 5.0]\nfov = 30.0"),
        Path::new("c.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.camera.eye, Some(sprung::Vec3::new(0.0, 1.0, 5.0)));
    assert_eq!(scene.camera.target, None);
    assert_eq!(scene.camera.fov, Some(30.0));
}

#[test]
fn run_lengths_beyond_a_trillion_steps_are_refused() {
    assert_error(
        &variant("steps = 10", "steps = 10000000000000"),
        3,
        &["`steps` = 10000000000000", "at most"],
    );
    assert_error(
        &variant("steps = 10", "duration = 1e300"),
        3,
        &["steps: at most"],
    );
}

/// The implicit solvers' keys, each refused out of range and with an
/// integrator that does not read it, on the line of the key (line 4).
#[test]
fn solver_keys() {
    let with = |integrator: &str, key: &str| {
        variant(
            "steps = 10\n",
            &format!("steps = 10\nintegrator = \"{integrator}\"\n{key}\n"),
        )
    };
    assert_error(
        &with("implicit_euler", "solver_tolerance = 0.0"),
        5,
        &["solver_tolerance", "positive"],
    );
    assert_error(
        &with("implicit_euler", "solver_tolerance = -1e-6"),
        5,
        &["solver_tolerance"],
    );
    assert_error(
        &with("implicit_euler", "max_iterations = 0"),
        5,
        &["max_iterations", "from 1 to 100 000"],
    );
    assert_error(
        &with("implicit_euler", "newton_iterations = 0"),
        5,
        &["newton_iterations", "from 1 to 100 Newton"],
    );
    assert_error(
        &with("projective", "iterations = 0"),
        5,
        &["iterations", "from 1 to 10 000"],
    );
    // Counts that would hold one step for hours (each Newton iteration a
    // full solve), refused at the load: one above each limit.
    assert_error(
        &with("implicit_euler", "max_iterations = 100001"),
        5,
        &["`max_iterations` = 100001", "from 1 to 100 000"],
    );
    assert_error(
        &with("implicit_euler", "newton_iterations = 4000000000"),
        5,
        &["`newton_iterations` = 4000000000", "from 1 to 100 Newton"],
    );
    assert_error(
        &with("projective", "iterations = 10001"),
        5,
        &["`iterations` = 10001", "from 1 to 10 000"],
    );
    assert_error(
        &with("implicit_euler", "max_iterations = -3"),
        5,
        &["max_iterations"],
    );
    // A key with an integrator that does not read it.
    for (integrator, key) in [
        ("symplectic_euler", "solver_tolerance = 1e-6"),
        ("rk4", "max_iterations = 100"),
        ("verlet", "newton_iterations = 2"),
        ("euler", "iterations = 10"),
        ("projective", "newton_iterations = 2"),
        ("implicit_euler", "iterations = 10"),
        ("projective", "preconditioner = \"jacobi\""),
    ] {
        let name = key.split(' ').next().unwrap_or_default();
        assert_error(
            &with(integrator, key),
            5,
            &[name, "is a setting of the", integrator],
        );
    }
    assert_error(
        &with("implicit_euler", "preconditioner = \"cholesky\""),
        5,
        &["preconditioner", "cholesky", "jacobi, laplacian"],
    );
    // And accepted where they belong.
    for (integrator, key) in [
        ("implicit_euler", "solver_tolerance = 1e-8"),
        ("implicit_euler", "newton_iterations = 3"),
        ("projective", "iterations = 20"),
        ("projective", "max_iterations = 50"),
        ("implicit_euler", "preconditioner = \"laplacian\""),
    ] {
        let scene = parse_scene(&with(integrator, key), Path::new("good.toml"));
        assert!(scene.is_ok(), "{integrator} {key}: {:?}", scene.err());
    }
}

/// The `[contact]` table, the per-body contact keys and `substeps`.
#[test]
fn contact_and_substep_keys() {
    let contact = |table: &str| format!("{GOOD}\n[contact]\n{table}\n");
    // GOOD has 9 lines; the table's header is line 11, its key line 12.
    assert_error(
        &contact("thickness = -0.01"),
        12,
        &["thickness", "positive"],
    );
    assert_error(&contact("thickness = 0.0"), 12, &["thickness"]);
    assert_error(&contact("friction = -1.0"), 12, &["friction", "negative"]);
    assert_error(&contact("stiffness = 0.0"), 12, &["stiffness"]);
    assert_error(&contact("radius = 1.0"), 12, &["radius"]);
    // Against the world's limits (max_distance = max_speed = 1e6 by
    // default): a thickness beyond the world or so thin that the default
    // stiffness m (10 m/s / h)² overflows; a stiffness whose energy, or a
    // damping whose work, within the limits passes 1e290 J.
    assert_error(
        &contact("thickness = 1e7"),
        12,
        &["thickness", "max_distance"],
    );
    assert_error(
        &contact("thickness = 1e-200"),
        12,
        &["thickness", "overflows"],
    );
    assert_error(&contact("stiffness = 1e300"), 12, &["stiffness", "1e290 J"]);
    assert_error(&contact("damping = 1e300"), 12, &["damping", "1e290 J"]);
    assert!(parse_scene(
        &contact("thickness = 1e6\nstiffness = 1e270\ndamping = 1e270"),
        Path::new("good.toml")
    )
    .is_ok());
    assert!(parse_scene(
        &contact("thickness = 0.02\nfriction = 0.5"),
        Path::new("good.toml")
    )
    .is_ok());
    // Self-collision needs a surface: GOOD's body is a chain of particles.
    assert_error(
        &variant("mass = 1.0", "mass = 1.0\nself_collision = true"),
        10,
        &["self_collision", "surface"],
    );
    // ... and contact: left out of contact, a body meets nothing.
    let surface = "[[body]]\nname = \"r\"\nring = { particles = 8, radius = 0.5 }\ncollide = false\nself_collision = true\n";
    assert_error(
        &format!("{GOOD}{surface}"),
        14,
        &["self_collision", "needs `collide` = true"],
    );
    let scene = parse_scene(
        &variant("mass = 1.0", "mass = 1.0\ncollide = false"),
        Path::new("good.toml"),
    )
    .expect("valid scene");
    assert!(!scene.world.bodies[0].contact.collide);
    // substeps: a count or "auto".
    let substeps =
        |value: &str| variant("steps = 10\n", &format!("steps = 10\nsubsteps = {value}\n"));
    assert_error(
        &substeps("\"sometimes\""),
        4,
        &["substeps", "sometimes", "auto"],
    );
    assert_error(&substeps("0"), 4, &["substeps", "from 1"]);
    assert_error(&substeps("-2"), 4, &["substeps"]);
    // A fraction, a float in exponent form or a list: refused in words,
    // not with the parser's internal message.
    for (bad, shown) in [("2.5", "2.5"), ("1e3", "1000.0"), ("[2]", "[2]")] {
        assert_error(
            &substeps(bad),
            4,
            &[&format!(
                "`substeps` = {shown}: give a whole number of substeps"
            )],
        );
    }
    for good in ["\"auto\"", "4"] {
        assert!(
            parse_scene(&substeps(good), Path::new("good.toml")).is_ok(),
            "{good}"
        );
    }
    // error_tolerance belongs to rk45.
    let tolerance = |integrator: &str, value: &str| {
        variant(
            "steps = 10\n",
            &format!("steps = 10\nintegrator = \"{integrator}\"\nerror_tolerance = {value}\n"),
        )
    };
    assert_error(&tolerance("rk4", "1e-6"), 5, &["error_tolerance", "rk45"]);
    assert_error(
        &tolerance("rk45", "0.0"),
        5,
        &["error_tolerance", "positive"],
    );
    // Tighter than the rounding of the error estimate lets rk45 meet:
    // refused at the load rather than failing at the first step.
    assert_error(
        &tolerance("rk45", "1e-300"),
        5,
        &["error_tolerance", "at least 1e-12"],
    );
    assert!(parse_scene(&tolerance("rk45", "1e-8"), Path::new("good.toml")).is_ok());
    assert!(parse_scene(&tolerance("rk45", "1e-12"), Path::new("good.toml")).is_ok());
}

/// Rods: indices out of range, zero length (a particle to itself, or a
/// given length of 0) and a `rod_lengths` list of the wrong length, each
/// on the line of its key (GOOD has 9 lines, so appended keys start on 10).
#[test]
fn bad_rods() {
    assert_error(
        &format!("{GOOD}rods = [[0, 5]]\n"),
        10,
        &[
            "body \"b\"",
            "`rods`[0]",
            "index 5 is out of range",
            "3 particles",
        ],
    );
    assert_error(
        &format!("{GOOD}rods = [[0, 2], [1, 1]]\n"),
        10,
        &["`rods`[1]", "length 0"],
    );
    assert_error(
        &format!("{GOOD}rods = [[0, 2]]\nrod_lengths = [0.0]\n"),
        11,
        &["`rods`[0]", "length 0"],
    );
    assert_error(
        &format!("{GOOD}rods = [[0, 2]]\nrod_lengths = [1.0, 2.0]\n"),
        11,
        &["`rod_lengths` has 2 entries", "1 rods"],
    );
    assert_error(
        &format!("{GOOD}rod_lengths = [1.0]\n"),
        10,
        &["`rod_lengths` has 1 entries", "0 rods"],
    );
    // Lengths that cannot all hold, on the line of the lengths: 0-1 and
    // 1-2 at 1 m each cannot close a 3 m rod 0-2.
    assert_error(
        &format!("{GOOD}rods = [[0, 1], [1, 2], [0, 2]]\nrod_lengths = [1.0, 1.0, 3.0]\n"),
        11,
        &[
            "`rods`[2] (3 m) is longer than the path of `rods` [0, 1]",
            "(2 m together)",
        ],
    );
}

/// Muscles: a spring index out of range, `|amplitude| >= 1`, a period that
/// is not positive, and unknown keys in the muscle's table.
#[test]
fn bad_muscles() {
    let muscle = |fields: &str| format!("{GOOD}muscles = [{{ {fields} }}]\n");
    assert_error(
        &muscle("spring = 2, amplitude = 0.1, period = 1.0"),
        10,
        &["`muscles`[0].spring = 2", "out of range", "2 springs"],
    );
    assert_error(
        &muscle("spring = 0, amplitude = 1.0, period = 1.0"),
        10,
        &["`muscles`[0].amplitude = 1", "below 1"],
    );
    assert_error(
        &muscle("spring = 0, amplitude = -1.5, period = 1.0"),
        10,
        &["`muscles`[0].amplitude = -1.5", "below 1"],
    );
    assert_error(
        &muscle("spring = 1, amplitude = 0.1, period = 0.0"),
        10,
        &["`muscles`[0].period = 0", "positive"],
    );
    assert_error(
        &muscle("spring = 1, amplitude = 0.1, period = 1.0, frequency = 2.0"),
        10,
        &["unknown field `frequency`"],
    );
    assert_error(
        &muscle("spring = 1, period = 1.0"),
        10,
        &["missing field `amplitude`"],
    );
}

/// `rigid = true` needs two particles, no pins and no muscles.
#[test]
fn bad_rigid_bodies() {
    // GOOD has 9 lines: `[[body]]` is line 10, `rigid` line 13.
    let dot = "[[body]]\nname = \"dot\"\nparticles = [[0.0, 5.0]]\nrigid = true\n";
    assert_error(
        &format!("{GOOD}{dot}"),
        13,
        &["body \"dot\"", "`rigid` = true", "two particles"],
    );
    assert_error(
        &format!("{GOOD}pinned = [0]\nrigid = true\n"),
        11,
        &["`rigid` = true", "`pinned`"],
    );
    // A muscle on a rigid body would drive a spring that moves nothing.
    assert_error(
        &format!(
            "{GOOD}muscles = [{{ spring = 0, amplitude = 0.2, period = 1.0 }}]\nrigid = true\n"
        ),
        11,
        &["`rigid` = true", "`muscles`", "moves nothing"],
    );
}

/// `[gravitation]`: a negative softening or constant; `gravitating`
/// without the table.
#[test]
fn bad_gravitation() {
    // GOOD has 9 lines: `[gravitation]` is line 10, its key line 11.
    assert_error(
        &format!("{GOOD}[gravitation]\nsoftening = -1.0\n"),
        11,
        &[
            "gravitation:",
            "`gravitation.softening` = -1",
            "non-negative",
        ],
    );
    // A softening whose square overflows made every pull and energy zero.
    assert_error(
        &format!("{GOOD}[gravitation]\nsoftening = 1e308\n"),
        11,
        &["`gravitation.softening` = 1e308", "at most 1e100"],
    );
    assert_error(
        &format!("{GOOD}[gravitation]\nconstant = 1.0\nsoftening = 0.1\nconstant_g = 1.0\n"),
        13,
        &["unknown field `constant_g`"],
    );
    assert_error(
        &format!("{GOOD}[gravitation]\nsoftening = 0.1\nconstant = -6.674e-11\n"),
        12,
        &["`gravitation.constant`", "non-negative"],
    );
    assert_error(
        &format!("{GOOD}gravitating = false\n"),
        10,
        &["`gravitating` needs a `[gravitation]` table"],
    );
    // A direct sum over every pair: 142² = 20 164 gravitating particles
    // (with GOOD's 3) are 2e8 pairs a step, refused before the run (a
    // 300² cloth ran for more than a minute without finishing a step);
    // the same cloth left out with `gravitating = false` loads.
    let big =
        "[[body]]\nname = \"big\"\ncloth = { nx = 142, ny = 142, width = 1.0, height = 1.0 }\n";
    assert_error(
        &format!("{GOOD}[gravitation]\nconstant = 1.0\n{big}"),
        10,
        &[
            "gravitation between 20167 particles",
            "2.0e8 pairs",
            "`gravitating = false`",
        ],
    );
    let left_out = format!("{GOOD}[gravitation]\nconstant = 1.0\n{big}gravitating = false\n");
    parse_scene(&left_out, Path::new("good.toml")).expect("the cloth left out of gravitation");
}

/// The world's limits must be positive and at most 1e100: beyond, the
/// energies within them overflow the diagnostics' sums, and the error
/// belongs on the limit's line (4), not on a body's masses.
#[test]
fn world_limits() {
    let with = |key: &str| variant("steps = 10\n", &format!("steps = 10\n{key}\n"));
    assert_error(
        &with("max_distance = 1e308"),
        4,
        &["`max_distance` = 1e308", "at most 1e100 (m)"],
    );
    assert_error(
        &with("max_speed = 1e101"),
        4,
        &["`max_speed` = 1e101", "at most 1e100 (m/s)"],
    );
    assert_error(
        &with("max_speed = 0.0"),
        4,
        &["`max_speed` = 0", "positive"],
    );
    let scene = parse_scene(&with("max_distance = 1e100"), Path::new("good.toml"))
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.world.settings.max_distance, 1e100);
}

/// `constraint_tolerance` must be positive, `constraint_iterations` from 1
/// to 100 000, on the line of the key (line 4).
#[test]
fn constraint_settings() {
    let with = |key: &str| variant("steps = 10\n", &format!("steps = 10\n{key}\n"));
    assert_error(
        &with("constraint_tolerance = 0.0"),
        4,
        &["`constraint_tolerance` = 0", "positive"],
    );
    assert_error(
        &with("constraint_tolerance = -1e-9"),
        4,
        &["`constraint_tolerance` = -1e-9", "positive"],
    );
    assert_error(
        &with("constraint_iterations = 0"),
        4,
        &["`constraint_iterations` = 0", "from 1 to 100 000"],
    );
    assert_error(
        &with("constraint_iterations = 100001"),
        4,
        &["`constraint_iterations` = 100001", "from 1 to 100 000"],
    );
    assert_error(
        &with("constraint_iterations = -5"),
        4,
        &["constraint_iterations"],
    );
    let scene = parse_scene(
        &with("constraint_tolerance = 1e-6\nconstraint_iterations = 50"),
        Path::new("good.toml"),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.world.settings.constraints.tolerance, 1e-6);
    assert_eq!(scene.world.settings.constraints.iterations, 50);
}

/// A scene with rods, muscles, a rigid body and `[gravitation]` loads whole.
#[test]
fn rods_muscles_rigid_and_gravitation_load() {
    let text = r#"[sim]
dt = 1e-3
steps = 10
gravity = [0.0, 0.0, 0.0]

[[body]]
name = "arm"
particles = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 0.0, 0.0]]
springs = [[2, 3], [0, 1]]
rods = [[1, 2], [0, 2]]
rod_lengths = [1.0, 2.0]
muscles = [{ spring = 0, amplitude = 0.5, period = 2.0, phase = 1.5707963267948966 }, { spring = 1, amplitude = 0.1, period = 1.0 }]

[[body]]
name = "block"
lattice = { nx = 2, ny = 2, nz = 2, spacing = 0.5 }
translate = [0.0, 5.0, 0.0]
rigid = true
gravitating = false

[[body]]
name = "moon"
particles = [[0.0, -5.0, 0.0], [1.0, -5.0, 0.0]]
mass = 1e9
rigid = true

[gravitation]
softening = 0.01
"#;
    let mut scene = parse_scene(text, Path::new("good.toml")).unwrap_or_else(|e| panic!("{e}"));
    let world = &scene.world;
    assert_eq!(world.rods.len(), 2);
    assert_eq!(world.rods.length, vec![1.0, 2.0]);
    assert_eq!(world.muscles.list.len(), 2);
    assert_eq!(world.rigid.list.len(), 2);
    // The first muscle is the scene's spring 0, [2, 3]: at t = 0 its rest
    // length is L0 (1 + 0.5 sin(π/2)) = 1.5 m.
    let muscle = &world.muscles.list[0];
    assert_eq!(world.springs.rest_length[muscle.spring], 1.5);
    assert_eq!(muscle.rest_length, 1.0);
    let gravitation = world
        .forces
        .get::<sprung::forces::Gravitation>()
        .expect("a gravitation force");
    assert_eq!(gravitation.constant, sprung::forces::GRAVITATIONAL_CONSTANT);
    assert_eq!(gravitation.softening, 0.01);
    let gravitating: Vec<bool> = world.bodies.iter().map(|b| b.gravitating).collect();
    assert_eq!(gravitating, [true, false, true]);
    assert!(world.bodies[1].rigid && !world.bodies[0].rigid);
    // It steps, and the rods and gravitation show in the energies.
    for _ in 0..scene.steps {
        scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
    }
    assert!(
        scene
            .world
            .rods
            .largest_error(&scene.world.particles.position)
            < 1e-8
    );
    assert!(
        scene
            .world
            .energies()
            .get("gravitation")
            .expect("a standard term")
            < 0.0
    );
}

#[test]
fn a_rod_between_pins_and_two_muscles_on_one_spring_are_refused() {
    let head = "[sim]\ndt = 1e-3\nsteps = 2\n\n[[body]]\nname = \"b\"\nparticles = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]\nsprings = [[0, 1], [1, 2]]\n";
    for (tail, line, needle) in [
        (
            "pinned = [0, 1]\nrods = [[0, 1]]\n",
            "s.toml:10:",
            "`rods`[0] joins two pinned particles",
        ),
        (
            "muscles = [{ spring = 1, amplitude = 0.1, period = 1.0 }, { spring = 1, amplitude = 0.2, period = 2.0 }]\n",
            "s.toml:9:",
            "another muscle drives this spring already",
        ),
    ] {
        let text = format!("{head}{tail}");
        let Err(error) = parse_scene(&text, Path::new("s.toml")) else {
            panic!("{tail}: accepted");
        };
        let error = error.to_string();
        assert!(error.contains(needle), "{error}");
        assert!(error.starts_with(line), "names the key's line: {error}");
    }
}

#[test]
fn a_2d_gas_body_off_its_plane_is_refused() {
    // A 2D gas takes the area its loop encloses in the xy-plane: a ring
    // turned out of that plane (its area there near zero, its pressure
    // without bound) or thrown out of it is refused on the gas's line.
    let ring = "[sim]\ndt = 1e-4\n\n[[body]]\nname = \"ring\"\nring = { particles = 16, radius = 0.5 }\ngas = { nrt = 1.0 }\n";
    assert_error(
        &format!("{ring}rotate = [90.0, 0.0, 0.0]\n"),
        7,
        &["a 2D gas body", "particle 1 has z = "],
    );
    assert_error(
        &format!("{ring}velocity = [0.0, 0.0, 5.0]\n"),
        7,
        &["a 2D gas body", "particle 0 has velocity z = 5"],
    );
    // In the plane, spun about z, or turned over (a half turn about x
    // leaves z of rounding size, some 1e-17 m): accepted.
    let spun = format!("{ring}rotate = [0.0, 0.0, 30.0]\nvelocity = [1.0, 2.0]\n");
    assert!(parse_scene(&spun, Path::new("spun.toml")).is_ok());
    let over = format!("{ring}rotate = [180.0, 0.0, 0.0]\nvelocity = [1.0, 2.0]\n");
    assert!(parse_scene(&over, Path::new("over.toml")).is_ok());
}

/// Placement of a 2D body: a turn about x or y takes a 2D body (one with
/// segments) out of the plane z = 0 where 2D gas and contact work, and two
/// angles were read as turns about x and y; a rope made rigid is told why
/// it has a pinned particle.
#[test]
fn turns_that_leave_the_plane_and_a_rigid_rope() {
    // GOOD has 9 lines: `[[body]]` is line 10, `rotate` line 13.
    let ring = "[[body]]\nname = \"r\"\nring = { particles = 12, radius = 0.5 }\n";
    assert_error(
        &format!("{GOOD}{ring}rotate = [30.0, 0.0, 0.0]\n"),
        13,
        &["body \"r\"", "tilts this 2D body", "[0.0, 0.0, angle]"],
    );
    assert_error(
        &format!("{GOOD}{ring}rotate = [30.0, 0.0]\n"),
        13,
        &["`rotate` takes three angles"],
    );
    let turned = format!("{GOOD}{ring}rotate = [0.0, 0.0, 30.0]\n");
    let scene = parse_scene(&turned, Path::new("good.toml")).expect("a turn in the plane");
    assert!(scene.world.particles.position.iter().all(|p| p.z == 0.0));
    // Moved along z without a turn: in a plane of its own, accepted.
    let moved = format!("{GOOD}{ring}translate = [0.0, 2.0, 1.0]\n");
    parse_scene(&moved, Path::new("good.toml")).expect("a 2D body moved along z");
    let rope = "[[body]]\nname = \"r\"\nrope = { particles = 5, length = 1.0 }\nrigid = true\n";
    assert_error(
        &format!("{GOOD}{rope}"),
        13,
        &[
            "`rigid` = true",
            "a rope pins its first particle",
            "`pinned = []`",
        ],
    );
}

/// A placement that ruins the body is refused on its own line: a
/// translation of 1e308 m rounds particles 1 m apart onto one place (it
/// was reported as a zero-length spring on the `springs` line), and a
/// scale or translation beyond the world's limit names `scale` or
/// `translate` (it named the `particles` line).
#[test]
fn placements_that_ruin_the_body_name_their_own_line() {
    // GOOD has 9 lines: the key below is line 10.
    assert_error(
        &format!("{GOOD}translate = [1e308, 0.0, 0.0]\n"),
        10,
        &["`translate` = [1e308, 0.0, 0.0]", "spring 0 at one place"],
    );
    assert_error(
        &format!("{GOOD}translate = [2e6, 0.0, 0.0]\n"),
        10,
        &[
            "beyond the world's limit",
            "where `scale`, `rotate` and `translate` put it",
        ],
    );
    assert_error(
        &format!("{GOOD}scale = 1e7\n"),
        10,
        &["beyond the world's limit", "where `scale`"],
    );
}

/// A rod longer than the world is wide (twice `max_distance`) cannot hold
/// within it: `rod_lengths = [1e300]` ran and died at the first step as a
/// non-finite state; it is refused on its line.
#[test]
fn a_rod_longer_than_the_world_is_refused() {
    // GOOD has 9 lines: `rods` is line 10, `rod_lengths` line 11.
    assert_error(
        &format!("{GOOD}rods = [[0, 2]]\nrod_lengths = [1e300]\n"),
        11,
        &[
            "`rod_lengths`[0]: 1.000e300",
            "a rod at most twice `max_distance`",
        ],
    );
    let long = format!("{GOOD}rods = [[0, 2]]\nrod_lengths = [3.0]\n");
    parse_scene(&long, Path::new("good.toml")).expect("a rod within the world");
}

#[test]
fn an_entry_of_an_array_over_several_lines_is_named_on_its_own_line() {
    // The springs, masses and pins written one entry a line (with a
    // comment): the error points at the bad entry's line, not the key's.
    let springs = variant(
        "springs = [[0, 1], [1, 2]]",
        "springs = [\n  [0, 1], # first\n  [1, 9],\n]",
    );
    assert_error(&springs, 10, &["`springs`[1] = [1, 9]", "out of range"]);
    let masses = variant("mass = 1.0", "masses = [\n  1.0,\n  1.0,\n  -2.0,\n]");
    assert_error(&masses, 12, &["`masses`[2] = -2", "must be positive"]);
    let pinned = variant("mass = 1.0", "mass = 1.0\npinned = [\n  0,\n  7,\n]");
    assert_error(&pinned, 12, &["`pinned`[1] = 7", "out of range"]);
    // On one line, the key's line, as before.
    let one_line = variant("[[0, 1], [1, 2]]", "[[0, 1], [1, 9]]");
    assert_error(&one_line, 8, &["`springs`[1] = [1, 9]"]);
}

#[test]
fn tables_and_keys_given_twice_or_as_lists_are_named() {
    // GOOD has 9 lines. A `[contact]` table written as a list of tables
    // (the parser's own words: "invalid type: map, expected a boolean"),
    // a table given twice, a key given twice (the parser's: "duplicate
    // key", naming neither).
    assert_error(
        &format!("{GOOD}[[contact]]\nthickness = 0.02\n"),
        10,
        &["`[[contact]]`", "one table, written `[contact]`"],
    );
    assert_error(
        &format!("{GOOD}[contact]\nthickness = 0.02\n[contact]\nfriction = 0.1\n"),
        12,
        &["`[contact]` is given twice"],
    );
    assert_error(
        &variant("mass = 1.0", "mass = 1.0\nmass = 2.0"),
        10,
        &["`mass` is given twice in its table"],
    );
}
