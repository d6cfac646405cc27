//! Penalty contacts with the colliders (docs/physics.md §5): the force of every
//! collider with a [`ContactResponse::Penalty`] response, as one entry of
//! the force list (projection colliders act in the step's collide stage
//! instead).
//!
//! Jacobians, per particle inside a collider and pushed out by it:
//! `∂f/∂x = -k_c n nᵀ`, `∂f/∂v = -c n nᵀ`. The turning of a sphere's normal
//! (which would make the matrix indefinite inside) and the friction force
//! are left out: [`Linearization::Approximate`].

use super::{Force, ForceContext, JacobianScale, Linearization, NormalPush, StiffnessBounds};
use crate::colliders::{self, Collider, ContactResponse};
use crate::units::{Real, Vec3};

/// The penalty forces of the world's colliders (reads
/// `ForceContext::colliders`).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ColliderContacts {
    /// The particles pushed at the last linearisation, and how.
    active: Vec<(usize, NormalPush)>,
}

impl ColliderContacts {
    /// Penalty contacts with nothing linearised yet.
    pub fn new() -> Self {
        ColliderContacts::default()
    }
}

impl Force for ColliderContacts {
    fn name(&self) -> &'static str {
        "collider contacts"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        for collider in context.colliders {
            colliders::penalty_force(
                collider,
                context.time,
                context.position,
                context.velocity,
                force,
            );
        }
    }

    /// Every collider's penalty stiffness `k_c` over each particle's mass,
    /// on every particle (any may reach a collider within the step); the
    /// penalty damping is left out.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        let penalty: Real = context
            .colliders
            .iter()
            .map(Collider::penalty_stiffness)
            .sum();
        for (bound, w) in bounds.stiffness.iter_mut().zip(context.inverse_mass) {
            *bound += penalty * w;
        }
    }

    fn energy_name(&self) -> Option<&'static str> {
        Some("contact")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        *energy += context
            .colliders
            .iter()
            .map(|c| c.contact_energy(context.time, context.position))
            .sum::<Real>();
    }

    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        self.active.clear();
        for collider in context.colliders {
            let ContactResponse::Penalty {
                stiffness, damping, ..
            } = collider.response
            else {
                continue;
            };
            let shape = collider.shape_at(context.time);
            let surface_velocity = collider.velocity_at(context.time);
            for (particle, (&x, &v)) in context.position.iter().zip(context.velocity).enumerate() {
                let (distance, normal) = shape.distance_and_normal(x);
                let normal_speed = (v - surface_velocity).dot(normal);
                if distance < 0.0 && -stiffness * distance - damping * normal_speed > 0.0 {
                    let push = NormalPush {
                        normal,
                        stiffness,
                        damping,
                    };
                    self.active.push((particle, push));
                }
            }
        }
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
        for &(particle, push) in &self.active {
            push.add_product(scale, std::iter::once((particle, 1.0)), p, out);
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        for &(particle, push) in &self.active {
            push.add_diagonal(scale, std::iter::once((particle, 1.0)), diagonal);
        }
    }
}
