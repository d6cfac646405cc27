//! `sprung run`: step a scene, record diagnostics and frames, stop at once
//! on a blow-up with the rows recorded so far (all finite).

use std::fmt;
use std::path::Path;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use sprung::error::{Readable, Seconds};
use sprung::integrate::Preconditioner;
use sprung::integrate::StepReport;
use sprung::{IntegratorKind, StepError, World};
use sprung_gpu::GpuError;
use sprung_io::{Scene, SceneError};

use crate::checkpoint;
use crate::interrupt::{self, Signal};
use crate::on_gpu;
use crate::outputs::Outputs;
use crate::scene_file::{SceneCopy, SceneInput};
use crate::RunOptions;

/// Why a command failed.
#[derive(Debug)]
pub enum CliError {
    /// A scene or an option that cannot be used (nothing was run).
    Input(String),
    /// The scene file's own error.
    Scene(SceneError),
    /// A file that could not be written.
    Io(String),
    /// A program we started (the viewer) failed with this exit status;
    /// `sprung` exits with the same status.
    Child(i32, String),
    /// The simulation blew up; what was recorded up to it was kept: the
    /// second field is the sentence that says what and where.
    BlowUp(StepError, String),
    /// SIGINT or SIGTERM stopped the run at the end of a step; what was
    /// recorded was kept: the sentence says where.
    Interrupted(Signal, String),
}

impl CliError {
    /// The process exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            CliError::BlowUp(..) => 3,
            CliError::Interrupted(signal, _) => signal.exit_code(),
            CliError::Child(code, _) => u8::try_from(*code).unwrap_or(1),
            _ => 1,
        }
    }
}

impl fmt::Display for CliError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CliError::Input(m) | CliError::Io(m) | CliError::Child(_, m) => f.write_str(m),
            CliError::Scene(e) => write!(f, "{e}"),
            CliError::BlowUp(e, kept) => write!(f, "{e}\n({kept})"),
            CliError::Interrupted(signal, m) => write!(f, "{}: {m}", signal.name()),
        }
    }
}

impl From<SceneError> for CliError {
    fn from(e: SceneError) -> Self {
        CliError::Scene(e)
    }
}

/// A stop while recording: a blow-up (a non-finite number a row would
/// hold), whose outputs so far are finished; or a write that failed, whose
/// outputs are kept as far as they were written. Either way the error says
/// where they are.
fn kept(stop: CliError, outputs: Outputs, world: &World) -> CliError {
    match stop {
        CliError::BlowUp(error, _) => match outputs.finish(world, 0, false) {
            Ok(place) => CliError::BlowUp(error, format!("kept up to the last good step: {place}")),
            Err(other) => other,
        },
        other => outputs.keep(other, world),
    }
}

/// `sprung run SCENE`: read the file (standard input for `-`, its
/// relative paths from `base_dir`), apply the `--set` overrides, then
/// [`run_scene`], which keeps the effective scene in the run's folder.
pub fn run_file(
    path: &Path,
    base_dir: Option<&Path>,
    options: &RunOptions,
) -> Result<(), CliError> {
    let input = SceneInput::read(path, base_dir)?;
    let scene = input.load(&options.set)?;
    let copy = input.copy(&options.set)?;
    let out = options.out.clone().unwrap_or_else(|| input.default_out());
    run_scene(scene, &out, options, Some(&copy))
}

/// Run `scene` with `options`, writing into `out` (and `copy`, the scene
/// it was built from, once the folder is ready).
pub fn run_scene(
    mut scene: Scene,
    out: &Path,
    options: &RunOptions,
    copy: Option<&SceneCopy>,
) -> Result<(), CliError> {
    if let Some(kind) = options.integrator {
        scene.world.set_integrator(kind);
    }
    let steps = planned_steps(&scene, options.steps, options.time)?;
    let every = scene.record_every(options.every);
    if every == 0 {
        return Err(CliError::Input("--every must be at least 1".into()));
    }
    if let Some((i, &p)) = options
        .probe
        .iter()
        .enumerate()
        .find(|&(i, p)| options.probe[..i].contains(p))
    {
        return Err(CliError::Input(format!(
            "--probe: particle {p} is named twice (entry {i}); each probe gives its own columns"
        )));
    }
    let particles = scene.world.particles.len();
    if let Some(&bad) = options.probe.iter().find(|&&p| p >= particles) {
        return Err(CliError::Input(format!(
            "--probe {bad}: no such particle (the scene has {particles}, numbered 0 to {})",
            particles.saturating_sub(1)
        )));
    }
    let resumed = match &options.resume {
        Some(path) => {
            let resumed = checkpoint::resume(path, &mut scene, every)?;
            if scene.world.steps() >= steps {
                return Err(CliError::Input(format!(
                    "{}: the state is at step {}, and this run ends at step {steps} (give a larger --steps or --time)",
                    path.display(),
                    scene.world.steps()
                )));
            }
            Some(resumed)
        }
        None => None,
    };
    // A contact thickness far beyond the particles' spacing is refused
    // before anything is written (later steps are guarded by the engine).
    scene
        .world
        .contact_pairs_now(scene.dt)
        .map_err(|e| CliError::Input(e.to_string()))?;
    // Refused here, before anything is written, where the GPU step lacks
    // what the scene asks.
    let mut gpu = on_gpu::start(&scene, options)?;
    if resumed.is_none() {
        let at_start = crate::check::start_warnings(&scene.world);
        for warning in scene.warnings.iter().chain(&at_start) {
            eprintln!("warning: {warning}");
        }
    }
    // Rows this run will record, at most (for the animation's budget).
    let records = (steps - scene.world.steps()) / every + 2;
    // What the run reads, which no output may be written over.
    let inputs: Vec<&Path> = [scene.path.as_path()]
        .into_iter()
        .filter(|path| path.is_file())
        .chain(copy.into_iter().flat_map(SceneCopy::mesh_sources))
        .chain(options.resume.as_deref())
        .collect();
    if let Some(copy) = copy {
        copy.check(out, &inputs)?;
    }
    let mut outputs = Outputs::open(
        out,
        &scene.world,
        (scene.dt, every),
        options,
        (resumed, &inputs),
        records,
    )?;
    if let Some(copy) = copy {
        copy.write(out)?;
    }
    if resumed.is_none() {
        if let Err(stop) = outputs.record(&scene.world) {
            return Err(kept(stop, outputs, &scene.world));
        }
    }
    interrupt::install();
    scene.world.set_profiling(options.profile);
    let progress = progress_bar(steps, options.quiet);
    progress.set_position(scene.world.steps());
    let first_step = scene.world.steps() + 1;
    // The preconditioner implicit Euler's last solve took.
    let mut chosen = None;
    let mut next = first_step;
    while next <= steps {
        if let Some(signal) = interrupt::received() {
            progress.abandon();
            let rows = outputs.rows();
            let place = outputs.finish(&scene.world, rows, options.save_state.is_some())?;
            let message = format!(
                "stopped after step {} (t = {} s): {place}",
                next - 1,
                Seconds(scene.world.time()),
            );
            return Err(CliError::Interrupted(signal, message));
        }
        // One step on the CPU; on the GPU, the steps up to the next row (or
        // a quarter of a second's worth).
        let step = match &gpu {
            Some(gpu) => gpu.stretch_end(next, steps, every),
            None => next,
        };
        next = step + 1;
        let stepped = match &mut gpu {
            Some(gpu) => match gpu.advance(&mut scene.world, step) {
                Ok(()) => Ok(StepReport::default()),
                Err(GpuError::Step(error)) => Err(error),
                Err(other) => {
                    progress.abandon();
                    let place = outputs.finish(&scene.world, 0, false)?;
                    let error = on_gpu::failed(&other);
                    return Err(CliError::Input(format!("{error} (kept: {place})")));
                }
            },
            None => scene.world.step(scene.dt),
        };
        let report = match stepped {
            Ok(report) => report,
            Err(error) => {
                progress.abandon();
                // The blown-up state is not saved: the last checkpoint stays.
                let place = outputs.finish(&scene.world, 0, false)?;
                let kept = format!("kept up to the last good step: {place}");
                return Err(CliError::BlowUp(error, kept));
            }
        };
        // Auto's change to the factor is news, but not where a resumed
        // run had it before it stopped.
        let auto = scene.world.settings.solver.preconditioner == Preconditioner::Auto;
        if auto
            && !options.quiet
            && report.preconditioner == Some(Preconditioner::Stiffness)
            && chosen != report.preconditioner
            && (chosen.is_some() || resumed.is_none())
        {
            progress.suspend(|| eprintln!("note: {}", factored_note(&scene)));
        }
        chosen = report.preconditioner.or(chosen);
        if report.unconverged && scene.world.solver_stats().unconverged_steps == 1 {
            progress.suspend(|| eprintln!("warning: {}", unconverged_warning(&scene, chosen)));
        } else if scene.world.constraint_stats().unconverged_steps == 1
            && scene
                .world
                .constraint_stats()
                .first_unconverged
                .map(|f| f.0)
                == Some(scene.world.steps())
        {
            progress.suspend(|| eprintln!("warning: {}", rods_warning(&scene)));
        }
        if step % every == 0 || step == steps {
            if let Err(stop) = outputs.record(&scene.world) {
                progress.abandon();
                return Err(kept(stop, outputs, &scene.world));
            }
        }
        if options.checkpoint_every.is_some_and(|k| step % k == 0) && step != steps {
            if let Err(stop) = outputs.checkpoint(&scene.world) {
                progress.abandon();
                return Err(outputs.keep(stop, &scene.world));
            }
        }
        if step % 256 == 0 || gpu.is_some() {
            progress.set_position(step);
        }
    }
    progress.finish_and_clear();
    // The last row, recorded because the run ended there, is not one of
    // the every-K rows a longer run has: a run resumed from here drops it.
    let rows = outputs.rows();
    let state_rows = rows - usize::from(steps % every != 0);
    let place = outputs.finish(&scene.world, state_rows, options.save_state.is_some())?;
    let rods_off = scene.world.constraint_stats().unconverged_steps;
    if rods_off > 0 {
        eprintln!(
            "warning: the rods stayed off their lengths beyond constraint_tolerance after constraint_iterations sweeps in {rods_off} of {steps} steps"
        );
    }
    let unconverged = scene.world.solver_stats().unconverged_steps;
    if unconverged > 0 {
        eprintln!(
            "warning: the {} stopped above its tolerance in {unconverged} of {steps} steps",
            solver_named(&scene.world, chosen)
        );
    }
    if options.profile {
        println!("{}", scene.world.profile());
        println!(
            "heap peak: {:.1} MB (the most the process held at once)",
            crate::bench::memory::peak() as f64 / 1e6
        );
    }
    if !options.quiet {
        println!(
            "{}: {} of {} s ({} s simulated, {}): {place}",
            scene.path.display(),
            match resumed {
                Some(_) => format!("steps {first_step} to {steps}"),
                None => format!("{steps} steps"),
            },
            Readable(scene.dt),
            Seconds(scene.world.time()),
            scene.world.integrator(),
        );
    }
    Ok(())
}

/// The warning for the first step whose rods stayed off their lengths.
fn rods_warning(scene: &Scene) -> String {
    let settings = scene.world.settings.constraints;
    let (step, error) = scene
        .world
        .constraint_stats()
        .first_unconverged
        .unwrap_or((scene.world.steps(), f64::NAN));
    format!(
        "step {step} (t = {} s): after constraint_iterations = {} sweeps a rod is still off its length by {error:.3e} (relative), above constraint_tolerance = {:.1e}; rods between very unequal masses converge slowly (raise `constraint_iterations`, lower `dt`, or even out the masses), and rods whose lengths cannot all hold at once (rods between pinned particles or rigid bodies, which the check of the lengths at load does not cover) never converge: check the lengths (warned once, counted at the end)",
        Seconds(scene.world.time()),
        settings.iterations,
        settings.tolerance
    )
}

/// The warning for the first step whose implicit solve stopped at its
/// iteration limit above its tolerance; `chosen` the preconditioner of
/// implicit Euler's last solve.
fn unconverged_warning(scene: &Scene, chosen: Option<Preconditioner>) -> String {
    let settings = scene.world.settings.solver;
    let (step, residual) = scene
        .world
        .solver_stats()
        .first_unconverged
        .unwrap_or((scene.world.steps(), f64::NAN));
    // Where the stiffness factor is in use it already takes the fewest
    // iterations: nothing to offer but the limits.
    let other = match chosen {
        Some(Preconditioner::Jacobi | Preconditioner::Laplacian) => {
            ", try `preconditioner = \"stiffness\"` (the springs' own matrix factored each step: a few iterations where stiff springs make hundreds)"
        }
        _ => "",
    };
    format!(
        "step {step} (t = {} s): the {} stopped after max_iterations = {} with a relative residual {residual:.3e}, above solver_tolerance = {:.1e}; the step was taken less accurately (raise `max_iterations` or `solver_tolerance` in [sim]{other}, or lower `dt`; warned once, counted at the end)",
        Seconds(scene.world.time()),
        solver_named(&scene.world, chosen),
        settings.max_iterations,
        settings.tolerance
    )
}

/// The note for the step at which the auto preconditioner took the
/// stiffness factor.
fn factored_note(scene: &Scene) -> String {
    format!(
        "step {} (t = {} s): implicit_euler's auto preconditioner took the springs' stiffness factor from here on: Jacobi needed more iterations than a step with the factor is estimated to cost (`preconditioner` in [sim] chooses one)",
        scene.world.steps(),
        Seconds(scene.world.time()),
    )
}

/// The implicit solver of `world`, with implicit Euler's preconditioner
/// (`chosen`, the one its last solve took, where auto chose):
/// "implicit_euler solver (jacobi preconditioner)", "implicit_euler solver
/// (auto preconditioner: stiffness)".
fn solver_named(world: &World, chosen: Option<Preconditioner>) -> String {
    let kind = world.integrator();
    if kind != IntegratorKind::ImplicitEuler {
        return format!("{kind} solver");
    }
    let asked = world.settings.solver.preconditioner;
    match chosen {
        Some(chosen) if asked == Preconditioner::Auto => {
            format!("{kind} solver (auto preconditioner: {})", chosen.name())
        }
        _ => format!("{kind} solver ({} preconditioner)", asked.name()),
    }
}

/// The number of steps to run `scene`: `steps`, or `time` (s) divided by
/// its time step, or the scene's own duration. Shared by `run` and `render`.
pub(crate) fn planned_steps(
    scene: &Scene,
    steps: Option<u64>,
    time: Option<f64>,
) -> Result<u64, CliError> {
    match (steps, time) {
        (Some(0), _) => Err(CliError::Input("--steps must be at least 1".into())),
        (Some(n), _) => Ok(n),
        (None, Some(t)) if !(t.is_finite() && t > 0.0) => Err(CliError::Input(format!(
            "--time {t}: must be a positive, finite time (s)"
        ))),
        (None, Some(t)) => scene.steps_in(t).ok_or_else(|| {
            CliError::Input(format!(
                "--time: {:.3e} steps is more than the {:.0e} a run may take",
                t / scene.dt,
                sprung_io::scene::MAX_STEPS as f64
            ))
        }),
        (None, None) => Ok(scene.steps),
    }
}

/// A progress bar with rate and time left on a terminal; hidden when stderr
/// is not a terminal or with `--quiet`.
fn progress_bar(steps: u64, quiet: bool) -> ProgressBar {
    if quiet {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::with_draw_target(Some(steps), ProgressDrawTarget::stderr());
    if let Ok(style) = ProgressStyle::with_template(
        "{bar:40.cyan/blue} {pos}/{len} steps  {rate}  {elapsed} elapsed, {eta} left",
    ) {
        let rate = |state: &ProgressState, out: &mut dyn fmt::Write| {
            let _ = write!(out, "{:.0} steps/s", state.per_sec());
        };
        bar.set_style(style.with_key("rate", rate));
    }
    bar.enable_steady_tick(Duration::from_millis(200));
    bar
}
