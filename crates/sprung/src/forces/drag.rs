//! Global air drag: `f_i -= c_air v_i` (PHYSICS.md §1).

use super::{Force, ForceContext};
use crate::{Real, Vec3};

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
        for (f, v) in force.iter_mut().zip(context.velocity) {
            *f -= self.coefficient * *v;
        }
    }
}
