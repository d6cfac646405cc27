//! The bounds the explicit methods' stable time step is taken from, which
//! every force of the list adds its share to ([`super::Force::add_stiffness`]).

use crate::units::Real;

/// Per particle, bounds on the rows of the mass-scaled Jacobians of the
/// forces, from which [`StiffnessBounds::stable_time_step`] takes the
/// explicit methods' stable step (docs/physics.md §6).
///
/// With `K = -∂f/∂x` (N/m) and `D = -∂f/∂v` (N·s/m), Gershgorin's theorem
/// bounds the squared angular frequencies `ω²` of the mass-scaled stiffness
/// `M^-½ K M^-½` by its largest absolute row sum, and the damping rates by
/// that of `M^-½ D M^-½`. Each force adds its entries' absolute values to
/// the rows of the particles it acts on: a spring of stiffness `k` between
/// `i` and `j` adds `k (1/m_i + 1/√(m_i m_j))` to row `i` (a pinned end, of
/// infinite mass, adds only `k / m_i` to the other), which for a uniform
/// chain gives docs/physics.md's `ω_max = 2 √(k/m)`.
///
/// ```
/// use sprung::forces::StiffnessBounds;
///
/// let mut bounds = StiffnessBounds::new(2);
/// bounds.stiffness[1] = 400.0; // ω² (1/s²): ω = 20 rad/s
/// bounds.damping[1] = 5.0; // γ (1/s)
/// assert_eq!(bounds.stable_time_step(), 2.0 / 25.0);
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StiffnessBounds {
    /// Per particle: a bound on its row of `|M^-½ K M^-½|`, the squared
    /// angular frequency `ω²` it can oscillate at (1/s²).
    pub stiffness: Vec<Real>,
    /// Per particle: a bound on its row of `|M^-½ D M^-½|`, the rate `γ`
    /// at which its velocity can be damped (1/s).
    pub damping: Vec<Real>,
}

impl StiffnessBounds {
    /// Zero bounds for `particles` particles.
    pub fn new(particles: usize) -> Self {
        let mut bounds = StiffnessBounds::default();
        bounds.reset(particles);
        bounds
    }

    /// Set the bounds to zero for `particles` particles (allocates only
    /// when the number grows).
    pub fn reset(&mut self, particles: usize) {
        for bound in [&mut self.stiffness, &mut self.damping] {
            bound.clear();
            bound.resize(particles, 0.0);
        }
    }

    /// A stable time step (s) for the explicit methods: `2 / max_i (ω_i +
    /// γ_i)`, with `ω_i = √stiffness[i]` and `γ_i = damping[i]`.
    /// Symplectic Euler and Verlet are stable below it; explicit Euler is
    /// never strictly stable on an undamped oscillator, and RK4 tolerates
    /// about 1.4 times more. Infinite when nothing is stiff or damping.
    pub fn stable_time_step(&self) -> Real {
        let worst = self
            .stiffness
            .iter()
            .zip(&self.damping)
            .fold(0.0, |worst: Real, (&k, &c)| worst.max(k.sqrt() + c));
        if worst > 0.0 {
            2.0 / worst
        } else {
            Real::INFINITY
        }
    }
}
