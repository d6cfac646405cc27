//! What a run writes, in one place: `diagnostics.csv`, the frames with
//! their series file or the glTF animation, and the saved state; each
//! written completely or not at all, however the run ends (finished,
//! interrupted, blown up), and at checkpoints.

use std::path::{Path, PathBuf};

use sprung::World;
use sprung_io::export::{self, Animation, Diagnostics, NotFiniteValue, OutputFormat};

use crate::checkpoint::{self, Resumed};
use crate::run::CliError;
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
    /// States saved at checkpoints.
    checkpoints: usize,
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
            checkpoints: 0,
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
            let path = self.out.join(ANIMATION);
            animation.write(&path).map_err(|e| io(&path, e))?;
        }
        let rows = self.diagnostics.rows();
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
                self.out.join(ANIMATION).display()
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
        let (options, dt, every) = (self.options, self.dt, self.every);
        self.diagnostics.finish().map_err(|e| io(&self.out, e))?;
        // Last, so that a state that cannot be written loses none of the
        // results above.
        if let (true, Some(path)) = (save, &options.save_state) {
            checkpoint::save(path, world, state_rows, dt, every).map_err(|e| match e {
                CliError::Io(why) => {
                    CliError::Io(format!("{why} (the run's results are kept: {place})"))
                }
                other => other,
            })?;
        }
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
    let own = DIAGNOSTICS_TABLES.iter().chain(&[ANIMATION]);
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

/// Refuse a run whose outputs (`--save-state`, or a table, animation or
/// frame in `out`) would be written over one of the files it reads,
/// `inputs` (the scene, its meshes, the state it resumes from).
fn check_inputs_kept(inputs: &[&Path], out: &Path, state: Option<&Path>) -> Result<(), CliError> {
    let out_resolved = resolved(out);
    let frames = out_resolved.join("frames");
    let state_resolved = state.map(resolved);
    for input in inputs {
        let input_resolved = resolved(input);
        let over = if state_resolved.as_ref() == Some(&input_resolved) {
            Some(format!("--save-state {}", state.unwrap_or(input).display()))
        } else if DIAGNOSTICS_TABLES
            .iter()
            .chain(&[ANIMATION])
            .any(|name| input_resolved == out_resolved.join(name))
            || (input_resolved.starts_with(&frames)
                && input_resolved
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("frame_")))
        {
            Some(format!("the run's outputs in --out {}", out.display()))
        } else {
            None
        };
        if let Some(output) = over {
            return Err(CliError::Input(format!(
                "{output} would be written over {}, which this run reads: give another path (nothing was written)",
                input.display()
            )));
        }
    }
    Ok(())
}

/// The folder a `--save-state` file goes in.
fn state_folder(state: &Path) -> &Path {
    match state.parent() {
        Some(folder) if !folder.as_os_str().is_empty() => folder,
        _ => Path::new("."),
    }
}

/// Refuse a `--save-state` file whose folder does not take a new file,
/// by making (and removing) an empty one beside it: found before the
/// run, not after it.
fn check_writable(state: &Path) -> Result<(), CliError> {
    let folder = state_folder(state);
    let probe = folder.join(format!(".sprung-probe-{}", std::process::id()));
    let made = std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe);
    match made {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(CliError::Input(format!(
            "--save-state {}: cannot write a file in {}: {e} (nothing was run)",
            state.display(),
            folder.display()
        ))),
    }
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
        return Err(CliError::Io(format!(
            "--out {}: is a file, not a folder; give a folder for the outputs",
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
