//! Candidate contact pairs, and how each is measured at a state: the
//! particles of its two sides with the weights of their closest points,
//! the normal, and how deep inside the thickness they are.

use super::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use crate::{Real, Vec3};

/// A particle against a triangle of a surface (3D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointTriangle {
    /// The particle.
    pub particle: u32,
    /// The triangle's particles.
    pub triangle: [u32; 3],
    /// The triangle's body.
    pub body: u32,
    /// +1 or -1: the side of the triangle (along `(b - a) × (c - a)`) the
    /// particle is pushed to (the outside of a closed surface; for an open
    /// one, the side it was on when the pair was found).
    pub side: Real,
}

/// A particle against a segment of a 2D loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSegment {
    /// The particle.
    pub particle: u32,
    /// The segment's particles.
    pub segment: [u32; 2],
    /// The segment's body.
    pub body: u32,
    /// +1 or -1: the side along the segment's normal `(Δy, -Δx)` the
    /// particle is pushed to.
    pub side: Real,
}

/// An edge against an edge (where at least one surface is open).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EdgeEdge {
    /// The first edge's particles.
    pub first: [u32; 2],
    /// The second edge's particles.
    pub second: [u32; 2],
    /// Unit direction from the second edge's closest point to the first's
    /// when the pair was found: the first edge is pushed this way.
    pub direction: Vec3,
}

/// Two particles of bodies without surfaces, each a ball of radius half the
/// thickness.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointPoint {
    /// The first particle.
    pub first: u32,
    /// The second particle.
    pub second: u32,
    /// Unit direction from the second to the first when the pair was found.
    pub direction: Vec3,
}

/// The candidate pairs of a step.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactPairs {
    /// Particles against triangles.
    pub point_triangle: Vec<PointTriangle>,
    /// Particles against 2D segments.
    pub point_segment: Vec<PointSegment>,
    /// Edges against edges.
    pub edge_edge: Vec<EdgeEdge>,
    /// Particles against particles.
    pub point_point: Vec<PointPoint>,
}

impl ContactPairs {
    /// Remove every pair (keeping the buffers).
    pub fn clear(&mut self) {
        self.point_triangle.clear();
        self.point_segment.clear();
        self.edge_edge.clear();
        self.point_point.clear();
    }

    /// Number of candidate pairs.
    pub fn len(&self) -> usize {
        self.point_triangle.len()
            + self.point_segment.len()
            + self.edge_edge.len()
            + self.point_point.len()
    }

    /// True when there is no candidate pair.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Call `visit` with each candidate pair's first particle (the particle
    /// of a point–element pair, whose mass sets the default stiffness) and
    /// all its particles.
    pub fn for_each_member(&self, mut visit: impl FnMut(u32, &mut dyn Iterator<Item = u32>)) {
        for p in &self.point_triangle {
            visit(
                p.particle,
                &mut std::iter::once(p.particle).chain(p.triangle),
            );
        }
        for p in &self.point_segment {
            visit(
                p.particle,
                &mut std::iter::once(p.particle).chain(p.segment),
            );
        }
        for p in &self.edge_edge {
            visit(p.first[0], &mut p.first.into_iter().chain(p.second));
        }
        for p in &self.point_point {
            visit(p.first, &mut [p.first, p.second].into_iter());
        }
    }

    /// Call `touch` with every pair closer than `thickness` (m) at
    /// `position` (m), in a fixed order. A particle meets each other body's
    /// surface at one place only, its closest element: near an edge or a
    /// corner of a mesh several elements are within reach, and counting
    /// each would push the particle several times over.
    pub(crate) fn for_each_touch(
        &self,
        position: &[Vec3],
        thickness: Real,
        mut touch: impl FnMut(Touch),
    ) {
        let x = |i: u32| position[i as usize];
        closest_per_body(
            &self.point_triangle,
            |pair| (pair.particle, pair.body),
            |pair| {
                let [a, b, c] = pair.triangle;
                let face = pair.side * (x(b) - x(a)).cross(x(c) - x(a));
                // In front of the triangle's plane by more than the
                // thickness: no point of it is within reach.
                let height = (x(pair.particle) - x(a)).dot(face);
                if height > 0.0 && height * height > thickness * thickness * face.length_squared() {
                    return None;
                }
                let weights = closest_on_triangle(x(pair.particle), x(a), x(b), x(c));
                let closest = weights[0] * x(a) + weights[1] * x(b) + weights[2] * x(c);
                let interior = weights.iter().all(|&w| w > 0.0);
                push(x(pair.particle) - closest, face, interior, thickness).map(
                    |(normal, depth)| Touch {
                        particles: [pair.particle, a, b, c],
                        weights: [1.0, -weights[0], -weights[1], -weights[2]],
                        count: 4,
                        normal,
                        depth,
                    },
                )
            },
            &mut touch,
        );
        closest_per_body(
            &self.point_segment,
            |pair| (pair.particle, pair.body),
            |pair| {
                let [a, b] = pair.segment;
                let d = x(b) - x(a);
                let face = pair.side * Vec3::new(d.y, -d.x, 0.0);
                let height = (x(pair.particle) - x(a)).dot(face);
                if height > 0.0 && height * height > thickness * thickness * face.length_squared() {
                    return None;
                }
                let t = closest_on_segment(x(pair.particle), x(a), x(b));
                let closest = x(a) + t * d;
                let interior = t > 0.0 && t < 1.0;
                push(x(pair.particle) - closest, face, interior, thickness).map(
                    |(normal, depth)| Touch {
                        particles: [pair.particle, a, b, 0],
                        weights: [1.0, -(1.0 - t), -t, 0.0],
                        count: 3,
                        normal,
                        depth,
                    },
                )
            },
            &mut touch,
        );
        for pair in &self.edge_edge {
            let ([p1, q1], [p2, q2]) = (pair.first, pair.second);
            let (s, t) = closest_between_segments(x(p1), x(q1), x(p2), x(q2));
            let gap = (x(p1) + s * (x(q1) - x(p1))) - (x(p2) + t * (x(q2) - x(p2)));
            if let Some((normal, depth)) = apart(gap, pair.direction, thickness) {
                touch(Touch {
                    particles: [p1, q1, p2, q2],
                    weights: [1.0 - s, s, -(1.0 - t), -t],
                    count: 4,
                    normal,
                    depth,
                });
            }
        }
        for pair in &self.point_point {
            let gap = x(pair.first) - x(pair.second);
            if let Some((normal, depth)) = apart(gap, pair.direction, thickness) {
                touch(Touch {
                    particles: [pair.first, pair.second, 0, 0],
                    weights: [1.0, -1.0, 0.0, 0.0],
                    count: 2,
                    normal,
                    depth,
                });
            }
        }
    }
}

/// Call `touch` with the deepest touch of each run of `pairs` that share a
/// particle and a body (`key`), measured by `measure`. The detect stage
/// writes a particle's pairs one after another, so a run is contiguous.
fn closest_per_body<P>(
    pairs: &[P],
    key: impl Fn(&P) -> (u32, u32),
    measure: impl Fn(&P) -> Option<Touch>,
    touch: &mut impl FnMut(Touch),
) {
    let mut start = 0;
    while start < pairs.len() {
        let particle = key(&pairs[start]).0;
        let mut end = start;
        while end < pairs.len() && key(&pairs[end]).0 == particle {
            end += 1;
        }
        // Within the particle's run, the deepest touch of each body, bodies
        // in the order they first appear.
        for (first, pair) in pairs[start..end].iter().enumerate() {
            let body = key(pair).1;
            if pairs[start..start + first].iter().any(|p| key(p).1 == body) {
                continue;
            }
            let deepest = pairs[start + first..end]
                .iter()
                .filter(|p| key(p).1 == body)
                .filter_map(&measure)
                .fold(None, |best: Option<Touch>, t| match best {
                    Some(b) if b.depth >= t.depth => Some(b),
                    _ => Some(t),
                });
            if let Some(t) = deepest {
                touch(t);
            }
        }
        start = end;
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

    /// Add `force` to the first side and its opposite to the second, shared
    /// by the weights.
    pub fn apply(&self, force: Vec3, out: &mut [Vec3]) {
        for k in 0..self.count {
            out[self.particles[k] as usize] += self.weights[k] * force;
        }
    }
}

/// Normal and depth of a particle at `offset` from its closest point on a
/// surface element whose normal (towards the side it is pushed to, any
/// length) is `face`: along the face's normal where the closest point is
/// inside the element; along the offset near its boundary, if in front.
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
fn apart(gap: Vec3, direction: Vec3, thickness: Real) -> Option<(Vec3, Real)> {
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
