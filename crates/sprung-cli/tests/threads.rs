//! The same scene on 1 and on 2 threads writes byte-identical
//! `diagnostics.csv` and frames: every parallel loop of the engine writes
//! each particle's entries only, adds shared contributions block by block
//! in a fixed order, and sums in a tree fixed by the length (see
//! `sprung::parallel`). The scenes are large enough (more than the 4096
//! particles of one `parallel::CHUNK`) for the work to be split.

mod common;

use common::{sprung, text, write};

/// A 100 × 100 cloth (10 000 particles: three chunks, three blocks of
/// springs) in wind, by the given integrator, hanging from two corners.
fn cloth(integrator: &str, dt: f64, steps: u32, extra: &str) -> String {
    format!(
        r#"[sim]
dt = {dt}
integrator = "{integrator}"
steps = {steps}
every = 1

[[body]]
name = "cloth"
cloth = {{ nx = 100, ny = 100, width = 1.0, height = 1.0 }}
mass = 0.002
stiffness = 2.0e4
damping = 0.01
rotate = [60.0, 0.0, 0.0]
pinned = [0, 99]
translate = [0.0, 1.0, 0.0]
{extra}

[wind]
velocity = [0.0, 0.0, 3.0]
model = "simple"
coefficient = 0.002
"#
    )
}

/// A gas ball of 10 242 particles (icosphere, 5 subdivisions) dropped on
/// a plane, starting 5 mm into it: the plane projects its lowest
/// particles out (with restitution and friction) from the first step, in
/// spans that both threads take.
fn gas_ball(integrator: &str) -> String {
    format!(
        r#"[sim]
dt = 3e-5
integrator = "{integrator}"
steps = 12
every = 1

[[body]]
name = "ball"
sphere = {{ radius = 0.5, subdivisions = 5 }}
total_mass = 1.0
stiffness = 5000.0
damping = 0.1
translate = [0.0, 0.495, 0.0]
velocity = [0.3, -1.0, 0.0]
gas = {{ nrt = 300.0, ramp_time = 0.0 }}

[[collider]]
plane = {{ point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }}
restitution = 0.3
friction = 0.3
"#
    )
}

/// Two gas balls of 2562 particles thrown into each other (touching
/// within the thickness from the start), and a falling cloth that
/// searches for contact with itself.
const CONTACTS: &str = r#"[sim]
dt = 4e-5
integrator = "symplectic_euler"
steps = 40
every = 1
gravity = [0.0, 0.0, 0.0]

[contact]
thickness = 0.01
friction = 0.3

[[body]]
name = "left"
sphere = { radius = 0.5, subdivisions = 4 }
total_mass = 1.0
stiffness = 2000.0
damping = 0.5
translate = [-0.503, 0.0, 0.0]
velocity = [2.0, 0.0, 0.0]
gas = { nrt = 500.0, ramp_time = 0.0 }

[[body]]
name = "right"
sphere = { radius = 0.5, subdivisions = 4 }
total_mass = 1.0
stiffness = 2000.0
damping = 0.5
translate = [0.503, 0.05, 0.0]
velocity = [-2.0, 0.0, 0.0]
gas = { nrt = 500.0, ramp_time = 0.0 }

[[body]]
name = "sheet"
cloth = { nx = 60, ny = 60, width = 1.0, height = 1.0 }
mass = 0.002
stiffness = 2000.0
damping = 0.01
translate = [-0.5, 1.0, 0.0]
velocity = [0.0, -1.0, 0.0]
self_collision = true
"#;

/// Run `scene` on `threads` threads, frames as VTK; the bytes of
/// diagnostics.csv and of every frame, in order.
fn run(scene: &str, threads: &str) -> Vec<(String, Vec<u8>)> {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = write(dir.path(), "scene.toml", scene);
    let out = dir.path().join("out");
    let output = sprung(
        &[
            "--threads",
            threads,
            "run",
            path.to_str().expect("utf-8 path"),
            "--out",
            out.to_str().expect("utf-8 path"),
            "--format",
            "vtk",
            "--quiet",
        ],
        dir.path(),
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let mut files = vec![(
        "diagnostics.csv".to_string(),
        std::fs::read(out.join("diagnostics.csv")).expect("diagnostics"),
    )];
    let mut frames: Vec<_> = std::fs::read_dir(out.join("frames"))
        .expect("frames")
        .flatten()
        .map(|e| e.path())
        .collect();
    frames.sort();
    assert!(!frames.is_empty(), "no frames written");
    for frame in frames {
        let name = frame
            .file_name()
            .expect("name")
            .to_string_lossy()
            .into_owned();
        files.push((name, std::fs::read(&frame).expect("frame")));
    }
    files
}

/// The files of 1 and 2 threads are the same bytes.
fn assert_same_on_one_and_two_threads(scene: &str, what: &str) {
    let one = run(scene, "1");
    let two = run(scene, "2");
    assert_eq!(one.len(), two.len(), "{what}: number of files");
    for ((name, a), (_, b)) in one.iter().zip(&two) {
        assert!(a == b, "{what}: {name} differs between 1 and 2 threads");
    }
}

#[test]
fn explicit_cloth_in_wind_is_the_same_on_one_and_two_threads() {
    let scene = cloth("symplectic_euler", 1e-4, 20, "");
    assert_same_on_one_and_two_threads(&scene, "symplectic Euler cloth");
    let scene = cloth("rk45", 1e-3, 3, "");
    assert_same_on_one_and_two_threads(&scene, "rk45 cloth");
}

#[test]
fn gas_ball_is_the_same_on_one_and_two_threads() {
    assert_same_on_one_and_two_threads(&gas_ball("rk4"), "rk4 gas ball");
    assert_same_on_one_and_two_threads(&gas_ball("verlet"), "verlet gas ball");
}

#[test]
fn contacts_are_the_same_on_one_and_two_threads() {
    assert_same_on_one_and_two_threads(CONTACTS, "contacts");
}

#[test]
fn friction_on_a_rigid_body_is_the_same_on_one_and_two_threads() {
    // The contact scene with a rigid die (0.2 kg) set on the right ball,
    // within the thickness, sliding across it at 1 m/s: its touches take
    // friction through its motion, on one thread, after the others.
    let scene = format!(
        "{CONTACTS}\n[[body]]\nname = \"die\"\n\
         lattice = {{ nx = 3, ny = 3, nz = 3, spacing = 0.05 }}\ntotal_mass = 0.2\n\
         stiffness = 500.0\nrigid = true\ntranslate = [0.45, 0.556, -0.05]\n\
         velocity = [1.0, 0.0, 0.0]\n"
    );
    assert_same_on_one_and_two_threads(&scene, "friction on a rigid die");
}

#[test]
fn implicit_solvers_are_the_same_on_one_and_two_threads() {
    let scene = cloth("implicit_euler", 1.0 / 60.0, 3, "");
    assert_same_on_one_and_two_threads(&scene, "implicit Euler cloth");
    let scene = cloth("projective", 1.0 / 60.0, 3, "");
    assert_same_on_one_and_two_threads(&scene, "projective cloth");
}

#[test]
fn gravitation_is_the_same_on_one_and_two_threads() {
    // A cloud of 5000 gravitating particles (more than one chunk of 4096,
    // so the pulls run on both threads; their energy is a parallel sum),
    // three RK4 steps, every row and frame recorded.
    let mut particles = String::new();
    for i in 0..5000u64 {
        let (a, b, c) = (
            (i * 7919 % 1000) as f64 / 1000.0,
            (i * 104729 % 997) as f64 / 997.0,
            (i * 1299709 % 991) as f64 / 991.0,
        );
        particles.push_str(&format!("[{a}, {b}, {c}], "));
    }
    let scene = format!(
        "[sim]\ndt = 1e-3\nintegrator = \"rk4\"\ngravity = [0.0, 0.0, 0.0]\nsteps = 3\nevery = 1\n\n\
         [gravitation]\nconstant = 1e-3\nsoftening = 0.01\n\n\
         [[body]]\nname = \"cloud\"\nparticles = [{particles}]\nmass = 0.001\ncollide = false\n"
    );
    assert_same_on_one_and_two_threads(&scene, "gravitation");
}

#[test]
fn a_pile_of_small_gas_balls_is_the_same_on_one_and_two_threads() {
    // 36 gas balls of 162 particles (5832 in all, more than a chunk), each
    // small enough for its pressure to be added on a thread of its own,
    // in a 6 × 6 grid on a floor, 5 mm apart: the bodies split between the
    // threads, and touch.
    let mut scene = String::from(
        "[sim]\ndt = 1e-4\nintegrator = \"symplectic_euler\"\nsteps = 20\nevery = 2\n\n\
         [[collider]]\nplane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }\n\
         friction = 0.3\n",
    );
    for i in 0..36 {
        let (x, z) = (0.205 * f64::from(i % 6), 0.205 * f64::from(i / 6));
        scene.push_str(&format!(
            "\n[[body]]\nname = \"ball{i}\"\nsphere = {{ radius = 0.1, subdivisions = 2 }}\n\
             total_mass = 0.1\nstiffness = 500.0\ndamping = 0.2\ntranslate = [{x}, 0.1, {z}]\n\
             gas = {{ nrt = 20.0, ramp_time = 0.0 }}\n"
        ));
    }
    assert_same_on_one_and_two_threads(&scene, "pile of gas balls");
}
