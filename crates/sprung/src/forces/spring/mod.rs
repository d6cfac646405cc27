//! Damped springs: Hooke's law plus a dashpot along the spring axis
//! (docs/physics.md §1).
//!
//! ```text
//! d = |x_i - x_j|,  t = (x_i - x_j)/d        (skipped when d == 0)
//! s = k (d - L0) + c ((v_i - v_j) · t)
//! f_i -= s t,  f_j += s t                   (one-sided: f_j only)
//! ```
//!
//! **Jacobians** (for the implicit solvers). The elastic part gives, for
//! particle `i`'s own block,
//! `∂f_i/∂x_i = -k t tᵀ - k (1 - L0/d) (I - t tᵀ)`, and `-` that block
//! towards `j`. Under compression (`d < L0`) the second term would make the
//! matrix indefinite (a compressed spring buckles sideways), and conjugate
//! gradients need a definite one, so its factor `1 - L0/d` is clamped at 0
//! (Choi and Ko, "Stable but responsive cloth", SIGGRAPH 2002). The dashpot
//! gives `∂f_i/∂v_i = -c t tᵀ`; its derivative with respect to positions
//! (the axis turning) is not symmetric and is left out. A one-sided spring
//! contributes only its child's own block, which keeps the matrix symmetric.
//! These are the approximations of [`Linearization::Approximate`]; the force
//! itself is exact, so Newton iterations still converge to the exact
//! backward-Euler step.

mod batch;

pub use batch::pulls_alone;
use batch::SpringBatch;

use super::{Force, ForceContext, JacobianScale, Linearization};
use crate::measure::Energies;
use crate::parallel::{self, Schedule};
use crate::springs::Springs;
use crate::{Real, Vec3};

/// The force of every spring in the world (reads `ForceContext::springs`),
/// with its Jacobians cached at the last linearisation.
///
/// The springs are added in blocks of neighbouring particles
/// ([`Schedule`]), blocks that share no particle in parallel: every particle
/// receives its springs' forces in the same order whatever the number of
/// threads. The schedule is made again whenever the springs' endpoints
/// change (a spring added or moved: a new [`Springs::topology`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpringForce {
    /// Per spring: the unit axis `t` and the clamped transverse stiffness
    /// `k max(0, 1 - L0/d)` (N/m) at the linearisation state.
    linearized: Vec<SpringJacobian>,
    /// The springs in blocks, with their particles.
    schedule: Schedule<2>,
    /// The endpoints the schedule was made for ([`Springs::topology`]).
    topology: u64,
}

/// One spring's Jacobian data at a state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct SpringJacobian {
    /// Unit axis `t = (x_i - x_j) / d` (zero for a spring of zero length).
    axis: Vec3,
    /// Transverse stiffness `k max(0, 1 - L0/d)` (N/m).
    across: Real,
}

impl SpringJacobian {
    /// `α ∂f_i/∂x_i·p + β ∂f_i/∂v_i·p` for spring stiffness `k` (N/m) and
    /// damping `c` (N·s/m).
    fn product(self, k: Real, c: Real, scale: JacobianScale, p: Vec3) -> Vec3 {
        // α (k t tᵀ + k⊥ (I - t tᵀ)) + β c t tᵀ = a t tᵀ + b I.
        let a = scale.position * (k - self.across) + scale.velocity * c;
        let b = scale.position * self.across;
        -(a * self.axis.dot(p) * self.axis + b * p)
    }

    /// The diagonal of `α ∂f_i/∂x_i + β ∂f_i/∂v_i`.
    fn diagonal(self, k: Real, c: Real, scale: JacobianScale) -> Vec3 {
        let squared = self.axis * self.axis;
        let elastic = k * squared + self.across * (Vec3::ONE - squared);
        -(scale.position * elastic + scale.velocity * c * squared)
    }
}

impl SpringForce {
    /// A spring force with no Jacobians cached yet.
    pub fn new() -> Self {
        SpringForce::default()
    }

    /// Schedule the springs, unless the schedule is for these very
    /// endpoints (the same [`Springs::topology`]).
    fn colour(&mut self, springs: &Springs, particles: usize) {
        if self.topology != springs.topology() || self.schedule.len() != springs.len() {
            let members = springs.first().iter().zip(springs.second());
            self.schedule = Schedule::new(members.map(|(&i, &j)| [i, j]), particles);
            self.topology = springs.topology();
        }
    }
}

impl Force for SpringForce {
    fn name(&self) -> &'static str {
        "springs"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let springs = context.springs;
        self.colour(springs, context.position.len());
        let (x, v) = (context.position, context.velocity);
        self.schedule.for_each_block(force, |block| {
            batch::accumulate_block(springs, x, v, &block, &mut SpringBatch::default());
        });
    }

    fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        energies.spring += spring_energy(context.springs, context.position);
    }

    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        let springs = context.springs;
        let x = context.position;
        self.colour(springs, x.len());
        self.linearized.clear();
        self.linearized
            .resize(springs.len(), SpringJacobian::default());
        parallel::for_each_span(&mut self.linearized[..], |start, chunk| {
            for (offset, jacobian) in chunk.iter_mut().enumerate() {
                let s = start + offset;
                let delta = x[springs.first()[s] as usize] - x[springs.second()[s] as usize];
                let length = delta.length();
                *jacobian = if length == 0.0 {
                    SpringJacobian::default()
                } else {
                    let stretch = 1.0 - springs.rest_length[s] / length;
                    SpringJacobian {
                        axis: delta / length,
                        across: springs.stiffness[s] * stretch.max(0.0),
                    }
                };
            }
        });
        Linearization::Approximate
    }

    fn add_jacobian_products(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        let springs = context.springs;
        self.schedule.scatter(out, |s, w| {
            let jacobian = self.linearized[s];
            let [i, j] = [w.particle(0), w.particle(1)];
            let (k, c) = (springs.stiffness[s], springs.damping[s]);
            if springs.one_sided[s] {
                w.add(1, jacobian.product(k, c, scale, p[j]));
            } else {
                let q = jacobian.product(k, c, scale, p[i] - p[j]);
                w.add(0, q);
                w.add(1, -q);
            }
        });
    }

    fn add_jacobian_diagonal(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        let springs = context.springs;
        self.schedule.scatter(diagonal, |s, w| {
            let d = self.linearized[s].diagonal(springs.stiffness[s], springs.damping[s], scale);
            if !springs.one_sided[s] {
                w.add(0, d);
            }
            w.add(1, d);
        });
    }
}

/// Elastic energy `Σ ½ k (d - L0)²` of `springs` at `position` (J),
/// summed in fixed chunks (the same bits on any number of threads).
pub fn spring_energy(springs: &Springs, position: &[Vec3]) -> Real {
    parallel::sum(springs.len(), |range| {
        range
            .map(|s| {
                let d = position[springs.first()[s] as usize]
                    .distance(position[springs.second()[s] as usize]);
                0.5 * springs.stiffness[s] * (d - springs.rest_length[s]).powi(2)
            })
            .sum()
    })
}
