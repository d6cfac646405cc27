//! Global air drag: `f_i -= c_air v_i` (docs/physics.md §1).

use super::jacobian::{add_isotropic_diagonal, add_isotropic_product};
use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::parallel;
use crate::units::{Real, Vec3};

/// Linear drag on every particle against its velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AirDrag {
    /// Drag coefficient `c_air` (N·s/m), non-negative.
    pub coefficient: Real,
}

impl Force for AirDrag {
    fn name(&self) -> &'static str {
        "air drag"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        if self.coefficient == 0.0 {
            return;
        }
        let (coefficient, velocity) = (self.coefficient, context.velocity);
        parallel::for_each_span(force, |start, force| {
            for (f, v) in force.iter_mut().zip(&velocity[start..]) {
                *f -= coefficient * *v;
            }
        });
    }

    /// `c_air / m` on every particle's damping.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        for (rate, w) in bounds.damping.iter_mut().zip(context.inverse_mass) {
            *rate += self.coefficient * w;
        }
    }

    /// Dissipative: no potential energy.
    fn energy_name(&self) -> Option<&'static str> {
        None
    }

    fn add_potential_energy(&self, _: &ForceContext, _: &mut Real) {}

    /// `∂f/∂x = 0`, `∂f/∂v = -c_air I`, exactly.
    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Exact
    }

    fn add_jacobian_products(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        add_isotropic_product((0.0, self.coefficient), scale, p, 0, out);
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        add_isotropic_diagonal((0.0, self.coefficient), scale, diagonal);
    }
}
