//! What a world measures of its state, read-only: energies, contacts,
//! volumes, pressures, momentum, centroids and the stable time step.

use crate::contact::{Contacts, TooManyPairs};
use crate::error::StepError;
use crate::forces::{self, ForceContext, StiffnessBounds};
use crate::measure::{self, Energies};
use crate::units::{Real, Vec3};

use super::step::detect_into;
use super::World;
use crate::integrate::Derivative;
use crate::model::State;

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
    ///
    /// A spring of rest length 1 m stretched to 1.5 m stores `½ k (d - L0)²`:
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, SpringData, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// world.set_gravity(Vec3::ZERO);
    /// let mut pair = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(1.5, 0.0, 0.0)]);
    /// pair.springs = vec![SpringData { rest_length: Some(1.0), ..SpringData::between(0, 1) }];
    /// world.add_body("pair", pair.with_stiffness(100.0)).unwrap();
    /// let energies = world.energies();
    /// assert_eq!(energies.get("spring"), Some(0.5 * 100.0 * 0.5 * 0.5));
    /// assert_eq!(energies.kinetic, 0.0);
    /// assert_eq!(energies.total(), 12.5);
    /// ```
    pub fn energies(&self) -> Energies {
        let mut energies = Energies::new(measure::kinetic_energy(&self.particles));
        let contacts = self.contacts_now();
        self.forces
            .add_energy(&self.context_with(&contacts), &mut energies);
        if self.limits.enabled() {
            *energies.term_mut(PLASTIC) = self.limits.plastic_work();
        }
        energies
    }

    /// The names of the potential terms of [`World::energies`], in order:
    /// the standard ones ([`measure::STANDARD_TERMS`]), then those the
    /// forces in the list give, then `plastic` where springs can yield or
    /// break (the energy they took out, [`crate::tearing`]).
    ///
    /// ```
    /// use sprung::measure::STANDARD_TERMS;
    /// use sprung::{IntegratorKind, World};
    ///
    /// let world = World::new(IntegratorKind::Verlet);
    /// assert_eq!(world.energy_names(), STANDARD_TERMS);
    /// assert_eq!(STANDARD_TERMS, ["spring", "gravity", "gas", "contact", "gravitation"]);
    /// ```
    pub fn energy_names(&self) -> Vec<&'static str> {
        let mut names = self.forces.energy_names();
        if self.limits.enabled() {
            names.push(PLASTIC);
        }
        names
    }

    /// Number of contact pairs between bodies closer than the contact
    /// thickness at the current state (among the candidates of the last
    /// detect stage that its allowance reaches: a state far from the last
    /// step's, set by hand, may count fewer; before the first step, among
    /// the pairs a detect stage finds now).
    ///
    /// Two particles of different bodies half a thickness apart touch; a third,
    /// a metre away, touches nothing:
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// let h = world.contacts.settings.thickness; // 1 cm by default
    /// let at = |x: f64| BodyData::from_positions(vec![Vec3::new(x, 0.0, 0.0)]);
    /// world.add_body("a", at(0.0)).unwrap();
    /// world.add_body("b", at(0.5 * h)).unwrap();
    /// world.add_body("c", at(1.0)).unwrap();
    /// assert_eq!(world.active_contacts(), 1);
    /// ```
    pub fn active_contacts(&self) -> usize {
        let mut count = 0;
        self.contacts_now().pairs.for_each_touch(
            &self.particles.position,
            self.contacts.settings.thickness,
            |_| count += 1,
        );
        count
    }

    /// The pairs of bodies that are pressed into each other: with more
    /// than half the contact thickness of theirs overlapping (a particle
    /// nearer than half the thickness to the other's surface, or inside
    /// it), at the current state. The first `most` pairs found, each
    /// `(a, b, particles)` with the bodies' indices (`a < b`, or `a == b`
    /// for a body folded into itself) and how many of its particles are
    /// that deep, in the bodies' order; then how many more particles are
    /// that deep in other pairs. At the start of a run, the CCD
    /// sees such bodies collide at every step until they part, and their
    /// contact pushes them apart at once.
    pub fn overlapping_bodies(&self, most: usize) -> (Vec<(usize, usize, usize)>, usize) {
        let half = 0.5 * self.contacts.settings.thickness;
        let body_of = |p: u32| {
            let p = p as usize;
            self.bodies.partition_point(|b| b.particles.end <= p)
        };
        let (mut pairs, mut others) = (Vec::<(usize, usize, usize)>::new(), 0);
        self.contacts_now().pairs.for_each_touch(
            &self.particles.position,
            self.contacts.settings.thickness,
            |touch| {
                if touch.depth <= half || touch.count == 0 {
                    return;
                }
                let first = body_of(touch.particles[0]);
                let second = body_of(touch.particles[touch.count - 1]);
                let key = (first.min(second), first.max(second));
                let full = pairs.len() >= most;
                match pairs.iter_mut().find(|(a, b, _)| (*a, *b) == key) {
                    Some(pair) => pair.2 += 1,
                    None if !full => pairs.push((key.0, key.1, 1)),
                    None => others += 1,
                }
            },
        );
        pairs.sort_unstable();
        (pairs, others)
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
        let state = State {
            time: self.time,
            position: &self.particles.position,
            velocity: &self.particles.velocity,
        };
        ForceContext::new(self.model_with(contacts), state)
    }

    /// Exact enclosed volume (m³), or area for a 2D body (m²), of body
    /// `body`; `None` if it is not closed.
    ///
    /// The icosahedron inscribed in the unit sphere (an icosphere of no
    /// subdivision) has edge `a = 1 / sin(2π/5)` and volume
    /// `5/12 (3 + √5) a³`; the cloth is open:
    ///
    /// ```
    /// use sprung::build::{self, ClothSprings, SurfaceSprings};
    /// use sprung::{IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// let ball = build::icosphere(1.0, 0, SurfaceSprings::default()).unwrap();
    /// let ball = world.add_body("ball", ball).unwrap();
    /// let sheet = build::cloth(3, 3, 1.0, 1.0, ClothSprings::default()).unwrap();
    /// let sheet = world.add_body("sheet", sheet).unwrap();
    /// let a = 1.0 / (0.4 * std::f64::consts::PI).sin();
    /// let exact = 5.0 / 12.0 * (3.0 + 5_f64.sqrt()) * a.powi(3);
    /// // The vertices are rounded to the nearest double: a few ulps apart.
    /// assert!((world.volume(ball).unwrap() - exact).abs() < 1e-14 * exact);
    /// assert_eq!(world.volume(sheet), None);
    /// ```
    pub fn volume(&self, body: usize) -> Option<Real> {
        self.bodies
            .get(body)?
            .enclosed_volume(&self.particles.position)
    }

    /// Pressure of body `body`'s gas (Pa; N/m for a 2D body); `None` without a gas or such a body.
    ///
    /// A gas ball's pressure is `nRT / V`, with `V` its exact volume:
    ///
    /// ```
    /// use sprung::build::{self, SurfaceSprings};
    /// use sprung::{Gas, IntegratorKind, World};
    ///
    /// let mut ball = build::icosphere(0.5, 1, SurfaceSprings::default()).unwrap();
    /// ball.gas = Some(Gas::new(300.0, 0.0)); // nRT = 300 J at once, no ramp
    /// let mut world = World::new(IntegratorKind::ImplicitEuler);
    /// let index = world.add_body("ball", ball).unwrap();
    /// let volume = world.volume(index).unwrap();
    /// assert_eq!(world.pressure(index), Some(300.0 / volume));
    /// ```
    pub fn pressure(&self, body: usize) -> Option<Real> {
        forces::pressure(self.bodies.get(body)?, &self.particles.position, self.time)
    }

    /// Total linear momentum (kg·m/s).
    ///
    /// Springs pull both their ends alike, so a free pair keeps its momentum:
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, SpringData, Vec3, World};
    ///
    /// let mut world = World::new(IntegratorKind::Rk4);
    /// world.set_gravity(Vec3::ZERO);
    /// let mut pair = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    /// pair.mass = vec![1.0, 3.0];
    /// pair.velocity = vec![Vec3::new(2.0, 1.0, 0.0), Vec3::ZERO];
    /// pair.springs = vec![SpringData::between(0, 1)];
    /// world.add_body("pair", pair.with_stiffness(50.0)).unwrap();
    /// let before = world.linear_momentum();
    /// assert_eq!(before, Vec3::new(2.0, 1.0, 0.0)); // Σ m v
    /// for _ in 0..100 {
    ///     world.step(1e-3).unwrap();
    /// }
    /// // Equal and opposite forces, to rounding.
    /// assert!(world.linear_momentum().distance(before) < 1e-12);
    /// ```
    pub fn linear_momentum(&self) -> Vec3 {
        measure::linear_momentum(&self.particles)
    }

    /// Mass-weighted centroid of body `body` (m); `None` if there is no such body.
    ///
    /// A sphere centred on the origin and moved to `(0, 2, 0)` has its centroid
    /// there (to rounding: the vertices are symmetric only up to it):
    ///
    /// ```
    /// use sprung::build::{self, SurfaceSprings};
    /// use sprung::{IntegratorKind, Vec3, World};
    ///
    /// let ball = build::icosphere(1.0, 1, SurfaceSprings::default()).unwrap();
    /// let ball = ball.placed(1.0, Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0));
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// let index = world.add_body("ball", ball).unwrap();
    /// let centroid = world.centroid(index).unwrap();
    /// assert!(centroid.distance(Vec3::new(0.0, 2.0, 0.0)) < 1e-15);
    /// assert_eq!(world.centroid(1), None);
    /// ```
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
    ///
    /// # Examples
    ///
    /// A uniform chain of masses `m` and springs `k` oscillates at most at
    /// `ω_max = 2 √(k/m)`, so its stable step is `2 / ω_max` (exact here:
    /// `k/m = 1600` is a square):
    ///
    /// ```
    /// use sprung::{build, IntegratorKind, World};
    ///
    /// let (k, m) = (400.0, 0.25);
    /// let chain = build::rope(6, 1.0).unwrap().with_stiffness(k).with_mass(m);
    /// let mut world = World::new(IntegratorKind::SymplecticEuler);
    /// world.add_body("chain", chain).unwrap();
    /// let omega_max = 2.0 * f64::sqrt(k / m);
    /// assert_eq!(world.stable_time_step(), 2.0 / omega_max);
    /// ```
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

/// The energy term of the work taken out by springs that yield and break
/// (J), summed since the start: with it the energy balance of a run whose
/// springs give still closes.
pub const PLASTIC: &str = "plastic";
