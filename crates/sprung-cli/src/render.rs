//! `sprung render`: PNG pictures (and an animated GIF) of a scene, run in
//! memory, or of a finished run's VTK frames. The drawing is
//! `sprung_view::render`; this module reads the command line, picks the
//! source and the output folder, and reports.

use std::path::{Path, PathBuf};

use clap::Args;
use sprung::{IntegratorKind, Real, Vec3};
use sprung_gpu::GpuError;
use sprung_io::{load_scene_overridden, Device, Override, SceneCamera};
use sprung_view::render::{
    read_run, record, record_by, render_to_dir, steps_between_pictures, RenderError,
    RenderSettings, Rendered, Snapshot, StrainColours, DEFAULT_FOV_DEGREES, DEFAULT_PICTURE_RATE,
};

use crate::error::CliError;
use crate::on_gpu;
use crate::values;

/// Arguments of `sprung render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// A scene file (.toml) to run and draw, or a run folder holding
    /// frames/frame_*.vtu or .vtk (written by `sprung run SCENE --format
    /// vtu` or `vtk`).
    source: PathBuf,
    /// Output folder (default: out/SCENE/render for a scene, DIR/render
    /// for a run folder).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Steps to run a scene (instead of its duration).
    #[arg(long, conflicts_with = "time", value_parser = values::steps)]
    steps: Option<u64>,
    /// Simulated time to run a scene (s), instead of its duration.
    #[arg(long, value_parser = values::positive)]
    time: Option<f64>,
    /// Draw every K steps of a scene (default: 25 pictures per simulated
    /// second), or every K-th frame of a run folder (default: all).
    #[arg(long, value_parser = values::at_least_one)]
    every: Option<u64>,
    /// Picture width (pixels).
    #[arg(long, default_value_t = 800, value_parser = values::picture_side)]
    width: u32,
    /// Picture height (pixels).
    #[arg(long, default_value_t = 600, value_parser = values::picture_side)]
    height: u32,
    /// Also write OUT/animation.gif (looping).
    #[arg(long)]
    gif: bool,
    /// GIF playback rate (pictures per second); default: real time.
    #[arg(long, allow_hyphen_values = true, value_parser = values::positive)]
    fps: Option<f64>,
    /// Strain at which spring colours saturate: fully red stretched, fully
    /// blue compressed (a fraction: 0.1 is 10 %).
    #[arg(long, default_value_t = 0.1, allow_hyphen_values = true, value_parser = values::positive)]
    strain: f64,
    /// Draw each face's outward normal.
    #[arg(long)]
    normals: bool,
    /// Draw every spring over the faces (default: only those along face
    /// edges; shear, bending and internal springs would hide the surface).
    #[arg(long)]
    all_springs: bool,
    /// Draw the path of particle I (its index in the world: bodies'
    /// particles in the order the scene gives them) up to each picture.
    #[arg(long, value_name = "I")]
    trace: Option<u32>,
    /// Camera position x,y,z (m); default: framed automatically.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    eye: Option<Vec3>,
    /// Point looked at x,y,z (m); default: the centre of the bodies.
    #[arg(long, value_parser = parse_point, allow_hyphen_values = true)]
    target: Option<Vec3>,
    /// Vertical field of view of the perspective camera (degrees; default:
    /// the scene's `[camera]` fov, else 40).
    #[arg(long, allow_hyphen_values = true, value_parser = values::field_of_view)]
    fov: Option<f64>,
    /// Override a scene's integrator.
    #[arg(long)]
    integrator: Option<IntegratorKind>,
    /// Where a scene's steps run: cpu, gpu or gpu_f64 (docs/gpu.md),
    /// instead of its `device`.
    #[arg(long)]
    device: Option<Device>,
    /// Set a key of a scene: `sim.dt=1e-4`, `body.NAME.stiffness=200`,
    /// `collider.0.friction=0.5` (repeatable; docs/scenes.md, "Overrides").
    #[arg(long = "set", value_name = "KEY=VALUE", value_parser = crate::values::OverrideArg)]
    set: Vec<Override>,
    /// Print nothing but errors and warnings.
    #[arg(long)]
    quiet: bool,
}

/// `x,y,z` as a point (m).
fn parse_point(text: &str) -> Result<Vec3, String> {
    let values: Result<Vec<Real>, _> = text.split(',').map(|v| v.trim().parse()).collect();
    match values.as_deref() {
        Ok(&[x, y, z]) if [x, y, z].iter().all(|v| v.is_finite()) => Ok(Vec3::new(x, y, z)),
        _ => Err(format!(
            "\"{text}\": expected three finite numbers x,y,z (m)"
        )),
    }
}

/// Run `sprung render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let mut settings = settings(args)?;
    let source = &args.source;
    if !source.exists() {
        return Err(CliError::Input(format!(
            "{}: no such scene file or run folder",
            source.display()
        )));
    }
    let (snapshots, out, blow_up) = if source.is_dir() {
        if args.steps.is_some()
            || args.time.is_some()
            || args.integrator.is_some()
            || !args.set.is_empty()
        {
            return Err(CliError::Input(format!(
                "{} is a run folder: --steps, --time, --integrator and --set apply to scene files only",
                source.display()
            )));
        }
        let every = match args.every {
            Some(0) => return Err(CliError::Input("--every must be at least 1".into())),
            Some(k) => usize::try_from(k).unwrap_or(usize::MAX),
            None => 1,
        };
        let snapshots = read_run(source, every).map_err(render_error)?;
        let out = args.out.clone().unwrap_or_else(|| source.join("render"));
        (snapshots, out, None)
    } else {
        let (snapshots, blow_up, camera) = run_scene(source, args)?;
        // The scene's [camera] where the command line says nothing.
        settings.camera.eye = settings.camera.eye.or(camera.eye);
        settings.camera.target = settings.camera.target.or(camera.target);
        if args.fov.is_none() {
            settings.camera.fov_degrees = camera.fov.unwrap_or(DEFAULT_FOV_DEGREES);
        }
        let stem = source.file_stem().unwrap_or_default().to_string_lossy();
        let out = args
            .out
            .clone()
            .unwrap_or_else(|| Path::new("out").join(stem.as_ref()).join("render"));
        (snapshots, out, blow_up)
    };
    if let (Some(i), Some(first)) = (args.trace, snapshots.first()) {
        if i as usize >= first.position.len() {
            return Err(CliError::Input(format!(
                "--trace {i}: no such particle (the scene has {})",
                first.position.len()
            )));
        }
    }
    let rendered = render_to_dir(&snapshots, &out, &settings).map_err(render_error)?;
    if let Some(error) = blow_up {
        let kept = format!(
            "the {} pictures up to the last good step are in {}",
            rendered.pictures.len(),
            out.display()
        );
        return Err(CliError::BlowUp(error, kept));
    }
    if !args.quiet {
        report(source, &out, &rendered, &settings);
    }
    Ok(())
}

/// The picture settings from the command line, checked.
fn settings(args: &RenderArgs) -> Result<RenderSettings, CliError> {
    sprung_view::render::check_size(args.width, args.height).map_err(render_error)?;
    let mut settings = RenderSettings::new(args.width, args.height);
    settings.style.strain = StrainColours::new(args.strain).ok_or_else(|| {
        CliError::Input(format!(
            "--strain {}: must be a positive, finite strain (0.1 is 10 %)",
            args.strain
        ))
    })?;
    settings.style.normals = args.normals;
    settings.style.all_springs = args.all_springs;
    settings.style.trace = args.trace;
    settings.gif = args.gif;
    if let Some(fps) = args.fps {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(CliError::Input(format!(
                "--fps {fps}: must be a positive, finite number of pictures per second"
            )));
        }
        settings.fps = Some(fps);
    }
    if let Some(fov) = args
        .fov
        .filter(|f| !(f.is_finite() && *f > 0.0 && *f < 180.0))
    {
        return Err(CliError::Input(format!(
            "--fov {fov}: must be between 0 and 180 degrees"
        )));
    }
    if let (Some(eye), Some(target)) = (args.eye, args.target) {
        if eye == target {
            return Err(CliError::Input(
                "--eye and --target are the same point: the camera needs a direction".into(),
            ));
        }
    }
    settings.camera.eye = args.eye;
    settings.camera.target = args.target;
    settings.camera.fov_degrees = args.fov.unwrap_or(DEFAULT_FOV_DEGREES);
    Ok(settings)
}

/// Load and run the scene in memory; the snapshots, the blow-up that
/// stopped it early, if any, and the scene's camera.
fn run_scene(
    path: &Path,
    args: &RenderArgs,
) -> Result<(Vec<Snapshot>, Option<sprung::StepError>, SceneCamera), CliError> {
    let mut scene = load_scene_overridden(path, &args.set)?;
    if let Some(kind) = args.integrator {
        scene.world.set_integrator(kind);
    }
    let steps = crate::run::planned_steps(&scene, args.steps, args.time)?;
    let every = match args.every {
        Some(0) => return Err(CliError::Input("--every must be at least 1".into())),
        Some(k) => k,
        None => steps_between_pictures(scene.dt, DEFAULT_PICTURE_RATE),
    };
    // The snapshots are kept until drawn: refuse a run whose pictures
    // would not fit in memory before stepping it.
    let pictures = steps / every + 2;
    let bytes = pictures as f64 * snapshot_bytes(&scene.world) as f64;
    if bytes > MAX_SNAPSHOT_BYTES as f64 {
        return Err(CliError::Input(format!(
            "{} pictures of {} particles would keep {:.1} GB in memory, more than the {:.1} GB `sprung render` allows: draw fewer (--every, --time, --steps)",
            pictures,
            scene.world.particles.len(),
            bytes / 1e9,
            MAX_SNAPSHOT_BYTES as f64 / 1e9
        )));
    }
    let recording = match args.device.unwrap_or(scene.device) {
        Device::Cpu => record(&mut scene.world, scene.dt, steps, every),
        device @ (Device::Gpu | Device::GpuF64) => {
            let mut gpu = on_gpu::put_on_gpu(&scene.world, scene.dt, device, args.quiet)?;
            record_by(&mut scene.world, steps, every, |world, count| {
                gpu.step(count);
                match gpu.read_into(world) {
                    Ok(()) => Ok(Ok(())),
                    Err(GpuError::Step(blow_up)) => Ok(Err(blow_up)),
                    Err(failure) => Err(on_gpu::failed(&failure)),
                }
            })?
        }
    };
    Ok((recording.snapshots, recording.blow_up, scene.camera))
}

/// Most memory the snapshots of a rendered scene may take (bytes): 2 GB.
const MAX_SNAPSHOT_BYTES: u64 = 2_000_000_000;

/// Memory of one snapshot of `world` (bytes): its positions and colliders.
fn snapshot_bytes(world: &sprung::World) -> u64 {
    let position = size_of::<Vec3>() as u64;
    let collider = size_of::<sprung::Shape>() as u64;
    world.particles.len() as u64 * position + world.colliders.len() as u64 * collider + 64
}

fn render_error(error: RenderError) -> CliError {
    match error {
        RenderError::Io { .. } | RenderError::Encode(_) => CliError::Io(error.to_string()),
        _ => CliError::Input(error.to_string()),
    }
}

fn report(source: &Path, out: &Path, rendered: &Rendered, settings: &RenderSettings) {
    if !rendered.strain_known {
        eprintln!(
            "note: some frames carry no spring rest lengths (written by an older sprung): \
             those springs are drawn grey"
        );
    }
    println!(
        "{}: {} pictures of {}×{}{} in {}",
        source.display(),
        rendered.pictures.len(),
        settings.width,
        settings.height,
        if rendered.gif.is_some() {
            " and animation.gif"
        } else {
            ""
        },
        out.display()
    );
}
