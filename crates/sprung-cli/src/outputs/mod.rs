//! What a run writes, in one place: `diagnostics.csv`, the frames with
//! their series file or the glTF animation, and the saved state; each
//! written completely or not at all, however the run ends (finished,
//! interrupted, blown up), and at checkpoints.

use std::path::{Path, PathBuf};

use sprung::World;
use sprung_io::export::{self, Animation, Diagnostics, NotFiniteValue, OutputFormat};

mod refusals;

pub(crate) use refusals::resolved;
use refusals::{
    check_inputs_kept, check_own_files, check_state_path, check_writable, state_folder,
    DIAGNOSTICS_TABLES,
};

use crate::checkpoint::{self, Resumed};
use crate::error::CliError;
use crate::RunOptions;

/// The glTF animation's file in a run's folder.
const ANIMATION: &str = "animation.glb";

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
    /// The step of the last state saved at a checkpoint, if any.
    last_checkpoint: Option<u64>,
    /// The first frame this process writes (the rows a resumed run kept).
    first_frame: usize,
    options: &'a RunOptions,
    dt: f64,
    every: u64,
}

impl<'a> Outputs<'a> {
    /// Prepare `out` for a run of `world` stepping by `dt` (s), recording
    /// every `every` steps, about `records` rows in all, going on from
    /// `resumed` if given, reading the files `inputs`: refuse what cannot
    /// be done (an output over an input, a state file that cannot be
    /// written) before anything is written.
    pub fn open(
        out: &Path,
        world: &World,
        (dt, every): (f64, u64),
        options: &'a RunOptions,
        (resumed, inputs): (Option<Resumed>, &[&Path]),
        records: u64,
    ) -> Result<Self, CliError> {
        let format = options.format;
        check_inputs_kept(inputs, out, options.save_state.as_deref())?;
        if format == Some(OutputFormat::Gltf) {
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
            if format == Some(OutputFormat::Gltf) {
                return Err(CliError::Input(format!(
                    "--save-state with --format gltf: the run keeps its frames in one {ANIMATION}, which a resumed run cannot add to, so its state could not be resumed (use --format vtu, vtk or obj)"
                )));
            }
            check_state_path(state, out)?;
            // A state in the run's folder is probed once the folder is made.
            if state_folder(state).is_dir() {
                check_writable(state)?;
            }
        }
        let csv = out.join("diagnostics.csv");
        let table = |name: &&str| out.join(name).is_file();
        if resumed.is_some() && !DIAGNOSTICS_TABLES.iter().any(table) {
            return Err(no_diagnostics(out));
        }
        if resumed.is_some() {
            check_resumed_format(out, format)?;
        }
        let frames_dir = out.join("frames");
        check_own_files(out, &frames_dir, options.save_state.as_deref())?;
        let first_frame = resumed.map_or(0, |r| r.rows);
        prepare_output(out, &frames_dir, first_frame)?;
        if let Some(state) = &options.save_state {
            check_writable(state)?;
        }
        if matches!(format, Some(OutputFormat::Frames(_))) {
            std::fs::create_dir_all(&frames_dir).map_err(|e| {
                CliError::Io(format!("cannot create {}: {e}", frames_dir.display()))
            })?;
        }
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
            last_checkpoint: None,
            first_frame,
            options,
            dt,
            every,
        })
    }

    /// Record a row of `world`'s state, and its frame. A row that would
    /// hold a non-finite number is not written: `CliError::BlowUp` (with no
    /// sentence of what was kept; see [`Outputs::finish`]).
    pub fn record(&mut self, world: &World) -> Result<(), CliError> {
        // Frame n goes with row n, in a resumed run too.
        let index = self.diagnostics.rows();
        self.diagnostics.record(world).map_err(|e| {
            let not_finite = e.get_ref().and_then(|e| e.downcast_ref::<NotFiniteValue>());
            match not_finite {
                // Stopped as a blow-up: the caller keeps what was written.
                Some(bad) => CliError::BlowUp(
                    world.not_finite(&bad.quantity, bad.value, self.dt),
                    String::new(),
                ),
                None => io(&self.out, e),
            }
        })?;
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
        self.series(world, self.diagnostics.times())?;
        self.save(world, self.diagnostics.rows())?;
        self.last_checkpoint = Some(world.steps());
        Ok(())
    }

    /// Rows recorded (kept rows of a resumed run included).
    pub fn rows(&self) -> usize {
        self.diagnostics.rows()
    }

    /// Finish every file of the run at `world`'s state; `state_rows` is
    /// the row count a resumed run goes on from (see `checkpoint`), and
    /// `save` whether to save the state. Returns a sentence of where the
    /// results are. Where a file cannot be written, what was written is
    /// kept ([`Outputs::keep`]) and the error says what.
    pub fn finish(
        mut self,
        world: &World,
        state_rows: usize,
        save: bool,
    ) -> Result<String, CliError> {
        let written = self
            .series(world, self.diagnostics.times())
            .and_then(|()| self.write_animation())
            .and_then(|()| self.diagnostics.flush().map_err(|e| io(&self.out, e)));
        if let Err(error) = written {
            return Err(self.keep(error, world));
        }
        let place = place(&self.out, self.format, self.diagnostics.rows(), self.frames);
        let (options, dt, every) = (self.options, self.dt, self.every);
        let checkpoint = self.checkpoint_sentence();
        self.diagnostics.finish().map_err(|e| io(&self.out, e))?;
        let Some(path) = &options.save_state else {
            return Ok(place);
        };
        if !save {
            return Ok(format!("{place}{checkpoint}"));
        }
        // Last, so that a state that cannot be written loses none of the
        // results above.
        match checkpoint::save(path, world, state_rows, dt, every) {
            Ok(()) => Ok(format!("{place}; state saved to {}", path.display())),
            Err(CliError::Io(why)) => Err(CliError::Io(format!(
                "{why} (the state was not saved{checkpoint}; the run's results are kept: {place})"
            ))),
            Err(other) => Err(other),
        }
    }

    /// After `error`, a write that failed during the run (a row, a frame,
    /// a checkpoint, the animation): finish what was written, the rows
    /// that reached `diagnostics.csv` whole, the frames with their series
    /// file, the animation where it can still be written; returns the
    /// error with a sentence of exactly what was kept.
    pub fn keep(self, error: CliError, world: &World) -> CliError {
        let csv = self.out.join("diagnostics.csv");
        let frames = self.frames;
        let (mut notes, mut kept_frames) = (String::new(), frames);
        match self.format {
            Some(OutputFormat::Frames(_)) if frames > 0 => {
                let times = self.diagnostics.times();
                let listed = times.len().min(self.first_frame + frames);
                if let Err(e) = self.series(world, &times[..listed]) {
                    notes.push_str(&format!("; the frames' series file was not written ({e})"));
                }
            }
            Some(OutputFormat::Gltf) => {
                if let Err(e) = self.write_animation() {
                    kept_frames = 0;
                    notes.push_str(&format!("; the animation was not written ({e})"));
                }
            }
            _ => {}
        }
        let checkpoint = self.checkpoint_sentence();
        let (out, format, options) = (self.out.clone(), self.format, self.options);
        let kept = match self.diagnostics.keep() {
            Ok(rows) => place(&out, format, rows, kept_frames),
            Err(e) => format!("no rows: {} could not be finished ({e})", csv.display()),
        };
        let state = match (&options.save_state, checkpoint.is_empty()) {
            (Some(_), true) => "; no state was saved".to_string(),
            _ => checkpoint,
        };
        CliError::Io(format!("{error}; kept: {kept}{notes}{state}"))
    }

    /// The glTF animation, written whole, where the run records one.
    fn write_animation(&self) -> Result<(), CliError> {
        match &self.animation {
            Some(animation) => {
                let path = self.out.join(ANIMATION);
                animation.write(&path).map_err(|e| io(&path, e))
            }
            None => Ok(()),
        }
    }

    /// "; the last checkpoint (step N) is in FILE", where this run saved one.
    fn checkpoint_sentence(&self) -> String {
        match (&self.options.save_state, self.last_checkpoint) {
            (Some(path), Some(step)) => {
                format!(
                    "; the last checkpoint (step {step}) is in {}",
                    path.display()
                )
            }
            _ => String::new(),
        }
    }

    /// The frames' time-series file listing frames at `times` (s), for
    /// frame formats that have one.
    fn series(&self, world: &World, times: &[f64]) -> Result<(), CliError> {
        match self.format {
            Some(OutputFormat::Frames(format)) => {
                export::write_series(&self.frames_dir, format, world, times)
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

/// Where `rows` rows and `frames` frames of a run in `out` recording
/// `format` are: "120 rows in out/diagnostics.csv, 120 frames in
/// out/frames".
fn place(out: &Path, format: Option<OutputFormat>, rows: usize, frames: usize) -> String {
    let mut place = format!("{rows} rows in {}", out.join("diagnostics.csv").display());
    match format {
        Some(OutputFormat::Frames(_)) if frames > 0 => place.push_str(&format!(
            ", {frames} frames in {}",
            out.join("frames").display()
        )),
        Some(OutputFormat::Gltf) if frames > 0 => place.push_str(&format!(
            ", an animation of {frames} frames in {}",
            out.join(ANIMATION).display()
        )),
        _ => {}
    }
    place
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

/// The format the run in `out` recorded its frames in, from its files:
/// its first frame (frame 0 goes with the first row) or its animation.
fn started_format(out: &Path) -> Option<OutputFormat> {
    if out.join(ANIMATION).is_file() {
        return Some(OutputFormat::Gltf);
    }
    let frames = out.join("frames");
    export::FrameFormat::ALL
        .into_iter()
        .find(|&f| export::frame_path(&frames, 0, f).is_file())
        .map(OutputFormat::Frames)
}

/// `--format`, as a user gives it.
fn format_flag(format: Option<OutputFormat>) -> String {
    match format {
        None => "no --format".into(),
        Some(OutputFormat::Gltf) => "--format gltf".into(),
        Some(OutputFormat::Frames(f)) => format!("--format {}", f.extension()),
    }
}

/// Refuse a resume into `out` with a `format` other than the one the run
/// was started with: its frames (or their absence) must go on as they
/// began, frame n with row n; a glTF animation cannot be added to.
fn check_resumed_format(out: &Path, format: Option<OutputFormat>) -> Result<(), CliError> {
    let started = started_format(out);
    if started == Some(OutputFormat::Gltf) {
        return Err(CliError::Input(format!(
            "--resume: the run in {} was recorded as glTF, the whole run in one {ANIMATION}, which a resumed run cannot add to: run it again from the start, with --format vtu, vtk or obj to resume it later",
            out.display()
        )));
    }
    if started != format {
        return Err(CliError::Input(format!(
            "--resume with {}: the run in {} was started with {} (resume with that, so that its frames go on with its rows{})",
            format_flag(format),
            out.display(),
            format_flag(started),
            if format == Some(OutputFormat::Gltf) {
                "; a glTF animation cannot be resumed anyway"
            } else {
                ""
            }
        )));
    }
    Ok(())
}

/// Create the output folder, and clear it of the frames from `first_frame`
/// on of every format and, for a run from the start, of the series files
/// and the glTF animation: what an earlier run left there would mix with
/// this run's outputs or contradict them. A resumed run (started in its
/// own format, `check_resumed_format`) keeps its frames before
/// `first_frame` and its series file, which it writes again.
fn prepare_output(out: &Path, frames: &Path, first_frame: usize) -> Result<(), CliError> {
    let fail = |e: std::io::Error, dir: &Path| {
        CliError::Io(format!("cannot create {}: {e}", dir.display()))
    };
    if out.exists() && !out.is_dir() {
        let what = match out.is_file() {
            true => "a file",
            false => "a device, FIFO or socket",
        };
        return Err(CliError::Io(format!(
            "--out {}: is {what}, not a folder; give a folder for the outputs",
            out.display()
        )));
    }
    std::fs::create_dir_all(out).map_err(|e| fail(e, out))?;
    let remove = |path: &Path| match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(CliError::Io(format!(
            "cannot remove {} (left by an earlier run): {e}",
            path.display()
        ))),
        _ => Ok(()),
    };
    if !frames.is_dir() && first_frame > 0 {
        return Ok(());
    }
    if first_frame == 0 {
        remove(&out.join(ANIMATION))?;
        for format in export::FrameFormat::ALL {
            if let Some(series) = export::series_path(frames, format) {
                remove(&series)?;
            }
        }
    }
    if !frames.is_dir() {
        return Ok(());
    }
    let stale = std::fs::read_dir(frames).map_err(|e| fail(e, frames))?;
    for entry in stale.flatten() {
        let name = entry.file_name();
        let name = name.to_string_lossy();
        let index = name
            .strip_prefix("frame_")
            .map(|rest| rest.split('.').next().unwrap_or_default().parse::<usize>());
        // Kept: frames of a resumed run's earlier part.
        if index.is_some_and(|n| n.map_or(true, |n| n >= first_frame)) {
            remove(&entry.path())?;
        }
    }
    Ok(())
}
