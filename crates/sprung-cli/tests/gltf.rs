//! `--format gltf`: one `animation.glb` per run that the `gltf` crate (a
//! reader that is not ours) reads back: a node and mesh per body (triangles
//! with normals for a surface, lines for a rope), every recorded frame a
//! morph target played by a weights animation at the rows' times. Each
//! frame's positions agree with the same run's `.vtu` frames to 1e-6 m,
//! which single precision allows within a few metres of the origin; the
//! times agree with `diagnostics.csv` to single precision.

mod common;

use std::path::Path;

use common::{sprung, text, write};
use sprung_io::export::read_vtk_frame;

/// A gas ball dropping onto a floor beside a swinging rope.
const SCENE: &str = r#"[sim]
dt = 5e-4
steps = 400
every = 40

[[body]]
name = "ball"
sphere = { radius = 0.5, subdivisions = 1 }
total_mass = 1.0
stiffness = 2000.0
damping = 0.5
translate = [0.0, 0.7, 0.0]
gas = { nrt = 300.0, ramp_time = 0.05 }

[[body]]
name = "rope"
rope = { particles = 6, length = 1.0 }
mass = 0.05
stiffness = 500.0
pinned = [0]
translate = [1.5, 1.5, 0.0]
rotate = [0.0, 0.0, -60.0]

[[collider]]
plane = { point = [0.0, 0.0, 0.0], normal = [0.0, 1.0, 0.0] }
"#;

#[test]
fn the_animation_replays_every_recorded_frame() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(d, "s.toml", SCENE);
    for (out, format) in [("g", "gltf"), ("v", "vtu")] {
        let output = sprung(
            &["run", "s.toml", "--out", out, "--format", format, "--quiet"],
            d,
        );
        assert!(output.status.success(), "{}", text(&output.stderr));
    }
    assert!(!d.join("g/frames").exists(), "no frame files for gltf");
    let bytes = std::fs::read(d.join("g/animation.glb")).expect("animation.glb");
    let gltf = gltf::Gltf::from_slice(&bytes).expect("the gltf crate reads it");
    let blob = gltf.blob.as_deref().expect("one binary buffer");
    let buffers = |_: gltf::Buffer| Some(blob);
    // The rows' times and the frames' exact positions.
    let csv = std::fs::read_to_string(d.join("g/diagnostics.csv")).expect("csv");
    let times: Vec<f64> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).expect("time").parse().expect("a time"))
        .collect();
    assert_eq!(times.len(), 11);
    let frames: Vec<Vec<[f64; 3]>> = (0..times.len())
        .map(|k| {
            let path = d.join(format!("v/frames/frame_{k:06}.vtu"));
            let text = std::fs::read_to_string(&path).expect("frame");
            let frame = read_vtk_frame(&text, &path).expect("reads");
            frame.points.iter().map(|p| p.to_array()).collect()
        })
        .collect();
    let animation = gltf.animations().next().expect("one animation");
    let nodes: Vec<gltf::Node> = gltf.nodes().collect();
    assert_eq!(nodes.len(), 2);
    let mut offset = 0; // the body's first particle
    for (node, (name, mode, count)) in nodes.iter().zip([
        ("ball", gltf::mesh::Mode::Triangles, 42),
        ("rope", gltf::mesh::Mode::Lines, 6),
    ]) {
        assert_eq!(node.name(), Some(name));
        let mesh = node.mesh().expect("a mesh");
        let primitive = mesh.primitives().next().expect("one primitive");
        assert_eq!(primitive.mode(), mode);
        let reader = primitive.reader(buffers);
        let base: Vec<[f32; 3]> = reader.read_positions().expect("positions").collect();
        assert_eq!(base.len(), count);
        if mode == gltf::mesh::Mode::Triangles {
            let normals: Vec<[f32; 3]> = reader.read_normals().expect("normals").collect();
            assert!(normals.iter().all(|n| {
                let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                (length - 1.0).abs() < 1e-5
            }));
        }
        let targets: Vec<Vec<[f32; 3]>> = reader
            .read_morph_targets()
            .map(|(positions, _, _)| positions.expect("target positions").collect())
            .collect();
        assert_eq!(
            targets.len(),
            times.len() - 1,
            "a target per frame after the first"
        );
        // This node's weights channel.
        let channel = animation
            .channels()
            .find(|c| c.target().node().index() == node.index())
            .expect("a channel");
        assert_eq!(
            channel.target().property(),
            gltf::animation::Property::MorphTargetWeights
        );
        let reader = channel.reader(buffers);
        let inputs: Vec<f32> = reader.read_inputs().expect("times").collect();
        let weights: Vec<f32> = match reader.read_outputs().expect("weights") {
            gltf::animation::util::ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
            _ => panic!("weights expected"),
        };
        assert_eq!(inputs.len(), times.len());
        for (k, (&t, &expected)) in inputs.iter().zip(&times).enumerate() {
            // Single precision: within 1e-7 of the time, and 1e-9 s near 0.
            assert!(
                (f64::from(t) - expected).abs() <= 1e-7 * expected.abs() + 1e-9,
                "frame {k}: {t} against {expected}"
            );
            let w = &weights[k * targets.len()..(k + 1) * targets.len()];
            // Frame k is the base plus the weighted targets.
            for (i, b) in base.iter().enumerate() {
                let exact = frames[k][offset + i];
                for axis in 0..3 {
                    let mut x = f64::from(b[axis]);
                    for (target, &weight) in targets.iter().zip(w) {
                        x += f64::from(weight) * f64::from(target[i][axis]);
                    }
                    assert!(
                        (x - exact[axis]).abs() <= 1e-6,
                        "{name}, frame {k}, vertex {i}: {x} against {}",
                        exact[axis]
                    );
                }
            }
        }
        offset += count;
    }
}

/// The file grows linearly in its frames: each frame adds its positions
/// and one stored weight (sparse), not a weight for every other frame. A
/// 6-particle rope recorded every step: 72 bytes of positions a frame, so
/// dense weights (4 bytes × frames a frame) would make 400 frames about
/// four times the file of 200; linear growth with the base mesh and
/// header shared makes it at most twice.
#[test]
fn the_file_grows_linearly_in_its_frames() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    let rope = SCENE.split("[[body]]").nth(2).expect("the rope");
    write(d, "r.toml", &format!("[sim]\ndt = 5e-4\n\n[[body]]{rope}"));
    let size = |steps: &str, out: &str| {
        let args = ["run", "r.toml", "--format", "gltf", "--every", "1"];
        let output = sprung(&[&args[..], &["--steps", steps, "--out", out]].concat(), d);
        assert!(output.status.success(), "{}", text(&output.stderr));
        std::fs::metadata(d.join(out).join("animation.glb"))
            .expect("glb")
            .len()
    };
    let (short, long) = (size("200", "a"), size("400", "b"));
    assert!(long > short, "{long} {short}");
    assert!(
        long <= 2 * short,
        "{long} bytes for 401 frames, {short} for 201"
    );
}

/// Too many frames for the animation's budget is refused before the run.
#[test]
fn an_animation_too_large_is_refused_before_the_run() {
    let dir = tempfile::tempdir().expect("tempdir");
    write(dir.path(), "s.toml", SCENE);
    let output = sprung(
        &[
            "run",
            "s.toml",
            "--format",
            "gltf",
            "--steps",
            "1000000000",
            "--every",
            "1",
            "--out",
            "o",
        ],
        dir.path(),
    );
    assert_eq!(output.status.code(), Some(1));
    let stderr = text(&output.stderr);
    assert!(stderr.contains("GB an animation may gather"), "{stderr}");
    assert!(!Path::new(&dir.path().join("o/diagnostics.csv")).exists());
}

/// A body held by rigid rods only (the pendulum) is drawn along its rods,
/// and one of loose particles as points.
#[test]
fn rods_are_lines_and_loose_particles_points() {
    let dir = tempfile::tempdir().expect("tempdir");
    let d = dir.path();
    write(
        d,
        "s.toml",
        "[sim]\ndt = 1e-3\nsteps = 20\nevery = 10\n\n[[body]]\nname = \"pendulum\"\n\
         particles = [[0, 0, 0], [1, 0, 0], [2, 0, 0]]\nrods = [[0, 1], [1, 2]]\nmass = 1.0\npinned = [0]\n\n\
         [[body]]\nname = \"dust\"\nparticles = [[0, 3, 0], [1, 3, 0], [2, 3, 0]]\nmass = 0.1\n",
    );
    let output = sprung(
        &["run", "s.toml", "--format", "gltf", "--out", "o", "--quiet"],
        d,
    );
    assert!(output.status.success(), "{}", text(&output.stderr));
    let bytes = std::fs::read(d.join("o/animation.glb")).expect("animation.glb");
    let gltf = gltf::Gltf::from_slice(&bytes).expect("reads");
    let blob = gltf.blob.as_deref().expect("one buffer");
    let modes: Vec<(gltf::mesh::Mode, usize)> = gltf
        .meshes()
        .map(|m| {
            let p = m.primitives().next().expect("a primitive");
            let indices = p
                .reader(|_| Some(blob))
                .read_indices()
                .map_or(0, |i| i.into_u32().count());
            (p.mode(), indices)
        })
        .collect();
    assert_eq!(
        modes,
        vec![(gltf::mesh::Mode::Lines, 4), (gltf::mesh::Mode::Points, 0)]
    );
}
