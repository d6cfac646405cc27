//! The world's derivative function, as the integrators see it: the forces
//! of the list at trial states, the masses, the Jacobian products.

use crate::body::Body;
use crate::colliders::{self, Collider, ContactConstraint};
use crate::contact::Contacts;
use crate::forces::{ForceContext, ForceList, JacobianScale, Jacobians, Linearization};
use crate::integrate::{Derivative, Integrator, State};
use crate::particles::Particles;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

use super::World;
use crate::stage::{Stage, Timer};

impl World {
    /// Split the world into its derivative function and the state the
    /// integrator advances (disjoint borrows of its fields).
    pub(super) fn split(
        &mut self,
    ) -> (Dynamics<'_>, &mut [Vec3], &mut [Vec3], &mut dyn Integrator) {
        let Particles {
            position,
            velocity,
            mass,
            inverse_mass,
            ..
        } = &mut self.particles;
        let dynamics = Dynamics {
            forces: &mut self.forces,
            timer: &self.timer,
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
}

/// The parts of a world that every force reads, besides the state.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame<'a> {
    pub colliders: &'a [Collider],
    pub contacts: &'a Contacts,
    pub springs: &'a Springs,
    pub bodies: &'a [Body],
    pub mass: &'a [Real],
    pub inverse_mass: &'a [Real],
}

impl<'a> Frame<'a> {
    /// The force context at `time` and the state `(position, velocity)`.
    pub(super) fn context<'s>(
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
/// integrators. Integrators call it at every trial state they need; the
/// forces' time is the [`Stage::Forces`] stage's, taken out of the
/// integrate stage's.
pub struct Dynamics<'a> {
    forces: &'a mut ForceList,
    timer: &'a Timer,
    frame: Frame<'a>,
}

impl Dynamics<'_> {
    /// Run `forces` as the forces stage: the integrate stage's time so far
    /// closed, the forces' own timed.
    fn timed<T>(timer: &Timer, forces: impl FnOnce() -> T) -> T {
        timer.split(Stage::Integrate);
        let out = forces();
        timer.lap(Stage::Forces);
        out
    }
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
        Self::timed(self.timer, || self.forces.accumulate(&context, force));
    }

    fn contact_constraints(&self, state: State, dt: Real, out: &mut Vec<ContactConstraint>) {
        out.clear();
        // Rigid bodies meet the colliders as bodies, after the step.
        for body in self.frame.bodies.iter().filter(|b| !b.rigid) {
            for collider in self.frame.colliders {
                colliders::add_contact_constraints(
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
        let context = self
            .frame
            .context(state.time, state.position, state.velocity);
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
        let context = self
            .frame
            .context(state.time, state.position, state.velocity);
        Self::timed(self.timer, || {
            self.forces
                .jacobian_diagonal(&context, which, scale, diagonal)
        });
    }
}
