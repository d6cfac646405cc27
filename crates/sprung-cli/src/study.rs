//! `sprung study`: studies of the engine on a scene. `stability`: for
//! every integrator, the largest stable time step (bisection over trial
//! runs of a fixed simulated time) and the wall-clock cost per simulated
//! second at that step, as a table, `stability.csv` and `stability.png`.

mod energy;
mod output;
mod search;

use std::path::{Path, PathBuf};

use clap::{Args, Subcommand};
use sprung::forces::{MouseSpring, Wind};
use sprung::{IntegratorKind, Real, World};
use sprung_io::{parse_scene, SceneError};

use crate::error::CliError;
use energy::EnergyCheck;
use search::{Cost, Limit, Plan, MAX_TRIAL_WORK};

/// The longest default trial time (s): the scene's duration, at most this.
pub const DEFAULT_MAX_TIME: Real = 2.0;

/// The studies.
#[derive(Debug, Subcommand)]
pub enum StudyCommand {
    /// For every integrator: the largest stable dt and the wall-clock cost per simulated second at it (table, CSV, plot).
    Stability(StabilityArgs),
}

/// Arguments of `sprung study stability`.
#[derive(Debug, Args)]
#[command(after_help = "\
For each integrator, trial runs of --time simulated seconds (each from a fresh copy of the scene, \
the step count rounded up) decide whether a time step dt is stable: a run is unstable if it blows up \
(the engine's blow-up guard, or a failed implicit solve), or, in a scene without driving forces, if \
its total energy ever rises above its start by more than MARGIN × S, where S is the sum of the sizes \
of the energy terms at the start or, if larger, the largest change of the gravity and gas terms \
over the trial (their zero is arbitrary: a rope released along y = 0 starts with no energy at all). \
Driving forces (wind, the hand, a collider moving along a path, a \
gas whose nRT is scheduled: a ramp, keyframes or a leak) feed energy in, so there only blow-ups count; \
the output says whether the energy criterion applied.

The search starts at the scene's stable-step estimate (its dt where there is none), doubles dt while \
stable up to --time (one step for the whole run: such integrators are reported as stable at every \
step tried, ≥), or halves it while unstable down to 1e-8 s (none found), then bisects on log dt until \
the unstable step is less than 2 % above the stable one. A trial may take at most 1e8 particle-steps \
(steps × particles): a study whose first trial needs more is refused, a search that would need more \
stops there. The cost is the wall-clock time of whole runs at the step found (only the steps, no \
energy checks) per simulated second.

Writes DIR/stability.csv (integrator,largest_stable_dt,capped,stable_estimate,\
cost_per_simulated_second,steps_per_second,energy_criterion; s, s, true/false, s, s/s, 1/s, \
true/false; empty where there is no value) and DIR/stability.png (cost against largest stable dt, \
log-log), default DIR out/study/SCENE.
Example: sprung study stability scenes/oscillator.toml")]
pub struct StabilityArgs {
    /// The scene file (TOML).
    scene: PathBuf,
    /// Output folder (default: out/study/SCENE).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Simulated time of each trial run (s) [default: the scene's duration, at most 2 s].
    #[arg(long, allow_negative_numbers = true, value_parser = crate::values::positive)]
    time: Option<f64>,
    /// Allowed rise of the total energy, as a fraction of the sum of the sizes of the energy terms at the start.
    #[arg(long, default_value_t = 0.01, allow_negative_numbers = true, value_parser = crate::values::positive)]
    margin: f64,
    /// Study only these integrators (repeat the option or separate with commas) [default: all].
    #[arg(long, value_delimiter = ',')]
    integrator: Vec<IntegratorKind>,
    /// Print nothing but errors and warnings.
    #[arg(long)]
    quiet: bool,
}

/// Run a study.
pub fn run(command: &StudyCommand) -> Result<(), CliError> {
    match command {
        StudyCommand::Stability(args) => stability(args),
    }
}

/// What the study found for one integrator.
#[derive(Debug, Clone)]
pub struct Row {
    /// The integrator.
    pub kind: IntegratorKind,
    /// Its limit.
    pub limit: Limit,
    /// The cost at the largest stable step, where one was found and its
    /// timed run succeeded.
    pub cost: Option<Cost>,
}

/// The setting of a study, for its output.
#[derive(Debug, Clone)]
pub struct Setting {
    /// The scene file.
    pub path: PathBuf,
    /// Particles in the scene.
    pub particles: usize,
    /// Simulated time of each trial (s).
    pub time: Real,
    /// The scene's stable-step estimate (s; infinite when nothing is stiff).
    pub estimate: Real,
    /// The energy margin (a fraction).
    pub margin: Real,
    /// The sum of the sizes of the energy terms at the start (J).
    pub scale: Real,
    /// The scene's driving forces, in words (empty: none).
    pub driving: Vec<String>,
}

impl Setting {
    /// Whether the energy criterion applied: no driving forces.
    pub fn energy_criterion(&self) -> bool {
        self.driving.is_empty()
    }
}

fn stability(args: &StabilityArgs) -> Result<(), CliError> {
    let margin = args.margin;
    if !(margin.is_finite() && margin > 0.0) {
        return Err(CliError::Input(format!(
            "--margin {margin}: must be a positive, finite fraction (0.01 allows a rise of 1 % of the energy scale)"
        )));
    }
    if let Some(t) = args.time.filter(|t| !(t.is_finite() && *t > 0.0)) {
        return Err(CliError::Input(format!(
            "--time {t}: must be a positive, finite time (s)"
        )));
    }
    let text = std::fs::read_to_string(&args.scene).map_err(|e| {
        SceneError::new(
            &args.scene,
            None,
            format!("cannot read the scene file: {e}"),
        )
    })?;
    let scene = parse_scene(&text, &args.scene)?;
    let world = &scene.world;
    let time = args
        .time
        .unwrap_or((scene.steps as Real * scene.dt).min(DEFAULT_MAX_TIME));
    let estimate = world.stable_time_step();
    let energies = world.energies();
    let scale = energies
        .terms()
        .fold(energies.kinetic.abs(), |sum, (_, e)| sum + e.abs());
    let setting = Setting {
        path: args.scene.clone(),
        particles: world.particles.len(),
        time,
        estimate,
        margin,
        scale,
        driving: driving_forces(world),
    };
    let plan = Plan {
        text: &text,
        path: &args.scene,
        time,
        energy: setting.energy_criterion().then_some(EnergyCheck {
            margin,
            start_scale: scale,
        }),
        start: if estimate.is_finite() {
            estimate
        } else {
            scene.dt
        },
        particles: setting.particles,
        verbose: !args.quiet,
    };
    let first = plan.start.min(plan.cap());
    if plan.work(first) > MAX_TRIAL_WORK {
        return Err(CliError::Input(format!(
            "{}: the first trial (dt = {first:.3e} s, the {}) would take {} steps × {} particles = {:.2e} particle-steps, more than the {MAX_TRIAL_WORK:.0e} a trial may take: shorten --time (now {time} s)",
            args.scene.display(),
            if estimate.is_finite() { "scene's stable estimate" } else { "scene's dt" },
            plan.steps(first),
            setting.particles,
            plan.work(first)
        )));
    }
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().unwrap_or_default();
        Path::new("out").join("study").join(stem)
    });
    let mut kinds: Vec<IntegratorKind> = Vec::new();
    let chosen = if args.integrator.is_empty() {
        &IntegratorKind::ALL[..]
    } else {
        &args.integrator[..]
    };
    for &kind in chosen {
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    if !args.quiet {
        eprintln!("{}", output::describe(&setting));
    }
    let mut rows = Vec::new();
    for kind in kinds {
        let limit = search::search(&plan, kind)?;
        let cost = match limit.stable() {
            Some(dt) => search::cost(&plan, kind, dt)?,
            None => None,
        };
        rows.push(Row { kind, limit, cost });
    }
    output::write(&out, &setting, &rows)?;
    if !args.quiet {
        println!("{}", output::table(&setting, &rows));
        println!(
            "wrote {} and {}",
            out.join(output::CSV).display(),
            out.join(output::PNG).display()
        );
    }
    Ok(())
}

/// The forces of `world` that feed energy in, in words: wind, the hand,
/// colliders moving along a path, gases whose nRT is scheduled.
fn driving_forces(world: &World) -> Vec<String> {
    let mut found = Vec::new();
    if world.forces.get::<Wind>().is_some() {
        found.push("wind".to_string());
    }
    if world.forces.get::<MouseSpring>().is_some() {
        found.push("the hand (mouse spring)".to_string());
    }
    let moving = world.colliders.iter().filter(|c| c.path.is_some()).count();
    if moving > 0 {
        found.push(format!("{moving} collider(s) moving along a path"));
    }
    for body in &world.bodies {
        let Some(gas) = &body.gas else { continue };
        let mut schedule = Vec::new();
        if gas.ramp_time > 0.0 {
            schedule.push("a ramp");
        }
        if !gas.keyframes.is_empty() {
            schedule.push("keyframes");
        }
        if gas.leak_rate > 0.0 {
            schedule.push("a leak");
        }
        if !schedule.is_empty() {
            found.push(format!(
                "the gas of body \"{}\" ({})",
                body.name,
                schedule.join(", ")
            ));
        }
    }
    found
}
