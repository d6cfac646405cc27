//! Uniform gravity: `f_i += m_i g`, energy `E_g = -Σ m_i (g · x_i)`.

use super::{Force, ForceContext, JacobianScale, Linearization};
use crate::measure::Energies;
use crate::Vec3;

/// Uniform gravitational acceleration `g` (m/s²) on every particle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gravity {
    /// Acceleration of gravity (m/s²), e.g. `(0, -9.81, 0)`.
    pub acceleration: Vec3,
}

impl Force for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        if self.acceleration == Vec3::ZERO {
            return;
        }
        for (f, &m) in force.iter_mut().zip(context.mass) {
            *f += m * self.acceleration;
        }
    }

    fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        energies.gravity -= context
            .position
            .iter()
            .zip(context.mass)
            .map(|(x, &m)| m * self.acceleration.dot(*x))
            .sum::<f64>();
    }

    /// Constant force: both Jacobians are exactly zero.
    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Exact
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
