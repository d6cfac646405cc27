//! The world: particles, springs, bodies, forces, colliders and the
//! integrator, and the step that moves them.
//!
//! [`World::step`] is a short walk over named stages: [`Stage`] lists
//! them, in their order, with what each does (ARCHITECTURE.md has a
//! section each: files, types, threads, refusals), and
//! [`World::set_profiling`] times each.
//!
//! [`Stage`]: crate::Stage

use crate::body::Body;
use crate::colliders::Collider;
use crate::constrain::{ConstraintSettings, Muscles, RigidBodies, RodReport, Rods};
use crate::contact::ccd::CcdReport;
use crate::contact::Contacts;
use crate::forces::BodyContacts;
use crate::forces::ColliderContacts;
use crate::forces::{AirDrag, ForceList, GasPressure, Gravity, SpringForce, StiffnessBounds};
use crate::integrate::{Integrator, IntegratorKind, SolverSettings, StepReport};
use crate::model::Model;
use crate::parallel;
use crate::particles::Particles;
use crate::springs::Springs;
use crate::stage::{Profile, Timer};
use crate::tearing::Join;
use crate::tearing::SpringLimits;
use crate::units::{Real, Vec3};

mod bodies;
mod ccd;
mod observe;
mod state;
mod step;
mod tearing;

/// The CCD's runaway measure, in body sizes: it lives with the CCD
/// (`sprung::contact::ccd::RUNAWAY_SIZES`), named here as before.
pub use crate::contact::ccd::RUNAWAY_SIZES;
/// The derivative function of the world's model and forces: it lives with
/// the integrators (`sprung::integrate::Dynamics`), named here as before.
pub use crate::integrate::Dynamics;
pub use observe::PLASTIC;

/// The approach speed (m/s) below which a rigid body's contact with a
/// collider rests instead of bouncing (engines use such a threshold:
/// Box2D's is 1 m/s); a drop from 0.5 mm lands this fast.
pub const RESTING_SPEED: Real = 0.1;

/// Most substeps [`Substeps::Auto`] splits a step into.
pub const MAX_SUBSTEPS: u32 = 1_000_000;

/// How many substeps each step of the world is split into.
///
/// With [`Substeps::Auto`], a step ten times the stable one is split into as
/// many substeps as keep each below 0.9 of it (`⌈10 / 0.9⌉ = 12`):
///
/// ```
/// use sprung::{build, IntegratorKind, Substeps, World};
///
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// let rope = build::rope(10, 1.0).unwrap().with_stiffness(1e4);
/// world.add_body("rope", rope).unwrap();
/// world.settings.substeps = Substeps::Auto;
/// let stable = world.stable_time_step();
/// let report = world.step(10.0 * stable).unwrap();
/// assert_eq!(report.substeps, Some(12));
/// assert!(report.step_size.unwrap() < stable);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Substeps {
    /// Always this many (at least 1).
    Fixed(u32),
    /// For the explicit fixed-step integrators, as many as the stability
    /// estimate asks (springs, penalty colliders, contacts); one for the
    /// implicit and adaptive ones.
    Auto,
}

/// World-wide settings: blow-up limits and the implicit solvers' tolerances.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// A particle farther than this from the origin (m) means the run has
    /// blown up. Default 1e6 m.
    pub max_distance: Real,
    /// A particle faster than this (m/s) means the run has blown up.
    /// Default 1e6 m/s.
    pub max_speed: Real,
    /// Tolerances and iteration limits of the implicit integrators.
    pub solver: SolverSettings,
    /// Substeps of each step. Default one.
    pub substeps: Substeps,
    /// Tolerance and sweeps of the rods' projection.
    pub constraints: ConstraintSettings,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            max_distance: 1e6,
            max_speed: 1e6,
            solver: SolverSettings::default(),
            substeps: Substeps::Fixed(1),
            constraints: ConstraintSettings::default(),
        }
    }
}

/// Acceleration of gravity a new world starts with (m/s²).
pub const DEFAULT_GRAVITY: Vec3 = Vec3::new(0.0, -9.81, 0.0);

/// How often an implicit solver stopped above its tolerance during a run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SolverStats {
    /// Steps whose solve ended at its iteration limit above the tolerance.
    pub unconverged_steps: u64,
    /// The first such step and its final relative residual.
    pub first_unconverged: Option<(u64, Real)>,
}

/// How often the rods' projection stopped at `constraint_iterations` with
/// a rod still off its length by more than `constraint_tolerance`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ConstraintStats {
    /// Steps that ended with a rod beyond the tolerance.
    pub unconverged_steps: u64,
    /// The first such step and its largest relative length error.
    pub first_unconverged: Option<(u64, Real)>,
}

/// A simulated world.
#[derive(Debug)]
pub struct World {
    /// Every particle of every body.
    pub particles: Particles,
    /// Every spring of every body.
    pub springs: Springs,
    /// The bodies, in the order they were added (add them with
    /// [`World::add_body`], which keeps the index of names that
    /// [`World::body`] looks them up in).
    pub bodies: Vec<Body>,
    /// Every force acting on the particles: a new world has gravity
    /// ([`DEFAULT_GRAVITY`]), the springs, the gas pressure and the penalty
    /// contacts of the colliders; wind, drag, the hand and any other force
    /// are added to it.
    pub forces: ForceList,
    /// Colliders the particles must stay out of.
    pub colliders: Vec<Collider>,
    /// Contact between bodies: settings and the step's candidate pairs.
    pub contacts: Contacts,
    /// Blow-up limits and solver tolerances.
    pub settings: Settings,
    /// Rigid rods (distance constraints) of every body.
    pub rods: Rods,
    /// Springs whose rest lengths change in time.
    pub muscles: Muscles,
    /// Rigid bodies.
    pub rigid: RigidBodies,
    /// Joins between bodies, in the order added ([`World::add_join`]).
    pub joins: Vec<Join>,
    /// The strains past which springs yield and break, and what they did.
    pub limits: SpringLimits,
    /// Each body's index by name (names are unique).
    names: std::collections::HashMap<String, usize>,
    /// Positions at the start of the (sub)step, for the rods' directions.
    step_start: Vec<Vec3>,
    /// Positions before the rods' projection (scratch).
    rod_scratch: Vec<Vec3>,
    /// Positions at the start of the (sub)step, for the CCD's
    /// continuous collision detection (empty where it has nothing to do).
    ccd_start: Vec<Vec3>,
    /// What the CCD did in the last step.
    last_ccd: CcdReport,
    /// Why this step's CCD stopped short, if it did.
    ccd_stop: Option<ccd::CcdStop>,
    /// What the rods' projection did in the last step.
    last_rods: RodReport,
    constraint_stats: ConstraintStats,
    integrator: Box<dyn Integrator>,
    time: Real,
    /// Kahan compensation of `time`, so that many small steps add up to the
    /// exact duration (20 000 steps of 2.5e-4 s make 5 s, not 5.000000000000365 s).
    time_compensation: Real,
    steps: u64,
    last_report: StepReport,
    solver_stats: SolverStats,
    /// The stable-step bounds of automatic substeps (kept for their buffers).
    stiffness_bounds: StiffnessBounds,
    /// The stages' clock, when profiling.
    timer: Timer,
}

impl World {
    /// An empty world with default settings, stepped by `integrator`. The
    /// first world of a process sizes the engine's threads from
    /// `SPRUNG_THREADS` if it is set (see [`parallel::configure`]).
    ///
    /// # Examples
    ///
    /// A new world is empty, at time zero, with Earth's gravity:
    ///
    /// ```
    /// use sprung::world::DEFAULT_GRAVITY;
    /// use sprung::{IntegratorKind, Vec3, World};
    ///
    /// let world = World::new(IntegratorKind::Rk4);
    /// assert_eq!(world.integrator(), IntegratorKind::Rk4);
    /// assert_eq!(world.gravity(), DEFAULT_GRAVITY);
    /// assert_eq!(DEFAULT_GRAVITY, Vec3::new(0.0, -9.81, 0.0));
    /// assert_eq!((world.time(), world.steps()), (0.0, 0));
    /// assert!(world.particles.is_empty() && world.bodies.is_empty());
    /// ```
    pub fn new(integrator: IntegratorKind) -> Self {
        parallel::configure_from_env();
        let mut forces = ForceList::new();
        forces.set(Gravity {
            acceleration: DEFAULT_GRAVITY,
        });
        forces.set(SpringForce::new());
        forces.set(GasPressure::new());
        forces.set(ColliderContacts::new());
        forces.set(BodyContacts::new());
        World {
            particles: Particles::default(),
            springs: Springs::default(),
            bodies: Vec::new(),
            forces,
            colliders: Vec::new(),
            contacts: Contacts::default(),
            settings: Settings::default(),
            rods: Rods::default(),
            muscles: Muscles::default(),
            rigid: RigidBodies::default(),
            joins: Vec::new(),
            limits: SpringLimits::default(),
            names: std::collections::HashMap::new(),
            step_start: Vec::new(),
            rod_scratch: Vec::new(),
            ccd_start: Vec::new(),
            last_ccd: CcdReport::default(),
            ccd_stop: None,
            last_rods: RodReport::default(),
            constraint_stats: ConstraintStats::default(),
            integrator: integrator.create(),
            time: 0.0,
            time_compensation: 0.0,
            steps: 0,
            last_report: StepReport::default(),
            solver_stats: SolverStats::default(),
            stiffness_bounds: StiffnessBounds::default(),
            timer: Timer::default(),
        }
    }

    /// Acceleration of gravity (m/s²): the sum of the uniform accelerations
    /// of the forces in the list ([`Gravity`]'s), zero without one.
    pub fn gravity(&self) -> Vec3 {
        self.forces.uniform_acceleration()
    }

    /// Set the acceleration of gravity (m/s²).
    ///
    /// On the Moon, a 3 kg rock weighs `m g` (the force is exact: one product):
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// let moon = Vec3::new(0.0, -1.62, 0.0);
    /// world.set_gravity(moon);
    /// assert_eq!(world.gravity(), moon);
    /// let rock = BodyData::from_positions(vec![Vec3::ZERO]).with_mass(3.0);
    /// world.add_body("rock", rock).unwrap();
    /// world.evaluate_forces();
    /// assert_eq!(world.particles.force[0], 3.0 * moon);
    /// ```
    pub fn set_gravity(&mut self, acceleration: Vec3) {
        self.forces.set(Gravity { acceleration });
    }

    /// Set the global air drag coefficient `c_air` (N·s/m); 0 removes it.
    ///
    /// Under drag alone, symplectic Euler multiplies a particle's velocity by
    /// `1 - c dt / m` each step. With `c = 0.5`, `m = 1`, `dt = 1/8` the factor
    /// is 15/16, and eight steps of it are exact in binary:
    ///
    /// ```
    /// use sprung::forces::AirDrag;
    /// use sprung::{BodyData, IntegratorKind, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.set_gravity(Vec3::ZERO);
    /// world.set_air_drag(0.5);
    /// let ball = BodyData::from_positions(vec![Vec3::ZERO]).with_velocity(Vec3::X);
    /// world.add_body("ball", ball).unwrap();
    /// for _ in 0..8 {
    ///     world.step(0.125).unwrap();
    /// }
    /// assert_eq!(world.particles.velocity[0].x, (1.0 - 0.5 * 0.125_f64).powi(8));
    /// world.set_air_drag(0.0);
    /// assert!(world.forces.get::<AirDrag>().is_none());
    /// ```
    pub fn set_air_drag(&mut self, coefficient: Real) {
        if coefficient == 0.0 {
            self.forces.remove::<AirDrag>();
        } else {
            self.forces.set(AirDrag { coefficient });
        }
    }

    /// What the last step's integrator reported (iterations and residual of
    /// an implicit solve).
    pub fn last_step_report(&self) -> StepReport {
        self.last_report
    }

    /// How often the implicit solver stopped above its tolerance so far.
    pub fn solver_stats(&self) -> SolverStats {
        self.solver_stats
    }

    /// Time each stage of every step from now on ([`World::profile`]), or
    /// stop. Off (the default), the timers cost one untaken branch a stage.
    ///
    /// A midpoint step evaluates the forces twice:
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, Stage, World};
    ///
    /// let mut world = World::new(IntegratorKind::Midpoint);
    /// world.add_body("rope", build::rope(10, 1.0).unwrap().with_stiffness(100.0)).unwrap();
    /// world.step(1e-3).unwrap();
    /// assert_eq!(world.profile().steps(), 0); // off by default
    /// world.set_profiling(true);
    /// for _ in 0..10 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// let profile = world.profile();
    /// assert_eq!(profile.steps(), 10);
    /// assert_eq!(profile.calls(Stage::Forces), 20);
    /// assert!(profile.staged() <= profile.wall());
    /// world.reset_profile();
    /// assert_eq!(world.profile().steps(), 0);
    /// ```
    pub fn set_profiling(&mut self, on: bool) {
        self.timer.set(on);
    }

    /// Whether the stages are timed ([`World::set_profiling`]).
    pub fn is_profiling(&self) -> bool {
        self.timer.is_on()
    }

    /// Where the steps taken while profiling spent their time, stage by
    /// stage ([`Stage`](crate::Stage)): times, shares of the steps' wall time and calls.
    pub fn profile(&self) -> Profile {
        self.timer.profile()
    }

    /// Forget the profile so far (to time a window of a run).
    pub fn reset_profile(&mut self) {
        self.timer.reset();
    }

    /// Simulated time (s).
    pub fn time(&self) -> Real {
        self.time
    }

    /// Number of steps taken.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The integrator in use.
    pub fn integrator(&self) -> IntegratorKind {
        self.integrator.kind()
    }

    /// Switch the integrator; positions, velocities and time are kept.
    ///
    /// Start a run explicitly and go on implicitly at a step ten times the
    /// stable one:
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.add_body("rope", build::rope(8, 1.0).unwrap().with_stiffness(100.0)).unwrap();
    /// for _ in 0..10 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// let (time, position) = (world.time(), world.particles.position.clone());
    /// world.set_integrator(IntegratorKind::ImplicitEuler);
    /// assert_eq!(world.integrator(), IntegratorKind::ImplicitEuler);
    /// assert_eq!((world.time(), &world.particles.position), (time, &position));
    /// let dt = 10.0 * world.stable_time_step();
    /// let report = world.step(dt).unwrap();
    /// assert!(report.iterations.is_some()); // a conjugate-gradient solve
    /// ```
    pub fn set_integrator(&mut self, kind: IntegratorKind) {
        if kind != self.integrator.kind() {
            self.integrator = kind.create();
        }
    }

    /// Start the integrator afresh, without the history it keeps between
    /// steps (as after [`World::set_integrator`]): for a caller that has
    /// set positions or velocities from outside, so that the next step
    /// starts from them alone.
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.add_body("rope", build::rope(3, 1.0).unwrap()).unwrap();
    /// world.step(1e-3).unwrap();
    /// world.particles.position[2].x += 0.1; // moved by hand
    /// world.restart_integrator();
    /// assert_eq!(world.integrator(), IntegratorKind::Verlet);
    /// ```
    pub fn restart_integrator(&mut self) {
        self.integrator = self.integrator.kind().create();
    }

    /// The index of the body called `name` (what [`World::volume`],
    /// [`World::pressure`] and [`World::centroid`] take), if any.
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.add_body("a", build::rope(3, 1.0).unwrap()).unwrap();
    /// world.add_body("b", build::rope(3, 1.0).unwrap()).unwrap();
    /// assert_eq!(world.body_index("b"), Some(1));
    /// assert_eq!(world.body_index("c"), None);
    /// ```
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.names.get(name).copied()
    }

    /// The body called `name`, if any.
    ///
    /// ```
    /// use sprung::build::{self, ClothSprings};
    /// use sprung::{IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.add_body("rope", build::rope(4, 1.0).unwrap()).unwrap();
    /// let flag = build::cloth(3, 2, 1.0, 0.5, ClothSprings::default()).unwrap();
    /// world.add_body("flag", flag).unwrap();
    /// let flag = world.body("flag").unwrap();
    /// assert_eq!(flag.particles, 4..10); // after the rope's 4
    /// assert_eq!(flag.faces.len(), 4);
    /// assert!(world.body("sail").is_none());
    /// ```
    pub fn body(&self, name: &str) -> Option<&Body> {
        self.names.get(name).map(|&i| &self.bodies[i])
    }

    /// What the rods' projection did in the last step: sweeps and the
    /// largest relative length error left.
    pub fn last_rod_report(&self) -> RodReport {
        self.last_rods
    }

    /// What the CCD behind the contacts did in the last step
    /// ([`crate::contact::ccd`]): its impulses and impact zones, summed
    /// over the substeps.
    pub fn last_ccd_report(&self) -> CcdReport {
        self.last_ccd
    }

    /// How often the rods' projection stopped above its tolerance so far
    /// (rods joining very unequal masses converge slowly).
    pub fn constraint_stats(&self) -> ConstraintStats {
        self.constraint_stats
    }

    /// Every spring of the world (indices in [`World::springs`]) in the
    /// scene's order: body by body, each body's in the order its scene
    /// gave them ([`Body::springs_in_scene_order`]), then any spring of no
    /// body in the order stored. What the outputs list springs in.
    pub fn springs_in_scene_order(&self) -> Vec<usize> {
        let mut listed = vec![false; self.springs.len()];
        let mut order: Vec<usize> = Vec::with_capacity(self.springs.len());
        for body in &self.bodies {
            for s in body.springs_in_scene_order() {
                if let Some(seen) = listed.get_mut(s).filter(|seen| !**seen) {
                    *seen = true;
                    order.push(s);
                }
            }
        }
        order.extend((0..self.springs.len()).filter(|&s| !listed[s]));
        order
    }
}

impl World {
    /// The world's model data as a step reads it (docs: [`Model`]): the
    /// masses, springs, bodies, colliders and the contact pairs now.
    pub fn model(&self) -> Model<'_> {
        self.model_with(&self.contacts)
    }

    /// [`World::model`] with `contacts` for the contact state.
    pub(super) fn model_with<'a>(&'a self, contacts: &'a Contacts) -> Model<'a> {
        Model {
            mass: &self.particles.mass,
            inverse_mass: &self.particles.inverse_mass,
            springs: &self.springs,
            bodies: &self.bodies,
            colliders: &self.colliders,
            contacts,
        }
    }

    /// The world's parts as its integrate stage takes them, borrowed apart:
    /// the model, the force list (the step's controls among its forces),
    /// and the positions (m) and velocities (m/s) an integrator advances.
    /// With [`Dynamics::new`] and an integrator of its own, a program steps
    /// the world by hand as the function `(model, state, forces, dt) →
    /// state` (the example of [`Dynamics`]).
    pub fn parts_mut(&mut self) -> (Model<'_>, &mut ForceList, &mut [Vec3], &mut [Vec3]) {
        let (model, forces, position, velocity, _, _) = self.parts();
        (model, forces, position, velocity)
    }

    /// [`World::parts_mut`], with the integrator and the stage timer.
    #[allow(clippy::type_complexity)]
    fn parts(
        &mut self,
    ) -> (
        Model<'_>,
        &mut ForceList,
        &mut [Vec3],
        &mut [Vec3],
        &mut dyn Integrator,
        &Timer,
    ) {
        let Particles {
            position,
            velocity,
            mass,
            inverse_mass,
            ..
        } = &mut self.particles;
        let model = Model {
            mass,
            inverse_mass,
            springs: &self.springs,
            bodies: &self.bodies,
            colliders: &self.colliders,
            contacts: &self.contacts,
        };
        let integrator = self.integrator.as_mut();
        (
            model,
            &mut self.forces,
            position,
            velocity,
            integrator,
            &self.timer,
        )
    }

    /// Split the world into its derivative function (the model and the
    /// forces, timed by the world's stage timer) and what the integrator
    /// advances: the integrate stage's `(model, state, forces, dt) → state`.
    pub(super) fn split(
        &mut self,
    ) -> (Dynamics<'_>, &mut [Vec3], &mut [Vec3], &mut dyn Integrator) {
        let (model, forces, position, velocity, integrator, timer) = self.parts();
        let dynamics = Dynamics::new(model, forces).timed_by(timer);
        (dynamics, position, velocity, integrator)
    }
}
