//! The penalty force of the contacts between bodies, as an entry of the
//! world's force list (see the module documentation of [`crate::contact`]).

use super::{
    Force, ForceContext, ImpulseContext, JacobianScale, Linearization, NormalPush, StiffnessBounds,
};
use crate::contact::friction::{self, Pushed, Spans};
use crate::contact::pairs::{Touch, Touches, PREFETCH_TOUCHES};
use crate::contact::{self as contact, rigid_friction};
use crate::parallel;
use crate::units::{Real, Vec3};
use rayon::prelude::*;

/// The penalty forces of the candidate contact pairs of the step (reads
/// `ForceContext::contacts`).
///
/// For a pair closer than the thickness `h` at distance `d` along the
/// normal `n` (from the second side to the first), with relative velocity
/// `u` of the closest points: a normal force `f_n = max(0, k (h - d) - c
/// (u·n))` pushes the sides apart. Friction acts as impulses after the
/// step, on the touches and normal forces of this force's last evaluation
/// in the step: a world whose force list lacks this force has no friction
/// between bodies either. Jacobians: `-k n nᵀ` and `-c n nᵀ` on the
/// relative motion of pairs that push (the turning of the normal left out:
/// [`Linearization::Approximate`]).
#[derive(Debug, Clone, Default)]
pub struct BodyContacts {
    /// The pairs that pushed at the last linearisation.
    active: Vec<Active>,
    /// The touches of the last evaluation (kept for their buffers).
    touches: Touches,
    /// The normal force of each touch at the last evaluation and where its
    /// particles lie, piece by piece of the touches.
    pushes: Vec<Vec<Pushed>>,
    /// How many touches of the last evaluation span how many particles.
    spans: Spans,
    /// The friction stage's buffers for the touches with rigid bodies.
    rigid_friction: rigid_friction::Scratch,
}

/// A pushing pair at the linearisation state: its touch and how it pushed.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Active {
    touch: Touch,
    push: NormalPush,
}

impl Active {
    /// The touch's particles and closest-point weights.
    fn members(&self) -> impl Iterator<Item = (usize, Real)> + Clone + '_ {
        let touch = &self.touch;
        (0..touch.count).map(|k| (touch.particles[k] as usize, touch.weights[k]))
    }
}

impl BodyContacts {
    /// Body contacts with nothing linearised yet.
    pub fn new() -> Self {
        BodyContacts::default()
    }
}

/// The stiffness and damping of `touch` in `context`, from the effective
/// mass of its two sides at their closest points ([`contact::effective_mass`]).
fn coefficients(context: &ForceContext, touch: &Touch) -> (Real, Real) {
    let count = touch.count;
    let inverse_mass: [Real; 4] = std::array::from_fn(|i| {
        if i < count {
            context.inverse_mass[touch.particles[i] as usize]
        } else {
            0.0
        }
    });
    // Nothing of weight moves: the first particle's mass.
    let mass = contact::effective_mass(&touch.weights[..count], &inverse_mass[..count])
        .unwrap_or_else(|| context.mass[touch.particles[0] as usize]);
    context.contacts.settings.coefficients(mass)
}

impl Force for BodyContacts {
    fn name(&self) -> &'static str {
        "body contacts"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let contacts = context.contacts;
        self.touches.measure(
            &contacts.pairs,
            context.position,
            contacts.settings.thickness,
        );
        // The normal forces, piece by piece of the touches, in parallel
        // when there are many; with the touches' spans, counted exactly (the
        // same whatever the threads).
        let pieces = self.touches.pieces();
        self.pushes.resize_with(pieces.len(), Vec::new);
        let normal_forces = |(touches, pushes): (&Vec<Touch>, &mut Vec<Pushed>)| {
            let mut spans: Spans = [0; 32];
            pushes.clear();
            pushes.extend(touches.iter().enumerate().map(|(i, touch)| {
                if let Some(ahead) = touches.get(i + PREFETCH_TOUCHES) {
                    ahead.prefetch(context.velocity, context.inverse_mass);
                }
                let (k, c) = coefficients(context, touch);
                let normal_speed = touch.relative(context.velocity).dot(touch.normal);
                let [lowest, highest] = touch.extent();
                let span = highest - lowest;
                spans[((u32::BITS - span.leading_zeros()) as usize).min(31)] += 1;
                Pushed {
                    push: (k * touch.depth - c * normal_speed).max(0.0),
                    lowest,
                    span,
                }
            }));
            spans
        };
        let add = |a: Spans, b: Spans| std::array::from_fn(|k| a[k] + b[k]);
        let many = self.touches.len() > parallel::CHUNK;
        self.spans = if many {
            pieces
                .par_iter()
                .zip(self.pushes.par_iter_mut())
                .map(normal_forces)
                .reduce(|| [0; 32], add)
        } else {
            pieces
                .iter()
                .zip(self.pushes.iter_mut())
                .map(normal_forces)
                .fold([0; 32], add)
        };
        // Added in the touches' order: a random scatter, each thread into
        // its own share of the particles when there are many, taking the
        // touches whose particles reach into it.
        let touches = || {
            pieces
                .iter()
                .zip(&self.pushes)
                .flat_map(|(touches, pushes)| touches.iter().zip(pushes))
        };
        if many {
            parallel::for_each_share(force, |first, share| {
                let end = first + share.len();
                for (touch, pushed) in touches() {
                    let lowest = pushed.lowest as usize;
                    if lowest < end && lowest + pushed.span as usize >= first {
                        touch.apply_within(pushed.push * touch.normal, first, share);
                    }
                }
            });
        } else {
            for (touch, pushed) in touches() {
                touch.apply(pushed.push * touch.normal, force);
            }
        }
    }

    /// For each candidate pair that can touch in the step, its default
    /// coefficients `m (v_ref / h)²` and `m v_ref / h` for its effective
    /// mass `m = 1 / Σ w_i² / m_i` add at most `2 (v_ref / h)²` and `2 v_ref
    /// / h` to each moving member's row of the mass-scaled matrices (whatever
    /// the masses): its block is `k u uᵀ` with `u_i = w_i / √m_i`, whose row
    /// `i` sums to `k |u_i| Σ |u_j| ≤ k |u_i| √(4 Σ u_j²)`, and `|u_i| ≤
    /// √(Σ u_j²) = 1 / √m`. A given stiffness `k` (or damping) adds `2 k /
    /// m_i` (the weights sum to at most 2). A particle's pairs with the
    /// elements of one body count it once, as it touches only the closest.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        let settings = &context.contacts.settings;
        let rate = contact::REFERENCE_SPEED / settings.thickness;
        context.contacts.pairs.for_each_member(|members| {
            for i in members {
                let w = context.inverse_mass[i as usize];
                if w == 0.0 {
                    continue;
                }
                bounds.stiffness[i as usize] += settings
                    .stiffness
                    .map_or(2.0 * rate * rate, |k| 2.0 * k * w);
                bounds.damping[i as usize] += settings.damping.map_or(2.0 * rate, |c| 2.0 * c * w);
            }
        });
    }

    fn energy_name(&self) -> Option<&'static str> {
        Some("contact")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        let contacts = context.contacts;
        contacts
            .pairs
            .for_each_touch(context.position, contacts.settings.thickness, |touch| {
                let (k, _) = coefficients(context, &touch);
                *energy += 0.5 * k * touch.depth * touch.depth;
            });
    }

    /// Coulomb friction on the touches of the last evaluation
    /// (see the module docs of [`crate::contact`]).
    fn apply_impulses(&mut self, context: &mut ImpulseContext) {
        let pieces = (self.touches.pieces(), &self.pushes[..], &self.spans);
        friction::apply_friction(pieces, context, &mut self.rigid_friction);
    }

    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        self.active.clear();
        let contacts = context.contacts;
        contacts
            .pairs
            .for_each_touch(context.position, contacts.settings.thickness, |touch| {
                let (stiffness, damping) = coefficients(context, &touch);
                let normal_speed = touch.relative(context.velocity).dot(touch.normal);
                if stiffness * touch.depth - damping * normal_speed > 0.0 {
                    let push = NormalPush {
                        normal: touch.normal,
                        stiffness,
                        damping,
                    };
                    self.active.push(Active { touch, push });
                }
            });
        match self.active.is_empty() {
            true => Linearization::Zero,
            false => Linearization::Approximate,
        }
    }

    fn add_jacobian_products(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        for a in &self.active {
            a.push.add_product(scale, a.members(), p, out);
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        for a in &self.active {
            a.push.add_diagonal(scale, a.members(), diagonal);
        }
    }
}
