//! `sprung run`: step a scene, record diagnostics and frames, stop at once
//! on a blow-up with the rows recorded so far (all finite).

use std::path::Path;

use sprung::error::{Readable, Seconds};
use sprung::integrate::{Preconditioner, StepReport};
use sprung::World;
use sprung_gpu::GpuError;
use sprung_io::Scene;

use crate::checkpoint::{self, Resumed};
use crate::error::CliError;
use crate::interrupt;
use crate::on_gpu;
use crate::outputs::Outputs;
use crate::scene_file::{SceneCopy, SceneInput};
use crate::RunOptions;

mod notes;

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
/// it was built from, once the folder is ready): the run checked, its
/// outputs opened, every step taken and recorded, the end reported.
pub fn run_scene(
    mut scene: Scene,
    out: &Path,
    options: &RunOptions,
    copy: Option<&SceneCopy>,
) -> Result<(), CliError> {
    let plan = Plan::check(&mut scene, options)?;
    // Refused here, before anything is written, where the GPU step lacks
    // what the scene asks.
    let mut gpu = on_gpu::start(&scene, options)?;
    if plan.resumed.is_none() {
        let at_start = crate::check::start_warnings(&scene.world);
        for warning in scene.warnings.iter().chain(&at_start) {
            eprintln!("warning: {warning}");
        }
    }
    let outputs = open_outputs(&scene, out, options, copy, &plan)?;
    let (outputs, chosen) = step_to_end(&mut scene, &mut gpu, outputs, &plan, options)?;
    report_end(&scene, outputs, &plan, chosen, options)
}

/// What a run was asked, checked before anything is written.
struct Plan {
    /// The step the run ends at.
    steps: u64,
    /// A row is recorded every this many steps.
    every: u64,
    /// Where a resumed run starts, or `None` for a run from step 0.
    resumed: Option<Resumed>,
    /// The first step this run takes.
    first_step: u64,
}

impl Plan {
    /// Check `options` against `scene` (setting its integrator and, for
    /// `--resume`, its state): the steps, `--every`, the probes, the state
    /// to resume and the contact pairs at the start.
    fn check(scene: &mut Scene, options: &RunOptions) -> Result<Plan, CliError> {
        if let Some(kind) = options.integrator {
            scene.world.set_integrator(kind);
        }
        let steps = planned_steps(scene, options.steps, options.time)?;
        let every = scene.record_every(options.every);
        if every == 0 {
            return Err(CliError::Input("--every must be at least 1".into()));
        }
        check_probes(&options.probe, scene.world.particles.len())?;
        let resumed = match &options.resume {
            Some(path) => {
                let resumed = checkpoint::resume(path, scene, every)?;
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
        Ok(Plan {
            steps,
            every,
            resumed,
            first_step: scene.world.steps() + 1,
        })
    }
}

/// Refuse a probe named twice or one past the `particles` the scene has.
fn check_probes(probes: &[usize], particles: usize) -> Result<(), CliError> {
    if let Some((i, &p)) = probes
        .iter()
        .enumerate()
        .find(|&(i, p)| probes[..i].contains(p))
    {
        return Err(CliError::Input(format!(
            "--probe: particle {p} is named twice (entry {i}); each probe gives its own columns"
        )));
    }
    if let Some(&bad) = probes.iter().find(|&&p| p >= particles) {
        return Err(CliError::Input(format!(
            "--probe {bad}: no such particle (the scene has {particles}, numbered 0 to {})",
            particles.saturating_sub(1)
        )));
    }
    Ok(())
}

/// Open the run's outputs in `out` (refusing any that would be written
/// over what the run reads), write the scene's `copy` there, and record
/// the first row of a run from step 0.
fn open_outputs<'a>(
    scene: &Scene,
    out: &Path,
    options: &'a RunOptions,
    copy: Option<&SceneCopy>,
    plan: &Plan,
) -> Result<Outputs<'a>, CliError> {
    // Rows this run will record, at most (for the animation's budget).
    let records = (plan.steps - scene.world.steps()) / plan.every + 2;
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
        (scene.dt, plan.every),
        options,
        (plan.resumed, &inputs),
        records,
    )?;
    if let Some(copy) = copy {
        copy.write(out)?;
    }
    if plan.resumed.is_none() {
        if let Err(stop) = outputs.record(&scene.world) {
            return Err(kept(stop, outputs, &scene.world));
        }
    }
    Ok(outputs)
}

/// Take every step from the plan's first to its last, on the CPU or on
/// `gpu`, recording every `every` steps and checkpointing where asked;
/// stop at once, keeping what was written, on a blow-up, a failed write
/// or SIGINT/SIGTERM. Returns the outputs, to be finished, and the
/// preconditioner implicit Euler's last solve took.
fn step_to_end<'a>(
    scene: &mut Scene,
    gpu: &mut Option<on_gpu::OnGpu>,
    mut outputs: Outputs<'a>,
    plan: &Plan,
    options: &RunOptions,
) -> Result<(Outputs<'a>, Option<Preconditioner>), CliError> {
    let (steps, every) = (plan.steps, plan.every);
    interrupt::install();
    scene.world.set_profiling(options.profile);
    let progress = notes::progress_bar(steps, options.quiet);
    progress.set_position(scene.world.steps());
    // The preconditioner implicit Euler's last solve took.
    let mut chosen = None;
    let mut next = plan.first_step;
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
        let step = match gpu {
            Some(gpu) => gpu.stretch_end(next, steps, every),
            None => next,
        };
        next = step + 1;
        let stepped = match gpu {
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
        notes::after_step(
            scene,
            &report,
            &mut chosen,
            plan.resumed.is_some(),
            options.quiet,
            &progress,
        );
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
    Ok((outputs, chosen))
}

/// Finish the outputs of a run that reached its last step, and tell what
/// it did: the steps whose solve or rods stayed off their tolerance, the
/// profile where asked, where the outputs are.
fn report_end(
    scene: &Scene,
    outputs: Outputs,
    plan: &Plan,
    chosen: Option<Preconditioner>,
    options: &RunOptions,
) -> Result<(), CliError> {
    let (steps, every) = (plan.steps, plan.every);
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
            notes::solver_named(&scene.world, chosen)
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
            match plan.resumed {
                Some(_) => format!("steps {} to {steps}", plan.first_step),
                None => format!("{steps} steps"),
            },
            Readable(scene.dt),
            Seconds(scene.world.time()),
            scene.world.integrator(),
        );
    }
    Ok(())
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
