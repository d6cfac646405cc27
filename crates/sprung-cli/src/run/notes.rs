//! What `sprung run` tells its user while and after it runs: the progress
//! bar, the warnings of a solve or a rod that stayed off its tolerance,
//! and the note of auto's change of preconditioner.

use std::fmt;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressState, ProgressStyle};
use sprung::error::Seconds;
use sprung::integrate::{Preconditioner, StepReport};
use sprung::{IntegratorKind, World};
use sprung_io::Scene;

/// Tell, once, what the step just taken (`report`) brings news of: auto's
/// change to the stiffness factor (not where a resumed run had it before
/// it stopped), the first solve or the first rods that stayed above their
/// tolerance. `chosen` is the preconditioner implicit Euler's last solve
/// took, updated here.
pub(super) fn after_step(
    scene: &Scene,
    report: &StepReport,
    chosen: &mut Option<Preconditioner>,
    resumed: bool,
    quiet: bool,
    progress: &ProgressBar,
) {
    let auto = scene.world.settings.solver.preconditioner == Preconditioner::Auto;
    if auto
        && !quiet
        && report.preconditioner == Some(Preconditioner::Stiffness)
        && *chosen != report.preconditioner
        && (chosen.is_some() || !resumed)
    {
        progress.suspend(|| eprintln!("note: {}", factored_note(scene)));
    }
    *chosen = report.preconditioner.or(*chosen);
    if report.unconverged && scene.world.solver_stats().unconverged_steps == 1 {
        progress.suspend(|| eprintln!("warning: {}", unconverged_warning(scene, *chosen)));
    } else if scene.world.constraint_stats().unconverged_steps == 1
        && scene
            .world
            .constraint_stats()
            .first_unconverged
            .map(|f| f.0)
            == Some(scene.world.steps())
    {
        progress.suspend(|| eprintln!("warning: {}", rods_warning(scene)));
    }
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
pub(super) fn solver_named(world: &World, chosen: Option<Preconditioner>) -> String {
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

/// A progress bar with rate and time left on a terminal; hidden when stderr
/// is not a terminal or with `--quiet`.
pub(super) fn progress_bar(steps: u64, quiet: bool) -> ProgressBar {
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
