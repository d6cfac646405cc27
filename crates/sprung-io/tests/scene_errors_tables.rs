//! Bad keys and tables in scene files: each is refused before the run with
//! a message naming the file, the line and the key (docs/scenes.md,
//! issue "bad input"): unknown keys, wrong types and numbers that
//! are not finite, the `[[collider]]`, `[wind]`, `[camera]` and
//! `[gravitation]` tables, and tables and keys given twice or as lists;
//! and the good base scene (`common::scene_errors::GOOD`) they change is
//! good. The line numbers asserted are those of the offending key in the
//! texts below.

mod common;

use std::path::Path;

use sprung_io::parse_scene;

use common::scene_errors::{assert_error, variant, GOOD};

#[test]
fn the_base_scene_is_good() {
    let scene = parse_scene(GOOD, Path::new("good.toml")).expect("valid scene");
    assert_eq!(scene.world.particles.len(), 3);
    assert_eq!(scene.world.springs.len(), 2);
    assert_eq!(scene.steps, 10);
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
fn wrong_type() {
    assert_error(
        &variant("mass = 1.0", "mass = \"heavy\""),
        9,
        &["invalid type", "string"],
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
