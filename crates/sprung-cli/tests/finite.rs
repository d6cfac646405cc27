//! Finite in, finite out: scene values whose combination could overflow
//! are refused up front with the file, line and key, by the one bound the
//! energies keep to (lengths within the world's reach, colliders within
//! the world, the clock within 1e290 s); and a row that would still hold a
//! non-finite number stops the run as a blow-up (status 3) with nothing
//! non-finite written.

mod common;

use std::path::Path;

use common::{sprung, text, write};

/// Run `scene` (written as `s.toml`) in `dir` with `extra` arguments;
/// returns the status and the error.
fn run(dir: &Path, scene: &str, extra: &[&str]) -> (Option<i32>, String) {
    write(dir, "s.toml", scene);
    let args = [&["run", "s.toml", "--out", "o"][..], extra].concat();
    let output = sprung(&args, dir);
    (output.status.code(), text(&output.stderr))
}

/// No number in any file of `dir/o` is infinite or NaN.
fn all_finite(dir: &Path) {
    let Ok(entries) = std::fs::read_dir(dir.join("o")) else {
        return;
    };
    for entry in entries.flatten() {
        if let Ok(text) = std::fs::read_to_string(entry.path()) {
            for word in text.split(|c: char| c == ',' || c.is_whitespace()) {
                let lower = word.to_ascii_lowercase();
                assert!(
                    !(lower == "inf" || lower == "-inf" || lower == "nan"),
                    "{}: {word}",
                    entry.path().display()
                );
            }
        }
    }
}

const PAIR_2D: &str = "[sim]\ndt = 1e-3\nsteps = 5\n\n[[body]]\nname = \"c\"\nparticles = [[0.0, 0.0], [0.0, -1.0]]\nsprings = [[0, 1]]\nrest_lengths = [1e160]\npinned = [0]\n";

#[test]
fn a_rest_length_beyond_the_world_is_refused_on_its_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let (code, stderr) = run(dir.path(), PAIR_2D, &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("s.toml:9: body \"c\": `rest_lengths`[0]: 1.000e160 is beyond the world's limit 2.000e6"), "{stderr}");
    assert!(!dir.path().join("o").exists());
}

#[test]
fn a_collider_beyond_the_world_or_too_stiff_for_it_is_refused() {
    let cloth = "[sim]\ndt = 1e-3\nsteps = 5\n\n[[body]]\nname = \"cl\"\ncloth = { nx = 4, ny = 4, width = 1.0, height = 1.0 }\nstiffness = 1000.0\n\n[[collider]]\n";
    let dir = tempfile::tempdir().expect("tempdir");
    let far = format!("{cloth}plane = {{ point = [0, 1e300, 0], normal = [0, 1, 0] }}\n");
    let (code, stderr) = run(dir.path(), &far, &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains(
            "s.toml:11: collider: `point`[0]: 1.000e300 is beyond the world's limit 1.000e6"
        ),
        "{stderr}"
    );
    // Within the world, but a penalty of 1e300 N/m at a depth of 2e6 m
    // would hold 2e312 J.
    let stiff = format!(
        "{cloth}plane = {{ point = [0, 0, 0], normal = [0, 1, 0] }}\npenalty_stiffness = 1e300\n"
    );
    let (code, stderr) = run(dir.path(), &stiff, &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("s.toml:12: collider: `penalty_stiffness`[0] = 1.000e300: too large"),
        "{stderr}"
    );
    // A sphere whose surface passes far from the world.
    let sphere = format!("{cloth}sphere = {{ centre = [0, 0, 0], radius = 1e9 }}\n");
    let (code, stderr) = run(dir.path(), &sphere, &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(
        stderr.contains("s.toml:11: collider: `centre`[0]"),
        "{stderr}"
    );
    assert!(!dir.path().join("o").exists());
}

#[test]
fn a_clock_that_would_overflow_is_refused_or_stopped() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let pair = |dt: &str| {
        format!("[sim]\ndt = {dt}\nsteps = 3\n\n[[body]]\nname = \"c\"\nparticles = [[0.0, 0.0, 0.0], [0.0, -1.0, 0.0]]\nsprings = [[0, 1]]\npinned = [0]\n")
    };
    // 3 steps of 1e308 s end past any finite time: refused up front.
    let (code, stderr) = run(d, &pair("1e308"), &[]);
    assert_eq!(code, Some(1), "{stderr}");
    assert!(stderr.contains("s.toml:2: `dt` × steps"), "{stderr}");
    assert!(!d.join("o").exists());
    // Allowed, but the first step throws the bob out of the world: a
    // blow-up (status 3), and the rows written so far hold finite numbers.
    let (code, stderr) = run(d, &pair("1e280"), &[]);
    assert_eq!(code, Some(3), "{stderr}");
    assert!(stderr.contains("simulation blew up at step 1"), "{stderr}");
    all_finite(d);
}

/// The state saved in `dir/o/s.bin`, if any, holds finite numbers in every
/// entry a state has (read back against the scene's world).
fn state_finite(dir: &Path, case: usize) -> bool {
    let path = dir.join("o/s.bin");
    if !path.exists() {
        return false;
    }
    let scene = sprung_io::load_scene(&dir.join("s.toml")).expect("the scene that ran");
    let state = sprung_io::state::read_state(&path, &scene.world)
        .unwrap_or_else(|e| panic!("case {case}: the saved state does not read back: {e}"));
    let names = [
        "position",
        "velocity",
        "time",
        "steps",
        "run.dt",
        "run.every",
        "run.rows",
        "rk45.next_step",
        "verlet.last_dt",
        "verlet.previous_position",
        "verlet.written_position",
        "verlet.written_velocity",
        "contact.searched_at",
    ];
    for name in names {
        if let Ok(values) = state.get_any(name) {
            assert!(
                values.iter().all(|v| v.is_finite()),
                "case {case}: the state's {name} holds a non-finite number"
            );
        }
    }
    true
}

/// The glTF animation in `dir/o`, if any: no non-finite `f32` in its
/// binary chunk (positions, normals, times, weights; its `u32` indices are
/// far below the bit patterns of inf and NaN) and none in its JSON.
fn glb_finite(dir: &Path, case: usize) -> bool {
    let Ok(bytes) = std::fs::read(dir.join("o/animation.glb")) else {
        return false;
    };
    let glb = gltf::Glb::from_slice(&bytes).expect("a glb");
    let json = String::from_utf8_lossy(&glb.json).to_ascii_lowercase();
    assert!(
        !json.contains("nan") && !json.contains("inf"),
        "case {case}: {json}"
    );
    let bin = glb.bin.expect("its buffer");
    for word in bin.chunks_exact(4) {
        let value = f32::from_le_bytes([word[0], word[1], word[2], word[3]]);
        assert!(
            value.is_finite(),
            "case {case}: the animation holds {value}"
        );
    }
    true
}

/// A small deterministic generator (xorshift64*): the same scenes every
/// run, so a failure names a scene that can be run again.
struct Draw(u64);

impl Draw {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A number in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// `sane` 94 times in 100 (a scene of 26 keys has one or two drawn);
    /// otherwise an extreme finite value,
    /// ±10^e with e uniform over [-300, 300].
    fn value(&mut self, sane: f64) -> String {
        if self.unit() < 0.94 {
            return format!("{sane:?}");
        }
        let exponent = (self.unit() * 600.0 - 300.0).round();
        let sign = if self.unit() < 0.5 { "-" } else { "" };
        format!("{sign}1e{exponent}")
    }
}

/// Scenes with every numeric key drawn, now and then, from ±1e±300: each
/// is refused (status 1), stopped as a blow-up (3) or runs (0), and no
/// number in any file it wrote (the diagnostics, the VTU frames and series
/// file with the saved state, or the glTF animation, every other case) is
/// infinite or NaN.
#[test]
fn extreme_finite_values_never_write_a_non_finite_number() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let mut draw = Draw(0x5eed_1234_abcd_0001);
    let mut outcomes = [0usize; 4];
    // States and animations read back.
    let mut checked = (0, 0);
    for case in 0..300 {
        let mut v = |sane: f64| draw.value(sane);
        let scene = format!(
            "[sim]\ndt = {}\nsteps = 20\ngravity = [0.0, {}, 0.0]\nair_drag = {}\nmax_distance = {}\nmax_speed = {}\n\n\
             [[body]]\nname = \"pair\"\nparticles = [[0.0, 0.0, 0.0], [{}, -1.0, 0.0], [1.0, {}, 0.5]]\nmasses = [{}, 1.0, {}]\n\
             springs = [[0, 1], [1, 2]]\nrest_lengths = [{}, 1.0]\nstiffness = [{}, 100.0]\ndamping = {}\n\
             velocities = [[0.0, 0.0, 0.0], [{}, 0.0, 0.0], [0.0, 0.0, {}]]\npinned = [0]\n\n\
             [[body]]\nname = \"ball\"\nsphere = {{ radius = {}, subdivisions = 1 }}\nstiffness = {}\n\
             gas = {{ nrt = {}, ramp_time = {} }}\ntranslate = [3.0, {}, 0.0]\ntotal_mass = {}\n\n\
             [[collider]]\nplane = {{ point = [0.0, {}, 0.0], normal = [0.0, 1.0, 0.0] }}\npenalty_stiffness = {}\n\n\
             [[collider]]\nsphere = {{ centre = [{}, 0.0, 0.0], radius = {} }}\n\n\
             [gravitation]\nconstant = {}\nsoftening = {}\n",
            v(1e-3), v(-9.81), v(0.0), v(1e6), v(1e6),
            v(1.0), v(-1.0), v(1.0), v(1.0),
            v(1.0), v(100.0), v(0.1),
            v(0.5), v(-0.5),
            v(0.5), v(500.0),
            v(10.0), v(0.1), v(2.0), v(1.0),
            v(-5.0), v(1e4),
            v(-3.0), v(0.5),
            v(6.674e-11), v(0.0),
        );
        write(d, "s.toml", &scene);
        let _ = std::fs::remove_dir_all(d.join("o"));
        // Frames as VTU with a saved state, or as one glTF animation.
        let format: &[&str] = if case % 2 == 0 {
            &["--format", "vtu", "--save-state", "o/s.bin"]
        } else {
            &["--format", "gltf"]
        };
        let args = [&["run", "s.toml", "--out", "o", "--every", "5"][..], format].concat();
        let output = sprung(&args, d);
        let code = output.status.code();
        assert!(
            matches!(code, Some(0 | 1 | 3)),
            "case {case}: status {code:?}: {}\n{scene}",
            text(&output.stderr)
        );
        outcomes[code.unwrap_or(2) as usize] += 1;
        all_finite(d);
        checked.0 += usize::from(state_finite(d, case));
        checked.1 += usize::from(glb_finite(d, case));
        let frames = d.join("o/frames");
        if let Ok(entries) = std::fs::read_dir(&frames) {
            for entry in entries.flatten() {
                let text = std::fs::read_to_string(entry.path()).unwrap_or_default();
                for word in
                    text.split(|c: char| c.is_whitespace() || c == '"' || c == '<' || c == '>')
                {
                    let lower = word.to_ascii_lowercase();
                    assert!(
                        !matches!(lower.as_str(), "inf" | "-inf" | "nan"),
                        "case {case}: {} holds {word}\n{scene}",
                        entry.path().display()
                    );
                }
            }
        }
    }
    // The draw reaches all three outcomes, and states and animations were
    // written (else it tests too little).
    assert!(checked.0 > 0 && checked.1 > 0, "{checked:?}");
    assert!(
        outcomes[0] > 0 && outcomes[1] > 0 && outcomes[3] > 0,
        "{outcomes:?}"
    );
}
