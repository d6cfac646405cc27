//! Writing a run's pictures: `OUT/frame_000000.png` ... and, if asked,
//! `OUT/animation.gif`, every file complete or not at all
//! ([`sprung_io::export::AtomicFile`]).

use std::path::{Path, PathBuf};

use sprung::{Real, Vec3};
use sprung_io::export::AtomicFile;

use super::camera::{Bounds, Camera, CameraSetting};
use super::draw::draw;
use super::gif::{delay_centiseconds, GifWriter};
use super::image::Image;
use super::snapshot::Snapshot;
use super::source::DEFAULT_PICTURE_RATE;
use super::style::Style;
use super::RenderError;

/// The largest picture side accepted (pixels).
pub const MAX_SIZE: u32 = 8192;
/// The smallest picture side accepted (pixels).
pub const MIN_SIZE: u32 = 8;
/// The animation's file name in the output folder.
pub const GIF_NAME: &str = "animation.gif";

/// What to write.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderSettings {
    /// Picture width (pixels).
    pub width: u32,
    /// Picture height (pixels).
    pub height: u32,
    /// The camera (automatic unless eye or target are given).
    pub camera: CameraSetting,
    /// Colours and line widths.
    pub style: Style,
    /// Also write `animation.gif`.
    pub gif: bool,
    /// GIF pictures per second of playback (1/s); `None`: real time, the
    /// simulated time between pictures.
    pub fps: Option<Real>,
}

impl RenderSettings {
    /// Defaults for `width` × `height` pixels: automatic camera, the
    /// default style for that size, PNG only.
    pub fn new(width: u32, height: u32) -> Self {
        RenderSettings {
            width,
            height,
            camera: CameraSetting::default(),
            style: Style::for_size(width, height),
            gif: false,
            fps: None,
        }
    }
}

/// What was written.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    /// The PNG files, in order.
    pub pictures: Vec<PathBuf>,
    /// The GIF, when asked for.
    pub gif: Option<PathBuf>,
    /// The camera used for every picture.
    pub camera: Camera,
    /// False when some spring's rest length was unknown (frames written
    /// before VTK frames carried `rest_length`): those springs are grey.
    pub strain_known: bool,
}

/// Refuse picture sizes outside [`MIN_SIZE`]..=[`MAX_SIZE`] pixels.
pub fn check_size(width: u32, height: u32) -> Result<(), RenderError> {
    let ok = |side: u32| (MIN_SIZE..=MAX_SIZE).contains(&side);
    if ok(width) && ok(height) {
        Ok(())
    } else {
        Err(RenderError::BadSize(format!(
            "{width}×{height} pixels: each side must be from {MIN_SIZE} to {MAX_SIZE}"
        )))
    }
}

/// The camera for `snapshots` with `settings`, and the box it frames: one
/// for the whole run, so the view does not jump.
pub fn frame_run(snapshots: &[Snapshot], settings: &RenderSettings) -> (Camera, Bounds) {
    let bounds = Bounds::of_snapshots(snapshots).unwrap_or(Bounds {
        min: Vec3::new(-1.0, -1.0, 0.0),
        max: Vec3::new(1.0, 1.0, 0.0),
        planar: true,
    });
    let camera = Camera::frame(
        snapshots,
        &bounds,
        &settings.camera,
        settings.width,
        settings.height,
    );
    (camera, bounds)
}

/// Draw every snapshot in memory with one camera for the run ([`frame_run`]):
/// the pictures, and, when `settings.gif` is set, the animated GIF's bytes
/// (each picture shown for the simulated time to the next, or `1/fps`).
/// The same pictures [`render_to_dir`] writes.
///
/// ```
/// use sprung::{build, IntegratorKind, World};
/// use sprung_view::render::{record, render_in_memory, RenderSettings, Snapshot};
///
/// let mut world = World::new(IntegratorKind::Verlet);
/// world.add_body("rope", build::rope(8, 1.0).unwrap().with_stiffness(100.0)).unwrap();
/// let recording = record(&mut world, 1e-3, 100, 50);
/// let mut settings = RenderSettings::new(64, 48);
/// settings.gif = true;
/// let (pictures, gif) = render_in_memory(&recording.snapshots, &settings).unwrap();
/// assert_eq!(pictures.len(), 3); // the start, step 50 and step 100
/// assert_eq!((pictures[0].width(), pictures[0].height()), (64, 48));
/// assert!(gif.unwrap().starts_with(b"GIF89a"));
/// ```
pub fn render_in_memory(
    snapshots: &[Snapshot],
    settings: &RenderSettings,
) -> Result<(Vec<Image>, Option<Vec<u8>>), RenderError> {
    check(snapshots, settings)?;
    let (camera, bounds) = frame_run(snapshots, settings);
    let mut gif = match settings.gif {
        true => Some(GifWriter::in_memory(settings.width, settings.height)?),
        false => None,
    };
    let mut pictures = Vec::with_capacity(snapshots.len());
    let mut trace = Vec::new();
    for (k, snapshot) in snapshots.iter().enumerate() {
        let image = draw_one(snapshot, &camera, &bounds, settings, &mut trace)?;
        if let Some(gif) = gif.as_mut() {
            gif.push(&image, delay(snapshots, k, settings.fps))?;
        }
        pictures.push(image);
    }
    let gif = gif.map(GifWriter::into_bytes).transpose()?;
    Ok((pictures, gif))
}

/// Refuse a size, an empty run or a frame rate that cannot be drawn.
fn check(snapshots: &[Snapshot], settings: &RenderSettings) -> Result<(), RenderError> {
    check_size(settings.width, settings.height)?;
    if snapshots.is_empty() {
        return Err(RenderError::Empty);
    }
    if let Some(fps) = settings.fps {
        if !(fps.is_finite() && fps > 0.0) {
            return Err(RenderError::BadOption(format!(
                "fps {fps}: must be positive and finite (pictures per second)"
            )));
        }
    }
    Ok(())
}

/// Draw `snapshot`, extending the traced particle's path first.
fn draw_one(
    snapshot: &Snapshot,
    camera: &Camera,
    bounds: &Bounds,
    settings: &RenderSettings,
    trace: &mut Vec<Vec3>,
) -> Result<Image, RenderError> {
    if let Some(i) = settings.style.trace {
        if let Some(&p) = snapshot.position.get(i as usize) {
            trace.push(p);
        }
    }
    draw(snapshot, camera, bounds, &settings.style, trace)
}

/// Draw every snapshot into `out` (created if needed; earlier
/// `frame_*.png` there are removed first so sequences do not mix).
pub fn render_to_dir(
    snapshots: &[Snapshot],
    out: &Path,
    settings: &RenderSettings,
) -> Result<Rendered, RenderError> {
    check(snapshots, settings)?;
    prepare(out)?;
    let (camera, bounds) = frame_run(snapshots, settings);
    let mut gif = match settings.gif {
        true => Some(GifWriter::create(
            &out.join(GIF_NAME),
            settings.width,
            settings.height,
        )?),
        false => None,
    };
    let mut pictures = Vec::with_capacity(snapshots.len());
    let mut trace = Vec::new();
    for (k, snapshot) in snapshots.iter().enumerate() {
        let image = draw_one(snapshot, &camera, &bounds, settings, &mut trace)?;
        let path = out.join(format!("frame_{k:06}.png"));
        AtomicFile::write(&path, &image.encode_png()?).map_err(|e| RenderError::io(&path, e))?;
        pictures.push(path);
        if let Some(gif) = gif.as_mut() {
            gif.push(&image, delay(snapshots, k, settings.fps))?;
        }
    }
    let gif = gif.map(GifWriter::finish).transpose()?;
    let strain_known = snapshots
        .iter()
        .all(|s| s.model.rest_length.iter().all(|l| !l.is_nan()));
    Ok(Rendered {
        pictures,
        gif,
        camera,
        strain_known,
    })
}

/// The GIF delay of picture `k` (1/100 s): 1/fps, or the simulated time to
/// the next picture (to the previous one for the last), or 1/25 s when
/// the times are unknown.
fn delay(snapshots: &[Snapshot], k: usize, fps: Option<Real>) -> u16 {
    if let Some(fps) = fps {
        return delay_centiseconds(1.0 / fps);
    }
    let time = |i: usize| snapshots.get(i).and_then(|s| s.time);
    let gap = match (time(k), time(k + 1), k.checked_sub(1).and_then(time)) {
        (Some(now), Some(next), _) => next - now,
        (Some(now), None, Some(before)) => now - before,
        _ => 1.0 / DEFAULT_PICTURE_RATE,
    };
    if gap > 0.0 {
        delay_centiseconds(gap)
    } else {
        delay_centiseconds(1.0 / DEFAULT_PICTURE_RATE)
    }
}

/// Create `out` and remove earlier pictures from it.
fn prepare(out: &Path) -> Result<(), RenderError> {
    std::fs::create_dir_all(out).map_err(|e| RenderError::io(out, e))?;
    let entries = std::fs::read_dir(out).map_err(|e| RenderError::io(out, e))?;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        if name.starts_with("frame_") && name.ends_with(".png") {
            let path = entry.path();
            std::fs::remove_file(&path).map_err(|e| RenderError::io(&path, e))?;
        }
    }
    Ok(())
}
