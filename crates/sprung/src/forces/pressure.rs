//! Gas pressure on closed bodies (docs/physics.md §4): `P = nRT / V`, and each
//! surface element of area `A` with outward normal `n` feels `F = P A n`,
//! shared equally among its vertices (⅓ each for a triangle, ½ each for a
//! 2D segment). Outside pressure is zero. The gas energy is
//! `E_gas = -nRT ln V`, so with constant `nRT` and no damping
//! `E_k + E_s + E_g + E_gas` is conserved.
//!
//! The forces on a closed surface sum to zero (`Σ A n = 0` for a closed
//! polyhedron or polygon), so the gas never moves the body's centre of mass.
//!
//! **Jacobian.** The force is `F_i = P ∂V/∂x_i` (the share above is
//! exactly the volume's gradient `g_i`, times `P`), so
//! `∂F/∂x = P ∂²V/∂x² - (nRT / V²) g gᵀ`. The second term, the stiffness of
//! the gas against a change of volume, couples every vertex of the body
//! with every other, but as a rank-one matrix its product costs one pass:
//! `-(nRT/V²) g (g · p)`. It is negative definite along `g` (the gas resists
//! being squashed) and is what keeps a ball stable when it is squashed at a
//! large step. The first term (the turning of the faces) is indefinite and
//! is left out: [`Linearization::Approximate`]. Bodies whose volume model
//! is not the exact one give no Jacobian (their gas is explicit).

use std::sync::atomic::{AtomicBool, Ordering};

use super::faces::{on_its_own, own_surface, BodySurface, Surfaces};
use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::body::Body;
use crate::gas::VolumeModel;
use crate::parallel;
use crate::units::{Real, Vec3};

/// The pressure of the gas in every body that has one, with its volume
/// stiffness cached at the last linearisation.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GasPressure {
    /// Per particle, the gradient of its body's volume `∂V/∂x_i` (m², or m
    /// in 2D) at the last linearisation; zero outside gas bodies.
    gradient: Vec<Vec3>,
    /// Per gas body with the exact volume model: its particles and
    /// `nRT / V²` (J/m⁶, or J/m⁴ in 2D).
    stiff: Vec<(std::ops::Range<usize>, Real)>,
    /// The bodies' surfaces of more than a chunk of elements, in blocks for
    /// the threads (smaller ones are taken in order, body by body).
    surfaces: Surfaces,
}

impl GasPressure {
    /// Gas pressure with nothing linearised yet.
    pub fn new() -> Self {
        GasPressure::default()
    }
}

/// Add the gradient of a body's enclosed volume (area in 2D) with respect
/// to each vertex, `∂V/∂x_i` (m², or m in 2D), times `scale`, to `out`,
/// element by element of its `surface` at `x` (m).
#[inline(always)]
fn add_volume_gradient(surface: BodySurface<'_>, x: &[Vec3], scale: Real, out: &mut [Vec3]) {
    match surface {
        BodySurface::Segments(segments) => segments.scatter(out, |_, w| {
            let d = x[w.particle(1)] - x[w.particle(0)];
            // l n = (Δy, -Δx) for a counter-clockwise loop.
            let share = 0.5 * scale * Vec3::new(d.y, -d.x, 0.0);
            w.add(0, share);
            w.add(1, share);
        }),
        BodySurface::Faces(faces) => faces.scatter(out, |_, w| {
            let [a, b, c] = [w.particle(0), w.particle(1), w.particle(2)];
            let area_normal = 0.5 * (x[b] - x[a]).cross(x[c] - x[a]);
            let share = scale / 3.0 * area_normal;
            (0..3).for_each(|k| w.add(k, share));
        }),
    }
}

impl Force for GasPressure {
    fn name(&self) -> &'static str {
        "gas pressure"
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let (bodies, x, time) = (context.bodies, context.position, context.time);
        // Bodies of small surfaces (a pile of gas balls) on the threads, a
        // body at a time: each adds into its own particles only. Then the
        // others, each large surface block by block on the threads.
        // (When body ranges changed by hand overlap or leave the world,
        // every gas body takes the world-wide path.)
        let left = AtomicBool::new(false);
        let body_range = |b: usize| bodies[b].particles.clone();
        let apart = parallel::for_each_range(force, bodies.len(), body_range, |b, own| {
            let body = &bodies[b];
            if body.gas.is_none() {
                return;
            }
            if !on_its_own(body) {
                left.store(true, Ordering::Relaxed);
            } else if let Some(pressure) = pressure(body, x, time).filter(|&p| p != 0.0) {
                add_volume_gradient(own_surface(body), x, pressure, own);
            }
        });
        if apart && !left.into_inner() {
            return;
        }
        for (index, body) in bodies.iter().enumerate() {
            if body.gas.is_none() || (apart && on_its_own(body)) {
                continue;
            }
            if let Some(pressure) = pressure(body, x, time).filter(|&p| p != 0.0) {
                let surface = self.surfaces.surface(index, body, x.len());
                add_volume_gradient(surface, x, pressure, force);
            }
        }
    }

    /// Not counted in the stable step: the gas's stiffness, `nRT / V²`
    /// times the outer product of the volume gradient, acts on the body's
    /// volume as a whole, and the springs of its surface hold the step.
    fn add_stiffness(&self, _: &ForceContext, _: &mut StiffnessBounds) {}

    fn energy_name(&self) -> Option<&'static str> {
        Some("gas")
    }

    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        for body in context.bodies {
            let Some(gas) = &body.gas else { continue };
            let volume = body.gas_volume(gas.volume_model, context.position);
            if volume > 0.0 {
                *energy -= gas.nrt_at(context.time) * volume.ln();
            }
        }
    }

    fn linearize(&mut self, context: &ForceContext) -> Linearization {
        let x = context.position;
        self.gradient.clear();
        self.gradient.resize(x.len(), Vec3::ZERO);
        self.stiff.clear();
        for (index, body) in context.bodies.iter().enumerate() {
            let Some(gas) = &body.gas else { continue };
            if gas.volume_model != VolumeModel::Exact {
                continue;
            }
            let volume = body.gas_volume(gas.volume_model, x);
            if volume > 0.0 {
                let surface = self.surfaces.surface(index, body, x.len());
                add_volume_gradient(surface, x, 1.0, &mut self.gradient);
                let stiffness = gas.nrt_at(context.time) / (volume * volume);
                self.stiff.push((body.particles.clone(), stiffness));
            }
        }
        match self.stiff.is_empty() {
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
        for (range, stiffness) in &self.stiff {
            let (gradient, p) = (&self.gradient[range.clone()], &p[range.clone()]);
            let along = parallel::sum(gradient.len(), |r| r.map(|i| gradient[i].dot(p[i])).sum());
            let factor = scale.position * stiffness * along;
            parallel::for_each_span(&mut out[range.clone()], |start, out| {
                for (o, g) in out.iter_mut().zip(&gradient[start..]) {
                    *o -= factor * *g;
                }
            });
        }
    }

    fn add_jacobian_diagonal(
        &self,
        _context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        for (range, stiffness) in &self.stiff {
            let factor = scale.position * stiffness;
            for (d, g) in diagonal[range.clone()]
                .iter_mut()
                .zip(&self.gradient[range.clone()])
            {
                *d -= factor * *g * *g;
            }
        }
    }
}

/// Pressure `nRT / V` of `body`'s gas at `position` and `time` (Pa, or N/m
/// in 2D); `None` without a gas or when the volume is not positive (the
/// body has turned inside out: no pressure is applied); 0 once the body's
/// surface has opened (a spring along it broke: the gas has escaped).
pub fn pressure(body: &Body, position: &[Vec3], time: Real) -> Option<Real> {
    let gas = body.gas.as_ref()?;
    if !body.closed {
        return Some(0.0);
    }
    let volume = body.gas_volume(gas.volume_model, position);
    (volume > 0.0).then(|| gas.nrt_at(time) / volume)
}
