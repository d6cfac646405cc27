//! The world: particles, springs, bodies, forces, colliders and the
//! integrator, and the step that moves them.
//!
//! One step is a short sequence of named stages:
//!
//! 1. **forces**: the integrator asks [`Dynamics`] for the forces of the one
//!    [`ForceList`] (gravity, springs, gas pressure, air drag, wind, the
//!    user's hand, penalty contacts, anything added) at every trial state it
//!    needs, and the implicit integrators for their Jacobian products;
//! 2. **integrate** positions and velocities (explicit, or implicit with a
//!    solver that reports its iterations in a [`StepReport`]);
//! 3. **collide**: projection-form colliders, where they are at the end of
//!    the step (moving ones follow their path), move particles back out,
//!    then friction between bodies;
//! 4. **constrain** ([`crate::constrain`]): rigid rods and rigid bodies
//!    put back on their lengths and shapes, velocities with them, so they
//!    hold exactly at the end of every step (muscles set their rest lengths
//!    before the forces);
//! 5. **guard**: a non-finite or runaway state stops the run with
//!    [`StepError::BlowUp`].

use crate::body::{self, Body, BodyData};
use crate::collide::{self, Collider, ContactConstraint};
use crate::constrain::{
    ConstraintSettings, Muscle, Muscles, RigidBodies, RigidBody, RodReport, Rods,
};
use crate::contact::{BodyContacts, Contacts, RigidParts, TooManyPairs};
use crate::error::{BlowUpReason, BuildError, StepError};
use crate::forces::{
    self, AirDrag, ForceContext, ForceList, GasPressure, Gravity, ImpulseContext, JacobianScale,
    Jacobians, Linearization, PenaltyContacts, SpringForce, StiffnessBounds,
};
use crate::integrate::{Derivative, Integrator, IntegratorKind, SolverSettings, State, StepReport};
use crate::measure::{self, Energies};
use crate::order;
use crate::parallel;
use crate::particles::Particles;
use crate::springs::{self, Springs};
use crate::state::{StateError, WorldState};
use crate::surface;
use crate::{Real, Vec3};

/// The approach speed (m/s) below which a rigid body's contact with a
/// collider rests instead of bouncing (engines use such a threshold:
/// Box2D's is 1 m/s); a drop from 0.5 mm lands this fast.
pub const RESTING_SPEED: Real = 0.1;

/// Most substeps [`Substeps::Auto`] splits a step into.
pub const MAX_SUBSTEPS: u32 = 1_000_000;

/// How many substeps each step of the world is split into.
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
    /// Each body's index by name (names are unique).
    names: std::collections::HashMap<String, usize>,
    /// Positions at the start of the (sub)step, for the rods' directions.
    step_start: Vec<Vec3>,
    /// Positions before the rods' projection (scratch).
    rod_scratch: Vec<Vec3>,
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
}

impl World {
    /// An empty world with default settings, stepped by `integrator`. The
    /// first world of a process sizes the engine's threads from
    /// `SPRUNG_THREADS` if it is set (see [`parallel::configure`]).
    pub fn new(integrator: IntegratorKind) -> Self {
        parallel::configure_from_env();
        let mut forces = ForceList::new();
        forces.set(Gravity {
            acceleration: DEFAULT_GRAVITY,
        });
        forces.set(SpringForce::new());
        forces.set(GasPressure::new());
        forces.set(PenaltyContacts::new());
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
            names: std::collections::HashMap::new(),
            step_start: Vec::new(),
            rod_scratch: Vec::new(),
            last_rods: RodReport::default(),
            constraint_stats: ConstraintStats::default(),
            integrator: integrator.create(),
            time: 0.0,
            time_compensation: 0.0,
            steps: 0,
            last_report: StepReport::default(),
            solver_stats: SolverStats::default(),
            stiffness_bounds: StiffnessBounds::default(),
        }
    }

    /// Acceleration of gravity (m/s²): the sum of the uniform accelerations
    /// of the forces in the list ([`Gravity`]'s), zero without one.
    pub fn gravity(&self) -> Vec3 {
        self.forces.uniform_acceleration()
    }

    /// Set the acceleration of gravity (m/s²).
    pub fn set_gravity(&mut self, acceleration: Vec3) {
        self.forces.set(Gravity { acceleration });
    }

    /// Set the global air drag coefficient `c_air` (N·s/m); 0 removes it.
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
    pub fn set_integrator(&mut self, kind: IntegratorKind) {
        if kind != self.integrator.kind() {
            self.integrator = kind.create();
        }
    }

    /// Check `data` and add it as a body called `name`; returns the body's
    /// index. Nothing is added when the body is refused.
    pub fn add_body(&mut self, name: &str, data: BodyData) -> Result<usize, BuildError> {
        data.validate()?;
        self.check_limits(&data)?;
        if name.is_empty() || name.contains([',', '"', '\n', '\r']) {
            return Err(BuildError::BadName(name.to_string()));
        }
        if self.names.contains_key(name) {
            return Err(BuildError::DuplicateName(name.to_string()));
        }
        let offset = self.particles.len();
        let mut pinned = vec![false; data.particle_count()];
        data.pinned.iter().for_each(|&i| pinned[i] = true);
        for (i, (&position, &mass)) in data.position.iter().zip(&data.mass).enumerate() {
            let velocity = data.velocity.get(i).copied().unwrap_or(Vec3::ZERO);
            self.particles.push(position, velocity, mass, pinned[i]);
        }
        let first_spring = self.springs.len();
        let index = |i: usize| (offset + i) as u32;
        // Runs of springs stepping along the particles first, then the rest
        // by lowest particle (in the numbering the spring force works in,
        // where the body's own has no locality): the orders the force reads
        // fastest (`springs::storage_order`).
        let ends: Vec<[u32; 2]> = data
            .springs
            .iter()
            .map(|s| [s.first as u32, s.second as u32])
            .collect();
        let mut order = springs::storage_order(&ends, None);
        let number = order::locality_numbering(&ends, &order, data.position.len());
        if number.is_some() {
            order = springs::storage_order(&ends, number.as_deref());
        }
        // Where each spring of the data went (for the muscles).
        let mut stored = vec![0; order.len()];
        for (place, &k) in order.iter().enumerate() {
            stored[k] = first_spring + place;
        }
        for s in order.iter().map(|&k| &data.springs[k]) {
            self.springs.push(
                index(s.first),
                index(s.second),
                data.rest_length(s),
                s.stiffness,
                s.damping,
                s.one_sided,
            );
        }
        let mut body = Body {
            name: name.to_string(),
            particles: offset..self.particles.len(),
            springs: first_spring..self.springs.len(),
            faces: data.faces.iter().map(|f| f.map(index)).collect(),
            segments: data.segments.iter().map(|s| s.map(index)).collect(),
            closed: data.is_closed(),
            gas: data.gas.clone(),
            edges: surface::unique_edges(&data.faces)
                .into_iter()
                .map(|e| e.map(index))
                .collect(),
            contact: data.contact,
            rods: self.rods.len()..self.rods.len() + data.rods.len(),
            rigid: data.rigid,
            gravitating: data.gravitating,
            spring_numbering: number,
            scene_springs: stored.iter().map(|&k| (k - first_spring) as u32).collect(),
        };
        for rod in &data.rods {
            self.rods
                .push(index(rod.first), index(rod.second), data.rod_length(rod));
        }
        for muscle in &data.muscles {
            let spring = stored[muscle.spring];
            let rest_length = self.springs.rest_length[spring];
            let factor = muscle.drive.factor(self.time);
            if factor.is_finite() && factor > 0.0 {
                self.springs.rest_length[spring] = rest_length * factor;
            }
            self.muscles.list.push(Muscle {
                spring,
                rest_length,
                drive: muscle.drive.clone(),
            });
        }
        if data.rigid {
            self.rigid.list.push(RigidBody::new(
                body.particles.clone(),
                &self.particles.position,
                &self.particles.mass,
            ));
        }
        orient_outward(&mut body, &self.particles.position);
        self.names.insert(body.name.clone(), self.bodies.len());
        self.bodies.push(body);
        Ok(self.bodies.len() - 1)
    }

    /// Refuse a body that starts beyond the blow-up limits, or whose masses
    /// or stiffnesses would give energies that overflow within them.
    fn check_limits(&self, data: &BodyData) -> Result<(), BuildError> {
        let limits = &self.settings;
        let g = self.gravity().length();
        let within = |field, vectors: &[Vec3], limit: Real| {
            vectors.iter().enumerate().try_for_each(|(index, &x)| {
                let value = magnitude(x);
                if value > limit {
                    Err(BuildError::BeyondLimit {
                        field,
                        index,
                        value,
                        limit,
                    })
                } else {
                    Ok(())
                }
            })
        };
        within("particles", &data.position, limits.max_distance)?;
        within("velocities", &data.velocity, limits.max_speed)?;
        // A rod longer than the world is wide cannot hold within it: its
        // ends would run past the limit at the first step.
        for (index, rod) in data.rods.iter().enumerate() {
            let value = data.rod_length(rod);
            if value > 2.0 * limits.max_distance {
                return Err(BuildError::BeyondLimit {
                    field: "rod_lengths",
                    index,
                    value,
                    limit: 2.0 * limits.max_distance,
                });
            }
        }
        let overflow = |field, index, value: Real, energy: Real| {
            (energy.is_nan() || energy >= crate::error::ENERGY_LIMIT).then_some(
                BuildError::EnergyOverflow {
                    field,
                    index,
                    value,
                    energy,
                },
            )
        };
        for (index, &m) in data.mass.iter().enumerate() {
            let energy = m * (g * limits.max_distance + 0.5 * limits.max_speed.powi(2));
            if let Some(error) = overflow("masses", index, m, energy) {
                return Err(error);
            }
        }
        for (index, s) in data.springs.iter().enumerate() {
            let reach = 2.0 * limits.max_distance;
            let energy = 0.5 * s.stiffness * reach * reach;
            if let Some(error) = overflow("stiffness", index, s.stiffness, energy) {
                return Err(error);
            }
        }
        Ok(())
    }

    /// The body called `name`, if any.
    pub fn body(&self, name: &str) -> Option<&Body> {
        self.names.get(name).map(|&i| &self.bodies[i])
    }

    /// Advance the world by `dt` (s): detect contacts, then per substep set
    /// the muscles, integrate, collide, add friction and constrain (rods,
    /// rigid bodies), then check that the state is still finite and within
    /// the limits of [`Settings`]. Returns
    /// what the integrator reported (also kept in
    /// [`World::last_step_report`]); a solve that stopped above its
    /// tolerance is counted in [`World::solver_stats`].
    ///
    /// Called from outside the engine's pool of threads, the step of a
    /// world of more than [`parallel::CHUNK`] particles (whose loops are
    /// shared among threads) is handed to the pool at once
    /// ([`parallel::in_pool`]) rather than each of its parallel loops one
    /// by one, the caller waiting each time; a smaller world, whose loops
    /// mostly run on the calling thread, steps right there (a hand-over
    /// costs more than its whole step).
    pub fn step(&mut self, dt: Real) -> Result<StepReport, StepError> {
        if self.particles.len() > parallel::CHUNK {
            parallel::in_pool(|| self.step_here(dt))
        } else {
            self.step_here(dt)
        }
    }

    /// [`World::step`], on the thread it is called from.
    fn step_here(&mut self, dt: Real) -> Result<StepReport, StepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(StepError::InvalidTimeStep { dt });
        }
        self.validate_settings()
            .map_err(StepError::InvalidSettings)?;
        self.detect(dt)?;
        let substeps = self.substeps(dt);
        let h = dt / Real::from(substeps);
        let mut report = StepReport::default();
        for _ in 0..substeps {
            self.move_muscles()?;
            if !self.rods.is_empty() {
                self.step_start.clear();
                self.step_start.extend_from_slice(&self.particles.position);
            }
            report = report.then(self.integrate(h)?);
            self.advance_time(h);
            self.collide();
            self.friction(h);
            self.constrain(h);
        }
        if substeps > 1 {
            report.substeps = Some(substeps);
            report.step_size = Some(h);
        }
        self.steps += 1;
        self.last_report = report;
        if self.last_rods.error > self.settings.constraints.tolerance {
            let stats = &mut self.constraint_stats;
            stats.unconverged_steps += 1;
            if stats.first_unconverged.is_none() {
                stats.first_unconverged = Some((self.steps, self.last_rods.error));
            }
        }
        if report.unconverged {
            let stats = &mut self.solver_stats;
            stats.unconverged_steps += 1;
            if stats.first_unconverged.is_none() {
                stats.first_unconverged = Some((self.steps, report.residual.unwrap_or(Real::NAN)));
            }
        }
        self.guard(dt)?;
        self.check_rods()?;
        Ok(report)
    }

    /// Fail the step if a rod is off its length by more than
    /// [`crate::constrain::ROD_FAILURE`] after the constrain stage, or by
    /// more than `constraint_tolerance` where that is looser.
    fn check_rods(&self) -> Result<(), StepError> {
        let RodReport {
            error,
            worst,
            sweeps,
        } = self.last_rods;
        let limit = crate::constrain::ROD_FAILURE.max(self.settings.constraints.tolerance);
        if error <= limit {
            return Ok(());
        }
        let body = self.bodies.iter().find(|b| b.rods.contains(&worst));
        Err(StepError::RodOff {
            step: self.steps,
            time: self.time,
            rod: body.map_or(worst, |b| worst - b.rods.start),
            body: body.map_or_else(|| "no body".into(), |b| format!("body \"{}\"", b.name)),
            error,
            limit,
            sweeps,
            iterations: self.settings.constraints.iterations,
        })
    }

    /// The muscles' rest lengths at the start of the (sub)step.
    fn move_muscles(&mut self) -> Result<(), StepError> {
        self.muscles
            .apply(self.time, &mut self.springs)
            .map_err(|(muscle, factor)| {
                StepError::InvalidSettings(BuildError::BadMuscle {
                    muscle,
                    field: "drive",
                    value: factor,
                    reason: "the drive must give a positive, finite factor of the rest length",
                })
            })
    }

    /// The friction stage: every force's impulses at the end of a (sub)step
    /// of `dt` (s) (the body contacts' Coulomb friction).
    fn friction(&mut self, dt: Real) {
        let mut context = ImpulseContext {
            time: self.time,
            dt,
            position: &mut self.particles.position,
            velocity: &mut self.particles.velocity,
            inverse_mass: &self.particles.inverse_mass,
            contacts: &self.contacts,
            rigid: RigidParts::new(&self.rigid.list, &self.particles.mass),
        };
        self.forces.apply_impulses(&mut context);
    }

    /// The constrain stage: rods, then rigid bodies, over a step of `dt` (s).
    fn constrain(&mut self, dt: Real) {
        let Particles {
            position,
            velocity,
            mass,
            inverse_mass,
            ..
        } = &mut self.particles;
        let constraints = self.settings.constraints;
        self.last_rods = self.rods.project(
            position,
            velocity,
            &self.step_start,
            inverse_mass,
            dt,
            constraints.tolerance,
            constraints.iterations,
            &mut self.rod_scratch,
        );
        // Below this approach speed a rigid body's contact rests rather
        // than bounces: two steps of gravity, and at least RESTING_SPEED
        // (a body rocking on a face would otherwise bounce for ever).
        let gravity = self.forces.uniform_acceleration().length();
        let rest_speed = (2.0 * dt * gravity).max(RESTING_SPEED);
        self.rigid.project(
            position,
            velocity,
            mass,
            &self.colliders,
            self.time,
            dt,
            rest_speed,
        );
    }

    /// What the rods' projection did in the last step: sweeps and the
    /// largest relative length error left.
    pub fn last_rod_report(&self) -> RodReport {
        self.last_rods
    }

    /// How often the rods' projection stopped above its tolerance so far
    /// (rods joining very unequal masses converge slowly).
    pub fn constraint_stats(&self) -> ConstraintStats {
        self.constraint_stats
    }

    /// Check the solver, contact and substep settings.
    fn validate_settings(&self) -> Result<(), BuildError> {
        self.settings.constraints.validate()?;
        self.settings.solver.validate()?;
        self.contacts
            .settings
            .validate_within(self.settings.max_distance, self.settings.max_speed)?;
        if self.settings.substeps == Substeps::Fixed(0) {
            return Err(BuildError::OutOfRange {
                field: "substeps",
                value: 0.0,
                reason: "must be at least 1, or \"auto\"",
            });
        }
        Ok(())
    }

    /// How many substeps a step of `dt` (s) takes: `settings.substeps`, or
    /// with [`Substeps::Auto`] and an explicit fixed-step integrator, as many
    /// as keep each below 0.9 of the stable step (springs, colliders and
    /// this step's contacts; see [`World::stable_time_step`]).
    fn substeps(&mut self, dt: Real) -> u32 {
        match self.settings.substeps {
            Substeps::Fixed(n) => n,
            Substeps::Auto => {
                let kind = self.integrator.kind();
                if kind.is_implicit() || kind == IntegratorKind::Rk45 {
                    return 1;
                }
                // The step's own pairs: its detect stage has run. The
                // bounds' buffers are the world's: no allocation a step.
                let mut bounds = std::mem::take(&mut self.stiffness_bounds);
                bounds.reset(self.particles.len());
                self.forces
                    .add_stiffness(&self.force_context(), &mut bounds);
                let stable = 0.9 * bounds.stable_time_step();
                self.stiffness_bounds = bounds;
                (dt / stable).ceil().clamp(1.0, MAX_SUBSTEPS as Real) as u32
            }
        }
    }

    /// The detect stage: the candidate contact pairs of this step.
    fn detect(&mut self, dt: Real) -> Result<(), StepError> {
        detect_into(
            &mut self.contacts,
            &self.bodies,
            &self.springs,
            &self.particles,
            dt,
        )
        .map_err(|too_many| self.too_many_contacts(too_many))
    }

    /// A refusal of the detect stage as the next step's error.
    fn too_many_contacts(&self, too_many: TooManyPairs) -> StepError {
        StepError::TooManyContacts {
            step: self.steps + 1,
            time: self.time,
            limit: too_many.limit,
            thickness: self.contacts.settings.thickness,
        }
    }

    fn integrate(&mut self, dt: Real) -> Result<StepReport, StepError> {
        let (time, steps, solver) = (self.time, self.steps, self.settings.solver);
        let (mut dynamics, position, velocity, integrator) = self.split();
        integrator
            .step(time, dt, position, velocity, &mut dynamics, &solver)
            .map_err(|source| StepError::Solver {
                step: steps + 1,
                time,
                source,
            })
    }

    /// Split the world into its derivative function and the state the
    /// integrator advances (disjoint borrows of its fields).
    fn split(&mut self) -> (Dynamics<'_>, &mut [Vec3], &mut [Vec3], &mut dyn Integrator) {
        let Particles {
            position,
            velocity,
            mass,
            inverse_mass,
            ..
        } = &mut self.particles;
        let dynamics = Dynamics {
            forces: &mut self.forces,
            frame: Frame {
                colliders: &self.colliders,
                contacts: &self.contacts,
                springs: &self.springs,
                bodies: &self.bodies,
                mass,
                inverse_mass,
            },
        };
        (dynamics, position, velocity, self.integrator.as_mut())
    }

    fn advance_time(&mut self, dt: Real) {
        let increment = dt - self.time_compensation;
        let time = self.time + increment;
        self.time_compensation = (time - self.time) - increment;
        self.time = time;
    }

    /// The projection stage, at the time after the step (`self.time` has
    /// been advanced), where moving colliders have got to.
    /// Rigid bodies meet the colliders as bodies, in the constrain stage.
    fn collide(&mut self) {
        if self.colliders.is_empty() {
            return;
        }
        let (colliders, time) = (&self.colliders, self.time);
        let particles = &mut self.particles;
        // Each particle meets the colliders in their order and on its own,
        // so the runs of bodies go to the threads in spans.
        for run in body::runs_of(&self.bodies, |b| !b.rigid) {
            let inverse_mass = &particles.inverse_mass[run.clone()];
            let spans = (
                &mut particles.position[run.clone()],
                &mut particles.velocity[run],
            );
            parallel::for_each_span(spans, |start, (x, v)| {
                let inverse_mass = &inverse_mass[start..start + x.len()];
                for collider in colliders {
                    collide::project(collider, time, x, v, inverse_mass);
                }
            });
        }
    }

    fn guard(&self, dt: Real) -> Result<(), StepError> {
        let limits = &self.settings;
        let particles = &self.particles;
        // First a branch-free scan the compiler vectorises, over the
        // coordinates as one flat array (no shuffling of three-vectors into
        // lanes): a coordinate within `limit / 1.75` each way puts its
        // particle within `√3 / 1.75 < 1` of the limit, and NaN and infinite
        // coordinates fail the comparison. A span with a coordinate beyond
        // it is measured exactly, a particle at a time; only a state that
        // fails that is searched for the first particle at fault and why.
        let distance_squared = limits.max_distance.powi(2).min(Real::MAX);
        let speed_squared = limits.max_speed.powi(2).min(Real::MAX);
        let distance_bound = limits.max_distance.min(Real::MAX) / 1.75;
        let speed_bound = limits.max_speed.min(Real::MAX) / 1.75;
        let outside = parallel::max(particles.len(), |range| {
            let x = &particles.position[range.clone()];
            let v = &particles.velocity[range];
            let within = coordinates_within(x, distance_bound)
                && coordinates_within(v, speed_bound)
                || x.iter().zip(v).fold(true, |within, (x, v)| {
                    within
                        & (x.length_squared() <= distance_squared)
                        & (v.length_squared() <= speed_squared)
                });
            if within {
                0.0
            } else {
                1.0
            }
        });
        if outside == 0.0 {
            return Ok(());
        }
        let bad = parallel::find_first(particles.len(), |i| {
            let (x, v) = (particles.position[i], particles.velocity[i]);
            if !(x.is_finite() && v.is_finite()) {
                Some(BlowUpReason::NonFinite)
            } else if x.length_squared() > limits.max_distance.powi(2) {
                Some(BlowUpReason::TooFar(magnitude(x)))
            } else if v.length_squared() > limits.max_speed.powi(2) {
                Some(BlowUpReason::TooFast(magnitude(v)))
            } else {
                None
            }
        });
        match bad {
            None => Ok(()),
            Some((particle, reason)) => Err(StepError::BlowUp {
                step: self.steps,
                time: self.time,
                particle,
                body: self
                    .bodies
                    .iter()
                    .find(|b| b.particles.contains(&particle))
                    .map(|b| {
                        format!(
                            "body \"{}\", its particle {}",
                            b.name,
                            particle - b.particles.start
                        )
                    })
                    .unwrap_or_else(|| "no body".into()),
                reason,
                dt,
                stable_dt: self.stable_time_step(),
            }),
        }
    }

    /// The state that changes from step to step (see [`crate::state`]):
    /// with the same scene, [`World::restore_state`] gives a world that
    /// steps on with the same bits as this one.
    pub fn save_state(&self) -> WorldState {
        let mut state = WorldState::default();
        let as_real = |count: u64| count as Real;
        state.put("steps", vec![as_real(self.steps)]);
        state.put("time", vec![self.time, self.time_compensation]);
        state.put_vectors("position", &self.particles.position);
        state.put_vectors("velocity", &self.particles.velocity);
        let muscles = self.muscles.list.iter();
        state.put(
            "muscle.rest_length",
            muscles
                .map(|m| self.springs.rest_length[m.spring])
                .collect(),
        );
        let rotations = self.rigid.list.iter();
        state.put(
            "rigid.rotation",
            rotations.flat_map(|r| r.rotation.to_array()).collect(),
        );
        let stats = |count: u64, first: Option<(u64, Real)>| {
            let (step, error) = first.map_or((0.0, 0.0), |(s, e)| (as_real(s), e));
            vec![as_real(count), step, error]
        };
        let (solver, rods) = (self.solver_stats, self.constraint_stats);
        state.put(
            "solver_stats",
            stats(solver.unconverged_steps, solver.first_unconverged),
        );
        state.put(
            "constraint_stats",
            stats(rods.unconverged_steps, rods.first_unconverged),
        );
        state.integrator = self.integrator.kind().name().to_string();
        self.integrator.save_history(&mut state);
        self.contacts.save_state(&mut state);
        state
    }

    /// Put back a state [`World::save_state`] gave, from a world built from
    /// the same scene (the integrator may differ: a different one starts
    /// without history, as after [`World::set_integrator`]). Nothing is changed when the
    /// state is refused (entries missing, of the wrong length, or not finite).
    pub fn restore_state(&mut self, state: &WorldState) -> Result<(), StateError> {
        let n = self.particles.len();
        // The history goes back to the integrator that saved it; another
        // one (switched on the command line) starts afresh.
        let mut integrator = self.integrator.kind().create();
        if state.integrator == self.integrator.kind().name() {
            integrator.restore_history(state, n)?;
        }
        let steps = state.get_count("steps")?;
        let time = state.get("time", 2)?;
        let position = state.get_vectors("position", n)?;
        let velocity = state.get_vectors("velocity", n)?;
        let rest_length = state.get("muscle.rest_length", self.muscles.list.len())?;
        let rotations = state.get("rigid.rotation", 4 * self.rigid.list.len())?;
        let stats = |name: &str| -> Result<(u64, Option<(u64, Real)>), StateError> {
            let values = state.get(name, 3)?;
            let count = |index: usize| {
                let value = values[index];
                (value >= 0.0 && value.fract() == 0.0)
                    .then_some(value as u64)
                    .ok_or_else(|| StateError::BadValue {
                        name: name.to_string(),
                        index,
                        value,
                    })
            };
            let first = count(1)?;
            Ok((count(0)?, (first > 0).then_some((first, values[2]))))
        };
        let (solver, rods) = (stats("solver_stats")?, stats("constraint_stats")?);
        let mut contacts = self.contacts.clone();
        contacts.restore_state(state, &self.bodies, n)?;
        self.integrator = integrator;
        self.contacts = contacts;
        self.steps = steps;
        (self.time, self.time_compensation) = (time[0], time[1]);
        self.particles.position = position;
        self.particles.velocity = velocity;
        for (muscle, &length) in self.muscles.list.iter().zip(rest_length) {
            self.springs.rest_length[muscle.spring] = length;
        }
        for (body, q) in self.rigid.list.iter_mut().zip(rotations.chunks_exact(4)) {
            body.rotation = glam::DQuat::from_xyzw(q[0], q[1], q[2], q[3]);
        }
        (
            self.solver_stats.unconverged_steps,
            self.solver_stats.first_unconverged,
        ) = solver;
        (
            self.constraint_stats.unconverged_steps,
            self.constraint_stats.first_unconverged,
        ) = rods;
        Ok(())
    }

    /// Evaluate every force at the current state into `particles.force` (N).
    pub fn evaluate_forces(&mut self) {
        let time = self.time;
        let mut force = std::mem::take(&mut self.particles.force);
        let (mut dynamics, position, velocity, _) = self.split();
        dynamics.force(time, position, velocity, &mut force);
        self.particles.force = force;
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

    /// Every energy term at the current state (J): kinetic, and the
    /// potential of every force in the list under its name
    /// ([`World::energy_names`]).
    pub fn energies(&self) -> Energies {
        let mut energies = Energies::new(measure::kinetic_energy(&self.particles));
        let contacts = self.contacts_now();
        self.forces
            .add_energy(&self.context_with(&contacts), &mut energies);
        energies
    }

    /// The names of the potential terms of [`World::energies`], in order:
    /// the standard ones ([`measure::STANDARD_TERMS`]), then those the
    /// forces in the list give.
    pub fn energy_names(&self) -> Vec<&'static str> {
        self.forces.energy_names()
    }

    /// Number of contact pairs between bodies closer than the contact
    /// thickness at the current state (among the candidates of the last
    /// detect stage that its allowance reaches: a state far from the last
    /// step's, set by hand, may count fewer; before the first step, among
    /// the pairs a detect stage finds now).
    pub fn active_contacts(&self) -> usize {
        let mut count = 0;
        self.contacts_now().pairs.for_each_touch(
            &self.particles.position,
            self.contacts.settings.thickness,
            |_| count += 1,
        );
        count
    }

    /// The contact state to measure the current state with: the world's
    /// own once a step has run (its last detect stage covers the state the
    /// step ended in), and before the first step a detect stage run now on
    /// a copy, so that the first row of a run counts the contacts bodies
    /// start in (the world's own pairs are still empty then). The copy is
    /// not kept: the first step searches as it would have.
    fn contacts_now(&self) -> std::borrow::Cow<'_, Contacts> {
        use std::borrow::Cow;
        if self.steps > 0 || !self.contacts.settings.enabled {
            return Cow::Borrowed(&self.contacts);
        }
        // No step to cover: the search reaches twice the thickness, which
        // holds every pair within it.
        self.detected_copy(Real::MIN_POSITIVE)
            .map_or(Cow::Borrowed(&self.contacts), Cow::Owned)
    }

    /// The context forces see at the world's current state, to evaluate one
    /// force on its own.
    pub fn force_context(&self) -> ForceContext<'_> {
        self.context_with(&self.contacts)
    }

    /// [`World::force_context`] with `contacts` for the contact state.
    fn context_with<'a>(&'a self, contacts: &'a Contacts) -> ForceContext<'a> {
        let frame = Frame {
            colliders: &self.colliders,
            contacts,
            springs: &self.springs,
            bodies: &self.bodies,
            mass: &self.particles.mass,
            inverse_mass: &self.particles.inverse_mass,
        };
        frame.context(
            self.time,
            &self.particles.position,
            &self.particles.velocity,
        )
    }

    /// Exact enclosed volume (m³), or area for a 2D body (m²), of body
    /// `body`; `None` if it is not closed.
    pub fn volume(&self, body: usize) -> Option<Real> {
        self.bodies
            .get(body)?
            .enclosed_volume(&self.particles.position)
    }

    /// Pressure of body `body`'s gas (Pa; N/m for a 2D body); `None` without a gas or such a body.
    pub fn pressure(&self, body: usize) -> Option<Real> {
        forces::pressure(self.bodies.get(body)?, &self.particles.position, self.time)
    }

    /// Total linear momentum (kg·m/s).
    pub fn linear_momentum(&self) -> Vec3 {
        measure::linear_momentum(&self.particles)
    }

    /// Mass-weighted centroid of body `body` (m); `None` if there is no such body.
    pub fn centroid(&self, body: usize) -> Option<Vec3> {
        Some(measure::centroid(&self.particles, self.bodies.get(body)?))
    }

    /// The candidate contact pairs the detect stage finds at the current
    /// state for a step of `dt` (s), on a copy of the contact state: the
    /// world is left as it was. An error where the first step would be
    /// refused for them ([`StepError::TooManyContacts`]), so that a run
    /// can refuse a scene before it starts.
    pub fn contact_pairs_now(&self, dt: Real) -> Result<usize, StepError> {
        self.detected_copy(dt)
            .map(|contacts| contacts.pairs.len())
            .map_err(|too_many| self.too_many_contacts(too_many))
    }

    /// A copy of the contact state after a detect stage for a step of `dt`
    /// (s) from the current state; the world's own is left as it is.
    fn detected_copy(&self, dt: Real) -> Result<Contacts, TooManyPairs> {
        let mut contacts = self.contacts.clone();
        detect_into(
            &mut contacts,
            &self.bodies,
            &self.springs,
            &self.particles,
            dt,
        )?;
        Ok(contacts)
    }

    /// A stable time step for the explicit methods (s): every force's
    /// bounds ([`crate::forces::Force::add_stiffness`],
    /// [`StiffnessBounds::stable_time_step`]). With the candidate contact pairs of
    /// the last step (none before the first: see
    /// [`World::stable_time_step_now`]).
    pub fn stable_time_step(&self) -> Real {
        self.stable_time_step_with(&self.contacts)
    }

    /// [`World::stable_time_step`] with the contacts of the current state:
    /// before the first step, those the bodies start in, found by a detect
    /// stage run on a copy (a search, as costly as a step's: for a check
    /// before a run, not for every frame).
    pub fn stable_time_step_now(&self) -> Real {
        self.stable_time_step_with(&self.contacts_now())
    }

    /// [`World::stable_time_step`] with the candidate pairs of `contacts`.
    fn stable_time_step_with(&self, contacts: &Contacts) -> Real {
        let mut bounds = StiffnessBounds::new(self.particles.len());
        self.forces
            .add_stiffness(&self.context_with(contacts), &mut bounds);
        bounds.stable_time_step()
    }
}

/// The detect stage at the state of `particles` into `contacts` (a
/// world's own, or a copy of them).
fn detect_into(
    contacts: &mut Contacts,
    bodies: &[Body],
    springs: &Springs,
    particles: &Particles,
    dt: Real,
) -> Result<(), TooManyPairs> {
    contacts.detect(
        bodies,
        springs,
        &particles.position,
        &particles.velocity,
        dt,
    )
}

vectorised! {
    /// Whether every coordinate of `vectors` lies within `±bound` (NaN
    /// lying nowhere): one flat pass over the reals, which the compiler
    /// vectorises.
    fn coordinates_within(vectors: &[Vec3], bound: Real) -> bool {
        let reals: &[Real] = bytemuck::cast_slice(vectors);
        reals.iter().fold(true, |within, c| within & (c.abs() <= bound))
    }
}

/// `|x|` for a finite `x`, finite even where `|x|²` overflows (the
/// largest component when `|x|` itself would).
fn magnitude(x: Vec3) -> Real {
    let largest = x.abs().max_element();
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    let length = largest * (x / largest).length();
    if length.is_finite() {
        length
    } else {
        largest
    }
}

/// Turn a closed body's faces (or segments) around if they enclose a
/// negative volume, so that their normals point out.
fn orient_outward(body: &mut Body, position: &[Vec3]) {
    if body.enclosed_volume(position).is_some_and(|v| v < 0.0) {
        body.faces.iter_mut().for_each(|f| f.swap(1, 2));
        body.segments.iter_mut().for_each(|s| s.swap(0, 1));
    }
}

/// The parts of a world that every force reads, besides the state.
#[derive(Debug, Clone, Copy)]
struct Frame<'a> {
    colliders: &'a [Collider],
    contacts: &'a Contacts,
    springs: &'a Springs,
    bodies: &'a [Body],
    mass: &'a [Real],
    inverse_mass: &'a [Real],
}

impl<'a> Frame<'a> {
    /// The force context at `time` and the state `(position, velocity)`.
    fn context<'s>(
        &self,
        time: Real,
        position: &'s [Vec3],
        velocity: &'s [Vec3],
    ) -> ForceContext<'s>
    where
        'a: 's,
    {
        ForceContext {
            time,
            position,
            velocity,
            mass: self.mass,
            inverse_mass: self.inverse_mass,
            springs: self.springs,
            bodies: self.bodies,
            colliders: self.colliders,
            contacts: self.contacts,
        }
    }
}

/// The world's derivative function: the forces of the list at a trial
/// state, the masses, and the Jacobian products for the implicit
/// integrators. Integrators call it at every trial state they need.
pub struct Dynamics<'a> {
    forces: &'a mut ForceList,
    frame: Frame<'a>,
}

impl Derivative for Dynamics<'_> {
    fn mass(&self) -> &[Real] {
        self.frame.mass
    }

    fn inverse_mass(&self) -> &[Real] {
        self.frame.inverse_mass
    }

    fn springs(&self) -> &Springs {
        static NO_SPRINGS: std::sync::LazyLock<Springs> =
            std::sync::LazyLock::new(Springs::default);
        let context = self.frame.context(0.0, &[], &[]);
        self.forces.springs(&context).unwrap_or(&NO_SPRINGS)
    }

    fn force(&mut self, time: Real, position: &[Vec3], velocity: &[Vec3], force: &mut [Vec3]) {
        let context = self.frame.context(time, position, velocity);
        self.forces.accumulate(&context, force);
    }

    fn contact_constraints(&self, state: State, dt: Real, out: &mut Vec<ContactConstraint>) {
        out.clear();
        // Rigid bodies meet the colliders as bodies, after the step.
        for body in self.frame.bodies.iter().filter(|b| !b.rigid) {
            for collider in self.frame.colliders {
                collide::add_contact_constraints(
                    collider,
                    state.time + dt,
                    dt,
                    body.particles.clone(),
                    state.position,
                    state.velocity,
                    self.frame.inverse_mass,
                    out,
                );
            }
        }
    }

    fn linearize(&mut self, state: State, which: Jacobians) -> Linearization {
        let context = self
            .frame
            .context(state.time, state.position, state.velocity);
        self.forces.linearize(&context, which)
    }

    fn jacobian_products(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        let context = self
            .frame
            .context(state.time, state.position, state.velocity);
        self.forces
            .jacobian_products(&context, which, scale, p, out);
    }

    fn jacobian_diagonal(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        let context = self
            .frame
            .context(state.time, state.position, state.velocity);
        self.forces
            .jacobian_diagonal(&context, which, scale, diagonal);
    }
}
