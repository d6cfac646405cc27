//! The shapes of Jacobian that several forces share: a push along a fixed
//! normal (the penalty contacts of colliders and of bodies) and an
//! isotropic pull (air drag, the user's hand).

use super::JacobianScale;
use crate::parallel;
use crate::units::{Real, Vec3};

/// A penalty contact pushing along a normal `n` with stiffness `k` (N/m)
/// and damping `c` (N·s/m) on the relative motion `Σ w_i x_i` of its
/// points (one particle of weight 1 against a collider; a touch's closest
/// points between bodies). Its Jacobians are `-k n nᵀ` and `-c n nᵀ` on
/// that relative motion, shared back by the same weights: the turning of
/// the normal and the motion of the closest points left out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct NormalPush {
    /// The unit contact normal.
    pub normal: Vec3,
    /// Penalty stiffness `k` (N/m).
    pub stiffness: Real,
    /// Penalty damping `c` along the normal (N·s/m).
    pub damping: Real,
}

impl NormalPush {
    /// `α k + β c`: minus the scaled Jacobians along the normal.
    fn weight(&self, scale: JacobianScale) -> Real {
        scale.position * self.stiffness + scale.velocity * self.damping
    }

    /// Add `-(α k + β c) n (n · Σ_j w_j p_j)`, times `w_i`, to `out[i]` for
    /// each member `(i, w_i)`.
    pub fn add_product(
        &self,
        scale: JacobianScale,
        members: impl Iterator<Item = (usize, Real)> + Clone,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        let relative: Vec3 = members.clone().map(|(i, w)| w * p[i]).sum();
        let push = -self.weight(scale) * relative.dot(self.normal) * self.normal;
        for (i, w) in members {
            out[i] += w * push;
        }
    }

    /// Add each member's own diagonal block's diagonal, `-(α k + β c) w_i²
    /// (n ∘ n)`, to `diagonal[i]`.
    pub fn add_diagonal(
        &self,
        scale: JacobianScale,
        members: impl Iterator<Item = (usize, Real)>,
        diagonal: &mut [Vec3],
    ) {
        let weight = self.weight(scale);
        let n2 = self.normal * self.normal;
        for (i, w) in members {
            diagonal[i] -= weight * w * w * n2;
        }
    }
}

/// The product `-(α k + β c) p_i` of isotropic Jacobians `∂f/∂x = -k I`,
/// `∂f/∂v = -c I` (stiffness `k`, N/m; damping `c`, N·s/m) on the
/// particles `first..first + out.len()`, added to `out` (those particles'
/// entries).
pub(crate) fn add_isotropic_product(
    (stiffness, damping): (Real, Real),
    scale: JacobianScale,
    p: &[Vec3],
    first: usize,
    out: &mut [Vec3],
) {
    let factor = -(scale.position * stiffness + scale.velocity * damping);
    parallel::for_each_span(out, |start, out| {
        for (o, p) in out.iter_mut().zip(&p[first + start..]) {
            *o += factor * *p;
        }
    });
}

/// The diagonal of the isotropic Jacobians of [`add_isotropic_product`],
/// `-(α k + β c)` in each of x, y and z, added to `diagonal` (the entries
/// of the particles it acts on).
pub(crate) fn add_isotropic_diagonal(
    (stiffness, damping): (Real, Real),
    scale: JacobianScale,
    diagonal: &mut [Vec3],
) {
    let factor = -(scale.position * stiffness + scale.velocity * damping);
    for d in diagonal {
        *d += Vec3::splat(factor);
    }
}
