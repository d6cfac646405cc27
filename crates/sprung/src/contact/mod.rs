//! Contact between bodies (docs/physics.md §5): every body against every other,
//! and a surface against itself where asked.
//!
//! **Method: penalty forces with a thickness.** A particle closer than the
//! contact thickness `h` to a triangle of another body (a segment in 2D), an
//! edge closer than `h` to another edge (where a surface is open: cloth),
//! and two particles of bodies without surfaces closer than `h`, are pushed
//! apart by a spring `k (h - d)` along the contact normal with damping on
//! the normal relative velocity. Each force is shared among the vertices
//! of the element by the weights of the closest point, with the opposite
//! force on the other side, so linear momentum is conserved exactly.
//! Coulomb friction on the relative tangential velocity acts as impulses
//! after each step, on the touches the penalty force last pushed, each
//! impulse at most `μ` times the normal force it pushed with times the
//! step: it holds a body at rest below the friction angle, which a
//! friction force that depends on the sliding speed cannot.
//!
//! Why penalty rather than impulses or projection: a penalty contact is a
//! force, so it is one more entry of the world's force list. It works
//! unchanged with every integrator, explicit or implicit (its Jacobian,
//! `-k n nᵀ` on the relative motion, joins the implicit solves, so stiff
//! contacts are stable at large steps), it has an energy (`½ k (h - d)²`, the
//! `contact` term), and it is continuous in the positions (its damping
//! starts with the touch, though: a jump the adaptive `rk45` meets with
//! very small steps where contacts keep starting). Its stiffness bounds the explicit time step like a spring does;
//! `substeps = "auto"` accounts for it. By default the stiffness is chosen
//! per contact from the effective mass `m` of its two sides at their
//! closest points ([`effective_mass`]: `1 / Σ w_i² / m_i`, two particles'
//! reduced mass): `k = m (v_ref / h)²` with `v_ref =`
//! [`REFERENCE_SPEED`], so that sides closing at that speed are stopped
//! within the thickness, and the damping is `c = m v_ref / h` (half of
//! critical). Every contact then oscillates at `v_ref / h` whatever the
//! masses: a light cloth under a heavy ball is not made stiffer than the
//! step can follow, as the heavier side's mass alone would.
//!
//! **Stages.** The *detect* stage ([`Contacts::detect`]) runs once per step
//! before integrating: a uniform grid ([`grid`]) finds, in time linear in
//! the number of elements, every pair of elements within the thickness
//! plus a margin covering the step's motion (the *reach*), and keeps them
//! as candidate pairs (`ContactPairs`): a pair is a candidate when it
//! would touch if the thickness were the reach. (A particle that got
//! through a closed surface, behind an element but not over its inside,
//! is no candidate of that element: if it then slides over that
//! element's inside, it is pushed out from the next search on.) The particles that may
//! meet another body go into the grid, one cell each, and each surface
//! element asks it for the particles within reach of its box; edges and
//! loose particles are found among themselves. The search runs in parallel
//! over chunks of elements and puts what it found in a fixed order (by
//! particle, then element, then in buckets of clearance, below), so the
//! pairs are the same whatever the number of threads. The penalty force
//! ([`BodyContacts`](crate::forces::BodyContacts)) evaluates only those pairs, at every trial state
//! the integrator asks for, measuring them in parallel and adding their
//! forces in the pairs' order.
//!
//! Each pair keeps its *clearance*, how far beyond the thickness it was
//! when found, and each step the detect stage sets the *allowance*, how
//! much closer any two elements can have come since: twice the farthest
//! a particle has moved since the search (counted from a common move),
//! plus the step's closing distance at the velocities it starts with,
//! plus how far the paths can bend as the velocities change (taken as
//! twice the last step's change). A pair whose clearance is larger cannot
//! touch in the step, and is passed over without reading its positions.
//! Most candidates of a cloth lying in folds are such pairs; each list of
//! pairs is kept in buckets of clearance, nearest first, so a measure
//! does not even read them.
//!
//! **A bound on the pairs.** A search may find at most
//! [`PAIRS_PER_ELEMENT`] candidate pairs per element that takes part
//! (querying particle, triangle, segment, edge or loose particle), and at
//! least [`MIN_PAIR_LIMIT`] in all ([`pair_limit`]). A thickness many
//! times the spacing of the particles would find hundreds per element,
//! their memory growing with its square; the step is refused instead
//! ([`crate::StepError::TooManyContacts`]), before anything moves.
//!
//! **Sides.** A closed surface pushes another body's particles along its
//! outward normal, so a particle that got inside is pushed out. An open
//! surface (cloth), and a closed one its own particles (they meet it from
//! inside when it folds in on itself), pushes towards the side the
//! particle was on when the pair was found, at the start of the step, so
//! a particle that crossed within a step is pushed back, not on through.
//! Edges meet edges where a surface is open or collides with itself.

pub mod ccd;
pub(crate) mod geometry;
#[doc(hidden)]
pub mod grid;
pub mod inside;

mod buckets;
mod detect;
pub(crate) mod friction;
mod links;
pub(crate) mod pairs;
#[cfg(test)]
mod random;
pub(crate) mod rigid_friction;
mod state;

pub(crate) use detect::TooManyPairs;
pub use detect::{pair_limit, MIN_PAIR_LIMIT, PAIRS_PER_ELEMENT};
pub(crate) use pairs::{
    ContactPairs, EdgeEdge, PointElement, PointPoint, PointSegment, PointTriangle,
};
pub(crate) use rigid_friction::RigidParts;

use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// The speed (m/s) a particle arriving at a contact is stopped from within
/// the thickness by the default stiffness.
pub const REFERENCE_SPEED: Real = 10.0;

/// The contact thickness by default (m).
pub const DEFAULT_THICKNESS: Real = 0.01;

/// How bodies touch (the `[contact]` scene table).
///
/// Two particles of different bodies meet as balls of diameter `h`, the
/// thickness: they close to less than `h`, never pass each other, and fly
/// apart again, momentum kept (equal and opposite forces) and some energy
/// lost (the default damping is half the critical one):
///
/// ```
/// use sprung::{BodyData, ContactSettings, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// world.set_gravity(Vec3::ZERO);
/// world.contacts.settings = ContactSettings { thickness: 0.05, ..ContactSettings::default() };
/// let ball = |x: f64, v: f64| {
///     BodyData::from_positions(vec![Vec3::new(x, 0.0, 0.0)]).with_velocity(Vec3::new(v, 0.0, 0.0))
/// };
/// world.add_body("left", ball(-0.1, 1.0)).unwrap();
/// world.add_body("right", ball(0.1, -1.0)).unwrap();
/// let mut closest = f64::INFINITY;
/// for _ in 0..300 {
///     world.step(1e-3).unwrap();
///     let x = &world.particles.position;
///     closest = closest.min(x[1].x - x[0].x);
/// }
/// assert!(0.0 < closest && closest < 0.05);
/// let v = &world.particles.velocity;
/// assert!(v[0].x < 0.0 && v[1].x > 0.0 && v[1].x < 1.0);
/// assert!(world.linear_momentum().length() < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSettings {
    /// Contact between bodies on or off. Default on.
    pub enabled: bool,
    /// Distance (m) below which surfaces push apart. Default 1 cm.
    pub thickness: Real,
    /// Coulomb friction coefficient `μ` on the relative tangential velocity
    /// (impulses after each step). Default 0.
    pub friction: Real,
    /// Penalty stiffness (N/m); `None`: `m (v_ref / h)²` per contact, with
    /// `m` the contact's effective mass ([`effective_mass`]).
    pub stiffness: Option<Real>,
    /// Penalty damping on the normal relative velocity (N·s/m); `None`:
    /// `m v_ref / h` per contact.
    pub damping: Option<Real>,
    /// The CCD behind the penalty ([`ccd`]): continuous collision
    /// detection over each step's motion, so that no particle passes
    /// through a surface. Default on.
    pub ccd: bool,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            enabled: true,
            thickness: DEFAULT_THICKNESS,
            friction: 0.0,
            stiffness: None,
            damping: None,
            ccd: true,
        }
    }
}

impl ContactSettings {
    /// Check the settings; errors name the `[contact]` key.
    pub fn validate(&self) -> Result<(), BuildError> {
        let checks = [
            ("contact.thickness", Some(self.thickness), true),
            ("contact.friction", Some(self.friction), false),
            ("contact.stiffness", self.stiffness, true),
            ("contact.damping", self.damping, false),
        ];
        for (field, value, positive) in checks {
            let Some(value) = value else { continue };
            let bad = !value.is_finite() || value < 0.0 || (positive && value == 0.0);
            if bad {
                return Err(BuildError::OutOfRange {
                    field,
                    value,
                    reason: if positive {
                        "must be positive and finite"
                    } else {
                        "must be finite and not negative"
                    },
                });
            }
        }
        Ok(())
    }

    /// [`ContactSettings::validate`], and the settings against the world's
    /// limits (`max_distance` in m, `max_speed` in m/s; see
    /// [`crate::world::Settings`]): a thickness beyond `max_distance`
    /// (every particle would touch everything within the world), or so thin
    /// that the default stiffness `m (v_ref / h)²` overflows; a stiffness
    /// whose energy, or a damping whose work, within the limits could
    /// exceed [`crate::error::ENERGY_LIMIT`] (as a spring's).
    pub fn validate_within(&self, max_distance: Real, max_speed: Real) -> Result<(), BuildError> {
        self.validate()?;
        let rate = REFERENCE_SPEED / self.thickness;
        if self.thickness > max_distance || !(rate * rate).is_finite() {
            return Err(BuildError::OutOfRange {
                field: "contact.thickness",
                value: self.thickness,
                reason: "must lie within the world's `max_distance` (m), and not be so thin that the default stiffness m (10 m/s / thickness)² overflows",
            });
        }
        let reach = 2.0 * max_distance;
        let limit = crate::error::ENERGY_LIMIT;
        if let Some(k) = self.stiffness.filter(|&k| 0.5 * k * reach * reach >= limit) {
            return Err(BuildError::OutOfRange {
                field: "contact.stiffness",
                value: k,
                reason: "too large: the energy of a contact within the world's limits (`max_distance` in [sim]) could exceed the 1e290 J the diagnostics can sum",
            });
        }
        if let Some(c) = self.damping.filter(|&c| c * max_speed * reach >= limit) {
            return Err(BuildError::OutOfRange {
                field: "contact.damping",
                value: c,
                reason: "too large: the work of a contact's damping within the world's limits (`max_distance`, `max_speed` in [sim]) could exceed the 1e290 J the diagnostics can sum",
            });
        }
        Ok(())
    }

    /// The penalty stiffness (N/m) and damping (N·s/m) of a contact whose
    /// sides have the effective mass `mass` (kg) along its normal (see
    /// [`effective_mass`]).
    pub fn coefficients(&self, mass: Real) -> (Real, Real) {
        let rate = REFERENCE_SPEED / self.thickness;
        (
            self.stiffness.unwrap_or(mass * rate * rate),
            self.damping.unwrap_or(mass * rate),
        )
    }
}

/// The effective mass (kg) of a contact between closest points `Σ w_i
/// x_i` (weights `weights` of particles of inverse masses
/// `inverse_mass`, 1/kg, positive on one side and negative on the other):
/// `1 / Σ w_i² / m_i`, what the contact's force accelerates along its
/// normal (two particles: their reduced mass), at most the heaviest moving
/// particle's mass: where only particles of small weight move (a pinned
/// particle against a triangle next to its pinned edge), the stiffness
/// would otherwise grow as `1 / w²` without bound. Pinned particles count
/// as infinitely heavy; `None` where nothing of weight moves (every
/// particle pinned, or only particles of weight zero moving).
pub fn effective_mass(weights: &[Real], inverse_mass: &[Real]) -> Option<Real> {
    let inverse: Real = weights
        .iter()
        .zip(inverse_mass)
        .map(|(w, m)| w * w * m)
        .sum();
    // The heaviest moving particle's inverse mass. One division for both
    // the cap and the mass: for positive `a` and `b` (subnormal or
    // infinite included), `min(1/a, 1/b) = 1/max(a, b)` holds exactly in
    // floating point, as a correctly rounded reciprocal never rises as
    // its argument does; divisions were most of this function's time.
    let heaviest_inverse = inverse_mass
        .iter()
        .copied()
        .filter(|&m| m > 0.0)
        .fold(Real::INFINITY, Real::min);
    (inverse > 0.0).then(|| 1.0 / inverse.max(heaviest_inverse))
}

/// The state at the end of a (sub)step that the friction stage changes by
/// impulses ([`Force::apply_impulses`](crate::forces::Force::apply_impulses)), and the world it belongs to.
#[derive(Debug)]
pub struct ImpulseContext<'a> {
    /// Simulated time at the end of the (sub)step (s).
    pub time: Real,
    /// The (sub)step's length (s).
    pub dt: Real,
    /// Positions (m), to move by a velocity change times `dt`.
    pub position: &'a mut [Vec3],
    /// Velocities (m/s), to change by the impulses over the masses.
    pub velocity: &'a mut [Vec3],
    /// Inverse masses (1/kg), zero for pinned particles.
    pub inverse_mass: &'a [Real],
    /// Contact between bodies: settings and the step's candidate pairs.
    pub contacts: &'a Contacts,
    /// The rigid bodies' particles and motions: impulses on them act on
    /// the bodies' motions.
    pub(crate) rigid: RigidParts<'a>,
}

#[cfg(test)]
mod tests {
    use super::effective_mass;
    use crate::units::Real;

    #[test]
    fn the_effective_mass_is_the_reduced_mass_at_most_the_heaviest_moving_one() {
        // Two particles of 1 and 3 kg: 3/4 kg. A 1 kg particle against a
        // triangle of 1 kg vertices at its centroid: 1 / (1 + 3/9) = 3/4
        // kg. A pinned particle against a triangle whose only moving
        // vertex (1 kg) has weight 1e-3: 1e6 kg by the formula, capped at
        // 1 kg. Every particle pinned, or only one of weight zero moving:
        // none.
        let close = |a: Option<f64>, b: f64| a.is_some_and(|a| (a - b).abs() <= 1e-15 * b);
        assert!(close(effective_mass(&[1.0, -1.0], &[1.0, 1.0 / 3.0]), 0.75));
        let third = 1.0 / 3.0;
        let centroid = effective_mass(&[1.0, -third, -third, -third], &[1.0; 4]);
        assert!(close(centroid, 0.75));
        let pinned = effective_mass(&[1.0, -0.999, -1e-3, 0.0], &[0.0, 0.0, 1.0, 0.0]);
        assert_eq!(pinned, Some(1.0));
        assert_eq!(effective_mass(&[1.0, -1.0], &[0.0, 0.0]), None);
        assert_eq!(effective_mass(&[1.0, -1.0, 0.0], &[0.0, 0.0, 2.0]), None);
    }

    #[test]
    fn one_division_gives_the_bits_of_the_reciprocals_compared() {
        // Claim: the effective mass, taken with one division as
        // `1 / max(Σ w² / m, 1 / M)`, is the same bits as `min(1 / Σ w² /
        // m, M)` with `M` the heaviest moving particle's mass, over masses
        // from subnormal to huge (the reciprocal of a subnormal inverse
        // mass overflows to infinity in both), and the largest inverse
        // mass a float holds.
        let inverse_masses = [1e-310, 1e-300, 0.37, 1.0, 3.0, 1e300, Real::MAX];
        for &a in &inverse_masses {
            for &b in &inverse_masses {
                for w in [1.0, 0.5, 1e-3, 0.0] {
                    let weights = [1.0, -w];
                    let inverse: Real = a + w * w * b;
                    let heaviest = (1.0 / a).max(1.0 / b);
                    let expected = (1.0 / inverse).min(heaviest);
                    let got = effective_mass(&weights, &[a, b]).expect("a moves");
                    assert_eq!(got.to_bits(), expected.to_bits(), "{a} {b} {w}");
                }
            }
        }
    }
}

/// The contact state of a world: settings, the candidate pairs of the
/// current step, and the broad phase's buffers.
#[derive(Debug, Clone, Default)]
pub struct Contacts {
    /// How bodies touch.
    pub settings: ContactSettings,
    /// The candidate pairs found by the last detect stage.
    pub(crate) pairs: ContactPairs,
    scratch: detect::Scratch,
    found: detect::Found,
    links: links::Links,
    pub(crate) ccd: ccd::Ccd,
}

impl Contacts {
    /// The number of candidate contact pairs the last detect stage kept
    /// (pairs of elements within the thickness plus the margin of the
    /// step's motion; [`crate::World::active_contacts`] counts those
    /// touching).
    pub fn candidate_pairs(&self) -> usize {
        self.pairs.len()
    }
}
