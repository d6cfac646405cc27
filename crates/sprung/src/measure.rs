//! Measurements of a world's state: energies, momentum and centroids.
//! Read-only; the step calls none of them. The stable time step is the
//! forces' ([`crate::forces::StiffnessBounds`]).

use crate::body::Body;
use crate::particles::Particles;
use crate::units::{Real, Vec3};

/// The potential-energy terms every world reports, in this order, whether
/// or not it has the forces that fill them: the springs', gravity's, the
/// gas's, the contacts' (colliders and bodies) and mutual gravitation's.
/// Runs of different scenes thus share their `diagnostics.csv` columns;
/// a force of another name adds its own term after them.
pub const STANDARD_TERMS: [&str; 5] = ["spring", "gravity", "gas", "contact", "gravitation"];

/// The energy of a world (J): its kinetic energy and one potential term per
/// name the forces give ([`crate::forces::Force::energy_name`]), the
/// [`STANDARD_TERMS`] first.
///
/// ```
/// use sprung::{BodyData, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::SymplecticEuler);
/// let mut ball = BodyData::from_positions(vec![Vec3::new(0.0, 2.0, 0.0)]);
/// ball.velocity = vec![Vec3::new(3.0, 0.0, 0.0)];
/// world.add_body("ball", ball.with_mass(2.0)).unwrap();
/// let energies = world.energies();
/// assert_eq!(energies.kinetic, 9.0); // ½ m v²
/// assert_eq!(energies.get("gravity"), Some(2.0 * 9.81 * 2.0)); // -m g·x
/// assert_eq!(energies.get("spring"), Some(0.0));
/// assert_eq!(energies.total(), 9.0 + 39.24);
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Energies {
    /// Kinetic energy `Σ ½ m |v|²` (J).
    pub kinetic: Real,
    /// The potential terms (name, J), in the order of their first force.
    terms: Vec<(&'static str, Real)>,
}

impl Default for Energies {
    fn default() -> Self {
        Energies::new(0.0)
    }
}

impl Energies {
    /// Kinetic energy `kinetic` (J) and every standard term at zero.
    pub fn new(kinetic: Real) -> Self {
        Energies {
            kinetic,
            terms: STANDARD_TERMS.iter().map(|&name| (name, 0.0)).collect(),
        }
    }

    /// The running value (J) of the term `name`, added at the end at zero
    /// if there is none yet.
    pub fn term_mut(&mut self, name: &'static str) -> &mut Real {
        let index = match self.terms.iter().position(|(n, _)| *n == name) {
            Some(index) => index,
            None => {
                self.terms.push((name, 0.0));
                self.terms.len() - 1
            }
        };
        &mut self.terms[index].1
    }

    /// The term `name` (J), if the world has it (`"kinetic"` included).
    pub fn get(&self, name: &str) -> Option<Real> {
        if name == "kinetic" {
            return Some(self.kinetic);
        }
        self.terms.iter().find(|(n, _)| *n == name).map(|(_, e)| *e)
    }

    /// The potential terms (name, J), in order.
    pub fn terms(&self) -> impl Iterator<Item = (&'static str, Real)> + '_ {
        self.terms.iter().copied()
    }

    /// The sum of every term (J): the kinetic energy, then the potential
    /// terms in order.
    pub fn total(&self) -> Real {
        self.terms.iter().fold(self.kinetic, |sum, (_, e)| sum + e)
    }
}

/// Kinetic energy `Σ ½ m |v|²` of the particles (J).
pub fn kinetic_energy(particles: &Particles) -> Real {
    particles
        .velocity
        .iter()
        .zip(&particles.mass)
        .map(|(v, &m)| 0.5 * m * v.length_squared())
        .sum()
}

/// Linear momentum `Σ m v` of the particles (kg·m/s); pinned ones, at
/// rest, add nothing.
pub fn linear_momentum(particles: &Particles) -> Vec3 {
    particles
        .velocity
        .iter()
        .zip(&particles.mass)
        .map(|(v, &m)| m * *v)
        .sum()
}

/// Mass-weighted centroid of `body`'s particles (m).
pub fn centroid(particles: &Particles, body: &Body) -> Vec3 {
    let range = body.particles.clone();
    let mass: Real = particles.mass[range.clone()].iter().sum();
    let moment: Vec3 = particles.position[range.clone()]
        .iter()
        .zip(&particles.mass[range])
        .map(|(x, &m)| m * *x)
        .sum();
    moment / mass
}
