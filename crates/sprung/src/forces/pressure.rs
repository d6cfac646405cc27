//! Gas pressure on closed bodies (PHYSICS.md §4): `P = nRT / V`, and each
//! surface element of area `A` with outward normal `n` feels `F = P A n`,
//! shared equally among its vertices (⅓ each for a triangle, ½ each for a
//! 2D segment). Outside pressure is zero. The gas energy is
//! `E_gas = -nRT ln V`, so with constant `nRT` and no damping
//! `E_k + E_s + E_g + E_gas` is conserved.
//!
//! The forces on a closed surface sum to zero (`Σ A n = 0` for a closed
//! polyhedron or polygon), so the gas never moves the body's centre of mass.
//!
//! In the implicit solvers the pressure is [`Linearization::Explicit`]: its
//! Jacobian couples every vertex with every other through the volume (a
//! dense matrix), and the gas is soft next to the springs, so it acts with
//! its value at the start of the step (further Newton iterations
//! re-evaluate it).

use super::{Force, ForceContext, JacobianScale, Linearization};
use crate::body::Body;
use crate::measure::Energies;
use crate::{Real, Vec3};

/// The pressure of the gas in every body that has one.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GasPressure;

impl Force for GasPressure {
    fn name(&self) -> &'static str {
        "gas pressure"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let x = context.position;
        for body in context.bodies {
            let Some(pressure) = pressure(body, x, context.time) else {
                continue;
            };
            if body.is_planar() {
                for &[a, b] in &body.segments {
                    let d = x[b as usize] - x[a as usize];
                    // l n = (Δy, -Δx) for a counter-clockwise loop.
                    let share = 0.5 * pressure * Vec3::new(d.y, -d.x, 0.0);
                    force[a as usize] += share;
                    force[b as usize] += share;
                }
            } else {
                for &[a, b, c] in &body.faces {
                    let (a, b, c) = (a as usize, b as usize, c as usize);
                    let area_normal = 0.5 * (x[b] - x[a]).cross(x[c] - x[a]);
                    let share = pressure / 3.0 * area_normal;
                    force[a] += share;
                    force[b] += share;
                    force[c] += share;
                }
            }
        }
    }

    fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        for body in context.bodies {
            let Some(gas) = &body.gas else { continue };
            let volume = gas.volume_model.volume(body, context.position);
            if volume > 0.0 {
                energies.gas -= gas.nrt_at(context.time) * volume.ln();
            }
        }
    }

    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Explicit
    }

    /// Explicit in the implicit solvers (see the module documentation).
    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }

    /// Explicit in the implicit solvers (see the module documentation).
    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}

/// Pressure `nRT / V` of `body`'s gas at `position` and `time` (Pa, or N/m
/// in 2D); `None` without a gas or when the volume is not positive (the
/// body has turned inside out: no pressure is applied).
pub fn pressure(body: &Body, position: &[Vec3], time: Real) -> Option<Real> {
    let gas = body.gas.as_ref()?;
    let volume = gas.volume_model.volume(body, position);
    (volume > 0.0).then(|| gas.nrt_at(time) / volume)
}
