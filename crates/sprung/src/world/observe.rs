//! What a world measures of its state, read-only: energies, contacts,
//! volumes, pressures, momentum, centroids and the stable time step.

use crate::contact::{Contacts, TooManyPairs};
use crate::error::StepError;
use crate::forces::{self, ForceContext, StiffnessBounds};
use crate::measure::{self, Energies};
use crate::{Real, Vec3};

use super::dynamics::Frame;
use super::step::detect_into;
use super::World;
use crate::integrate::Derivative;

impl World {
    /// Evaluate every force at the current state into `particles.force` (N).
    pub fn evaluate_forces(&mut self) {
        let time = self.time;
        let mut force = std::mem::take(&mut self.particles.force);
        let (mut dynamics, position, velocity, _) = self.split();
        dynamics.force(time, position, velocity, &mut force);
        self.particles.force = force;
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
    pub(super) fn contacts_now(&self) -> std::borrow::Cow<'_, Contacts> {
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
    pub(super) fn context_with<'a>(&'a self, contacts: &'a Contacts) -> ForceContext<'a> {
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
    pub(super) fn detected_copy(&self, dt: Real) -> Result<Contacts, TooManyPairs> {
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
    pub(super) fn stable_time_step_with(&self, contacts: &Contacts) -> Real {
        let mut bounds = StiffnessBounds::new(self.particles.len());
        self.forces
            .add_stiffness(&self.context_with(contacts), &mut bounds);
        bounds.stable_time_step()
    }
}
