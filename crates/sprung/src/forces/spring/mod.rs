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

use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::body::Body;
use crate::parallel::{self, Schedule};
use crate::springs::Springs;
use crate::units::{Real, Vec3};

/// The force of every spring in the world (reads `ForceContext::springs`),
/// with its Jacobians cached at the last linearisation.
///
/// The springs are added in blocks of neighbouring particles
/// (`Schedule`), blocks that share no particle in parallel: every particle
/// receives its springs' forces in the same order whatever the number of
/// threads. The schedule is made again whenever the springs' endpoints
/// change (a spring added or moved: a new [`Springs::topology`]).
///
/// Particles numbered with no locality (a mesh whose vertices come in no
/// order along it) would make every spring read its particles from all
/// over the state. Where a body is numbered so (the schedule would colour
/// its springs one by one) and a reverse Cuthill–McKee numbering brings
/// its springs' ends at least four times closer, the world keeps that
/// numbering (`order.rs`) and the force is computed in it
/// (`Renumbered`): the whole state gathered into it, the springs added
/// there, the forces gathered back. Everything outside (the state, the
/// outputs, the indices a user sees) keeps the world's numbering; the
/// implicit solvers' Jacobian products do too.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SpringForce {
    /// Per spring: the unit axis `t` and the clamped transverse stiffness
    /// `k max(0, 1 - L0/d)` (N/m) at the linearisation state.
    linearized: Vec<SpringJacobian>,
    /// The springs in blocks, with their particles.
    schedule: Schedule<2>,
    /// The springs in a numbering of their own, where it pays.
    renumbered: Option<Renumbered>,
    /// The endpoints the schedule was made for ([`Springs::topology`]).
    topology: u64,
}

/// The springs' force computed in a numbering of the particles that keeps
/// each spring's ends close (reverse Cuthill–McKee), with the state in
/// that numbering: buffers kept from step to step.
#[derive(Debug, Clone, Default, PartialEq)]
struct Renumbered {
    /// Per particle in this numbering, its number in the world.
    particle: Vec<u32>,
    /// Per particle of the world, its number here.
    number: Vec<u32>,
    /// The springs in blocks, by these numbers.
    schedule: Schedule<2>,
    /// Positions (m), velocities (m/s) and forces (N) in this numbering.
    position: Vec<Vec3>,
    velocity: Vec<Vec3>,
    force: Vec<Vec3>,
}

impl Renumbered {
    /// The numbering of the particles (among `particles`) that the
    /// `bodies` chose for their springs ([`Body::spring_numbering`]), if
    /// any did: every other particle keeps its number.
    fn of(springs: &Springs, bodies: &[Body], particles: usize) -> Option<Renumbered> {
        let mut number: Option<Vec<u32>> = None;
        for body in bodies {
            let Some(own) = &body.spring_numbering else {
                continue;
            };
            let range = body.particles.clone();
            if range.len() != own.len() || range.end > particles {
                // A body's range changed by hand since it was added.
                return None;
            }
            let number = number.get_or_insert_with(|| (0..particles as u32).collect());
            for (k, &n) in own.iter().enumerate() {
                number[range.start + k] = (range.start + n as usize) as u32;
            }
        }
        let number = number?;
        // Each particle numbered once, unless bodies' ranges were made to
        // overlap by hand: then the world's own numbering is kept.
        let mut particle = vec![u32::MAX; particles];
        for (p, &n) in number.iter().enumerate() {
            let slot = particle.get_mut(n as usize)?;
            if *slot != u32::MAX {
                return None;
            }
            *slot = p as u32;
        }
        let ends: Vec<[u32; 2]> = springs
            .first()
            .iter()
            .zip(springs.second())
            .map(|(&i, &j)| [i, j])
            .collect();
        let members = ends
            .iter()
            .map(|&[i, j]| [number[i as usize], number[j as usize]]);
        Some(Renumbered {
            schedule: Schedule::new(members, particles),
            position: vec![Vec3::ZERO; particles],
            velocity: vec![Vec3::ZERO; particles],
            force: vec![Vec3::ZERO; particles],
            particle,
            number,
        })
    }

    /// Add the force of `springs` at `x` (m), `v` (m/s) into `force` (N),
    /// all in the world's numbering.
    fn accumulate(&mut self, springs: &Springs, x: &[Vec3], v: &[Vec3], force: &mut [Vec3]) {
        let Renumbered {
            particle,
            number,
            schedule,
            position,
            velocity,
            force: here,
        } = self;
        parallel::for_each_span(
            (&mut position[..], &mut velocity[..], &mut here[..]),
            |start, (y, w, f)| {
                for (k, ((y, w), f)) in y.iter_mut().zip(w).zip(f).enumerate() {
                    let p = particle[start + k] as usize;
                    (*y, *w, *f) = (x[p], v[p], Vec3::ZERO);
                }
            },
        );
        let (y, w) = (&position[..], &velocity[..]);
        schedule.for_each_block(&mut here[..], |block| {
            batch::accumulate_block(springs, y, w, &block, &mut SpringBatch::default());
        });
        let here = &here[..];
        parallel::for_each_span(force, |start, force| {
            for (k, f) in force.iter_mut().enumerate() {
                *f += here[number[start + k] as usize];
            }
        });
    }
}

/// One spring's Jacobian data at a state.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct SpringJacobian {
    /// Unit axis `t = (x_i - x_j) / d` (zero for a spring of zero length).
    pub axis: Vec3,
    /// Transverse stiffness `k max(0, 1 - L0/d)` (N/m).
    pub across: Real,
}

impl SpringJacobian {
    /// Spring `s`'s Jacobian data at the positions `x` (m).
    pub fn at(springs: &Springs, s: usize, x: &[Vec3]) -> SpringJacobian {
        let delta = x[springs.first()[s] as usize] - x[springs.second()[s] as usize];
        let length = delta.length();
        if length == 0.0 {
            return SpringJacobian::default();
        }
        let stretch = 1.0 - springs.rest_length[s] / length;
        SpringJacobian {
            axis: delta / length,
            across: springs.stiffness[s] * stretch.max(0.0),
        }
    }

    /// `(a, b)` with `-(α ∂f_i/∂x_i + β ∂f_i/∂v_i) = a t tᵀ + b I`, for
    /// spring stiffness `k` (N/m) and damping `c` (N·s/m); both are at
    /// least 0 for `α, β, c ≥ 0`.
    pub fn coefficients(self, k: Real, c: Real, scale: JacobianScale) -> (Real, Real) {
        // α (k t tᵀ + k⊥ (I - t tᵀ)) + β c t tᵀ = a t tᵀ + b I.
        let a = scale.position * (k - self.across) + scale.velocity * c;
        let b = scale.position * self.across;
        (a, b)
    }

    /// `α ∂f_i/∂x_i·p + β ∂f_i/∂v_i·p` for spring stiffness `k` (N/m) and
    /// damping `c` (N·s/m).
    fn product(self, k: Real, c: Real, scale: JacobianScale, p: Vec3) -> Vec3 {
        let (a, b) = self.coefficients(k, c, scale);
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
    fn colour(&mut self, springs: &Springs, bodies: &[Body], particles: usize) {
        let renumbered_for = self.renumbered.as_ref().map(|r| r.number.len());
        if self.topology != springs.topology()
            || self.schedule.len() != springs.len()
            || renumbered_for.is_some_and(|count| count != particles)
        {
            let members = springs.first().iter().zip(springs.second());
            self.schedule = Schedule::new(members.map(|(&i, &j)| [i, j]), particles);
            self.renumbered = Renumbered::of(springs, bodies, particles);
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
        self.colour(springs, context.bodies, context.position.len());
        let (x, v) = (context.position, context.velocity);
        if let Some(renumbered) = &mut self.renumbered {
            renumbered.accumulate(springs, x, v, force);
            return;
        }
        self.schedule.for_each_block(force, |block| {
            batch::accumulate_block(springs, x, v, &block, &mut SpringBatch::default());
        });
    }

    /// A spring of stiffness `k` and damping `c` between `i` and `j` adds
    /// `k (w_i + √(w_i w_j))` to row `i`'s stiffness bound and `c (w_i +
    /// √(w_i w_j))` to its damping bound (`w` the inverse masses: a pinned
    /// neighbour counts as infinite mass), and the same to row `j`'s.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        let (springs, inverse_mass) = (context.springs, context.inverse_mass);
        for s in 0..springs.len() {
            let (i, j) = (springs.first()[s] as usize, springs.second()[s] as usize);
            let (wi, wj) = (inverse_mass[i], inverse_mass[j]);
            let coupling = (wi * wj).sqrt();
            for (me, w) in [(i, wi), (j, wj)] {
                bounds.stiffness[me] += springs.stiffness[s] * (w + coupling);
                bounds.damping[me] += springs.damping[s] * (w + coupling);
            }
        }
    }

    fn energy_name(&self) -> Option<&'static str> {
        Some("spring")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        *energy += spring_energy(context.springs, context.position);
    }

    fn springs<'a>(&self, context: &ForceContext<'a>) -> Option<&'a Springs> {
        Some(context.springs)
    }

    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        let springs = context.springs;
        let x = context.position;
        self.colour(springs, context.bodies, x.len());
        self.linearized.clear();
        self.linearized
            .resize(springs.len(), SpringJacobian::default());
        parallel::for_each_span(&mut self.linearized[..], |start, chunk| {
            for (offset, jacobian) in chunk.iter_mut().enumerate() {
                *jacobian = SpringJacobian::at(springs, start + offset, x);
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
