//! Bad bodies in scene files: each is refused before the run with a
//! message naming the file, the line and the key (docs/scenes.md,
//! issue "bad input"): a body's particles, masses, springs, pins
//! and builders, rods, muscles and rigid parts, 2D bodies, and where
//! placing a body puts it. The line numbers asserted are those of the
//! offending key in the texts below, most of them changes of the good base
//! scene (`common::scene_errors::GOOD`).

mod common;

use std::path::Path;

use sprung_io::parse_scene;

use common::scene_errors::{assert_error, variant, GOOD};

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
fn pinned_index_out_of_range() {
    assert_error(
        &format!("{GOOD}pinned = [7]\n"),
        10,
        &["`pinned`[0] = 7", "out of range"],
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
