//! Claims of `sprung_view::render`: the pictures of fixed tiny scenes
//! match stored references byte for byte, springs are coloured by strain,
//! the camera frames every frame of a run, a run read back from VTK frames
//! draws exactly as the run in memory, output is deterministic, and the
//! PNG and GIF files have the sizes and timing asked for.
//!
//! To regenerate the references after an intended change of the drawing,
//! run with `SPRUNG_BLESS=1` and look at the new files before committing.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use sprung::{build, IntegratorKind, Shape, Vec3, World};
use sprung_io::export::{write_frame, FrameFormat};
use sprung_view::render::{
    draw, frame_run, read_run, record, render_to_dir, strain, Bounds, Camera, Image, Model,
    RenderError, RenderSettings, Snapshot, StrainColours, Style,
};

fn reference_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/reference")
}

/// A small 2D scene: a hexagonal ring (filled outline) on a floor, one
/// spring stretched 30 %, one compressed 30 %, a pinned particle.
fn scene_2d() -> Snapshot {
    let mut position: Vec<Vec3> = (0..6)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 6.0;
            Vec3::new(0.5 * a.cos(), 0.6 + 0.5 * a.sin(), 0.0)
        })
        .collect();
    // A horizontal stretched spring and a compressed one, to the right.
    position.extend([
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(2.3, 1.0, 0.0),
        Vec3::new(1.0, 0.3, 0.0),
        Vec3::new(1.7, 0.3, 0.0),
    ]);
    let ring: Vec<[u32; 2]> = (0..6).map(|k| [k, (k + 1) % 6]).collect();
    let side = position[0].distance(position[1]);
    let mut springs = ring.clone();
    springs.extend([[6, 7], [8, 9]]);
    let mut rest_length = vec![side; 6];
    rest_length.extend([1.0, 1.0]);
    let mut pinned = vec![false; 10];
    pinned[6] = true;
    Snapshot {
        time: Some(0.0),
        position,
        model: Arc::new(Model {
            springs,
            rest_length,
            faces: Vec::new(),
            outlines: vec![(0..6).collect()],
            pinned,
            ..Model::default()
        }),
        colliders: vec![Shape::Plane {
            point: Vec3::ZERO,
            normal: Vec3::Y,
        }],
    }
}

/// A small 3D scene: a folded sheet of four triangles over a floor, a
/// sphere obstacle, and a stretched rope of two springs from a pin.
fn scene_3d() -> Snapshot {
    let position = vec![
        Vec3::new(0.0, 0.5, 0.0),
        Vec3::new(1.0, 0.5, 0.0),
        Vec3::new(0.0, 1.0, 1.0),
        Vec3::new(1.0, 1.0, 1.0),
        Vec3::new(0.0, 0.5, 2.0),
        Vec3::new(1.0, 0.5, 2.0),
        Vec3::new(-0.8, 1.6, 1.0),
        Vec3::new(-0.8, 1.0, 1.0),
        Vec3::new(-0.8, 0.2, 1.0),
    ];
    let faces = vec![[0, 1, 3], [0, 3, 2], [2, 3, 5], [2, 5, 4]];
    let springs = vec![
        [0, 1],
        [1, 3],
        [3, 2],
        [2, 0],
        [0, 3],
        [3, 5],
        [5, 4],
        [4, 2],
        [2, 5],
        [6, 7],
        [7, 8],
    ];
    let mut rest_length: Vec<f64> = springs
        .iter()
        .map(|&[i, j]| position[i as usize].distance(position[j as usize]))
        .collect();
    rest_length[9] = 0.5; // stretched 20 %
    rest_length[10] = 1.0; // compressed 20 %
    let mut pinned = vec![false; position.len()];
    pinned[6] = true;
    Snapshot {
        time: Some(0.0),
        position,
        model: Arc::new(Model {
            springs,
            rest_length,
            faces,
            outlines: Vec::new(),
            pinned,
            ..Model::default()
        }),
        colliders: vec![
            Shape::Plane {
                point: Vec3::ZERO,
                normal: Vec3::Y,
            },
            Shape::Sphere {
                centre: Vec3::new(1.8, 0.4, 1.0),
                radius: 0.4,
            },
        ],
    }
}

fn picture(snapshot: &Snapshot, settings: &RenderSettings) -> (Image, Camera) {
    let snapshots = std::slice::from_ref(snapshot);
    let (camera, bounds) = frame_run(snapshots, settings);
    let image = draw(snapshot, &camera, &bounds, &settings.style, &[]).expect("draws");
    (image, camera)
}

fn check_reference(name: &str, snapshot: &Snapshot) {
    let settings = RenderSettings::new(240, 180);
    let (image, _) = picture(snapshot, &settings);
    let bytes = image.encode_png().expect("encodes");
    let path = reference_dir().join(name);
    if std::env::var_os("SPRUNG_BLESS").is_some() {
        std::fs::create_dir_all(reference_dir()).expect("reference dir");
        std::fs::write(&path, &bytes).expect("write reference");
    }
    let expected = std::fs::read(&path).expect("the reference image exists");
    // Byte for byte: the drawing is single-threaded, uses no time stamps,
    // and tiny-skia and png are pinned by Cargo.lock. (A different CPU
    // architecture could round anti-aliasing differently; regenerate the
    // reference there with SPRUNG_BLESS=1 and look at it.)
    assert!(
        bytes == expected,
        "{name} differs from {}; if the change is intended, rerun with SPRUNG_BLESS=1 and look at it",
        path.display()
    );
}

#[test]
fn the_2d_reference_scene_matches_its_stored_image_byte_for_byte() {
    check_reference("scene_2d.png", &scene_2d());
}

#[test]
fn the_3d_reference_scene_matches_its_stored_image_byte_for_byte() {
    check_reference("scene_3d.png", &scene_3d());
}

/// The colour at the middle of spring `k` of `snapshot`.
fn spring_colour(image: &Image, camera: &Camera, snapshot: &Snapshot, k: usize) -> [u8; 3] {
    let [i, j] = snapshot.model.springs[k];
    let mid = 0.5 * (snapshot.position[i as usize] + snapshot.position[j as usize]);
    let (x, y) = camera.to_pixels(camera.view(mid));
    image
        .pixel(x.floor() as u32, y.floor() as u32)
        .expect("inside the picture")
}

#[test]
fn springs_are_red_stretched_blue_compressed_and_green_at_rest() {
    let snapshot = scene_2d();
    let mut settings = RenderSettings::new(400, 300);
    settings.style.line_width = 5.0; // the pixel sampled lies well inside the line
    let (image, camera) = picture(&snapshot, &settings);
    let [r, g, b] = spring_colour(&image, &camera, &snapshot, 0).map(i32::from);
    assert!(g > r + 60 && g > b + 60, "at rest: green, got {r},{g},{b}");
    let [r, g, b] = spring_colour(&image, &camera, &snapshot, 6).map(i32::from);
    assert!(
        r > g + 100 && r > b + 100,
        "stretched 30 %: red, got {r},{g},{b}"
    );
    let [r, g, b] = spring_colour(&image, &camera, &snapshot, 7).map(i32::from);
    assert!(
        b > r + 100 && b > g + 80,
        "compressed 30 %: blue, got {r},{g},{b}"
    );
}

#[test]
fn strain_colours_blend_linearly_and_saturate() {
    let colours = StrainColours::new(0.1).expect("valid");
    assert_eq!(colours.colour(0.0), strain::REST);
    assert_eq!(colours.colour(0.1), strain::STRETCHED);
    assert_eq!(colours.colour(0.5), strain::STRETCHED, "saturates");
    assert_eq!(colours.colour(-0.1), strain::COMPRESSED);
    assert_eq!(colours.colour(-0.9), strain::COMPRESSED, "saturates");
    assert_eq!(colours.colour(f64::NAN), strain::UNKNOWN);
    // Half way: the mean of the two ends, per channel (rounded).
    let half = colours.colour(0.05);
    for c in 0..3 {
        let mean = (f64::from(strain::REST[c]) + f64::from(strain::STRETCHED[c])) / 2.0;
        assert!((f64::from(half[c]) - mean).abs() <= 0.5, "{half:?}");
    }
    assert!((StrainColours::strain(1.1, 1.0) - 0.1).abs() < 1e-12);
    assert!(StrainColours::new(0.0).is_none() && StrainColours::new(f64::NAN).is_none());
}

/// A rope and a cloth pinned at two corners, no colliders (VTK frames do
/// not carry colliders).
fn hanging_world() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
    let rope = build::rope(8, 1.0).expect("rope").with_stiffness(300.0);
    world.add_body("rope", rope).expect("rope");
    let cloth = build::cloth(6, 6, 1.0, 1.0, build::ClothSprings::default())
        .expect("cloth")
        .with_stiffness(300.0)
        .with_pinned(vec![30, 35])
        .placed(1.0, Vec3::new(60.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0));
    world.add_body("cloth", cloth).expect("cloth");
    world
}

#[test]
fn a_run_read_back_from_vtk_frames_draws_exactly_as_the_run_in_memory() {
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = dir.path().join("frames");
    std::fs::create_dir_all(&frames).expect("frames dir");
    let (dt, steps, every) = (1e-3, 300, 50);
    let mut world = hanging_world();
    let in_memory = record(&mut world, dt, steps, every);
    assert!(in_memory.blow_up.is_none());
    let mut world = hanging_world();
    write_frame(&frames, 0, &world, FrameFormat::Vtk).expect("frame");
    for step in 1..=steps {
        world.step(dt).expect("stable");
        if step % every == 0 {
            write_frame(&frames, (step / every) as usize, &world, FrameFormat::Vtk).expect("frame");
        }
    }
    let read = read_run(dir.path(), 1).expect("reads");
    assert_eq!(read.len(), in_memory.snapshots.len());
    for (a, b) in read.iter().zip(&in_memory.snapshots) {
        assert_eq!(a.position, b.position, "positions round-trip exactly");
        assert_eq!(a.time, b.time);
        assert_eq!(*a.model, *b.model, "springs, rest lengths, faces, pins");
    }
    assert!(
        Arc::ptr_eq(&read[0].model, &read[1].model),
        "one shared model"
    );
    let settings = RenderSettings::new(200, 150);
    let a = render_to_dir(&read, &dir.path().join("a"), &settings).expect("renders");
    let b = render_to_dir(&in_memory.snapshots, &dir.path().join("b"), &settings).expect("renders");
    for (x, y) in a.pictures.iter().zip(&b.pictures) {
        assert_eq!(
            std::fs::read(x).expect("png"),
            std::fs::read(y).expect("png")
        );
    }
}

#[test]
fn rendering_twice_gives_the_same_bytes() {
    let dir = tempfile::tempdir().expect("tempdir");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/ball2d.toml");
    let mut settings = RenderSettings::new(160, 120);
    settings.gif = true;
    let mut outputs = Vec::new();
    for name in ["one", "two"] {
        let mut scene = sprung_io::load_scene(&scene).expect("scene");
        let recording = record(&mut scene.world, scene.dt, 600, 100);
        let out = dir.path().join(name);
        let rendered = render_to_dir(&recording.snapshots, &out, &settings).expect("renders");
        let mut files: Vec<PathBuf> = rendered.pictures.clone();
        files.extend(rendered.gif.clone());
        outputs.push(
            files
                .iter()
                .map(|f| std::fs::read(f).expect("file"))
                .collect::<Vec<_>>(),
        );
    }
    assert_eq!(outputs[0].len(), 8, "7 pictures and the GIF");
    assert!(
        outputs[0] == outputs[1],
        "the same run gives the same bytes"
    );
}

#[test]
fn the_automatic_camera_keeps_every_particle_of_every_frame_in_the_picture() {
    for (width, height) in [(200, 150), (120, 240)] {
        let mut world = hanging_world();
        let recording = record(&mut world, 1e-3, 400, 40);
        let settings = RenderSettings::new(width, height);
        let (camera, _) = frame_run(&recording.snapshots, &settings);
        assert!(!camera.is_orthographic(), "a 3D run is seen in perspective");
        let (mut lo_x, mut hi_x, mut lo_y, mut hi_y) = (f32::MAX, f32::MIN, f32::MAX, f32::MIN);
        for p in recording.snapshots.iter().flat_map(|s| &s.position) {
            let (x, y) = camera.to_pixels(camera.view(*p));
            (lo_x, hi_x, lo_y, hi_y) = (lo_x.min(x), hi_x.max(x), lo_y.min(y), hi_y.max(y));
        }
        let (w, h) = (width as f32, height as f32);
        assert!(lo_x >= 0.0 && hi_x <= w && lo_y >= 0.0 && hi_y <= h);
        // ... and fills it: the run spans at least 80 % of one side.
        assert!(hi_x - lo_x >= 0.8 * w || hi_y - lo_y >= 0.8 * h);
    }
    // A 2D scene is seen straight on, orthographic.
    let (camera, _) = frame_run(&[scene_2d()], &RenderSettings::new(100, 100));
    assert!(camera.is_orthographic());
    let bounds = Bounds::of_snapshots(&[scene_3d()]).expect("bounds");
    assert!(!bounds.planar);
}

#[test]
fn png_and_gif_files_have_the_size_and_timing_asked_for() {
    let dir = tempfile::tempdir().expect("tempdir");
    let mut world = hanging_world();
    // 0.04 s between pictures: a GIF delay of 4 hundredths.
    let recording = record(&mut world, 1e-3, 160, 40);
    let mut settings = RenderSettings::new(130, 70);
    settings.gif = true;
    let rendered = render_to_dir(&recording.snapshots, dir.path(), &settings).expect("renders");
    assert_eq!(rendered.pictures.len(), 5);
    for path in &rendered.pictures {
        let decoder = png::Decoder::new(std::io::BufReader::new(
            std::fs::File::open(path).expect("png"),
        ));
        let reader = decoder.read_info().expect("a PNG");
        assert_eq!((reader.info().width, reader.info().height), (130, 70));
    }
    let gif = rendered.gif.expect("a GIF");
    let mut options = gif::DecodeOptions::new();
    options.set_color_output(gif::ColorOutput::RGBA);
    let mut decoder = options
        .read_info(std::fs::File::open(&gif).expect("gif"))
        .expect("a GIF");
    assert_eq!((decoder.width(), decoder.height()), (130, 70));
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().expect("frame") {
        delays.push(frame.delay);
    }
    assert_eq!(delays, vec![4; 5]);
    assert_eq!(decoder.repeat(), gif::Repeat::Infinite, "it loops");
    // A fixed playback rate overrides the simulated time.
    settings.fps = Some(10.0);
    let rendered = render_to_dir(&recording.snapshots, dir.path(), &settings).expect("renders");
    let mut decoder = gif::DecodeOptions::new()
        .read_info(std::fs::File::open(rendered.gif.expect("gif")).expect("gif"))
        .expect("a GIF");
    while let Some(frame) = decoder.read_next_frame().expect("frame") {
        assert_eq!(frame.delay, 10);
    }
}

#[test]
fn bad_sizes_and_empty_runs_are_refused() {
    let dir = tempfile::tempdir().expect("tempdir");
    let snapshots = [scene_2d()];
    for (w, h) in [(0, 100), (100, 0), (100_000, 100), (7, 100)] {
        let settings = RenderSettings::new(w, h);
        let error = render_to_dir(&snapshots, dir.path(), &settings).expect_err("bad size");
        assert!(matches!(error, RenderError::BadSize(_)), "{error}");
    }
    let error = render_to_dir(&[], dir.path(), &RenderSettings::new(100, 100)).expect_err("empty");
    assert!(matches!(error, RenderError::Empty));
    let error = read_run(dir.path(), 1).expect_err("no frames");
    assert!(error.to_string().contains("no VTK frames"), "{error}");
    assert!(
        std::fs::read_dir(dir.path()).expect("dir").next().is_none(),
        "nothing written"
    );
}

#[test]
fn a_malformed_frame_is_an_error_naming_its_file_and_line() {
    let dir = tempfile::tempdir().expect("tempdir");
    let frames = dir.path().join("frames");
    std::fs::create_dir_all(&frames).expect("frames dir");
    let mut world = hanging_world();
    write_frame(&frames, 0, &world, FrameFormat::Vtk).expect("frame");
    world.step(1e-3).expect("step");
    let path = write_frame(&frames, 1, &world, FrameFormat::Vtk).expect("frame");
    let text = std::fs::read_to_string(&path).expect("frame");
    std::fs::write(&path, text.replacen("CELLS", "CELLS x", 1)).expect("write");
    let line = text
        .lines()
        .position(|l| l.starts_with("CELLS"))
        .expect("cells")
        + 1;
    let error = read_run(dir.path(), 1).expect_err("malformed");
    let message = error.to_string();
    assert!(
        message.contains(&format!("frame_000001.vtk:{line}:")),
        "{message}"
    );
}

#[test]
fn pictures_show_pins_normals_and_both_sides_of_a_sheet() {
    let snapshot = scene_3d();
    let settings = RenderSettings::new(240, 180);
    let (plain, camera) = picture(&snapshot, &settings);
    // The pinned particle is a dark square.
    let (x, y) = camera.to_pixels(camera.view(snapshot.position[6]));
    let pin = plain.pixel(x as u32, y as u32).expect("inside");
    assert!(pin.iter().all(|&c| c < 60), "{pin:?}");
    let mut style: Style = settings.style;
    style.normals = true;
    let bounds = Bounds::of_snapshots(std::slice::from_ref(&snapshot)).expect("bounds");
    let with_normals = draw(&snapshot, &camera, &bounds, &style, &[]).expect("draws");
    assert_ne!(plain, with_normals, "--normals draws something");
}

/// Whether `image` has a pixel of exactly `colour`.
fn shows(image: &Image, colour: [u8; 3]) -> bool {
    image.rgb().chunks_exact(3).any(|p| p == colour)
}

#[test]
fn rods_muscles_and_traces_are_drawn_in_their_own_colours() {
    use sprung::{BodyData, MuscleData, MuscleDrive, RodData, SpringData};
    use sprung_view::render::style::{phase_colour, ROD, TRACE};
    // A rod 0–1, a plain spring 1–2 and a muscle 2–3 of phase π (teal:
    // none of the strain colours, red, green or blue).
    let mut body = BodyData::from_positions(vec![
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ]);
    body.rods.push(RodData {
        first: 0,
        second: 1,
        length: None,
    });
    body.springs = vec![SpringData::between(1, 2), SpringData::between(2, 3)];
    body.muscles.push(MuscleData {
        spring: 1,
        drive: MuscleDrive::Sine {
            amplitude: 0.1,
            period: 1.0,
            phase: std::f64::consts::PI,
        },
    });
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.add_body("parts", body).unwrap();
    let model = Arc::new(Model::of_world(&world));
    assert_eq!(model.rods, vec![[0, 1]]);
    let snapshot = Snapshot::of_world(&world, &model);
    // Lines 2 px wide (at 800 × 600) cover whole pixels in their colour.
    let settings = RenderSettings::new(800, 600);
    let (camera, bounds) = frame_run(std::slice::from_ref(&snapshot), &settings);
    let trace = [Vec3::new(0.2, 0.5, 0.0), Vec3::new(0.8, 0.5, 0.0)];
    let image = draw(&snapshot, &camera, &bounds, &settings.style, &trace).unwrap();
    assert!(shows(&image, ROD), "no rod drawn");
    assert!(
        shows(&image, phase_colour(std::f64::consts::PI)),
        "no muscle drawn"
    );
    assert!(shows(&image, TRACE), "no trace drawn");
    let plain = draw(&snapshot, &camera, &bounds, &settings.style, &[]).unwrap();
    assert!(!shows(&plain, TRACE), "a trace with none asked for");
    // Muscles of other phases take other colours.
    assert_ne!(phase_colour(0.0), phase_colour(std::f64::consts::PI));
}

#[test]
fn rods_survive_a_vtk_frame() {
    use sprung::{BodyData, RodData, SpringData};
    // A rod 0–1 and a spring 1–2: the frame carries the rod as a line
    // flagged `rod`, read back as a rod, not a spring.
    let mut body = BodyData::from_positions(vec![
        Vec3::ZERO,
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(1.0, 1.0, 0.0),
    ]);
    body.rods.push(RodData {
        first: 0,
        second: 1,
        length: None,
    });
    body.springs = vec![SpringData::between(1, 2)];
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("parts", body).unwrap();
    let dir = tempfile::tempdir().unwrap();
    write_frame(dir.path(), 0, &world, FrameFormat::Vtk).unwrap();
    let path = dir.path().join("frame_000000.vtk");
    let text = std::fs::read_to_string(&path).unwrap();
    let frame = sprung_io::export::read_vtk_frame(&text, &path).unwrap();
    let model = Model::from_vtk(&frame);
    assert_eq!(model.rods, vec![[0, 1]]);
    assert_eq!(model.springs, vec![[1, 2]]);
    assert_eq!(model.rods, Model::of_world(&world).rods);
}
