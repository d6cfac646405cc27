//! Bad `[sim]` tables in scene files: each is refused before the run with
//! a message naming the file, the line and the key (docs/scenes.md,
//! issue "bad input"): the time step, the integrator, the length
//! of the run, the solvers' keys, the contact and substep keys, the
//! world's limits and the constraint settings. The line numbers asserted
//! are those of the offending key in the texts below, most of them changes
//! of the good base scene (`common::scene_errors::GOOD`).

mod common;

use std::path::Path;

use sprung_io::parse_scene;

use common::scene_errors::{assert_error, variant, GOOD};

#[test]
fn unknown_key_in_sim() {
    assert_error(
        &variant("steps = 10", "steps = 10\ntimestep = 3"),
        4,
        &["unknown field `timestep`"],
    );
}

#[test]
fn each_error_names_its_key_where_it_is_known() {
    // `SceneError::key`: the key as written in its table, misspelt ones
    // too, with the line of the key (in `[sim]`, in a body's own section,
    // in a builder's inline table); none where no one key is wrong.
    for (text, line, key) in [
        (
            variant("steps = 10", "steps = 10\ntimestep = 3"),
            4,
            Some("timestep"),
        ),
        (
            variant("mass = 1.0", "mass = 1.0\nstifness = 3"),
            10,
            Some("stifness"),
        ),
        (variant("dt = 1e-3", "dt = -1e-3"), 2, Some("dt")),
        (variant("dt = 1e-3", "dt = true"), 2, Some("dt")),
        (variant("mass = 1.0", "mass = -1.0"), 9, Some("mass")),
        (
            variant("mass = 1.0\n", "rope = { particles = 2, lenght = 1 }\n"),
            9,
            Some("lenght"),
        ),
        (variant("[sim]\n", "[sim]\n[sim]\n"), 2, Some("sim")),
        (variant("dt = 1e-3", "dt = = 1e-3"), 2, Some("dt")),
        (variant("steps = 10", "steps = 10\nwhat"), 4, None),
    ] {
        let error = common::scene_errors::error_of(&text);
        assert_eq!(
            (error.line, error.key.as_deref()),
            (Some(line), key),
            "{error}"
        );
    }
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
fn unknown_integrator() {
    assert_error(
        &variant("steps = 10", "steps = 10\nintegrator = \"leapfrog\""),
        4,
        &["unknown integrator \"leapfrog\"", "rk4"],
    );
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
