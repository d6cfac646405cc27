//! The stages of a step, in the order [`crate::World::step`] runs them,
//! and the profile of where a run's time went among them.
//!
//! A world times its stages only when asked
//! ([`crate::World::set_profiling`]): off, each stage's timer is one
//! untaken branch. On, one clock reading closes each stage and opens the
//! next, so the stages' times add up to the step's, less only the
//! hand-over of a large world's step to the pool of threads and the checks
//! of `dt` and the settings before the first stage.
//!
//! ```
//! use sprung::{build, IntegratorKind, Stage, World};
//!
//! let mut world = World::new(IntegratorKind::Rk4);
//! world.add_body("rope", build::rope(20, 1.0).unwrap().with_stiffness(200.0)).unwrap();
//! world.set_profiling(true);
//! for _ in 0..100 {
//!     world.step(1e-3).unwrap();
//! }
//! let profile = world.profile();
//! assert_eq!(profile.steps(), 100);
//! assert_eq!(profile.calls(Stage::Integrate), 100);
//! assert_eq!(profile.calls(Stage::Forces), 400); // RK4: four evaluations a step
//! let shares: f64 = Stage::ALL.iter().map(|&s| profile.share(s)).sum();
//! assert!(shares <= 1.0 + 1e-9);
//! println!("{profile}");
//! ```

use std::cell::Cell;
use std::fmt;
use std::time::{Duration, Instant};

/// A stage of the step, in the order the step runs them. Stages from
/// [`Stage::Muscles`] to [`Stage::Ccd`] run once per substep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Stage {
    /// The candidate contact pairs between bodies (the broad and narrow
    /// phases), or the last ones kept while their margin covers the motion.
    Detect,
    /// The stable-step estimate that splits a step into substeps
    /// (`substeps = "auto"`); nothing otherwise.
    Substeps,
    /// The muscles' rest lengths at the start of the substep.
    Muscles,
    /// Every force of the list at each trial state the integrator asks for,
    /// and for the implicit solvers their linearisation and Jacobian
    /// products: timed inside the integrate stage, and left out of its time.
    Forces,
    /// The integrator's own work: its stages' arithmetic, the implicit
    /// solvers' linear algebra.
    Integrate,
    /// Projection colliders move particles back out.
    Collide,
    /// Impulses after the forces: Coulomb friction between bodies.
    Friction,
    /// Rods and rigid bodies put back on their lengths and shapes.
    Constrain,
    /// Springs past their limits yield or break; faces along broken
    /// springs open.
    Give,
    /// The CCD: continuous collision detection over the step's
    /// motion, impulses and impact zones, so that no crossing survives.
    Ccd,
    /// The step's statistics and the check for a blown-up state.
    Guard,
}

/// The number of stages.
const STAGES: usize = 11;

impl Stage {
    /// Every stage, in the order the step runs them.
    pub const ALL: [Stage; STAGES] = [
        Stage::Detect,
        Stage::Substeps,
        Stage::Muscles,
        Stage::Forces,
        Stage::Integrate,
        Stage::Collide,
        Stage::Friction,
        Stage::Constrain,
        Stage::Give,
        Stage::Ccd,
        Stage::Guard,
    ];

    /// The stage's name, as `sprung run --profile` prints it.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Detect => "detect",
            Stage::Substeps => "substeps",
            Stage::Muscles => "muscles",
            Stage::Forces => "forces",
            Stage::Integrate => "integrate",
            Stage::Collide => "collide",
            Stage::Friction => "friction",
            Stage::Constrain => "constrain",
            Stage::Give => "give",
            Stage::Ccd => "ccd",
            Stage::Guard => "guard",
        }
    }
}

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// Where a world's steps spent their time, stage by stage
/// ([`crate::World::profile`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Profile {
    time: [Duration; STAGES],
    calls: [u64; STAGES],
    steps: u64,
    wall: Duration,
}

impl Profile {
    /// The time spent in `stage` over the profiled steps.
    pub fn time(&self, stage: Stage) -> Duration {
        self.time[stage as usize]
    }

    /// How often `stage` ran: once a step for detect, substeps and guard,
    /// once a substep for the others, once an evaluation for the forces.
    pub fn calls(&self, stage: Stage) -> u64 {
        self.calls[stage as usize]
    }

    /// The share of the steps' wall time spent in `stage` (0 to 1; 0 when
    /// nothing was timed).
    pub fn share(&self, stage: Stage) -> f64 {
        let wall = self.wall.as_secs_f64();
        if wall > 0.0 {
            self.time(stage).as_secs_f64() / wall
        } else {
            0.0
        }
    }

    /// The steps profiled.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The wall time of the profiled steps, from the call of
    /// [`crate::World::step`] to its return.
    pub fn wall(&self) -> Duration {
        self.wall
    }

    /// The sum of the stages' times: the wall time less the hand-over to
    /// the threads and the checks before the first stage.
    pub fn staged(&self) -> Duration {
        self.time.iter().sum()
    }
}

/// A table: each stage's time, share of the wall time and calls, then the
/// steps and their wall time.
impl fmt::Display for Profile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{:<10} {:>12} {:>7} {:>10}",
            "stage", "time (s)", "share", "calls"
        )?;
        for stage in Stage::ALL {
            writeln!(
                f,
                "{:<10} {:>12.6} {:>6.1}% {:>10}",
                stage.name(),
                self.time(stage).as_secs_f64(),
                100.0 * self.share(stage),
                self.calls(stage)
            )?;
        }
        let wall = self.wall.as_secs_f64();
        let staged = self.staged().as_secs_f64();
        writeln!(
            f,
            "{:<10} {:>12.6} {:>6.1}%",
            "stages",
            staged,
            100.0 * staged / wall.max(f64::MIN_POSITIVE)
        )?;
        let per_step = wall / (self.steps.max(1) as f64);
        write!(
            f,
            "{:<10} {:>12.6} {:>6.1}% {:>10} ({per_step:.3e} s a step)",
            "steps",
            wall,
            100.0 * f64::from(u8::from(wall > 0.0)),
            self.steps,
        )
    }
}

/// The clock a world's step times its stages by. Its methods take `&self`
/// (cells), so the derivative function can time the forces from inside the
/// integrator.
#[derive(Debug, Default)]
pub(crate) struct Timer {
    /// Whether to time at all.
    on: bool,
    /// When the open stage began, while a step runs.
    mark: Cell<Option<Instant>>,
    /// When the running step began.
    step_start: Cell<Option<Instant>>,
    profile: Cell<Profile>,
}

impl Timer {
    /// Time the stages from now on, or stop.
    pub fn set(&mut self, on: bool) {
        self.on = on;
    }

    /// Whether the stages are timed.
    pub fn is_on(&self) -> bool {
        self.on
    }

    /// The profile so far.
    pub fn profile(&self) -> Profile {
        self.profile.get()
    }

    /// Forget the profile so far.
    pub fn reset(&self) {
        self.profile.set(Profile::default());
    }

    /// A step begins (at the call of `World::step`).
    #[inline]
    pub fn begin_step(&self) {
        if self.on {
            self.step_start.set(Some(Instant::now()));
        }
    }

    /// The first stage opens.
    #[inline]
    pub fn open(&self) {
        if self.on {
            self.mark.set(Some(Instant::now()));
        }
    }

    /// The open stage is `stage`, and it ends now: its time since the last
    /// mark, and one call.
    #[inline]
    pub fn lap(&self, stage: Stage) {
        self.record(stage, 1);
    }

    /// The time since the last mark was `stage`'s, which goes on later
    /// (no call counted): the integrate stage, before it asks for forces.
    #[inline]
    pub fn split(&self, stage: Stage) {
        self.record(stage, 0);
    }

    #[inline]
    fn record(&self, stage: Stage, calls: u64) {
        if !self.on {
            return;
        }
        if let Some(mark) = self.mark.get() {
            let now = Instant::now();
            let mut profile = self.profile.get();
            profile.time[stage as usize] += now - mark;
            profile.calls[stage as usize] += calls;
            self.profile.set(profile);
            self.mark.set(Some(now));
        }
    }

    /// The step ended (or failed): count it and its wall time; the stages'
    /// clock stops until the next step.
    #[inline]
    pub fn end_step(&self) {
        self.mark.set(None);
        if let Some(start) = self.step_start.take() {
            let mut profile = self.profile.get();
            profile.steps += 1;
            profile.wall += start.elapsed();
            self.profile.set(profile);
        }
    }
}
