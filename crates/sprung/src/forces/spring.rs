//! Damped springs: Hooke's law plus a dashpot along the spring axis
//! (PHYSICS.md §1).
//!
//! ```text
//! d = |x_i - x_j|,  t = (x_i - x_j)/d        (skipped when d == 0)
//! s = k (d - L0) + c ((v_i - v_j) · t)
//! f_i -= s t,  f_j += s t                   (one-sided: f_j only)
//! ```

use super::{Force, ForceContext};
use crate::measure::Energies;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// The force of every spring in the world (reads `ForceContext::springs`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SpringForce;

impl Force for SpringForce {
    fn name(&self) -> &'static str {
        "springs"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let springs = context.springs;
        let (x, v) = (context.position, context.velocity);
        for s in 0..springs.len() {
            let (i, j) = (springs.first[s] as usize, springs.second[s] as usize);
            let delta = x[i] - x[j];
            let length = delta.length();
            if length == 0.0 {
                continue;
            }
            let axis = delta / length;
            let tension = springs.stiffness[s] * (length - springs.rest_length[s])
                + springs.damping[s] * (v[i] - v[j]).dot(axis);
            let pull = tension * axis;
            if !springs.one_sided[s] {
                force[i] -= pull;
            }
            force[j] += pull;
        }
    }

    fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        energies.spring += spring_energy(context.springs, context.position);
    }
}

/// Elastic energy `Σ ½ k (d - L0)²` of `springs` at `position` (J).
pub fn spring_energy(springs: &Springs, position: &[Vec3]) -> Real {
    (0..springs.len())
        .map(|s| {
            let d =
                position[springs.first[s] as usize].distance(position[springs.second[s] as usize]);
            0.5 * springs.stiffness[s] * (d - springs.rest_length[s]).powi(2)
        })
        .sum()
}
