//! The world: particles, springs, bodies, forces, colliders and the
//! integrator, and the step that moves them.
//!
//! One step is a short sequence of named stages:
//!
//! 1. **clear forces** and 2. **accumulate forces** (gravity, springs, gas
//!    pressure, air drag, wind, the mouse spring, the extra forces in [`World::forces`], penalty contacts), run by
//!    the integrator through [`Dynamics`] as many times as it needs;
//! 3. **integrate** positions and velocities;
//! 4. **constrain**: the place for distance constraints (rigid rods), which
//!    the engine does not have yet;
//! 5. **collide**: projection-form colliders, where they are at the end of
//!    the step (moving ones follow their path), move particles back out;
//! 6. **guard**: a non-finite or runaway state stops the run with
//!    [`StepError::BlowUp`].

use crate::body::{Body, BodyData};
use crate::collide::{self, Collider};
use crate::error::{BlowUpReason, BuildError, StepError};
use crate::forces::{
    self, AirDrag, Force, ForceContext, GasPressure, Gravity, MouseSpring, SpringForce, Wind,
};
use crate::integrate::{Derivative, Integrator, IntegratorKind};
use crate::measure::{self, Energies};
use crate::particles::Particles;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// World-wide physical settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Acceleration of gravity (m/s²). Default `(0, -9.81, 0)`.
    pub gravity: Vec3,
    /// Global air drag coefficient `c_air` (N·s/m). Default 0.
    pub air_drag: Real,
    /// A particle farther than this from the origin (m) means the run has
    /// blown up. Default 1e6 m.
    pub max_distance: Real,
    /// A particle faster than this (m/s) means the run has blown up.
    /// Default 1e6 m/s.
    pub max_speed: Real,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            gravity: Vec3::new(0.0, -9.81, 0.0),
            air_drag: 0.0,
            max_distance: 1e6,
            max_speed: 1e6,
        }
    }
}

/// A simulated world.
#[derive(Debug)]
pub struct World {
    /// Every particle of every body.
    pub particles: Particles,
    /// Every spring of every body.
    pub springs: Springs,
    /// The bodies, in the order they were added.
    pub bodies: Vec<Body>,
    /// Wind on every surface, if any.
    pub wind: Option<Wind>,
    /// The user's hand: a spring from a grabbed particle to the cursor.
    pub mouse: Option<MouseSpring>,
    /// Any other forces, added after the built-in ones.
    pub forces: Vec<Box<dyn Force>>,
    /// Colliders the particles must stay out of.
    pub colliders: Vec<Collider>,
    /// Gravity, drag and blow-up limits.
    pub settings: Settings,
    integrator: Box<dyn Integrator>,
    time: Real,
    /// Kahan compensation of `time`, so that many small steps add up to the
    /// exact duration (20 000 steps of 2.5e-4 s make 5 s, not 5.000000000000365 s).
    time_compensation: Real,
    steps: u64,
}

impl World {
    /// An empty world with default settings, stepped by `integrator`.
    pub fn new(integrator: IntegratorKind) -> Self {
        World {
            particles: Particles::default(),
            springs: Springs::default(),
            bodies: Vec::new(),
            wind: None,
            mouse: None,
            forces: Vec::new(),
            colliders: Vec::new(),
            settings: Settings::default(),
            integrator: integrator.create(),
            time: 0.0,
            time_compensation: 0.0,
            steps: 0,
        }
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
        if name.is_empty() || name.contains([',', '"', '\n', '\r']) {
            return Err(BuildError::BadName(name.to_string()));
        }
        if self.bodies.iter().any(|b| b.name == name) {
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
        for s in &data.springs {
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
        };
        orient_outward(&mut body, &self.particles.position);
        self.bodies.push(body);
        Ok(self.bodies.len() - 1)
    }

    /// The body called `name`, if any.
    pub fn body(&self, name: &str) -> Option<&Body> {
        self.bodies.iter().find(|b| b.name == name)
    }

    /// Advance the world by `dt` (s): integrate, collide, then check that the
    /// state is still finite and within the limits of [`Settings`].
    pub fn step(&mut self, dt: Real) -> Result<(), StepError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(StepError::InvalidTimeStep { dt });
        }
        self.integrate(dt);
        self.advance_time(dt);
        self.collide();
        self.steps += 1;
        self.guard(dt)
    }

    fn integrate(&mut self, dt: Real) {
        let time = self.time;
        let (mut dynamics, position, velocity, integrator) = self.split();
        integrator.step(time, dt, position, velocity, &mut dynamics);
    }

    /// Split the world into its derivative function and the state the
    /// integrator advances (disjoint borrows of its fields).
    fn split(&mut self) -> (Dynamics<'_>, &mut [Vec3], &mut [Vec3], &mut dyn Integrator) {
        let Particles {
            position,
            velocity,
            force,
            mass,
            inverse_mass,
        } = &mut self.particles;
        let dynamics = Dynamics {
            settings: &self.settings,
            wind: self.wind.as_mut(),
            mouse: self.mouse.as_mut(),
            forces: &mut self.forces,
            colliders: &self.colliders,
            springs: &self.springs,
            bodies: &self.bodies,
            mass,
            inverse_mass,
            force,
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
    fn collide(&mut self) {
        let particles = &mut self.particles;
        for collider in &self.colliders {
            collide::project(
                collider,
                self.time,
                &mut particles.position,
                &mut particles.velocity,
                &particles.inverse_mass,
            );
        }
    }

    fn guard(&self, dt: Real) -> Result<(), StepError> {
        let limits = &self.settings;
        let particles = &self.particles;
        let bad = particles
            .position
            .iter()
            .zip(&particles.velocity)
            .enumerate()
            .find_map(|(i, (x, v))| {
                if !(x.is_finite() && v.is_finite()) {
                    Some((i, BlowUpReason::NonFinite))
                } else if x.length_squared() > limits.max_distance.powi(2) {
                    Some((i, BlowUpReason::TooFar(x.length())))
                } else if v.length_squared() > limits.max_speed.powi(2) {
                    Some((i, BlowUpReason::TooFast(v.length())))
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

    /// Evaluate every force at the current state into `particles.force` (N).
    pub fn evaluate_forces(&mut self) {
        let time = self.time;
        let (mut dynamics, position, velocity, _) = self.split();
        dynamics.accumulate_forces(time, position, velocity);
    }

    /// Every energy term at the current state (J).
    pub fn energies(&self) -> Energies {
        let context = self.context();
        let mut energies = Energies {
            kinetic: measure::kinetic_energy(&self.particles),
            ..Energies::default()
        };
        Gravity {
            acceleration: self.settings.gravity,
        }
        .add_energy(&context, &mut energies);
        SpringForce.add_energy(&context, &mut energies);
        GasPressure.add_energy(&context, &mut energies);
        for force in &self.forces {
            force.add_energy(&context, &mut energies);
        }
        energies.contact = self.colliders.iter().fold(0.0, |sum, c| {
            sum + c.contact_energy(self.time, &self.particles.position)
        });
        energies
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

    /// A stable time step for the explicit methods (s); see
    /// [`measure::stable_time_step`].
    pub fn stable_time_step(&self) -> Real {
        measure::stable_time_step(&self.particles, &self.springs, &self.colliders)
    }

    fn context(&self) -> ForceContext<'_> {
        ForceContext {
            time: self.time,
            position: &self.particles.position,
            velocity: &self.particles.velocity,
            mass: &self.particles.mass,
            springs: &self.springs,
            bodies: &self.bodies,
        }
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

/// The world's derivative function: stages 1 and 2 of the step, then
/// `a = f / m`. Integrators call it at every trial state they need.
pub struct Dynamics<'a> {
    settings: &'a Settings,
    wind: Option<&'a mut Wind>,
    mouse: Option<&'a mut MouseSpring>,
    forces: &'a mut [Box<dyn Force>],
    colliders: &'a [Collider],
    springs: &'a Springs,
    bodies: &'a [Body],
    mass: &'a [Real],
    inverse_mass: &'a [Real],
    force: &'a mut Vec<Vec3>,
}

impl Dynamics<'_> {
    /// Clear the force buffer, then add every force at the trial state.
    fn accumulate_forces(&mut self, time: Real, position: &[Vec3], velocity: &[Vec3]) {
        self.force.fill(Vec3::ZERO);
        let context = ForceContext {
            time,
            position,
            velocity,
            mass: self.mass,
            springs: self.springs,
            bodies: self.bodies,
        };
        let force = self.force.as_mut_slice();
        Gravity {
            acceleration: self.settings.gravity,
        }
        .accumulate(&context, force);
        SpringForce.accumulate(&context, force);
        GasPressure.accumulate(&context, force);
        AirDrag {
            coefficient: self.settings.air_drag,
        }
        .accumulate(&context, force);
        if let Some(wind) = self.wind.as_deref_mut() {
            wind.accumulate(&context, force);
        }
        if let Some(mouse) = self.mouse.as_deref_mut() {
            mouse.accumulate(&context, force);
        }
        for extra in self.forces.iter_mut() {
            extra.accumulate(&context, force);
        }
        for collider in self.colliders {
            collide::penalty_force(collider, time, position, velocity, force);
        }
    }
}

impl Derivative for Dynamics<'_> {
    fn acceleration(
        &mut self,
        time: Real,
        position: &[Vec3],
        velocity: &[Vec3],
        acceleration: &mut [Vec3],
    ) {
        self.accumulate_forces(time, position, velocity);
        for ((a, f), &w) in acceleration
            .iter_mut()
            .zip(self.force.iter())
            .zip(self.inverse_mass)
        {
            *a = *f * w;
        }
    }
}
