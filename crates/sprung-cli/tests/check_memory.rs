//! `sprung check`'s figure of the memory a run takes is measured (the
//! world as loaded, its first steps, the loading's peak), and agrees with
//! the heap peak the run itself reports (`--profile`) to within 25 %;
//! where bodies press together at speed after those steps, it names the
//! most the CCD's pairs can add, and the run stays within it.

mod common;

use common::{sprung, text, write};

/// The first number (MB) after `label` in `output`.
fn megabytes(output: &str, label: &str) -> f64 {
    let line = output
        .lines()
        .find(|l| l.contains(label))
        .unwrap_or_else(|| panic!("no {label:?} in {output}"));
    let rest = &line[line.find(label).unwrap() + label.len()..];
    let number: String = rest
        .trim_start_matches(|c: char| !c.is_ascii_digit())
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == '.')
        .collect();
    number.parse().expect("a number")
}

#[test]
fn check_measures_the_memory_a_run_takes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    // Many bodies that touch: 100 small cloths in a stack, falling onto
    // each other (candidate contact pairs, their schedules, the CCD's
    // buffers), and 100 gas balls beside them.
    let mut scene = String::from("[sim]\ndt = 5e-4\nsteps = 3\nintegrator = \"rk4\"\n");
    for i in 0..100 {
        scene.push_str(&format!(
            "\n[[body]]\nname = \"c{i}\"\ncloth = {{ nx = 12, ny = 12, width = 1.0, height = 1.0 }}\nstiffness = 100.0\nrotate = [90.0, 0.0, 0.0]\ntranslate = [0.0, {}, 0.0]\n",
            f64::from(i) * 0.01
        ));
        scene.push_str(&format!(
            "\n[[body]]\nname = \"b{i}\"\nsphere = {{ radius = 0.1, subdivisions = 2 }}\nstiffness = 100.0\ngas = {{ nrt = 1.0 }}\ntranslate = [{}, 0.0, 3.0]\n",
            f64::from(i) * 0.3
        ));
    }
    write(d, "many.toml", &scene);
    let check = sprung(&["check", "many.toml"], d);
    assert!(check.status.success(), "{}", text(&check.stderr));
    let estimate = megabytes(&text(&check.stdout), "memory while running:");
    let run = sprung(
        &["run", "many.toml", "--out", "o", "--profile", "--quiet"],
        d,
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let peak = megabytes(&text(&run.stdout), "heap peak:");
    assert!(peak > 10.0, "a scene of {peak} MB is too small to tell");
    assert!(
        (estimate - peak).abs() <= 0.25 * peak,
        "check said {estimate} MB, the run's heap peaked at {peak} MB"
    );
}

#[test]
fn check_bounds_the_memory_of_contacts_that_come_later() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    // The bullet demo's ball at 100 m/s, 20 cm above a 30 × 30 cloth:
    // it reaches the cloth after check's two steps, and the CCD
    // then keeps about 1.8 million pairs of elements (tens of MB).
    let scene = "[sim]\ndt = 2.5e-4\nsteps = 60\nintegrator = \"symplectic_euler\"\n\n\
        [[body]]\nname = \"ball\"\nsphere = { radius = 0.1, subdivisions = 2 }\n\
        total_mass = 0.2\nstiffness = 2000.0\ndamping = 0.5\ntranslate = [0.0, 0.3, 0.0]\n\
        velocity = [0.0, -100.0, 0.0]\ngas = { nrt = 100.0, ramp_time = 0.0 }\n\n\
        [[body]]\nname = \"cloth\"\ncloth = { nx = 30, ny = 30, width = 1.0, height = 1.0 }\n\
        total_mass = 0.2\nstiffness = 500.0\ndamping = 0.05\nrotate = [90.0, 0.0, 0.0]\n\
        translate = [-0.5, 0.0, -0.5]\npinned = [0, 29, 870, 899]\n";
    write(d, "bullet.toml", scene);
    let check = sprung(&["check", "bullet.toml"], d);
    assert!(check.status.success(), "{}", text(&check.stderr));
    let said = text(&check.stdout);
    let estimate = megabytes(&said, "memory while running:");
    let contacts = megabytes(&said, "the CCD's pairs may add up to");
    // The bound is 3 × (at least 2 million pairs) × 16 bytes, and a
    // 4-byte stamp each: the 6,125 elements' 256 each are fewer than
    // the 2 million, and they make 18.8 million pairs.
    assert_eq!(contacts, 104.0, "{said}");
    let run = sprung(
        &["run", "bullet.toml", "--out", "o", "--profile", "--quiet"],
        d,
    );
    assert!(run.status.success(), "{}", text(&run.stderr));
    let peak = megabytes(&text(&run.stdout), "heap peak:");
    // The contacts came after check's steps: the run took more than the
    // measured figure (so this scene tells), and no more than the bound.
    assert!(
        peak > 1.25 * estimate,
        "the run's {peak} MB against {estimate} MB"
    );
    assert!(
        peak <= estimate + contacts,
        "the run's heap peaked at {peak} MB, over {estimate} + {contacts} MB"
    );
}
