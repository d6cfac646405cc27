//! The penalty force of the contacts between bodies, as an entry of the
//! world's force list (see the module documentation of [`super`]).

use super::pairs::{Touch, Touches};
use crate::forces::{Force, ForceContext, JacobianScale, Linearization};
use crate::measure::Energies;
use crate::parallel;
use crate::{Real, Vec3};
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
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BodyContacts {
    /// The pairs that pushed at the last linearisation.
    active: Vec<Active>,
    /// The touches of the last evaluation (kept for their buffers).
    touches: Touches,
    /// The normal force (N) of each touch at the last evaluation, piece by
    /// piece of the touches.
    pushes: Vec<Vec<Real>>,
}

/// A pushing pair at the linearisation state.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Active {
    touch: Touch,
    /// Penalty stiffness (N/m).
    stiffness: Real,
    /// Penalty damping (N·s/m).
    damping: Real,
}

impl BodyContacts {
    /// Body contacts with nothing linearised yet.
    pub fn new() -> Self {
        BodyContacts::default()
    }

    /// The touches of the last evaluation, with the normal force (N) each
    /// pushed with.
    pub(crate) fn pushes(&self) -> impl Iterator<Item = (&Touch, Real)> + Clone {
        self.touches
            .iter()
            .zip(self.pushes.iter().flatten().copied())
    }

    /// The touches of the last evaluation piece by piece, and the normal
    /// force (N) each pushed with, piece by piece as well.
    pub(crate) fn pieces(&self) -> (&[Vec<Touch>], &[Vec<Real>]) {
        (self.touches.pieces(), &self.pushes)
    }
}

/// The stiffness and damping of `touch` in `context` (from the mass of its
/// first particle: the particle of a point–element pair).
fn coefficients(context: &ForceContext, touch: &Touch) -> (Real, Real) {
    let mass = context.mass[touch.particles[0] as usize];
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
        // when there are many.
        let pieces = self.touches.pieces();
        self.pushes.resize_with(pieces.len(), Vec::new);
        let normal_forces = |(touches, pushes): (&Vec<Touch>, &mut Vec<Real>)| {
            pushes.clear();
            pushes.extend(touches.iter().map(|touch| {
                let (k, c) = coefficients(context, touch);
                let normal_speed = touch.relative(context.velocity).dot(touch.normal);
                (k * touch.depth - c * normal_speed).max(0.0)
            }));
        };
        let many = self.touches.len() > parallel::CHUNK;
        if many {
            pieces
                .par_iter()
                .zip(self.pushes.par_iter_mut())
                .for_each(normal_forces);
        } else {
            pieces
                .iter()
                .zip(self.pushes.iter_mut())
                .for_each(normal_forces);
        }
        // Added in the touches' order: a random scatter, each thread into
        // its own share of the particles when there are many.
        let pushes = self.pushes();
        if many {
            parallel::for_each_share(force, |first, share| {
                for (touch, push) in pushes.clone() {
                    touch.apply_within(push * touch.normal, first, share);
                }
            });
        } else {
            for (touch, push) in pushes {
                touch.apply(push * touch.normal, force);
            }
        }
    }

    fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        let contacts = context.contacts;
        contacts
            .pairs
            .for_each_touch(context.position, contacts.settings.thickness, |touch| {
                let (k, _) = coefficients(context, &touch);
                energies.contact += 0.5 * k * touch.depth * touch.depth;
            });
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
                    self.active.push(Active {
                        touch,
                        stiffness,
                        damping,
                    });
                }
            });
        Linearization::Approximate
    }

    fn add_jacobian_products(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        for a in &self.active {
            let weight = scale.position * a.stiffness + scale.velocity * a.damping;
            let along = a.touch.relative(p).dot(a.touch.normal);
            a.touch.apply(-weight * along * a.touch.normal, out);
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        for a in &self.active {
            let weight = scale.position * a.stiffness + scale.velocity * a.damping;
            let n2 = a.touch.normal * a.touch.normal;
            for k in 0..a.touch.count {
                let w = a.touch.weights[k];
                diagonal[a.touch.particles[k] as usize] -= weight * w * w * n2;
            }
        }
    }
}
