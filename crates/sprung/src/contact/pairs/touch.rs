//! One candidate pair measured at a state: its [`Touch`], the particles of
//! its two sides with the weights of their closest points, the normal, and
//! how deep inside the thickness they are.

use super::{beyond, EdgeEdge, PointElement, PointSegment, PointTriangle};
use crate::contact::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use crate::units::{Real, Vec3};

/// The geometry of a particle–element pair, which differs by the shape of
/// the element: a triangle (3D) or a segment of a 2D loop.
pub(crate) trait Shape {
    /// The side (+1 or -1) the particle is on at `position` (m), along the
    /// element's normal (`(b - a) × (c - a)`, `(Δy, -Δx)`), +1 in its
    /// plane: the side an open surface pushes it to.
    fn side_at(&self, position: &[Vec3]) -> Real;

    /// The touch of the pair at `position` (m) if the particle is within
    /// `thickness` (m) of the element in front of it, or anywhere behind
    /// it over its inside (a particle that got inside a closed surface is
    /// pushed out however deep).
    fn touch(&self, position: &[Vec3], thickness: Real) -> Option<Touch>;
}

impl<const N: usize> PointElement<N> {
    /// The pair's clearance (m) at `position` (m) for the contact
    /// `thickness` (m), if it is within `reach` (m); zero beyond.
    pub(crate) fn clearance_at(&self, position: &[Vec3], thickness: Real, reach: Real) -> Real
    where
        Self: Shape,
    {
        self.touch(position, reach)
            .map_or(0.0, |t| beyond(reach - t.depth, thickness))
    }
}

impl Shape for PointTriangle {
    fn side_at(&self, position: &[Vec3]) -> Real {
        let x = |i: u32| position[i as usize];
        let [a, b, c] = self.element;
        let p = x(self.particle);
        let w = closest_on_triangle(p, x(a), x(b), x(c));
        let q = w[0] * x(a) + w[1] * x(b) + w[2] * x(c);
        side_of(p - q, (x(b) - x(a)).cross(x(c) - x(a)))
    }

    #[inline(always)]
    fn touch(&self, position: &[Vec3], thickness: Real) -> Option<Touch> {
        let x = |i: u32| position[i as usize];
        let [a, b, c] = self.element;
        let p = x(self.particle);
        let (xa, xb, xc) = (x(a), x(b), x(c));
        let face = self.side * (xb - xa).cross(xc - xa);
        // In front of the triangle's plane by more than the thickness: no
        // point of it is within reach.
        let height = (p - xa).dot(face);
        if height > 0.0 && height * height > thickness * thickness * face.length_squared() {
            return None;
        }
        // In front of the plane and farther than the thickness from the
        // triangle's box: no point of it is within reach either.
        let reach = Vec3::splat(thickness);
        let (low, high) = (xa.min(xb).min(xc) - reach, xa.max(xb).max(xc) + reach);
        if height >= 0.0 && !(p.cmpge(low).all() && p.cmple(high).all()) {
            return None;
        }
        let weights = closest_on_triangle(p, xa, xb, xc);
        let closest = weights[0] * xa + weights[1] * xb + weights[2] * xc;
        let interior = weights.iter().all(|&w| w > 0.0);
        push(p - closest, face, interior, thickness).map(|(normal, depth)| Touch {
            particles: [self.particle, a, b, c],
            weights: [1.0, -weights[0], -weights[1], -weights[2]],
            count: 4,
            normal,
            depth,
        })
    }
}

impl Shape for PointSegment {
    fn side_at(&self, position: &[Vec3]) -> Real {
        let x = |i: u32| position[i as usize];
        let [a, b] = self.element;
        let p = x(self.particle);
        let d = x(b) - x(a);
        let q = x(a) + closest_on_segment(p, x(a), x(b)) * d;
        side_of(p - q, Vec3::new(d.y, -d.x, 0.0))
    }

    /// As the triangle's, in 2D (no box to pass over by).
    #[inline(always)]
    fn touch(&self, position: &[Vec3], thickness: Real) -> Option<Touch> {
        let x = |i: u32| position[i as usize];
        let [a, b] = self.element;
        let p = x(self.particle);
        let d = x(b) - x(a);
        let face = self.side * Vec3::new(d.y, -d.x, 0.0);
        let height = (p - x(a)).dot(face);
        if height > 0.0 && height * height > thickness * thickness * face.length_squared() {
            return None;
        }
        let t = closest_on_segment(p, x(a), x(b));
        let closest = x(a) + t * d;
        let interior = t > 0.0 && t < 1.0;
        push(p - closest, face, interior, thickness).map(|(normal, depth)| Touch {
            particles: [self.particle, a, b, 0],
            weights: [1.0, -(1.0 - t), -t, 0.0],
            count: 3,
            normal,
            depth,
        })
    }
}

/// The side (+1 or -1) of `offset` along `face`, +1 when in the plane.
fn side_of(offset: Vec3, face: Vec3) -> Real {
    if offset.dot(face) < 0.0 {
        -1.0
    } else {
        1.0
    }
}

impl EdgeEdge {
    /// The distance (m) between the edges at `position` (m).
    pub(crate) fn distance_at(&self, position: &[Vec3]) -> Real {
        let x = |i: u32| position[i as usize];
        let ([p1, q1], [p2, q2]) = (self.first, self.second);
        let (s, t) = closest_between_segments(x(p1), x(q1), x(p2), x(q2));
        ((x(p1) + s * (x(q1) - x(p1))) - (x(p2) + t * (x(q2) - x(p2)))).length()
    }
}

/// A pair closer than the thickness at a state: the relative position of
/// its two sides is `Σ weights[i] x[particles[i]]` (the first side's
/// closest point minus the second's), to be pushed along `normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Touch {
    /// The particles of both sides (the first `count` are used).
    pub particles: [u32; 4],
    /// Their weights: positive on the first side, negative on the second.
    pub weights: [Real; 4],
    /// How many particles take part.
    pub count: usize,
    /// Unit normal, from the second side to the first.
    pub normal: Vec3,
    /// How far inside the thickness (m), positive.
    pub depth: Real,
}

impl Touch {
    /// `Σ weights[i] v[particles[i]]`: the relative value of a per-particle
    /// quantity (velocity, a vector of a product).
    pub fn relative(&self, v: &[Vec3]) -> Vec3 {
        (0..self.count)
            .map(|k| self.weights[k] * v[self.particles[k] as usize])
            .sum()
    }

    /// Ask the processor for the touch's particles' velocities (m/s) and
    /// inverse masses (1/kg) ahead of their use.
    #[inline(always)]
    pub fn prefetch(&self, velocity: &[Vec3], inverse_mass: &[Real]) {
        for &p in &self.particles[..self.count] {
            let p = p as usize;
            if let (Some(v), Some(w)) = (velocity.get(p), inverse_mass.get(p)) {
                crate::cache::prefetch(v);
                crate::cache::prefetch(w);
            }
        }
    }

    /// The touch's lowest and highest particles.
    pub fn extent(&self) -> [u32; 2] {
        let particles = &self.particles[..self.count];
        [
            particles.iter().copied().min().unwrap_or(0),
            particles.iter().copied().max().unwrap_or(0),
        ]
    }

    /// Add `force` (N) to the first side and its opposite to the second,
    /// shared by the weights.
    pub fn apply(&self, force: Vec3, out: &mut [Vec3]) {
        self.apply_within(force, 0, out);
    }

    /// [`Touch::apply`] of `force` (N) to the particles of `share` only,
    /// the entries of particles `first..` (a thread's share of a parallel
    /// scatter, [`crate::parallel::for_each_share`]).
    #[inline(always)]
    pub fn apply_within(&self, force: Vec3, first: usize, share: &mut [Vec3]) {
        for k in 0..self.count {
            let into = (self.particles[k] as usize).wrapping_sub(first);
            if let Some(entry) = share.get_mut(into) {
                *entry += self.weights[k] * force;
            }
        }
    }
}

/// Normal and depth of a particle at `offset` from its closest point on a
/// surface element whose normal (towards the side it is pushed to, any
/// length) is `face`: along the face's normal where the closest point is
/// inside the element; along the offset near its boundary, if in front.
#[inline(always)]
fn push(offset: Vec3, face: Vec3, interior: bool, thickness: Real) -> Option<(Vec3, Real)> {
    let face = face.normalize_or_zero();
    let (normal, distance) = if interior && face != Vec3::ZERO {
        (face, offset.dot(face))
    } else {
        if offset.dot(face) < 0.0 {
            return None;
        }
        let length = offset.length();
        let normal = if length > 0.0 { offset / length } else { face };
        (normal, length)
    };
    let depth = thickness - distance;
    (depth > 0.0 && normal != Vec3::ZERO).then_some((normal, depth))
}

/// Normal and depth of two closest points `gap` apart that were apart
/// along `direction` when the pair was found: along the gap while they are
/// still on their sides, along `direction` (a negative separation) once
/// they have passed each other.
#[inline(always)]
pub(super) fn apart(gap: Vec3, direction: Vec3, thickness: Real) -> Option<(Vec3, Real)> {
    let along = gap.dot(direction);
    let (normal, separation) = if along > 0.0 {
        let length = gap.length();
        (gap / length, length)
    } else {
        (direction, along)
    };
    let depth = thickness - separation;
    (depth > 0.0).then_some((normal, depth))
}
