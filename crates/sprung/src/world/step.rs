//! The step: a walk over its stages, in the order [`Stage`] lists them.

use crate::body::{self, Body};
use crate::colliders;
use crate::constrain::RodReport;
use crate::contact::ccd::CcdReport;
use crate::contact::{Contacts, RigidParts, TooManyPairs};
use crate::error::{BlowUpReason, BuildError, StepError};
use crate::forces::ImpulseContext;
use crate::integrate::{IntegratorKind, StepReport};
use crate::parallel;
use crate::particles::Particles;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

use super::bodies::magnitude;
use super::World;
use super::{Substeps, MAX_SUBSTEPS, RESTING_SPEED};

/// Most rounds of rods and rigid bodies taking turns in the constrain
/// stage, where rods end on rigid bodies.
const RIGID_ROD_ROUNDS: usize = 100;
use crate::stage::Stage;

impl World {
    /// Advance the world by `dt` (s): detect contacts, then per substep set
    /// the muscles, integrate, collide, add friction and constrain (rods,
    /// rigid bodies), then check that the state is still finite and within
    /// the limits of [`Settings`](super::Settings). Returns
    /// what the integrator reported (also kept in
    /// [`World::last_step_report`]); a solve that stopped above its
    /// tolerance is counted in [`World::solver_stats`].
    ///
    /// Called from outside the engine's pool of threads, the step of a
    /// world of more than [`parallel::CHUNK`] particles, or of a few
    /// thousand whose springs are cut finer than a chunk (whose loops are
    /// shared among threads, [`parallel::particle_span`]), is handed to
    /// the pool at once
    /// ([`parallel::in_pool`]) rather than each of its parallel loops one
    /// by one, the caller waiting each time; a smaller world, whose loops
    /// mostly run on the calling thread, steps right there (a hand-over
    /// costs more than its whole step).
    ///
    /// # Examples
    ///
    /// A particle falling from rest under symplectic Euler (`v += g dt`, then
    /// `x += v dt`) has, after `n` steps, `v_n = -g n dt` and
    /// `x_n = -g dt² n (n + 1) / 2`. With `g = 8 m/s²` and `dt = 1/16 s` every
    /// number is a short binary fraction, so the closed form holds to the bit:
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.set_gravity(Vec3::new(0.0, -8.0, 0.0));
    /// world.add_body("ball", BodyData::from_positions(vec![Vec3::ZERO])).unwrap();
    /// let (g, dt, n) = (8.0, 1.0 / 16.0, 10);
    /// for _ in 0..n {
    ///     world.step(dt).unwrap();
    /// }
    /// let n = f64::from(n);
    /// assert_eq!(world.particles.velocity[0].y, -g * n * dt);
    /// assert_eq!(world.particles.position[0].y, -g * dt * dt * n * (n + 1.0) / 2.0);
    /// assert_eq!((world.time(), world.steps()), (n * dt, 10));
    /// ```
    pub fn step(&mut self, dt: Real) -> Result<StepReport, StepError> {
        self.timer.begin_step();
        // Its own span always, never one left by another world's step this
        // thread was lent to while waiting (a Batch's worlds share threads).
        let span = parallel::particle_span(self.springs.len(), self.particles.len());
        let report = if self.particles.len() > parallel::CHUNK
            || (span < parallel::CHUNK && parallel::threads() > 1)
        {
            parallel::in_pool(|| parallel::with_span(span, || self.step_here(dt)))
        } else {
            parallel::with_span(span, || self.step_here(dt))
        };
        self.timer.end_step();
        report
    }

    /// [`World::step`], on the thread it is called from: a walk over the
    /// stages ([`Stage`]), each timed when profiling.
    pub(super) fn step_here(&mut self, dt: Real) -> Result<StepReport, StepError> {
        self.check_step(dt)?;
        self.timer.open();
        self.stage(Stage::Detect, |w| w.detect(dt))?;
        let substeps = self.stage(Stage::Substeps, |w| w.substeps(dt));
        let h = dt / Real::from(substeps);
        let mut report = StepReport::default();
        let guarded = self.mark_guarded();
        let mut ccd = CcdReport::default();
        self.ccd_stop = None;
        for _ in 0..substeps {
            if guarded {
                self.ccd_start.clone_from(&self.particles.position);
            }
            self.stage(Stage::Muscles, World::move_muscles)?;
            report = report.then(self.stage(Stage::Integrate, |w| w.integrate(h))?);
            self.stage(Stage::Collide, World::collide);
            self.stage(Stage::Friction, |w| w.friction(h));
            self.stage(Stage::Constrain, |w| w.constrain(h));
            self.stage(Stage::Give, World::give);
            ccd = ccd.then(self.stage(Stage::Ccd, |w| w.ccd(h)));
            if self.ccd_stop.is_some() {
                // The guard stage stops the run on it.
                break;
            }
        }
        self.last_ccd = ccd;
        if substeps > 1 {
            report.substeps = Some(substeps);
            report.step_size = Some(h);
        }
        self.stage(Stage::Guard, |w| w.guard_step(dt, report))?;
        Ok(report)
    }

    /// Run `stage` (`run`) and close its timer.
    fn stage<T>(&mut self, stage: Stage, run: impl FnOnce(&mut World) -> T) -> T {
        let out = run(self);
        self.timer.lap(stage);
        out
    }

    /// Refuse a step of `dt` (s) that is not positive and finite, or
    /// settings that changed to bad ones since the last step.
    fn check_step(&self, dt: Real) -> Result<(), StepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(StepError::InvalidTimeStep { dt });
        }
        // Finite in, finite out: the clock too.
        let time = self.time + dt;
        if !time.is_finite() {
            return Err(self.not_finite("time", time, dt));
        }
        self.validate_settings().map_err(StepError::InvalidSettings)
    }

    /// The error for a reported `quantity` (named as its column) whose
    /// `value` is not finite, at the world's step and time, stepping by
    /// `dt` (s): what a writer of rows or frames returns instead of writing
    /// it.
    pub fn not_finite(&self, quantity: &str, value: Real, dt: Real) -> StepError {
        StepError::NotFinite {
            step: self.steps,
            time: self.time,
            quantity: quantity.to_string(),
            value,
            dt,
            stable_dt: self.stable_time_step(),
        }
    }

    /// The guard stage of a step of `dt` (s) whose integrator reported
    /// `report`: count the step and its unconverged solves, then fail it if
    /// the state blew up or a rod is off its length.
    fn guard_step(&mut self, dt: Real, report: StepReport) -> Result<(), StepError> {
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
        if let Some(stop) = self.ccd_stop.take() {
            return Err(self.ccd_error(stop, dt));
        }
        self.check_rods()
    }

    /// Fail the step if a rod is off its length by more than
    /// [`crate::constrain::ROD_FAILURE`] after the constrain stage, or by
    /// more than `constraint_tolerance` where that is looser.
    pub(super) fn check_rods(&self) -> Result<(), StepError> {
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
    pub(super) fn move_muscles(&mut self) -> Result<(), StepError> {
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
    pub(super) fn friction(&mut self, dt: Real) {
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

    /// The constrain stage: rods, then rigid bodies (taking turns where
    /// rods end on rigid bodies), over a step of `dt` (s).
    pub(super) fn constrain(&mut self, dt: Real) {
        let Particles {
            position,
            velocity,
            mass,
            inverse_mass,
            ..
        } = &mut self.particles;
        let constraints = self.settings.constraints;
        // Below this approach speed a rigid body's contact rests rather
        // than bounces: two steps of gravity, and at least RESTING_SPEED
        // (a body rocking on a face would otherwise bounce for ever).
        let gravity = self.forces.uniform_acceleration().length();
        let rest_speed = (2.0 * dt * gravity).max(RESTING_SPEED);
        // Rods that end on a rigid body (joins to a pole): its shape
        // matching moves their ends again, so the two take turns until the
        // rods hold (alternating projections, converging linearly).
        let on_rigid = |p: u32| {
            self.rigid
                .list
                .iter()
                .any(|r| r.particles.contains(&(p as usize)))
        };
        let rods = &self.rods;
        let turns = !self.rigid.list.is_empty()
            && rods.first.iter().chain(&rods.second).any(|&p| on_rigid(p));
        for _ in 0..=RIGID_ROD_ROUNDS {
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
            self.rigid.project(
                position,
                velocity,
                mass,
                &self.colliders,
                self.time,
                dt,
                rest_speed,
            );
            if !turns {
                break;
            }
            (self.last_rods.worst, self.last_rods.error) = self.rods.worst(position);
            if self.last_rods.error <= constraints.tolerance {
                break;
            }
        }
    }

    /// Check the solver, contact and substep settings.
    pub(super) fn validate_settings(&self) -> Result<(), BuildError> {
        self.settings.constraints.validate()?;
        self.settings.solver.validate()?;
        self.contacts
            .settings
            .validate_within(self.settings.max_distance, self.settings.max_speed)?;
        for collider in &self.colliders {
            collider.validate_within(self.settings.max_distance)?;
        }
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
    pub(super) fn substeps(&mut self, dt: Real) -> u32 {
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
    pub(super) fn detect(&mut self, dt: Real) -> Result<(), StepError> {
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
    pub(super) fn too_many_contacts(&self, too_many: TooManyPairs) -> StepError {
        StepError::TooManyContacts {
            step: self.steps + 1,
            time: self.time,
            limit: too_many.limit,
            per_element: crate::contact::PAIRS_PER_ELEMENT,
            least: crate::contact::MIN_PAIR_LIMIT,
            thickness: self.contacts.settings.thickness,
        }
    }

    /// The integrate stage: positions and velocities over a (sub)step of
    /// `dt` (s), the forces evaluated (and timed) as the integrator asks;
    /// the time advances.
    pub(super) fn integrate(&mut self, dt: Real) -> Result<StepReport, StepError> {
        if !self.rods.is_empty() {
            // The rods keep their directions from the start of the step.
            self.step_start.clear();
            self.step_start.extend_from_slice(&self.particles.position);
        }
        let (time, steps, solver) = (self.time, self.steps, self.settings.solver);
        let (mut dynamics, position, velocity, integrator) = self.split();
        let report = integrator
            .step(time, dt, position, velocity, &mut dynamics, &solver)
            .map_err(|source| StepError::Solver {
                step: steps + 1,
                time,
                source,
            })?;
        self.advance_time(dt);
        Ok(report)
    }

    /// Count `steps` steps of `dt` (s) taken outside the engine (by the
    /// GPU step, `sprung-gpu`) whose end state is already in
    /// [`World::particles`]: the clock advances as that many calls of
    /// [`World::step`] advance it (each substep's time added with the same
    /// compensated sum, so the times are the same bits), and the state is
    /// guarded as after a step (a particle past `max_distance` or
    /// `max_speed`, or not finite, is the error of the last of them).
    /// Substeps are counted as [`Substeps::Fixed`] says (one under
    /// [`Substeps::Auto`], which the GPU step refuses).
    ///
    /// ```
    /// use sprung::{IntegratorKind, Substeps, World};
    ///
    /// let mut stepped = World::new(IntegratorKind::Verlet);
    /// stepped.settings.substeps = Substeps::Fixed(3);
    /// for _ in 0..7 {
    ///     stepped.step(0.1).unwrap();
    /// }
    /// let mut counted = World::new(IntegratorKind::Verlet);
    /// counted.settings.substeps = Substeps::Fixed(3);
    /// counted.took_steps(0.1, 7).unwrap();
    /// assert_eq!((counted.time(), counted.steps()), (stepped.time(), stepped.steps()));
    /// assert_eq!(counted.steps(), 7);
    /// ```
    pub fn took_steps(&mut self, dt: Real, steps: u64) -> Result<(), StepError> {
        self.check_step(dt)?;
        let substeps = match self.settings.substeps {
            Substeps::Fixed(n) => n,
            Substeps::Auto => 1,
        };
        let h = dt / Real::from(substeps);
        for _ in 0..steps {
            for _ in 0..substeps {
                self.advance_time(h);
            }
            self.steps += 1;
        }
        self.last_report = StepReport::default();
        self.guard(dt)
    }

    pub(super) fn advance_time(&mut self, dt: Real) {
        let increment = dt - self.time_compensation;
        let time = self.time + increment;
        self.time_compensation = (time - self.time) - increment;
        self.time = time;
    }

    /// The projection stage, at the time after the step (`self.time` has
    /// been advanced), where moving colliders have got to.
    /// Rigid bodies meet the colliders as bodies, in the constrain stage.
    pub(super) fn collide(&mut self) {
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
                    colliders::project(collider, time, x, v, inverse_mass);
                }
            });
        }
    }

    pub(super) fn guard(&self, dt: Real) -> Result<(), StepError> {
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
}

/// The detect stage at the state of `particles` into `contacts` (a
/// world's own, or a copy of them).
pub(super) fn detect_into(
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
