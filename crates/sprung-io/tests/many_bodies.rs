//! A scene of many small bodies (issue 49, "loading linear in the
//! bodies"): every body's warnings are placed at their own lines, counted
//! on from the last body's rather than from the top of the file for each
//! (which made loading quadratic in the bodies), and an error placed
//! after them, back near the top, still at its line.

use std::fmt::Write;
use std::path::Path;

use sprung_io::parse_scene;

/// Ropes placed as the reproducer places them, each pinning its
/// first particle twice and giving it a velocity (two warnings a body);
/// with the lines of each body's `pinned` and `velocity` keys.
fn ropes(bodies: usize) -> (String, Vec<(usize, usize)>) {
    let mut text = String::from("[sim]\ndt = 1e-3\nsteps = 1\n\n");
    for j in 0..bodies {
        // Some bodies' tables are longer, so the lines do not step evenly.
        let comment = if j % 7 == 3 {
            "# a longer table\n\n"
        } else {
            ""
        };
        write!(
            text,
            "[[body]]\n{comment}name = \"b{j}\"\nrope = {{ particles = 3, length = 1.0 }}\ntranslate = [{}.0, 0.0, {}.0]\npinned = [0, 0]\nvelocity = [0.0, 0.0, 1.0]\n\n",
            j % 100,
            3 * (j / 100),
        )
        .unwrap();
    }
    let numbered = || text.lines().zip(1..);
    let pinned = numbered()
        .filter(|(l, _)| l.starts_with("pinned"))
        .map(|(_, n)| n);
    let velocity = numbered()
        .filter(|(l, _)| l.starts_with("velocity"))
        .map(|(_, n)| n);
    let lines = pinned.zip(velocity).collect();
    (text, lines)
}

#[test]
fn each_of_many_bodies_warnings_is_placed_at_its_line() {
    let bodies = 2000;
    let (text, lines) = ropes(bodies);
    let scene = parse_scene(&text, Path::new("many.toml")).expect("valid scene");
    assert_eq!(scene.world.bodies.len(), bodies);
    assert_eq!(scene.warnings.len(), 2 * bodies);
    for (j, (pinned, velocity)) in lines.iter().enumerate() {
        let twice = &scene.warnings[2 * j];
        assert_eq!(
            twice,
            &format!("many.toml:{pinned}: body \"b{j}\": `pinned` lists particle 0 more than once (each is pinned once)")
        );
        let moving = &scene.warnings[2 * j + 1];
        assert!(
            moving.starts_with(&format!(
                "many.toml:{velocity}: body \"b{j}\": particle 0 given a velocity is pinned"
            )),
            "{moving}"
        );
    }
    // The bodies are as the loader built them: each three particles, the
    // first pinned, at its place.
    for (j, body) in scene.world.bodies.iter().enumerate() {
        assert_eq!(body.particles, 3 * j..3 * j + 3);
        let first = scene.world.particles.position[body.particles.start];
        assert_eq!(first.x, (j % 100) as f64);
        assert_eq!(first.z, (3 * (j / 100)) as f64);
        assert_eq!(
            scene.world.particles.inverse_mass[body.particles.start],
            0.0
        );
    }

    // An error placed after every body's warnings, at the first body: its
    // line (of `wind_scale`, the 7th) is counted from the top again.
    let unwindy = text.replacen("name = \"b0\"\n", "name = \"b0\"\nwind_scale = 2.0\n", 1);
    let error = parse_scene(&unwindy, Path::new("many.toml")).unwrap_err();
    assert_eq!(
        error.to_string(),
        "many.toml:7: body \"b0\": `wind_scale` needs a `[wind]` table"
    );
}
