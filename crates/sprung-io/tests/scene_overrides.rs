//! Overrides of a scene's keys (`--set KEY=VALUE`): the effective scene
//! written back as TOML builds the same world, bit for bit; each override
//! changes exactly its key; and each error names the key it is about.

use std::path::{Path, PathBuf};

use sprung_io::demos::{Bundled, DEMOS};
use sprung_io::toml::Value;
use sprung_io::{
    apply_overrides, parse_scene_overridden, parse_scene_with, Disk, FileSource, Override, Scene,
    SceneError,
};

/// The scenes folder of the repository.
fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

/// Everything of a scene that its world is built from, each number in
/// full (`{:?}` writes the shortest text that reads back to the same
/// bits), and the particles after a few steps, which the forces (gas,
/// wind, gravitation, contact) move.
fn fingerprint(mut scene: Scene, steps: usize) -> Vec<String> {
    let world = &scene.world;
    let mut parts = vec![
        format!(
            "{:?} {:?} {:?} {:?}",
            scene.dt, scene.steps, scene.every, scene.camera
        ),
        format!("{:?}", world.particles),
        // Not the number of the springs' topology, which every world
        // draws afresh from a counter.
        format!("{:?}", world.springs)
            .split(", topology:")
            .next()
            .unwrap_or_default()
            .to_string(),
        format!("{:?}", world.bodies),
        format!("{:?}", world.colliders),
        format!("{:?}", world.settings),
        format!("{:?}", world.contacts.settings),
        format!("{:?} {:?} {:?}", world.rods, world.muscles, world.rigid),
        format!("{:?}", world.integrator()),
        format!("{:?}", scene.warnings),
    ];
    for _ in 0..steps {
        scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
    }
    parts.push(format!("{:?}", scene.world.particles.position));
    parts.push(format!("{:?}", scene.world.particles.velocity));
    parts
}

/// The scene `text` at `path` and the scene of its text written back with
/// no override build bit-identical worlds that step alike.
fn assert_round_trip(text: &str, path: &Path, files: &dyn FileSource) {
    let written = apply_overrides(text, path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let original = parse_scene_with(text, path, files).unwrap_or_else(|e| panic!("{e}"));
    let again = parse_scene_with(&written, path, files)
        .unwrap_or_else(|e| panic!("{}: written back: {e}\n{written}", path.display()));
    assert_same(&fingerprint(original, 5), &fingerprint(again, 5), path);
}

/// The fingerprints `a` and `b` are equal; else the first difference,
/// with some text around it.
fn assert_same(a: &[String], b: &[String], what: &Path) {
    for (a, b) in a.iter().zip(b) {
        if let Some(at) = a.bytes().zip(b.bytes()).position(|(x, y)| x != y) {
            let from = at.saturating_sub(100);
            let window = |s: &str| {
                s.get(from..(at + 100).min(s.len()))
                    .unwrap_or(s)
                    .to_string()
            };
            panic!("{}: differs:\n{}\n{}", what.display(), window(a), window(b));
        }
        assert_eq!(a.len(), b.len(), "{}", what.display());
    }
}

#[test]
fn every_demo_and_scene_written_back_builds_the_same_world() {
    // Claim: the effective scene of no override, written by the TOML
    // writer (its numbers in full, `[[body]]` sections with their own
    // sub-tables), builds the same world to the bit as the file, and it
    // steps alike: for every demo and every file of scenes/.
    for demo in DEMOS {
        assert_round_trip(demo.text, &demo.path(), &Bundled);
    }
    let mut files = 0;
    for entry in std::fs::read_dir(scenes()).expect("scenes/") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "toml") {
            let text = std::fs::read_to_string(&path).expect("scene");
            assert_round_trip(&text, &path, &Disk);
            files += 1;
        }
    }
    assert!(files >= DEMOS.len(), "{files} scenes");
}

#[test]
fn the_every_key_block_and_inline_bodies_written_back_build_the_same_world() {
    // docs/scenes.md's block of every key (its horse found beside the
    // scenes), and bodies given inline as `body = [...]`, one with a space
    // in its name, with numbers that try the writer: the smallest
    // subnormal, 1e-300 (written out in full), -0.0 and 17 digits.
    let page = include_str!("../../../docs/scenes.md");
    let start = page.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let block = &page[start..start + page[start..].find("```").expect("its end")];
    assert_round_trip(block, &scenes().join("every_key.toml"), &Disk);
    let inline = r#"
body = [
  { name = "a b", particles = [[0, 0, 0], [1, 0, 0], [-0.0, 5e-324, 0.1]], springs = [[0, 1], [1, 2]], masses = [1e-300, 0.1, 123456789.12345679] },
  { name = "rope", rope = { particles = 4, length = 1.0 }, gas = { nrt = 1.0 } },
]

[sim]
dt = 1e-3
steps = 3
"#;
    // The rope cannot hold gas: the written text is refused alike.
    let written = apply_overrides(inline, Path::new("i.toml"), &[]).expect("written");
    let error = |text: &str| parse_scene_with(text, Path::new("i.toml"), &Disk).unwrap_err();
    assert_eq!(error(inline).message, error(&written).message);
    let inline = inline.replace(", gas = { nrt = 1.0 }", "");
    assert_round_trip(&inline, Path::new("i.toml"), &Disk);
}

/// `KEY=VALUE` arguments as overrides.
fn set(arguments: &[&str]) -> Vec<Override> {
    arguments
        .iter()
        .map(|a| a.parse().unwrap_or_else(|e| panic!("{e}")))
        .collect()
}

const SCENE: &str = r#"# a ball on a rope
[sim]
dt = 1e-3
steps = 10
gravity = [0.0, -9.81, 0.0]

[[body]]
name = "rope"
rope = { particles = 5, length = 1.0 }
stiffness = 100.0

[[body]]
name = "ball"
sphere = { radius = 0.5 }
gas = { nrt = 10.0 }
translate = [3.0, 0.0, 0.0]

[[collider]]
plane = { point = [0.0, -2.0, 0.0], normal = [0.0, 1.0, 0.0] }

[[collider]]
plane = { point = [0.0, -3.0, 0.0], normal = [0.0, 1.0, 0.0] }
"#;

fn overridden(arguments: &[&str]) -> Result<Scene, SceneError> {
    parse_scene_overridden(SCENE, Path::new("s.toml"), &set(arguments), &Disk)
}

fn error(arguments: &[&str]) -> SceneError {
    overridden(arguments).map(|_| ()).unwrap_err()
}

#[test]
fn values_are_read_as_toml_or_as_a_bare_word() {
    let one = |argument: &str| argument.parse::<Override>().map(|o| (o.key, o.value));
    assert_eq!(
        one("sim.dt=1e-4"),
        Ok(("sim.dt".into(), Value::Float(1e-4)))
    );
    assert_eq!(one(" a.b = 200 "), Ok(("a.b".into(), Value::Integer(200))));
    assert_eq!(one("a=true"), Ok(("a".into(), Value::Boolean(true))));
    assert_eq!(
        one("a=\"rk4\""),
        Ok(("a".into(), Value::String("rk4".into())))
    );
    assert_eq!(one("a=rk4"), Ok(("a".into(), Value::String("rk4".into()))));
    assert_eq!(
        one("a=symplectic_euler"),
        Ok(("a".into(), Value::String("symplectic_euler".into())))
    );
    // The key ends at the first `=` outside its quoted parts.
    assert_eq!(
        one("a=\"b=c\""),
        Ok(("a".into(), Value::String("b=c".into())))
    );
    assert_eq!(
        one("body.\"x=1\".mass=2"),
        Ok(("body.\"x=1\".mass".into(), Value::Integer(2)))
    );
    let list = one("sim.gravity=[0, -1.5, 0]").expect("a list").1;
    assert_eq!(list.to_string(), "[0, -1.5, 0]");
    let table = one("body.c.cloth={ nx = 4, ny = 4 }").expect("a table").1;
    assert_eq!(table.get("nx"), Some(&Value::Integer(4)));
    // Refused, naming the argument.
    for (argument, fragment) in [
        ("sim.dt", "there is no `=`"),
        ("=1", "the key is empty"),
        ("sim.dt=", "the value of `sim.dt` is empty"),
        ("sim..dt=1", "an empty part"),
        ("sim.dt.=1", "ends with a dot"),
        ("sim dt=1", "`sim dt`: ` ` in `sim dt`"),
        ("a=[1,", "is not a TOML value"),
        ("a=two words", "is not a TOML value"),
    ] {
        let error = argument.parse::<Override>().unwrap_err();
        let message = error.to_string();
        assert!(message.starts_with(&format!("`{argument}`: ")), "{message}");
        assert!(message.contains(fragment), "{message} lacks {fragment}");
    }
}

#[test]
fn each_override_changes_its_key_and_nothing_else() {
    // The scene with an override builds what the file edited by hand
    // builds, to the bit.
    let edited = |from: &str, to: &str| {
        assert!(SCENE.contains(from), "{from}");
        parse_scene_with(&SCENE.replacen(from, to, 1), Path::new("s.toml"), &Disk).expect("edited")
    };
    let same = |arguments: &[&str], by_hand: Scene| {
        let scene = overridden(arguments).unwrap_or_else(|e| panic!("{e}"));
        let what = PathBuf::from(arguments.join(" "));
        assert_same(&fingerprint(scene, 3), &fingerprint(by_hand, 3), &what);
    };
    same(&["sim.dt=2.5e-4"], edited("dt = 1e-3", "dt = 2.5e-4"));
    same(
        &["sim.integrator=rk4"],
        edited("steps = 10", "steps = 10\nintegrator = \"rk4\""),
    );
    same(
        &["body.ball.gas.nrt=80"],
        edited("nrt = 10.0", "nrt = 80.0"),
    );
    same(&["body.1.gas.nrt=80"], edited("nrt = 10.0", "nrt = 80.0"));
    same(
        &["body.rope.stiffness=7"],
        edited("stiffness = 100.0", "stiffness = 7.0"),
    );
    same(
        &["body.rope.rope.particles=3"],
        edited("particles = 5", "particles = 3"),
    );
    let second = "[0.0, -3.0, 0.0], normal = [0.0, 1.0, 0.0] }";
    same(
        &["collider.1.friction=0.5"],
        edited(second, &format!("{second}\nfriction = 0.5")),
    );
    same(&["sim.gravity.1=-1"], edited("-9.81", "-1.0"));
    same(
        &["body.ball.translate.0=4"],
        edited("[3.0, 0.0, 0.0]", "[4.0, 0.0, 0.0]"),
    );
    // A table the scene lacks is made.
    same(
        &["contact.friction=0.25"],
        edited("\n[[body]]", "[contact]\nfriction = 0.25\n\n[[body]]"),
    );
    // In order: the last of two overrides of a key wins.
    same(
        &["sim.dt=1", "sim.dt=2e-3"],
        edited("dt = 1e-3", "dt = 2e-3"),
    );
    // `[[body]]` tables or `body = [...]`: the same keys.
    let inline = "body = [{ name = \"r 2\", rope = { particles = 4, length = 1.0 } }]\n[sim]\ndt = 1e-3\nsteps = 2\n";
    let scene = parse_scene_overridden(
        inline,
        Path::new("i.toml"),
        &set(&["body.\"r 2\".mass=2"]),
        &Disk,
    )
    .expect("inline");
    assert_eq!(scene.world.particles.mass, vec![2.0; 4]);
}

#[test]
fn an_override_that_breaks_the_scene_is_named_by_its_key() {
    let stifness = error(&["sim.dt=2e-3", "body.ball.stifness=1"]);
    assert_eq!(stifness.key.as_deref(), Some("body.ball.stifness"));
    assert_eq!(stifness.line, None);
    assert!(
        stifness
            .to_string()
            .starts_with("s.toml: `--set body.ball.stifness`: unknown field `stifness`, expected one of `name`, "),
        "{stifness}"
    );
    let fast = error(&["sim.dt=\"fast\""]);
    assert_eq!(fast.key.as_deref(), Some("sim.dt"));
    assert_eq!(
        fast.message,
        "`--set sim.dt`: invalid type: string \"fast\", expected f64"
    );
    // A value the scene refuses, the culprit found among several.
    let negative = error(&[
        "sim.steps=3",
        "body.rope.rope.length=-1",
        "collider.0.friction=0.1",
    ]);
    assert_eq!(
        negative.key.as_deref(),
        Some("body.rope.rope.length"),
        "{negative}"
    );
    // Where the key leads nowhere.
    for (arguments, key, fragment) in [
        (
            &["body.bal.mass=1"][..],
            "body.bal.mass",
            "there is no body named \"bal\": the bodies are \"rope\", \"ball\" (or pick one by its index from 0)",
        ),
        (
            &["collider.2.friction=1"],
            "collider.2.friction",
            "there is no collider 2: `collider` has 2 colliders, numbered from 0 to 1",
        ),
        (
            &["sim.dt.x=1"],
            "sim.dt.x",
            "`sim.dt` is a float (0.001), not a table: there is no `x` in it",
        ),
        (
            &["sim.gravity.a=1"],
            "sim.gravity.a",
            "`sim.gravity` is a list without names: pick an entry by its index from 0 to 2 (`sim.gravity.0`)",
        ),
    ] {
        let error = error(arguments);
        assert_eq!(error.key.as_deref(), Some(key), "{error}");
        assert_eq!(error.message, format!("`--set {key}`: {fragment}"));
    }
    let none = parse_scene_overridden(
        "[sim]\ndt = 1e-3\n",
        Path::new("e.toml"),
        &set(&["body.x.mass=1"]),
        &Disk,
    )
    .unwrap_err();
    assert_eq!(
        none.message,
        "`--set body.x.mass`: there is no body named \"x\": the scene has no bodies"
    );
}

#[test]
fn the_scenes_own_error_is_reported_at_its_line_with_or_without_overrides() {
    // A misspelt key: its line and its key, overrides or not (the file's
    // error comes first).
    let typo = SCENE.replace("steps = 10", "steps = 10\ntimestep = 3");
    for overrides in [
        vec![],
        set(&["sim.dt=2e-3"]),
        set(&["body.ball.stifness=1"]),
    ] {
        let error =
            parse_scene_overridden(&typo, Path::new("s.toml"), &overrides, &Disk).unwrap_err();
        assert_eq!(error.line, Some(5), "{error}");
        assert_eq!(error.key.as_deref(), Some("timestep"), "{error}");
        assert!(error
            .message
            .starts_with("unknown field `timestep`, expected one of `dt`, "));
    }
    // Not TOML: the reader's error, at its line.
    let broken = SCENE.replace("stiffness = 100.0", "stiffness = = 100.0");
    let plain = parse_scene_with(&broken, Path::new("s.toml"), &Disk).unwrap_err();
    let with = parse_scene_overridden(&broken, Path::new("s.toml"), &set(&["sim.dt=1"]), &Disk)
        .unwrap_err();
    assert_eq!((plain.line, &plain), (Some(10), &with));
    // A key of the wrong type in the file: the key known.
    let wrong = SCENE.replace("dt = 1e-3", "dt = \"1e-3\"");
    let error = parse_scene_with(&wrong, Path::new("s.toml"), &Disk).unwrap_err();
    assert_eq!(
        (error.line, error.key.as_deref()),
        (Some(3), Some("dt")),
        "{error}"
    );
}

#[test]
fn an_overridden_scenes_warnings_name_no_line() {
    // Pinned twice: warned with its line in the file, and without one
    // when an override was applied (its line in the effective text is not
    // the file's).
    let scene = SCENE.replace("stiffness = 100.0", "stiffness = 100.0\npinned = [0, 0]");
    let plain = parse_scene_with(&scene, Path::new("s.toml"), &Disk).expect("loads");
    let with = parse_scene_overridden(&scene, Path::new("s.toml"), &set(&["sim.dt=1e-3"]), &Disk)
        .expect("loads");
    assert_eq!(plain.warnings.len(), 1);
    let message = plain.warnings[0]
        .strip_prefix("s.toml:11: ")
        .expect("the line of `pinned`");
    assert_eq!(with.warnings, vec![format!("s.toml: {message}")]);
}

#[test]
fn mesh_paths_resolve_from_the_scene_folder() {
    // poke.toml's `mesh = "meshes/horse.obj"`, with an override: the horse
    // is read from scenes/meshes as without it.
    let path = scenes().join("poke.toml");
    let text = std::fs::read_to_string(&path).expect("poke");
    let scene =
        parse_scene_overridden(&text, &path, &set(&["sim.duration=4e-4"]), &Disk).expect("poke");
    assert_eq!(scene.steps, 1);
    assert!(
        scene.world.particles.len() > 1000,
        "{}",
        scene.world.particles.len()
    );
}
