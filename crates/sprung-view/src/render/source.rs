//! Where the snapshots come from: a world run in memory ([`record`]), or
//! the VTK frames of a finished run read back in order ([`read_run`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use sprung::{Real, StepError, World};
use sprung_io::export::read_vtk_frame;

use super::snapshot::{Model, Snapshot};
use super::RenderError;

/// Pictures per simulated second when nothing else is asked.
pub const DEFAULT_PICTURE_RATE: Real = 25.0;

/// Steps of `dt` (s) between pictures for `rate` pictures per simulated
/// second (1/s): `round(1 / (rate dt))`, at least 1.
pub fn steps_between_pictures(dt: Real, rate: Real) -> u64 {
    let steps = (1.0 / (rate * dt)).round();
    if steps.is_finite() && steps >= 1.0 {
        steps as u64
    } else {
        1
    }
}

/// The snapshots of a world run in memory.
#[derive(Debug)]
pub struct Recording {
    /// One snapshot at the start, every `every` steps, and at the end.
    pub snapshots: Vec<Snapshot>,
    /// The blow-up that stopped the run early, if it did; the snapshots are
    /// those before it (all finite).
    pub blow_up: Option<StepError>,
}

/// Step `world` `steps` times by `dt` (s), taking a snapshot before the
/// first step, after every `every` steps (0 counts as 1) and after the
/// last. A blow-up stops the run and is returned with the snapshots so far.
pub fn record(world: &mut World, dt: Real, steps: u64, every: u64) -> Recording {
    let advance = |world: &mut World, count| {
        Ok::<_, std::convert::Infallible>((0..count).try_for_each(|_| world.step(dt).map(drop)))
    };
    match record_by(world, steps, every, advance) {
        Ok(recording) => recording,
        Err(never) => match never {},
    }
}

/// [`record`], the steps taken by `advance(world, count)` (`count` steps
/// at a time, up to the next snapshot: the GPU step's way, which reads
/// the state back only then). `advance` answers `Ok(Err(blow_up))` for a
/// blow-up, which ends the recording, and `Err(failure)` for a failure
/// of its own, which is returned instead.
pub fn record_by<E>(
    world: &mut World,
    steps: u64,
    every: u64,
    mut advance: impl FnMut(&mut World, u64) -> Result<Result<(), StepError>, E>,
) -> Result<Recording, E> {
    let every = every.max(1);
    let mut model = Arc::new(Model::of_world(world));
    let mut snapshots = vec![Snapshot::of_world(world, &model)];
    let mut done = 0;
    while done < steps {
        let count = (every - done % every).min(steps - done);
        if let Err(error) = advance(world, count)? {
            return Ok(Recording {
                snapshots,
                blow_up: Some(error),
            });
        }
        done += count;
        // Springs that yield or break change the model (rest lengths,
        // springs gone, faces opened): drawn afresh.
        if world.limits.enabled() {
            model = Arc::new(Model::of_world(world));
        }
        snapshots.push(Snapshot::of_world(world, &model));
    }
    Ok(Recording {
        snapshots,
        blow_up: None,
    })
}

/// The VTK frames of the run in `dir`: `dir/frames/frame_*.vtu` or
/// `frame_*.vtk` (or in `dir` when it is the frames folder itself), sorted
/// by name; `.vtu` frames when there are both. No frame at all is an error
/// naming the folder.
pub fn frame_files(dir: &Path) -> Result<Vec<PathBuf>, RenderError> {
    let frames = dir.join("frames");
    let folder = if frames.is_dir() {
        frames
    } else {
        dir.to_path_buf()
    };
    let entries = std::fs::read_dir(&folder).map_err(|e| RenderError::io(&folder, e))?;
    let frames: Vec<PathBuf> = entries
        .flatten()
        .map(|entry| entry.path())
        .filter(|path| {
            path.is_file()
                && path
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("frame_"))
        })
        .collect();
    let of = |extension: &str| -> Vec<PathBuf> {
        let mut files: Vec<PathBuf> = frames
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == extension))
            .cloned()
            .collect();
        files.sort();
        files
    };
    let vtu = of("vtu");
    let files = if vtu.is_empty() { of("vtk") } else { vtu };
    if files.is_empty() {
        return Err(RenderError::NoFrames(dir.join("frames")));
    }
    Ok(files)
}

/// Read every `every`-th frame of the run in `dir` (the first and the last
/// always; `every` 0 counts as 1); see [`frame_files`]. A malformed frame
/// is an error naming its file and line.
pub fn read_run(dir: &Path, every: usize) -> Result<Vec<Snapshot>, RenderError> {
    let files = frame_files(dir)?;
    let every = every.max(1);
    let last = files.len() - 1;
    let mut snapshots: Vec<Snapshot> = Vec::new();
    for (k, file) in files.iter().enumerate() {
        if k % every != 0 && k != last {
            continue;
        }
        let text = std::fs::read_to_string(file).map_err(|e| RenderError::io(file, e))?;
        let frame = read_vtk_frame(&text, file)?;
        let previous = snapshots.last().map(|s| &s.model);
        let snapshot = Snapshot::from_vtk(&frame, previous);
        snapshots.push(snapshot);
    }
    Ok(snapshots)
}
