//! The derivative function of a model and its forces, as the integrators
//! see it: the forces of the list at trial states, the masses, the
//! Jacobian products. With it an integrator's step is a function of the
//! model's data, the state, the forces (the step's controls among them)
//! and `dt`: [`Integrator::step`](super::Integrator::step) writes the next
//! state in place.

use crate::colliders::{self, ContactConstraint};
use crate::forces::{ForceContext, ForceList, JacobianScale, Jacobians, Linearization};
use crate::model::{Model, State};
use crate::springs::Springs;
use crate::stage::{Stage, Timer};
use crate::units::{Real, Vec3};

use super::Derivative;

/// The derivative function of a [`Model`] and its [`ForceList`]: the
/// forces of the list at a trial state, the masses, and the Jacobian
/// products for the implicit integrators. Integrators call it at every
/// trial state they need. Inside a world's step (`World::step`) the
/// forces' time is the [`Stage::Forces`] stage's, taken out of the
/// integrate stage's.
///
/// # Examples
///
/// A world's integrate stage as a function, `(model, state, forces, dt)
/// → state`: a copy of a world stepped by hand through its parts takes the
/// bits [`World::step`](crate::world::World::step) takes (a world without
/// colliders, contact, rods or muscles, whose other stages change
/// nothing).
///
/// ```
/// use sprung::build::rope;
/// use sprung::integrate::{Dynamics, IntegratorKind};
/// use sprung::{Vec3, World};
///
/// let hanging = || {
///     let mut world = World::new(IntegratorKind::Rk4);
///     world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
///     let line = rope(8, 0.5).unwrap().with_stiffness(200.0).with_damping(0.5);
///     world.add_body("rope", line.with_velocity(Vec3::X)).unwrap();
///     world
/// };
/// let (mut world, mut by_hand) = (hanging(), hanging());
/// world.step(1e-3).unwrap();
///
/// let solver = by_hand.settings.solver;
/// let (model, forces, position, velocity) = by_hand.parts_mut();
/// let mut dynamics = Dynamics::new(model, forces);
/// let mut integrator = IntegratorKind::Rk4.create();
/// integrator.step(0.0, 1e-3, position, velocity, &mut dynamics, &solver).unwrap();
/// assert_eq!(by_hand.particles.position, world.particles.position);
/// assert_eq!(by_hand.particles.velocity, world.particles.velocity);
/// ```
pub struct Dynamics<'a> {
    forces: &'a mut ForceList,
    model: Model<'a>,
    /// The world's stage timer, where a world's step runs it.
    timer: Option<&'a Timer>,
}

impl<'a> Dynamics<'a> {
    /// The derivative function of `model` under the forces of `forces`.
    pub fn new(model: Model<'a>, forces: &'a mut ForceList) -> Self {
        Dynamics {
            forces,
            model,
            timer: None,
        }
    }

    /// The same, timing the forces as the [`Stage::Forces`] stage of
    /// `timer` (a world's step).
    pub(crate) fn timed_by(self, timer: &'a Timer) -> Self {
        Dynamics {
            timer: Some(timer),
            ..self
        }
    }

    /// The context of the forces at `time` and `(position, velocity)`.
    fn context<'s>(
        &self,
        time: Real,
        position: &'s [Vec3],
        velocity: &'s [Vec3],
    ) -> ForceContext<'s>
    where
        'a: 's,
    {
        let state = State {
            time,
            position,
            velocity,
        };
        ForceContext::new(self.model, state)
    }

    /// Run `forces` as the forces stage: the integrate stage's time so far
    /// closed, the forces' own timed (where a timer runs).
    fn timed<T>(timer: Option<&Timer>, forces: impl FnOnce() -> T) -> T {
        let Some(timer) = timer else {
            return forces();
        };
        timer.split(Stage::Integrate);
        let out = forces();
        timer.lap(Stage::Forces);
        out
    }
}

impl Derivative for Dynamics<'_> {
    fn mass(&self) -> &[Real] {
        self.model.mass
    }

    fn inverse_mass(&self) -> &[Real] {
        self.model.inverse_mass
    }

    fn springs(&self) -> &Springs {
        static NO_SPRINGS: std::sync::LazyLock<Springs> =
            std::sync::LazyLock::new(Springs::default);
        let context = self.context(0.0, &[], &[]);
        self.forces.springs(&context).unwrap_or(&NO_SPRINGS)
    }

    fn uniform_acceleration(&self) -> Vec3 {
        self.forces.uniform_acceleration()
    }

    fn force(&mut self, time: Real, position: &[Vec3], velocity: &[Vec3], force: &mut [Vec3]) {
        let context = self.context(time, position, velocity);
        Self::timed(self.timer, || self.forces.accumulate(&context, force));
    }

    fn contact_constraints(&self, state: State, dt: Real, out: &mut Vec<ContactConstraint>) {
        out.clear();
        // Rigid bodies meet the colliders as bodies, after the step.
        for body in self.model.bodies.iter().filter(|b| !b.rigid) {
            for collider in self.model.colliders {
                colliders::add_contact_constraints(
                    collider,
                    state.time + dt,
                    dt,
                    body.particles.clone(),
                    state.position,
                    state.velocity,
                    self.model.inverse_mass,
                    out,
                );
            }
        }
    }

    fn linearize(&mut self, state: State, which: Jacobians) -> Linearization {
        let context = self.context(state.time, state.position, state.velocity);
        Self::timed(self.timer, || self.forces.linearize(&context, which))
    }

    fn jacobian_products(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        let context = self.context(state.time, state.position, state.velocity);
        Self::timed(self.timer, || {
            self.forces
                .jacobian_products(&context, which, scale, p, out)
        });
    }

    fn jacobian_diagonal(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        let context = self.context(state.time, state.position, state.velocity);
        Self::timed(self.timer, || {
            self.forces
                .jacobian_diagonal(&context, which, scale, diagonal)
        });
    }
}
