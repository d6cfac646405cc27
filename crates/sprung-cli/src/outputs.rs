//! What a run writes, in one place: `diagnostics.csv`, the frames with
//! their series file or the glTF animation, and the saved state; each
//! written completely or not at all, however the run ends (finished,
//! interrupted, blown up), and at checkpoints.

use std::path::{Path, PathBuf};

use sprung::World;
use sprung_io::export::{self, Animation, Diagnostics, OutputFormat};

use crate::checkpoint::{self, Resumed};
use crate::run::CliError;
use crate::RunOptions;

/// The most bytes a glTF animation may gather in memory (2 GB).
pub const ANIMATION_BUDGET: u64 = 2_000_000_000;

/// The outputs of one run.
pub struct Outputs<'a> {
    out: PathBuf,
    frames_dir: PathBuf,
    diagnostics: Diagnostics,
    format: Option<OutputFormat>,
    animation: Option<Animation>,
    /// Frames written by this process.
    frames: usize,
    /// States saved at checkpoints.
    checkpoints: usize,
    options: &'a RunOptions,
    dt: f64,
    every: u64,
}

impl<'a> Outputs<'a> {
    /// Prepare `out` for a run of `world` stepping by `dt` (s), recording
    /// every `every` steps, about `records` rows in all, going on from
    /// `resumed` if given: refuse what cannot be done before anything is
    /// written.
    pub fn open(
        out: &Path,
        world: &World,
        (dt, every): (f64, u64),
        options: &'a RunOptions,
        resumed: Option<Resumed>,
        records: u64,
    ) -> Result<Self, CliError> {
        let format = options.format;
        if format == Some(OutputFormat::Gltf) {
            if resumed.is_some() {
                return Err(CliError::Input(
                    "--format gltf keeps the whole run in one animation.glb, which a resumed run cannot add to (resume with --format vtu, vtk or obj)".into(),
                ));
            }
            let bytes = Animation::estimated_bytes(world, records);
            if bytes > ANIMATION_BUDGET {
                return Err(CliError::Input(format!(
                    "--format gltf: {records} frames of {} particles would take about {:.1} GB, more than the {:.0} GB an animation may gather (record fewer frames with --every, or use --format vtu)",
                    world.particles.len(),
                    bytes as f64 / 1e9,
                    ANIMATION_BUDGET as f64 / 1e9
                )));
            }
        }
        if let Some(state) = &options.save_state {
            check_state_path(state, out)?;
        }
        let csv = out.join("diagnostics.csv");
        let table = |name: &&str| out.join(name).is_file();
        if resumed.is_some() && !DIAGNOSTICS_TABLES.iter().any(table) {
            return Err(no_diagnostics(out));
        }
        let frames_dir = out.join("frames");
        // The series file lists every frame from the first: a resumed run
        // adds to the frames of the run it goes on with, in their format.
        if let (Some(r), Some(OutputFormat::Frames(frame_format))) = (resumed, format) {
            let last = export::frame_path(&frames_dir, r.rows.saturating_sub(1), frame_format);
            if r.rows > 0 && !last.is_file() {
                return Err(CliError::Input(format!(
                    "--resume --format {}: the run in {} has no {}, so its frames are in another format or none (resume with the --format it was started with, or with none)",
                    frame_format.extension(),
                    out.display(),
                    last.display()
                )));
            }
        }
        let first_frame = resumed.map_or(0, |r| r.rows);
        let frame_files = matches!(format, Some(OutputFormat::Frames(_)));
        prepare_output(
            out,
            frame_files.then_some(frames_dir.as_path()),
            first_frame,
        )?;
        let diagnostics = match resumed {
            None => Diagnostics::create(&csv, world, &options.probe).map_err(|e| io(out, e))?,
            Some(r) => Diagnostics::resume(&csv, world, &options.probe, r.rows)
                .map_err(|e| CliError::Input(e.to_string()))?
                .ok_or_else(|| no_diagnostics(out))?,
        };
        Ok(Outputs {
            out: out.to_path_buf(),
            frames_dir,
            diagnostics,
            format,
            animation: (format == Some(OutputFormat::Gltf)).then(|| Animation::new(world)),
            frames: 0,
            checkpoints: 0,
            options,
            dt,
            every,
        })
    }

    /// Record a row of `world`'s state, and its frame.
    pub fn record(&mut self, world: &World) -> Result<(), CliError> {
        // Frame n goes with row n, in a resumed run too.
        let index = self.diagnostics.rows();
        self.diagnostics
            .record(world)
            .map_err(|e| io(&self.out, e))?;
        match self.format {
            Some(OutputFormat::Frames(format)) => {
                export::write_frame(&self.frames_dir, index, world, format)
                    .map_err(|e| io(&self.frames_dir, e))?;
                self.frames += 1;
            }
            Some(OutputFormat::Gltf) => {
                if let Some(animation) = &mut self.animation {
                    animation.record(world);
                    self.frames += 1;
                }
            }
            None => {}
        }
        Ok(())
    }

    /// A checkpoint: everything recorded so far on disk (the rows flushed,
    /// the series file), and the state saved, when asked for.
    pub fn checkpoint(&mut self, world: &World) -> Result<(), CliError> {
        self.diagnostics.flush().map_err(|e| io(&self.out, e))?;
        self.series(world)?;
        self.save(world, self.diagnostics.rows())?;
        self.checkpoints += 1;
        Ok(())
    }

    /// Rows recorded (kept rows of a resumed run included).
    pub fn rows(&self) -> usize {
        self.diagnostics.rows()
    }

    /// Finish every file of the run at `world`'s state; `state_rows` is
    /// the row count a resumed run goes on from (see `checkpoint`), and
    /// `save` whether to save the state. Returns a sentence of where the
    /// results are.
    pub fn finish(self, world: &World, state_rows: usize, save: bool) -> Result<String, CliError> {
        self.series(world)?;
        if let Some(animation) = &self.animation {
            let path = self.out.join("animation.glb");
            animation.write(&path).map_err(|e| io(&path, e))?;
        }
        let rows = self.diagnostics.rows();
        if save {
            self.save(world, state_rows)?;
        }
        let mut place = format!(
            "{rows} rows in {}",
            self.out.join("diagnostics.csv").display()
        );
        match self.format {
            Some(OutputFormat::Frames(_)) if self.frames > 0 => place.push_str(&format!(
                ", {} frames in {}",
                self.frames,
                self.frames_dir.display()
            )),
            Some(OutputFormat::Gltf) => place.push_str(&format!(
                ", an animation of {} frames in {}",
                self.frames,
                self.out.join("animation.glb").display()
            )),
            _ => {}
        }
        if let (Some(path), true) = (&self.options.save_state, save || self.checkpoints > 0) {
            let which = if save {
                "state saved to"
            } else {
                "the last checkpoint is in"
            };
            place.push_str(&format!("; {which} {}", path.display()));
        }
        self.diagnostics.finish().map_err(|e| io(&self.out, e))?;
        Ok(place)
    }

    /// The frames' time-series file, for frame formats that have one.
    fn series(&self, world: &World) -> Result<(), CliError> {
        match self.format {
            Some(OutputFormat::Frames(format)) => {
                export::write_series(&self.frames_dir, format, world, self.diagnostics.times())
                    .map_err(|e| io(&self.frames_dir, e))
            }
            _ => Ok(()),
        }
    }

    fn save(&self, world: &World, rows: usize) -> Result<(), CliError> {
        match &self.options.save_state {
            Some(path) => checkpoint::save(path, world, rows, self.dt, self.every),
            None => Ok(()),
        }
    }
}

fn io(path: &Path, e: std::io::Error) -> CliError {
    CliError::Io(format!("cannot write to {}: {e}", path.display()))
}

/// The error of a resumed run whose `out` holds no diagnostics.
fn no_diagnostics(out: &Path) -> CliError {
    CliError::Input(format!(
        "--resume goes on with the run in {}, but there is no diagnostics.csv there (give the --out of the run that saved the state)",
        out.display()
    ))
}

/// The tables of a run's diagnostics that a resumed run can go on from
/// (`Diagnostics::resume` reads the first that exists).
const DIAGNOSTICS_TABLES: [&str; 3] = [
    "diagnostics.csv",
    "diagnostics.csv.partial",
    "diagnostics.csv.previous",
];

/// `path` made absolute, with its longest existing part resolved (links
/// followed, `..` taken away), so two names of one file compare equal.
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut base = absolute.clone();
    let mut rest = Vec::new();
    while !base.exists() {
        let Some(last) = base.components().next_back() else {
            return absolute;
        };
        rest.push(last.as_os_str().to_owned());
        if !base.pop() {
            return absolute;
        }
    }
    let mut resolved = base.canonicalize().unwrap_or(base);
    // The part that does not exist yet has no links: its `..` go back a
    // name.
    for name in rest.iter().rev() {
        match name.to_str() {
            Some("..") => {
                resolved.pop();
            }
            Some(".") => {}
            _ => resolved.push(name),
        }
    }
    resolved
}

/// Refuse a `--save-state` path that cannot be written, or would be written
/// over one of the run's own outputs in `out` (or over `out` itself),
/// before anything is made.
fn check_state_path(state: &Path, out: &Path) -> Result<(), CliError> {
    let shown = state.display().to_string();
    let refuse = |why: String| Err(CliError::Input(format!("--save-state {shown}: {why}")));
    if state.as_os_str().is_empty() {
        return refuse("is empty (give a file name)".into());
    }
    let (state, out) = (resolved(state), resolved(out));
    if state.is_dir() {
        return refuse("is a folder (give a file name)".into());
    }
    if out.starts_with(&state) {
        return refuse(format!("is the run's folder {} or holds it", out.display()));
    }
    let own = DIAGNOSTICS_TABLES.iter().chain(&["animation.glb"]);
    if own.clone().any(|name| state == out.join(name)) || state.starts_with(out.join("frames")) {
        return refuse(format!(
            "is one of the run's own outputs in {} (give another file)",
            out.display()
        ));
    }
    let folder = state.parent().unwrap_or(Path::new("."));
    if !folder.is_dir() && folder != out {
        return refuse(format!(
            "there is no folder {} to write it in",
            folder.display()
        ));
    }
    Ok(())
}

/// Create the output folder and, for frames, `frames/` without frames
/// numbered from `first_frame` on (earlier frames of this run's format
/// would mix into the new sequence; a resumed run keeps those before).
fn prepare_output(out: &Path, frames: Option<&Path>, first_frame: usize) -> Result<(), CliError> {
    let fail = |e: std::io::Error, dir: &Path| {
        CliError::Io(format!("cannot create {}: {e}", dir.display()))
    };
    std::fs::create_dir_all(out).map_err(|e| fail(e, out))?;
    if let Some(dir) = frames {
        std::fs::create_dir_all(dir).map_err(|e| fail(e, dir))?;
        let stale = std::fs::read_dir(dir).map_err(|e| fail(e, dir))?;
        for entry in stale.flatten() {
            let name = entry.file_name();
            let name = name.to_string_lossy();
            let index = name
                .strip_prefix("frame_")
                .map(|rest| rest.split('.').next().unwrap_or_default().parse::<usize>());
            // Kept: frames of a resumed run's earlier part.
            if index.is_some_and(|n| n.map_or(true, |n| n >= first_frame)) {
                std::fs::remove_file(entry.path()).map_err(|e| fail(e, dir))?;
            }
        }
    }
    Ok(())
}
