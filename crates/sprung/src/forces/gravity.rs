//! Uniform gravity: `f_i += m_i g`, energy `E_g = -Σ m_i (g · x_i)`.

use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::parallel;
use crate::units::{Real, Vec3};

/// Uniform gravitational acceleration `g` (m/s²) on every particle.
///
/// A new world has it ([`crate::World::set_gravity`] replaces it). Under a
/// constant force the path is a parabola, `x0 + v0 t + ½ g t²`, which RK4
/// follows exactly (it is exact for polynomials up to its order), so only
/// rounding is left after 100 steps:
///
/// ```
/// use sprung::forces::Gravity;
/// use sprung::world::DEFAULT_GRAVITY;
/// use sprung::{BodyData, IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::Rk4);
/// let g = world.forces.get::<Gravity>().unwrap().acceleration;
/// assert_eq!(g, DEFAULT_GRAVITY);
/// let v0 = Vec3::new(3.0, 4.0, 0.0);
/// let stone = BodyData::from_positions(vec![Vec3::ZERO]).with_velocity(v0);
/// world.add_body("stone", stone).unwrap();
/// for _ in 0..100 {
///     world.step(0.01).unwrap();
/// }
/// let t = world.time();
/// let parabola = v0 * t + 0.5 * g * t * t;
/// assert!(world.particles.position[0].distance(parabola) < 1e-12);
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Gravity {
    /// Acceleration of gravity (m/s²), e.g. `(0, -9.81, 0)`.
    pub acceleration: Vec3,
}

impl Force for Gravity {
    fn name(&self) -> &'static str {
        "gravity"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        if self.acceleration == Vec3::ZERO {
            return;
        }
        let g = self.acceleration;
        parallel::for_each_span(force, |start, force| {
            add_weight(force, &context.mass[start..], g);
        });
    }

    fn write(&mut self, context: &ForceContext, force: &mut [Vec3]) -> bool {
        if force.len() != context.mass.len() {
            // Not one entry per particle: cleared and added instead.
            return false;
        }
        let g = self.acceleration;
        parallel::for_each_span(force, |start, force| {
            weigh(force, &context.mass[start..], g);
        });
        true
    }

    /// A constant force: neither stiff nor damping.
    fn add_stiffness(&self, _: &ForceContext, _: &mut StiffnessBounds) {}

    fn energy_name(&self) -> Option<&'static str> {
        Some("gravity")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        let (x, m, g) = (context.position, context.mass, self.acceleration);
        *energy -= parallel::sum(x.len(), |range| range.map(|i| m[i] * g.dot(x[i])).sum());
    }

    fn uniform_acceleration(&self) -> Vec3 {
        self.acceleration
    }

    /// Constant force: both Jacobians are exactly zero.
    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Zero
    }

    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }

    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}

vectorised! {
    /// `f_i = m_i g` over a span of particles, for masses `m_i` (kg) and
    /// gravity `g` (m/s²): forces in N.
    fn weigh(force: &mut [Vec3], mass: &[Real], g: Vec3) {
        for (f, &m) in force.iter_mut().zip(mass) {
            *f = m * g;
        }
    }
}

vectorised! {
    /// `f_i += m_i g` over a span of particles, as [`weigh`].
    fn add_weight(force: &mut [Vec3], mass: &[Real], g: Vec3) {
        for (f, &m) in force.iter_mut().zip(mass) {
            *f += m * g;
        }
    }
}
