//! `--format gltf`: one `animation.glb` per run that the `gltf` crate (a
//! reader that is not ours) reads back: a node and mesh per body (triangles
//! with normals for a surface, lines for a rope), every recorded frame a
//! morph target played by a weights animation at the rows' times, a long
//! run's frames in spans of meshes shown one at a time by their scale.
//! Each frame's positions agree with the same run's `.vtu` frames to 1e-6
//! m, which single precision allows within a few metres of the origin; the
//! times agree with `diagnostics.csv` to single precision. A body that
//! tears shows the `.vtu`'s faces at every frame and no more, here and in
//! three.js in Chromium (`web-tests/gltf.mjs`).

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Output, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use common::{sprung, text, write};
use gltf::animation::util::ReadOutputs;
use gltf::animation::{Interpolation, Property};
use sprung_io::export::{read_vtk_frame, VtkFrame, FRAMES_PER_MESH};

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
        assert_eq!(channel.target().property(), Property::MorphTargetWeights);
        let reader = channel.reader(buffers);
        let inputs: Vec<f32> = reader.read_inputs().expect("times").collect();
        let weights: Vec<f32> = match reader.read_outputs().expect("weights") {
            ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
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
/// header shared makes it at most twice. So do the weights an importer
/// keys one by one (Blender: every target at every time of its channel):
/// a span of at most `FRAMES_PER_MESH + 1` frames a mesh keys at most
/// that many targets at each of its times, `(K + 1)(frames + spans)` in
/// all, where one mesh of every frame would key frames².
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
        let path = d.join(out).join("animation.glb");
        let bytes = std::fs::read(&path).expect("glb");
        (bytes.len(), weights_keyed(&bytes))
    };
    let ((short, short_keys), (long, long_keys)) = (size("200", "a"), size("400", "b"));
    assert!(long > short, "{long} {short}");
    assert!(
        long <= 2 * short,
        "{long} bytes for 401 frames, {short} for 201"
    );
    for (frames, keys) in [(201usize, short_keys), (401, long_keys)] {
        let spans = (frames - 1).div_ceil(FRAMES_PER_MESH);
        let bound = (FRAMES_PER_MESH + 1) * (frames + spans);
        assert!(
            keys <= bound,
            "{frames} frames: {keys} weights keyed, more than {bound}"
        );
    }
}

/// The weights an importer that keys every target at every time of its
/// channel sets for the `.glb` `bytes`: keys × targets, summed over the
/// weights channels.
fn weights_keyed(bytes: &[u8]) -> usize {
    let gltf = gltf::Gltf::from_slice(bytes).expect("reads");
    let animation = gltf.animations().next().expect("an animation");
    animation
        .channels()
        .filter(|c| c.target().property() == Property::MorphTargetWeights)
        .map(|c| {
            let keys = c.sampler().input().count();
            let mesh = c.target().node().mesh().expect("a mesh");
            let targets = mesh
                .primitives()
                .next()
                .map_or(0, |p| p.morph_targets().count());
            keys * targets
        })
        .sum()
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

/// The tear scene (`scenes/tear.toml`: a cloth pulled apart by two bars)
/// for its first 0.1 s, a frame every 5 steps: 101 frames, so two spans
/// of meshes, and its springs start breaking at about 0.05 s. Run once for
/// the tests that read it, as glTF (`g/`) and as `.vtu` frames (`v/`) of
/// the same steps.
fn torn_run() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf-tear");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("a folder for the run");
        let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/tear.toml");
        let scene = scene.to_str().expect("a UTF-8 path");
        for (out, format) in [("g", "gltf"), ("v", "vtu")] {
            let args = ["run", scene, "--steps", "500", "--every", "5"];
            let more = ["--format", format, "--out", out, "--quiet"];
            let output = sprung(&[&args[..], &more].concat(), &dir);
            assert!(output.status.success(), "{}", text(&output.stderr));
        }
        dir
    })
}

/// The rows' times (s) of the run in `dir`.
fn row_times(dir: &Path) -> Vec<f64> {
    let csv = std::fs::read_to_string(dir.join("diagnostics.csv")).expect("csv");
    csv.lines()
        .skip(1)
        .map(|l| l.split(',').nth(1).expect("time").parse().expect("a time"))
        .collect()
}

/// The `.vtu` frames in `dir/frames`, `count` of them.
fn vtu_frames(dir: &Path, count: usize) -> Vec<VtkFrame> {
    (0..count)
        .map(|k| {
            let path = dir.join(format!("frames/frame_{k:06}.vtu"));
            let text = std::fs::read_to_string(&path).expect("frame");
            read_vtk_frame(&text, &path).expect("reads")
        })
        .collect()
}

/// The value of `property` of `node` at time `t` (s) by the file's
/// animation, as a player samples it: the first key before the first, the
/// key at `t` where one is (exactly), else the key before (step) or the
/// line between the two around `t` (linear). `None` where not animated.
fn animated(
    gltf: &gltf::Gltf,
    blob: &[u8],
    node: &gltf::Node,
    property: Property,
    t: f32,
) -> Option<Vec<f32>> {
    let animation = gltf.animations().next()?;
    let channel = animation
        .channels()
        .find(|c| c.target().node().index() == node.index() && c.target().property() == property)?;
    let reader = channel.reader(|_| Some(blob));
    let inputs: Vec<f32> = reader.read_inputs().expect("times").collect();
    let outputs: Vec<f32> = match reader.read_outputs().expect("values") {
        ReadOutputs::MorphTargetWeights(w) => w.into_f32().collect(),
        ReadOutputs::Scales(s) => s.flatten().collect(),
        _ => panic!("weights or scales expected"),
    };
    let width = outputs.len() / inputs.len();
    let key = |k: usize| outputs[k * width..(k + 1) * width].to_vec();
    let Some(k) = inputs.partition_point(|&x| x <= t).checked_sub(1) else {
        return Some(key(0));
    };
    let step = channel.sampler().interpolation() == Interpolation::Step;
    if inputs[k] == t || k + 1 == inputs.len() || step {
        return Some(key(k));
    }
    let s = (t - inputs[k]) / (inputs[k + 1] - inputs[k]);
    let (a, b) = (key(k), key(k + 1));
    Some(a.iter().zip(&b).map(|(a, b)| a + s * (b - a)).collect())
}

/// A mesh node as a player shows it at one time.
struct Shown {
    /// The body: the name of the scene's node it is, or is under.
    body: String,
    mode: gltf::mesh::Mode,
    /// The node's scale then (1 shown, 0 hidden).
    scale: f64,
    /// Vertex positions (m), morphed and scaled, in double.
    positions: Vec<[f64; 3]>,
    /// Morphed normals (surfaces), in double.
    normals: Vec<[f64; 3]>,
    /// The vertices of the elements, in order (its indices, or every
    /// vertex in order for a primitive without).
    elements: Vec<u32>,
}

/// `base` plus the `weights`-weighted `targets`, in double; an accessor
/// without data (`None`) is zeros.
fn morphed(
    base: Option<Vec<[f32; 3]>>,
    targets: &[Option<Vec<[f32; 3]>>],
    weights: &[f32],
    count: usize,
) -> Vec<[f64; 3]> {
    let zeros = vec![[0.0f32; 3]; count];
    let base = base.unwrap_or_else(|| zeros.clone());
    (0..count)
        .map(|i| {
            let mut x = base[i].map(f64::from);
            for (target, &w) in targets.iter().zip(weights) {
                let d = target.as_ref().map_or([0.0; 3], |d| d[i]);
                for axis in 0..3 {
                    x[axis] += f64::from(w) * f64::from(d[axis]);
                }
            }
            x
        })
        .collect()
}

/// Every mesh node of the file as a player shows it at time `t` (s).
fn shown(gltf: &gltf::Gltf, blob: &[u8], t: f32) -> Vec<Shown> {
    let mut out = Vec::new();
    for top in gltf.default_scene().expect("a scene").nodes() {
        let body = top.name().expect("a body's name").to_string();
        let nodes: Vec<gltf::Node> = match top.mesh() {
            Some(_) => vec![top.clone()],
            None => top.children().collect(),
        };
        for node in nodes {
            let (translation, rotation, scale) = node.transform().decomposed();
            assert_eq!((translation, rotation), ([0.0; 3], [0.0, 0.0, 0.0, 1.0]));
            let scale = animated(gltf, blob, &node, Property::Scale, t)
                .map_or(scale, |s| [s[0], s[1], s[2]]);
            assert!(scale[0] == scale[1] && scale[1] == scale[2], "{scale:?}");
            let mesh = node.mesh().expect("a mesh");
            let primitive = mesh.primitives().next().expect("a primitive");
            let count = primitive
                .get(&gltf::Semantic::Positions)
                .expect("positions")
                .count();
            let reader = primitive.reader(|_| Some(blob));
            let weights = animated(gltf, blob, &node, Property::MorphTargetWeights, t)
                .or_else(|| mesh.weights().map(<[f32]>::to_vec))
                .unwrap_or_default();
            let (moves, turns): (Vec<_>, Vec<_>) = reader
                .read_morph_targets()
                .map(|(p, n, _)| (p.map(|p| p.collect()), n.map(|n| n.collect())))
                .unzip();
            let base = reader.read_positions().map(|p| p.collect());
            let s = f64::from(scale[0]);
            let positions = morphed(base, &moves, &weights, count)
                .into_iter()
                .map(|x| x.map(|v| v * s))
                .collect();
            let normals = match reader.read_normals() {
                Some(n) => morphed(Some(n.collect()), &turns, &weights, count),
                None => Vec::new(),
            };
            let elements = reader
                .read_indices()
                .map_or_else(|| (0..count as u32).collect(), |i| i.into_u32().collect());
            out.push(Shown {
                body: body.clone(),
                mode: primitive.mode(),
                scale: s,
                positions,
                normals,
                elements,
            });
        }
    }
    out
}

/// The area of triangle `[a, b, c]` (m²).
fn area([a, b, c]: [[f64; 3]; 3]) -> f64 {
    let (u, v) = (
        [0, 1, 2].map(|i| b[i] - a[i]),
        [0, 1, 2].map(|i| c[i] - a[i]),
    );
    let cross = [
        u[1] * v[2] - u[2] * v[1],
        u[2] * v[0] - u[0] * v[2],
        u[0] * v[1] - u[1] * v[0],
    ];
    0.5 * cross.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// The triangles of the shown meshes with an area (corner positions).
fn triangles_with_area(shown: &[Shown]) -> Vec<[[f64; 3]; 3]> {
    shown
        .iter()
        .filter(|s| s.mode == gltf::mesh::Mode::Triangles)
        .flat_map(|s| {
            s.elements
                .chunks_exact(3)
                .map(|t| [0, 1, 2].map(|c| s.positions[t[c] as usize]))
        })
        .filter(|&t| area(t) > 0.0)
        .collect()
}

/// The claim of a body that can tear: at every frame's time the players'
/// triangles with an area are the `.vtu` frame's triangles (the faces
/// along a broken spring gone), in order, at its positions; the others
/// have none (a gone face's corners at one point, a hidden span scaled to
/// 0). The cloth has its own three vertices per face; a face's corners come
/// back as the `f32` nearest the `.vtu`'s `f64` (its mesh at the origin,
/// its target at weight exactly 1 at a key's time: one rounding, within
/// 2^-24 of the coordinate). Its normals stay unit vectors (a gone face
/// keeps the first frame's).
#[test]
fn a_torn_cloth_shows_the_vtu_triangles_at_every_frame() {
    let d = torn_run();
    let bytes = std::fs::read(d.join("g/animation.glb")).expect("animation.glb");
    let gltf = gltf::Gltf::from_slice(&bytes).expect("the gltf crate reads it");
    let blob = gltf.blob.as_deref().expect("one binary buffer");
    let times = row_times(&d.join("g"));
    assert_eq!(times.len(), 101);
    let frames = vtu_frames(&d.join("v"), times.len());
    let mut counts = Vec::new();
    for (k, (frame, &time)) in frames.iter().zip(&times).enumerate() {
        let shown = shown(&gltf, blob, time as f32);
        // Every body shows one mesh node then, the others hidden.
        for body in ["cloth", "left", "right"] {
            let scales: Vec<f64> = shown
                .iter()
                .filter(|s| s.body == body)
                .map(|s| s.scale)
                .collect();
            assert!(
                scales.iter().all(|&s| s == 0.0 || s == 1.0),
                "{body}, frame {k}: {scales:?}"
            );
            assert_eq!(
                scales.iter().filter(|&&s| s == 1.0).count(),
                1,
                "{body}, frame {k}: {scales:?}"
            );
        }
        let cloth = shown
            .iter()
            .find(|s| s.body == "cloth" && s.scale == 1.0)
            .expect("the cloth");
        assert_eq!(cloth.positions.len(), 3 * 270, "three vertices a face");
        for (i, n) in cloth.normals.iter().enumerate() {
            let length = n.iter().map(|x| x * x).sum::<f64>().sqrt();
            // Unit in f32 (a few units of 2^-24 in each component).
            assert!(
                (length - 1.0).abs() <= 1e-6,
                "frame {k}, vertex {i}: normal {n:?}"
            );
        }
        let kept = triangles_with_area(&shown);
        assert_eq!(
            kept.len(),
            frame.polygons.len(),
            "frame {k} at {time} s: triangles with an area against the vtu's"
        );
        for (i, (corners, polygon)) in kept.iter().zip(&frame.polygons).enumerate() {
            for (corner, &p) in corners.iter().zip(polygon) {
                let exact = frame.points[p as usize].to_array();
                for axis in 0..3 {
                    // One rounding to f32: half a unit in the last place,
                    // 2^-24 relative (2^-150, half the least subnormal, near 0).
                    let tolerance = exact[axis].abs() * 2f64.powi(-24) + 2f64.powi(-150);
                    assert!(
                        (corner[axis] - exact[axis]).abs() <= tolerance,
                        "frame {k}, triangle {i}, point {p}: {} against {}",
                        corner[axis],
                        exact[axis]
                    );
                }
            }
        }
        counts.push(kept.len());
    }
    assert_eq!(counts[0], 270, "the whole cloth at first");
    let last = *counts.last().expect("frames");
    assert!(last < 270, "the cloth tears within the run: {counts:?}");
}

/// The page `web-tests/gltf.mjs` reads: each frame's time (the `f32` the
/// file holds, written as the double it is) and its `.vtu` triangles.
fn expected_counts(times: &[f64], frames: &[VtkFrame]) -> String {
    let rows: Vec<String> = times
        .iter()
        .zip(frames)
        .map(|(&t, f)| {
            format!(
                "{{\"time\":{},\"triangles\":{}}}",
                f64::from(t as f32),
                f.polygons.len()
            )
        })
        .collect();
    format!("{{\"frames\":[{}]}}\n", rows.join(","))
}

/// three.js (GLTFLoader and AnimationMixer, in headless Chromium) plays
/// the torn cloth as the `.vtu` frames have it: at every frame's time, one
/// before the tear and those after included, its triangles with an area
/// (read back through three's morph targets) are the `.vtu`'s count.
/// Needs Node, `npm ci` in crates/sprung-viewer/web-tests (Playwright and
/// three) and Chromium, which scripts/test.sh installs.
#[test]
fn three_js_shows_the_tear_at_the_frame_it_happens() {
    let d = torn_run();
    let times = row_times(&d.join("g"));
    let frames = vtu_frames(&d.join("v"), times.len());
    std::fs::write(d.join("g/expected.json"), expected_counts(&times, &frames))
        .expect("expected.json");
    let tests = Path::new(env!("CARGO_MANIFEST_DIR")).join("../sprung-viewer/web-tests");
    let needs = |what: &str| -> ! {
        panic!("{what}: this test needs it, and scripts/test.sh installs it (run the tests with scripts/test.sh, not only `cargo test`)")
    };
    for package in ["playwright-core", "three"] {
        if !tests.join("node_modules").join(package).is_dir() {
            needs(&format!(
                "{package} is not installed (`npm ci` in crates/sprung-viewer/web-tests)"
            ));
        }
    }
    let chromium = std::env::var("CHROMIUM").unwrap_or_else(|_| "/usr/bin/chromium".into());
    if !Path::new(&chromium).is_file() {
        needs(&format!(
            "Chromium is not at {chromium} (Debian package chromium)"
        ));
    }
    let child = Command::new("node")
        .arg("gltf.mjs")
        .arg(d.join("g"))
        .env("CHROMIUM", &chromium)
        .current_dir(&tests)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| needs(&format!("node (Node.js) does not start: {e}")));
    let output = wait_with_limit(child, Duration::from_secs(240));
    let (stdout, stderr) = (text(&output.stdout), text(&output.stderr));
    assert!(output.status.success(), "{stderr}\n{stdout}");
    println!("{stdout}");
}

/// Wait for `child` to end, killing it after `limit`.
fn wait_with_limit(mut child: Child, limit: Duration) -> Output {
    let start = Instant::now();
    while child.try_wait().expect("the child").is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let output = child.wait_with_output().expect("its output");
            panic!(
                "still running after {limit:?}, killed:\n{}\n{}",
                text(&output.stderr),
                text(&output.stdout)
            );
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    child.wait_with_output().expect("its output")
}
