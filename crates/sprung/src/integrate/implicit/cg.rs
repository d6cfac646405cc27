//! Preconditioned conjugate gradients over particle vectors, with
//! constraints: pinned particles keep their entries of the starting guess
//! (zero) in every direction, particles in contact with a projection
//! collider along its normal, and those directions are filtered out of
//! every residual and product (the "modified PCG" of Baraff and Witkin,
//! "Large steps in cloth simulation", SIGGRAPH 1998, §5.3). The matrix and
//! the preconditioner come from the caller as an [`Operator`].

use crate::colliders::ContactConstraint;
use crate::parallel;
use crate::units::{Real, Vec3};

/// A symmetric positive definite matrix `A` and a preconditioner `P ≈ A`,
/// both over particle vectors.
pub(super) trait Operator {
    /// Write `A p` into `out`.
    fn apply(&mut self, p: &[Vec3], out: &mut [Vec3]);
    /// Write `P⁻¹ r` into `z`.
    fn precondition(&mut self, r: &[Vec3], z: &mut [Vec3]);
}

/// The Jacobi preconditioner: `P⁻¹ r = r / diag(A)`, per component.
pub(super) fn jacobi(inverse_diagonal: &[Vec3], r: &[Vec3], z: &mut [Vec3]) {
    parallel::for_each_span(z, |start, z| {
        for ((z, r), d) in z
            .iter_mut()
            .zip(&r[start..])
            .zip(&inverse_diagonal[start..])
        {
            *z = *r * *d;
        }
    });
}

/// How a solve ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct CgOutcome {
    /// Iterations taken.
    pub iterations: u32,
    /// Final relative residual `|b - A x| / max(|b|, scale)` (0 when both
    /// are 0).
    pub residual: Real,
    /// The residual reached the tolerance.
    pub converged: bool,
}

/// The constraints and limits of one solve.
#[derive(Debug, Clone, Copy)]
pub(super) struct Limits<'a> {
    /// Inverse masses: 0 marks a pinned particle, whose entries keep the
    /// starting guess.
    pub inverse_mass: &'a [Real],
    /// Contacts: each particle's entry keeps the starting guess along the
    /// contact normal.
    pub contacts: &'a [ContactConstraint],
    /// Relative residual at which to stop.
    pub tolerance: Real,
    /// The step's own scale of the right side (its units): the residual is
    /// measured against the larger of it and `|b|`, so that a right side
    /// of rounding noise (a body at rest) takes no iterations. 0 for none.
    pub scale: Real,
    /// Most iterations.
    pub max_iterations: u32,
}

/// Conjugate gradients with its scratch vectors.
#[derive(Debug, Default)]
pub(super) struct ConjugateGradient {
    residual: Vec<Vec3>,
    preconditioned: Vec<Vec3>,
    direction: Vec<Vec3>,
    product: Vec<Vec3>,
}

/// `Σ a_i · b_i` over particle vectors.
/// (In the fixed tree of [`parallel::sum`]: the same bits on any number of
/// threads.)
fn dot(a: &[Vec3], b: &[Vec3]) -> Real {
    parallel::sum(a.len().min(b.len()), |range| {
        a[range.clone()]
            .iter()
            .zip(&b[range])
            .map(|(a, b)| a.dot(*b))
            .sum()
    })
}

/// `y += alpha x` over particle vectors.
fn add_scaled(y: &mut [Vec3], alpha: Real, x: &[Vec3]) {
    parallel::for_each_span(y, |start, y| {
        for (y, x) in y.iter_mut().zip(&x[start..]) {
            *y += alpha * *x;
        }
    });
}

/// Remove the constrained directions from `v`: all of a pinned particle's,
/// the normal of a particle in contact.
fn filter(v: &mut [Vec3], limits: &Limits) {
    let inverse_mass = limits.inverse_mass;
    parallel::for_each_span(&mut *v, |start, v| {
        for (v, &w) in v.iter_mut().zip(&inverse_mass[start..]) {
            if w == 0.0 {
                *v = Vec3::ZERO;
            }
        }
    });
    for c in limits.contacts {
        let v = &mut v[c.particle];
        *v -= v.dot(c.normal) * c.normal;
    }
}

impl ConjugateGradient {
    /// Solve `A x = b` in the directions left free by the constraints,
    /// starting from `x` (whose constrained directions are kept: zero for
    /// pinned particles, the prescribed values along contact normals). Stops
    /// when the relative residual is at most the tolerance or after the
    /// most iterations; takes none when the right side is already within
    /// the tolerance of the limits' scale.
    pub fn solve(
        &mut self,
        operator: &mut dyn Operator,
        b: &[Vec3],
        x: &mut [Vec3],
        limits: Limits,
    ) -> CgOutcome {
        let n = b.len();
        for buffer in [
            &mut self.residual,
            &mut self.preconditioned,
            &mut self.direction,
            &mut self.product,
        ] {
            buffer.resize(n, Vec3::ZERO);
        }
        if x.iter().any(|x| *x != Vec3::ZERO) {
            operator.apply(x, &mut self.product);
            self.residual.copy_from_slice(b);
            add_scaled(&mut self.residual, -1.0, &self.product);
        } else {
            self.residual.copy_from_slice(b);
        }
        filter(&mut self.residual, &limits);
        let b_norm = dot(&self.residual, &self.residual).sqrt();
        let reference = b_norm.max(limits.scale);
        if b_norm <= limits.tolerance * reference {
            return CgOutcome {
                iterations: 0,
                residual: if reference > 0.0 {
                    b_norm / reference
                } else {
                    0.0
                },
                converged: true,
            };
        }
        operator.precondition(&self.residual, &mut self.preconditioned);
        filter(&mut self.preconditioned, &limits);
        self.direction.copy_from_slice(&self.preconditioned);
        let mut rz = dot(&self.residual, &self.preconditioned);
        let mut residual = b_norm / reference;
        let mut iterations = 0;
        while iterations < limits.max_iterations {
            // Asked to stop (`crate::interrupt`): the solution so far, as
            // at the iteration limit.
            if iterations > 0 && crate::interrupt::requested() {
                break;
            }
            operator.apply(&self.direction, &mut self.product);
            filter(&mut self.product, &limits);
            let curvature = dot(&self.direction, &self.product);
            if curvature.is_nan() || curvature <= 0.0 {
                // Not positive definite along this direction (or not
                // finite): no further progress is possible.
                break;
            }
            let alpha = rz / curvature;
            add_scaled(x, alpha, &self.direction);
            add_scaled(&mut self.residual, -alpha, &self.product);
            iterations += 1;
            residual = dot(&self.residual, &self.residual).sqrt() / reference;
            if residual <= limits.tolerance {
                break;
            }
            operator.precondition(&self.residual, &mut self.preconditioned);
            filter(&mut self.preconditioned, &limits);
            let rz_next = dot(&self.residual, &self.preconditioned);
            let beta = rz_next / rz;
            rz = rz_next;
            let preconditioned = &self.preconditioned;
            parallel::for_each_span(&mut self.direction[..], |start, p| {
                for (p, z) in p.iter_mut().zip(&preconditioned[start..]) {
                    *p = *z + beta * *p;
                }
            });
        }
        CgOutcome {
            iterations,
            residual,
            converged: residual <= limits.tolerance,
        }
    }

    /// The impulse each contact needed to hold its constraint in the
    /// solution `x` of `A x = b`: `(A x - b) · n` at its particle, written to
    /// `out` in the order of `contacts` (positive: it pushed).
    pub fn contact_impulses(
        &mut self,
        operator: &mut dyn Operator,
        b: &[Vec3],
        x: &[Vec3],
        contacts: &[ContactConstraint],
        out: &mut Vec<Real>,
    ) {
        out.clear();
        if contacts.is_empty() {
            return;
        }
        self.product.resize(x.len(), Vec3::ZERO);
        operator.apply(x, &mut self.product);
        out.extend(
            contacts
                .iter()
                .map(|c| (self.product[c.particle] - b[c.particle]).dot(c.normal)),
        );
    }
}
