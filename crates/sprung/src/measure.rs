//! Measurements of a world's state: energies, momentum, centroids and a
//! stable time-step estimate. Read-only; the step calls none of them except
//! the time-step estimate when a blow-up is reported.

use crate::body::Body;
use crate::collide::Collider;
use crate::contact::{Contacts, REFERENCE_SPEED};
use crate::particles::Particles;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// The energy terms of a world (J).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Energies {
    /// Kinetic energy `Σ ½ m |v|²` (J).
    pub kinetic: Real,
    /// Elastic energy of the springs `Σ ½ k (d - L0)²` (J).
    pub spring: Real,
    /// Gravitational potential energy `-Σ m (g · x)` (J).
    pub gravity: Real,
    /// Energy of the gas inside closed bodies, `-nRT ln V` (J).
    pub gas: Real,
    /// Elastic energy of penalty contacts (J).
    pub contact: Real,
    /// Potential energy of mutual gravitation, `-Σ_{i<j} G m_i m_j / √(r² + ε²)` (J).
    pub gravitation: Real,
}

impl Energies {
    /// The sum of every term (J).
    pub fn total(&self) -> Real {
        self.kinetic + self.spring + self.gravity + self.gas + self.contact + self.gravitation
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

/// Linear momentum `Σ m v` of the movable particles (kg·m/s).
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

/// A stable time step (s) for the explicit methods: `2 / (ω_max + γ_max)`.
///
/// `ω_max²` is bounded by Gershgorin's theorem on the mass-scaled stiffness
/// matrix `M^-½ K M^-½`: for particle `i`, the sum over its springs of
/// `k (1/m_i + 1/√(m_i m_j))` (a pinned neighbour counts as infinite mass),
/// plus the penalty stiffness of colliders over `m_i`, plus, for each
/// candidate contact pair of the step it is part of that can touch in the
/// step (its clearance within the allowance), `2 (v_ref / h)²` for the
/// default stiffness (whatever the masses: it is set from the contact's
/// effective mass) or twice a given stiffness over `m_i`; a particle's
/// pairs with the elements of one body count it once, as it touches only
/// the closest. For a uniform chain this gives docs/physics.md's `ω_max = 2 √(k/m)`.
/// `γ_max` is the same bound for the damping coefficients, plus the
/// damping `rates` (1/s) of the other forces (air drag, wind;
/// [`crate::forces::Force::add_damping_rates`]): it limits explicit steps
/// of a heavily damped system. Symplectic Euler and Verlet
/// are stable below this step; explicit Euler is never strictly stable on
/// an undamped oscillator, and RK4 tolerates about 1.4 times more.
/// Infinite when nothing is stiff.
pub fn stable_time_step(
    particles: &Particles,
    springs: &Springs,
    colliders: &[Collider],
    contacts: &Contacts,
    rates: Vec<Real>,
) -> Real {
    let n = particles.len();
    let mut stiffness_bound = vec![0.0; n];
    // The damping bound starts from the forces' rates.
    let mut damping_bound = rates;
    damping_bound.resize(n, 0.0);
    for s in 0..springs.len() {
        let (i, j) = (springs.first()[s] as usize, springs.second()[s] as usize);
        let (wi, wj) = (particles.inverse_mass[i], particles.inverse_mass[j]);
        let coupling = (wi * wj).sqrt();
        for (me, w) in [(i, wi), (j, wj)] {
            stiffness_bound[me] += springs.stiffness[s] * (w + coupling);
            damping_bound[me] += springs.damping[s] * (w + coupling);
        }
    }
    // A contact of the default coefficients, `m (v_ref / h)²` and
    // `m v_ref / h` for its effective mass `m = 1 / Σ w_i² / m_i`, adds at
    // most `2 (v_ref / h)²` and `2 v_ref / h` to each moving member's row of
    // the mass-scaled matrices: its block is `k u uᵀ` with `u_i = w_i /
    // √m_i`, whose row `i` sums to `k |u_i| Σ |u_j| ≤ k |u_i| √(4 Σ u_j²)`,
    // and `|u_i| ≤ √(Σ u_j²) = 1 / √m`. A given stiffness `k` (or damping)
    // adds `2 k / m_i` (the weights sum to at most 2).
    let settings = &contacts.settings;
    let rate = REFERENCE_SPEED / settings.thickness;
    contacts.pairs.for_each_member(|members| {
        for i in members {
            let w = particles.inverse_mass[i as usize];
            if w == 0.0 {
                continue;
            }
            stiffness_bound[i as usize] += settings
                .stiffness
                .map_or(2.0 * rate * rate, |k| 2.0 * k * w);
            damping_bound[i as usize] += settings.damping.map_or(2.0 * rate, |c| 2.0 * c * w);
        }
    });
    let penalty: Real = colliders.iter().map(Collider::penalty_stiffness).sum();
    let mut worst: Real = 0.0;
    for i in 0..n {
        let omega = (stiffness_bound[i] + penalty * particles.inverse_mass[i]).sqrt();
        worst = worst.max(omega + damping_bound[i]);
    }
    if worst > 0.0 {
        2.0 / worst
    } else {
        Real::INFINITY
    }
}
