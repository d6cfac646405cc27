//! `[[join]]` tables and the strain limits of bodies (`break_strain`,
//! `yield_strain`, `hardening`) in scene files: a good scene builds its
//! joins and limits; bad ones are refused with the file, the line and the
//! key (docs/scenes.md).

mod common;

use std::path::Path;

use sprung::tearing::JoinLink;
use sprung_io::parse_scene;

use common::scene_errors::assert_error;

/// Two bodies and a join between them: lines 18 to 22 are the join.
const JOINED: &str = r#"[sim]
dt = 1e-3
steps = 10

[[body]]
name = "a"
particles = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
springs = [[0, 1]]
break_strain = 0.5

[[body]]
name = "b"
particles = [[2.0, 0.0, 0.0], [3.0, 0.0, 0.0]]
springs = [[0, 1]]
yield_strain = 0.1
hardening = 0.5

[[join]]
a = ["a", 1]
b = ["b", 0]
stiffness = 200.0
break_strain = 0.3
"#;

#[test]
fn joins_and_limits_are_built_from_the_scene() {
    let scene = parse_scene(JOINED, Path::new("joined.toml")).expect("valid scene");
    let world = &scene.world;
    assert_eq!(world.joins.len(), 1);
    let join = &world.joins[0];
    assert_eq!(join.particles, [1, 2]);
    let JoinLink::Spring(s) = join.link else {
        panic!("a spring join")
    };
    assert_eq!(world.springs.rest_length[s], 1.0);
    assert_eq!(world.springs.stiffness[s], 200.0);
    assert_eq!(world.limits.break_strain(s), 0.3);
    assert_eq!(world.limits.break_strain(0), 0.5);
    assert_eq!(world.limits.yield_strain(0), f64::INFINITY);
    assert_eq!(world.limits.yield_strain(1), 0.1);
    assert!(world.energy_names().contains(&"plastic"));
    // A rod join instead.
    let rod = JOINED.replace(
        "stiffness = 200.0\nbreak_strain = 0.3\n",
        "rod = true\nrest_length = 0.5\n",
    );
    let scene = parse_scene(&rod, Path::new("rod.toml")).expect("valid scene");
    assert_eq!(scene.world.joins[0].link, JoinLink::Rod(0));
    assert_eq!(scene.world.rods.length, [0.5]);
}

fn with(from: &str, to: &str) -> String {
    assert!(JOINED.contains(from), "test setup: {from:?}");
    JOINED.replacen(from, to, 1)
}

#[test]
fn a_join_naming_an_unknown_body_or_particle_is_refused_on_its_line() {
    assert_error(
        &with("b = [\"b\", 0]", "b = [\"c\", 0]"),
        20,
        &["join 0", "body \"c\""],
    );
    assert_error(
        &with("a = [\"a\", 1]", "a = [\"a\", 2]"),
        19,
        &[
            "join 0",
            "[\"a\", 2]: particle index out of range (the body has 2 particles)",
        ],
    );
    assert_error(
        &with("b = [\"b\", 0]", "b = [\"a\", 1]"),
        19,
        &["same particle"],
    );
    assert_error(&with("stiffness = 200.0\n", ""), 19, &["needs `stiffness`"]);
    assert_error(
        &with("a = [\"a\", 1]", "a = [\"a\"]"),
        19,
        &["`a`", "expected a tuple of size 2"],
    );
}

#[test]
fn bad_strains_are_refused_on_their_lines() {
    assert_error(
        &with("break_strain = 0.3", "break_strain = -0.3"),
        22,
        &["join 0", "`break_strain` = -0.3", "positive and finite"],
    );
    assert_error(
        &with("break_strain = 0.3", "break_strain = nan"),
        22,
        &["`break_strain` = NaN"],
    );
    assert_error(
        &with("break_strain = 0.3", "rod = true\nbreak_strain = 0.3"),
        23,
        &["needs a spring join"],
    );
    assert_error(
        &with("break_strain = 0.5", "break_strain = -1.0"),
        9,
        &["body \"a\"", "`break_strain` = -1"],
    );
    assert_error(
        &with("yield_strain = 0.1", "yield_strain = nan"),
        15,
        &["body \"b\"", "`yield_strain` = NaN"],
    );
    assert_error(
        &with("hardening = 0.5", "hardening = -0.5"),
        16,
        &["body \"b\"", "`hardening` = -0.5"],
    );
    assert_error(
        &with(
            "yield_strain = 0.1",
            "yield_strain = 0.1\nbreak_strain = 0.1",
        ),
        15,
        &[
            "body \"b\"",
            "`yield_strain` = 0.1: must be below `break_strain` = 0.1",
        ],
    );
}
