//! The search of `sprung study stability`: trial runs of a fixed simulated
//! time from a fresh copy of the scene, a bracket found by doubling or
//! halving the time step, then bisection on log dt; and the timed run that
//! gives the cost at the step found.

use std::path::Path;
use std::time::{Duration, Instant};

use sprung::{IntegratorKind, Real, StepError, World};
use sprung_io::parse_scene;

use super::energy::{EnergyCheck, EnergyWatch};
use crate::error::CliError;

/// Bisection stops once the smallest unstable step tried is less than
/// this factor above the largest stable one.
pub const BRACKET: Real = 1.02;

/// The smallest time step tried (s): below it an integrator has no stable
/// step ("none found").
pub const FLOOR: Real = 1e-8;

/// The most work one trial run may take, in particle-steps (steps ×
/// particles): some 10 s of symplectic Euler on a cloth (about 10⁷
/// particle-steps per second on one thread). A study whose first
/// trial needs more is refused; a downward search that would need more
/// stops there ("none found").
pub const MAX_TRIAL_WORK: Real = 1e8;

/// The cost is timed over whole runs, repeated until they add up to at
/// least this much wall-clock time ...
const MIN_TIMED: Duration = Duration::from_millis(50);
/// ... or this many runs.
const MAX_TIMED_RUNS: u32 = 20;

/// What the trials run and how they are judged.
#[derive(Debug, Clone, Copy)]
pub struct Plan<'a> {
    /// The scene file's text; every trial builds a fresh world from it.
    pub text: &'a str,
    /// The scene file (named in errors, anchors its mesh paths).
    pub path: &'a Path,
    /// Simulated time of each trial run (s).
    pub time: Real,
    /// The energy criterion; `None` where it does not apply.
    pub energy: Option<EnergyCheck>,
    /// The first time step tried (s).
    pub start: Real,
    /// Particles in the scene (for [`MAX_TRIAL_WORK`]).
    pub particles: usize,
    /// Print each trial to stderr.
    pub verbose: bool,
}

impl Plan<'_> {
    /// Steps of a trial at `dt` (s): the trial time divided by `dt`,
    /// rounded up (a rounding error of 10⁻⁹ step does not add a step).
    pub fn steps(&self, dt: Real) -> u64 {
        (self.time / dt - 1e-9).ceil().max(1.0) as u64
    }

    /// Work of a trial at `dt` (s), in particle-steps.
    pub fn work(&self, dt: Real) -> Real {
        self.steps(dt) as Real * self.particles.max(1) as Real
    }

    /// The largest step tried (s): one step as long as the whole trial.
    pub fn cap(&self) -> Real {
        self.time
    }

    fn world(&self, kind: IntegratorKind) -> Result<World, CliError> {
        let mut world = parse_scene(self.text, self.path)?.world;
        world.set_integrator(kind);
        Ok(world)
    }
}

/// How a trial run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Verdict {
    /// Ran its whole time; the implicit solver stopped above its tolerance
    /// in this many steps.
    Stable {
        /// Steps whose implicit solve stopped above its tolerance.
        unconverged: u64,
    },
    /// Unstable, and why, in words ("blew up at step 12").
    Unstable(String),
}

/// What the search found for one integrator.
#[derive(Debug, Clone, PartialEq)]
pub enum Limit {
    /// A stable step and an unstable one less than [`BRACKET`] above it.
    Bracketed {
        /// The largest stable step found (s).
        stable: Real,
        /// The smallest unstable step tried (s).
        unstable: Real,
        /// Why the trial at `unstable` failed.
        why: String,
        /// Unconverged implicit solves in the trial at `stable`.
        unconverged: u64,
    },
    /// Stable at every step tried, up to [`Plan::cap`] (s).
    Capped {
        /// The cap (s).
        stable: Real,
        /// Unconverged implicit solves in the trial at the cap.
        unconverged: u64,
    },
    /// No stable step down to `smallest` (s), the last one tried.
    NoneFound {
        /// The smallest step tried (s).
        smallest: Real,
        /// Why the search stopped there.
        why: String,
    },
}

impl Limit {
    /// The largest stable step found (s), if any.
    pub fn stable(&self) -> Option<Real> {
        match self {
            Limit::Bracketed { stable, .. } | Limit::Capped { stable, .. } => Some(*stable),
            Limit::NoneFound { .. } => None,
        }
    }
}

/// Run `kind` over the plan's time at `dt` (s), checking the energy after
/// every step where the criterion applies. A blow-up ends the trial at
/// once, and so does a rise past the margin where the scale cannot grow.
pub fn trial(plan: &Plan, kind: IntegratorKind, dt: Real) -> Result<Verdict, CliError> {
    let mut world = plan.world(kind)?;
    let steps = plan.steps(dt);
    let mut energy = plan.energy.map(|check| EnergyWatch::new(check, &world));
    let mut verdict = Verdict::Stable { unconverged: 0 };
    for step in 1..=steps {
        match world.step(dt) {
            Ok(_) => {}
            Err(StepError::BlowUp { reason, .. }) => {
                verdict = Verdict::Unstable(format!("blew up at step {step}: {reason}"));
                break;
            }
            Err(StepError::RodOff {
                rod, body, error, ..
            }) => {
                verdict = Verdict::Unstable(format!(
                    "rod {rod} of {body} off its length by {error:.3e} (relative) at step {step}"
                ));
                break;
            }
            Err(StepError::Solver { source, .. }) => {
                verdict = Verdict::Unstable(format!("solver failed at step {step}: {source}"));
                break;
            }
            // Pairs searched with the step's motion: a large trial step,
            // or a run that speeds up, finds too many.
            Err(StepError::TooManyContacts { limit, .. }) => {
                verdict = Verdict::Unstable(format!(
                    "more than {limit} contact pairs at step {step} (the motion of a step widens the search)"
                ));
                break;
            }
            Err(e) => return Err(CliError::Input(format!("{}: {e}", plan.path.display()))),
        }
        if let Some(why) = energy.as_mut().and_then(|e| e.observe(&world, step)) {
            verdict = Verdict::Unstable(why);
            break;
        }
    }
    if let (Verdict::Stable { .. }, Some(why)) = (&verdict, energy.and_then(|e| e.verdict())) {
        verdict = Verdict::Unstable(why);
    }
    if let Verdict::Stable { unconverged } = &mut verdict {
        *unconverged = world.solver_stats().unconverged_steps;
    }
    if plan.verbose {
        let result = match &verdict {
            Verdict::Stable { .. } => "stable".to_string(),
            Verdict::Unstable(why) => format!("unstable ({why})"),
        };
        eprintln!(
            "  {:<16} dt = {dt:.4e} s × {steps} steps: {result}",
            kind.name()
        );
    }
    Ok(verdict)
}

/// Search the largest stable step of `kind`: from [`Plan::start`], double
/// up to the cap while stable, or halve down to [`FLOOR`] while unstable;
/// then bisect on log dt until the bracket is within [`BRACKET`]. Assumes
/// that stability does not come back above a step that failed.
pub fn search(plan: &Plan, kind: IntegratorKind) -> Result<Limit, CliError> {
    let cap = plan.cap();
    let mut dt = plan.start.min(cap);
    let (mut stable, mut unstable, mut why, mut unconverged) = match trial(plan, kind, dt)? {
        Verdict::Stable { unconverged } => {
            let mut found = (dt, unconverged);
            loop {
                if found.0 >= cap {
                    return Ok(Limit::Capped {
                        stable: cap,
                        unconverged: found.1,
                    });
                }
                dt = (2.0 * found.0).min(cap);
                match trial(plan, kind, dt)? {
                    Verdict::Stable { unconverged } => found = (dt, unconverged),
                    Verdict::Unstable(why) => break (found.0, dt, why, found.1),
                }
            }
        }
        Verdict::Unstable(mut why) => {
            let mut failed = dt;
            loop {
                dt = 0.5 * failed;
                if dt < FLOOR {
                    return Ok(Limit::NoneFound {
                        smallest: failed,
                        why: format!("unstable at every step tried down to {failed:.3e} s ({why}); the search stops below {FLOOR:.0e} s"),
                    });
                }
                if plan.work(dt) > MAX_TRIAL_WORK {
                    return Ok(Limit::NoneFound {
                        smallest: failed,
                        why: format!(
                            "unstable down to {failed:.3e} s ({why}); a trial at {dt:.3e} s would take {:.2e} particle-steps, more than the {MAX_TRIAL_WORK:.0e} allowed",
                            plan.work(dt)
                        ),
                    });
                }
                match trial(plan, kind, dt)? {
                    Verdict::Stable { unconverged } => break (dt, failed, why, unconverged),
                    Verdict::Unstable(reason) => (failed, why) = (dt, reason),
                }
            }
        }
    };
    while unstable / stable >= BRACKET {
        let middle = (stable * unstable).sqrt();
        match trial(plan, kind, middle)? {
            Verdict::Stable { unconverged: u } => (stable, unconverged) = (middle, u),
            Verdict::Unstable(reason) => (unstable, why) = (middle, reason),
        }
    }
    Ok(Limit::Bracketed {
        stable,
        unstable,
        why,
        unconverged,
    })
}

/// The wall-clock cost of `kind` at `dt`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Cost {
    /// Wall-clock seconds per simulated second (s/s).
    pub per_simulated_second: Real,
    /// Steps per wall-clock second (1/s).
    pub steps_per_second: Real,
}

/// Time runs of the plan's time at `dt` (s) with `kind`, only the steps
/// (no energy checks; building the world is not timed), repeated until
/// they add up to 50 ms or 20 runs; `None` if a timed run fails (the trial
/// at `dt` did not).
pub fn cost(plan: &Plan, kind: IntegratorKind, dt: Real) -> Result<Option<Cost>, CliError> {
    let steps = plan.steps(dt);
    let (mut timed, mut runs) = (Duration::ZERO, 0u32);
    while timed < MIN_TIMED && runs < MAX_TIMED_RUNS {
        let mut world = plan.world(kind)?;
        let start = Instant::now();
        for _ in 0..steps {
            if world.step(dt).is_err() {
                return Ok(None);
            }
        }
        timed += start.elapsed();
        runs += 1;
    }
    let seconds = timed.as_secs_f64().max(1e-9);
    let total_steps = steps as Real * Real::from(runs);
    Ok(Some(Cost {
        per_simulated_second: seconds / (total_steps * dt),
        steps_per_second: total_steps / seconds,
    }))
}
