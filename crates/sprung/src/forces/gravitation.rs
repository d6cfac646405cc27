//! Mutual gravitation between particles (Newton's law of universal
//! gravitation), with optional softening:
//!
//! `f_i = Σ_j G m_i m_j (x_j - x_i) / (|x_j - x_i|² + ε²)^{3/2}`,
//! energy `E = -Σ_{i<j} G m_i m_j / √(|x_j - x_i|² + ε²)`,
//!
//! between every pair of particles of the bodies that take part
//! ([`crate::BodyData::gravitating`]). Direct summation, `O(N²)`: each
//! particle gathers the pull of every other in a fixed order on whatever
//! thread takes it, so the result does not depend on the threads. In the
//! implicit solvers it acts with its value at the start of the step
//! ([`Linearization::Explicit`]).

use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::error::BuildError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// The gravitational constant `G` (N·m²/kg², CODATA 2018).
pub const GRAVITATIONAL_CONSTANT: Real = 6.674e-11;

/// Mutual gravitation (the `[gravitation]` scene table).
///
/// Two bodies 2 m apart pull each other with `G m1 m2 / d²` and have the
/// energy `-G m1 m2 / d` (without softening):
///
/// ```
/// use sprung::forces::Gravitation;
/// use sprung::{BodyData, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::Rk4);
/// world.set_gravity(Vec3::ZERO);
/// let at = |x: f64, m: f64| BodyData::from_positions(vec![Vec3::new(x, 0.0, 0.0)]).with_mass(m);
/// world.add_body("sun", at(0.0, 4.0)).unwrap();
/// world.add_body("moon", at(2.0, 0.5)).unwrap();
/// let g = 1e-3; // N·m²/kg², large enough to see
/// world.forces.push(Box::new(Gravitation::new(g, 0.0).unwrap()));
/// world.evaluate_forces();
/// let pull = g * 4.0 * 0.5 / (2.0 * 2.0);
/// assert_eq!(world.particles.force[0], Vec3::new(pull, 0.0, 0.0));
/// assert_eq!(world.particles.force[1], Vec3::new(-pull, 0.0, 0.0));
/// assert_eq!(world.energies().get("gravitation"), Some(-g * 4.0 * 0.5 / 2.0));
/// assert!(Gravitation::new(-1.0, 0.0).is_err());
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Gravitation {
    /// `G` (N·m²/kg²).
    pub constant: Real,
    /// Softening length `ε` (m): the pull of two particles closer than it
    /// levels off instead of diverging.
    pub softening: Real,
    /// The particles that take part, built from the bodies on first use.
    members: Vec<u32>,
    /// Per particle, whether it takes part.
    member: Vec<bool>,
    /// The bodies' `gravitating` flags and the particle count the members
    /// were taken from.
    built_for: (Vec<bool>, usize),
}

/// The most particles that may take part in gravitation: its direct sum
/// visits every pair each step, 2e8 pairs at this count (about a second a
/// step on two cores), and the scene loaders refuse more before a run
/// that would never end.
pub const MAX_GRAVITATING: usize = 20_000;

/// How many particles of `bodies` take part in gravitation (their
/// [`crate::Body::gravitating`] flag).
pub fn gravitating_particles(bodies: &[crate::body::Body]) -> usize {
    bodies
        .iter()
        .filter(|b| b.gravitating)
        .map(|b| b.particles.len())
        .sum()
}

/// How many pairs the direct sum visits every step among `particles`
/// gravitating particles, `n (n - 1) / 2` (a real: 20 000 particles give
/// 2e8).
pub fn gravitating_pairs(particles: usize) -> f64 {
    let n = particles as f64;
    n * (n - 1.0) / 2.0
}

/// The largest softening (m): its square, added to the squared distances,
/// stays far from overflowing (at 1e308 it did, and every pull and energy
/// came out zero).
pub const MAX_SOFTENING: Real = 1e100;

impl Gravitation {
    /// Gravitation with constant `constant` (N·m²/kg²) and softening
    /// `softening` (m); refused unless both are finite and not negative,
    /// and the softening at most 1e100 m (its square must not
    /// overflow).
    pub fn new(constant: Real, softening: Real) -> Result<Self, BuildError> {
        if !(constant.is_finite() && constant >= 0.0) {
            return Err(BuildError::OutOfRange {
                field: "gravitation.constant",
                value: constant,
                reason: "must be a finite, non-negative constant (N·m²/kg²)",
            });
        }
        if !(softening.is_finite() && (0.0..=MAX_SOFTENING).contains(&softening)) {
            return Err(BuildError::OutOfRange {
                field: "gravitation.softening",
                value: softening,
                reason: "must be a non-negative length (m) of at most 1e100",
            });
        }
        Ok(Gravitation {
            constant,
            softening,
            members: Vec::new(),
            member: Vec::new(),
            built_for: (Vec::new(), usize::MAX),
        })
    }

    /// Whether the members were taken from these bodies as they are now.
    fn is_current(&self, context: &ForceContext) -> bool {
        let (flags, particles) = &self.built_for;
        *particles == context.position.len()
            && flags
                .iter()
                .eq(context.bodies.iter().map(|b| &b.gravitating))
    }

    fn refresh(&mut self, context: &ForceContext) {
        if self.is_current(context) {
            return;
        }
        self.built_for = (
            context.bodies.iter().map(|b| b.gravitating).collect(),
            context.position.len(),
        );
        self.member.clear();
        self.member.resize(context.position.len(), false);
        self.members.clear();
        for body in context.bodies.iter().filter(|b| b.gravitating) {
            for i in body.particles.clone() {
                self.member[i] = true;
                self.members.push(i as u32);
            }
        }
    }

    /// `(x_j - x_i) / (|x_j - x_i|² + ε²)^{3/2}` (1/m²).
    fn pull(&self, from: Vec3, to: Vec3) -> Vec3 {
        let d = to - from;
        let r2 = d.length_squared() + self.softening * self.softening;
        if r2 == 0.0 {
            return Vec3::ZERO;
        }
        d / (r2 * r2.sqrt())
    }
}

impl Force for Gravitation {
    fn name(&self) -> &'static str {
        "gravitation"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        self.refresh(context);
        let (x, m, g) = (context.position, context.mass, self.constant);
        let this = &*self;
        parallel::for_each_span(force, |start, force| {
            for (k, f) in force.iter_mut().enumerate() {
                let i = start + k;
                if !this.member[i] {
                    continue;
                }
                let mut sum = Vec3::ZERO;
                for &j in &this.members {
                    let j = j as usize;
                    if j != i {
                        sum += m[j] * this.pull(x[i], x[j]);
                    }
                }
                *f += g * m[i] * sum;
            }
        });
    }

    /// Not counted in the stable step: an orbit's step is set by its
    /// period and closest approach, not by a stiffness, and the adaptive
    /// `rk45` follows them.
    fn add_stiffness(&self, _: &ForceContext, _: &mut StiffnessBounds) {}

    fn energy_name(&self) -> Option<&'static str> {
        Some("gravitation")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        let (x, m) = (context.position, context.mass);
        // Before the first force evaluation the members are not built yet
        // (the energy of step 0): take them from the bodies.
        let fresh: Vec<u32>;
        let members = if self.is_current(context) {
            &self.members
        } else {
            fresh = context
                .bodies
                .iter()
                .filter(|b| b.gravitating)
                .flat_map(|b| b.particles.clone().map(|i| i as u32))
                .collect();
            &fresh
        };
        let eps2 = self.softening * self.softening;
        *energy -= self.constant
            * parallel::sum(members.len(), |range| {
                range
                    .map(|a| {
                        let i = members[a] as usize;
                        members[a + 1..]
                            .iter()
                            .map(|&j| {
                                let j = j as usize;
                                let r2 = x[i].distance_squared(x[j]) + eps2;
                                if r2 == 0.0 {
                                    0.0
                                } else {
                                    m[i] * m[j] / r2.sqrt()
                                }
                            })
                            .sum::<Real>()
                    })
                    .sum()
            });
    }

    /// Held at its start-of-step value in the implicit solves.
    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        self.refresh(context);
        Linearization::Explicit
    }

    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }

    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}
