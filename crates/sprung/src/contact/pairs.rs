//! Candidate contact pairs: the four kinds, the lists of a step in
//! buckets of clearance, and the particles they may push. How one pair is
//! measured at a state is in `touch`; measuring them all, in `measure`.

mod measure;
mod touch;

#[cfg(test)]
mod tests;

pub(crate) use measure::{Touches, PREFETCH_TOUCHES};
pub(crate) use touch::Touch;

use super::buckets::Buckets;
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
    /// How far (m) beyond the thickness the particle was from the triangle
    /// when the pair was found (zero within it, or behind).
    pub clearance: Real,
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
    /// How far (m) beyond the thickness the particle was from the segment
    /// when the pair was found (zero within it, or behind).
    pub clearance: Real,
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
    /// How far (m) beyond the thickness the edges were apart when the pair
    /// was found (zero within it).
    pub clearance: Real,
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
    /// How far (m) beyond the thickness the particles were apart when the
    /// pair was found (zero within it).
    pub clearance: Real,
}

/// How far (m) beyond `thickness` (m) a `distance` (m) is; zero within.
pub(crate) fn beyond(distance: Real, thickness: Real) -> Real {
    (distance - thickness).max(0.0)
}

/// Buffers to sort the lists of pairs into buckets.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Spare {
    point_triangle: Vec<PointTriangle>,
    point_segment: Vec<PointSegment>,
    edge_edge: Vec<EdgeEdge>,
    point_point: Vec<PointPoint>,
}

/// The candidate pairs of a step. The lists are the engine's own: each is
/// kept in buckets of clearance that a change from outside would break.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPairs {
    /// Particles against triangles.
    pub(crate) point_triangle: Vec<PointTriangle>,
    /// Particles against 2D segments.
    pub(crate) point_segment: Vec<PointSegment>,
    /// Edges against edges.
    pub(crate) edge_edge: Vec<EdgeEdge>,
    /// Particles against particles.
    pub(crate) point_point: Vec<PointPoint>,
    /// How much closer (m) any two elements can have come since the pairs
    /// were found, at the states of the current step (set by the detect
    /// stage from how far the particles have moved since, how fast they go
    /// and how much their velocities changed in the last step): a pair
    /// whose clearance is larger cannot touch, and is not measured.
    /// Infinite (every pair measured) until the detect stage sets it, and
    /// on a step with no last step to compare.
    pub(crate) allowance: Real,
    /// Where the buckets of clearance of each list start, by [`Kind`].
    buckets: [Buckets; 4],
}

impl Default for ContactPairs {
    fn default() -> Self {
        ContactPairs {
            point_triangle: Vec::new(),
            point_segment: Vec::new(),
            edge_edge: Vec::new(),
            point_point: Vec::new(),
            allowance: Real::INFINITY,
            buckets: Default::default(),
        }
    }
}

impl ContactPairs {
    /// Remove every pair (keeping the buffers).
    pub fn clear(&mut self) {
        self.point_triangle.clear();
        self.point_segment.clear();
        self.edge_edge.clear();
        self.point_point.clear();
        self.buckets = Default::default();
    }

    /// Put every list of pairs in buckets of clearance `width` (m) wide,
    /// nearest first ([`Buckets::sort`]): single pairs of edges and of
    /// particles, and each particle's run of particle–element pairs as a
    /// whole (`spare` holds the buffers).
    pub(crate) fn bucket(&mut self, width: Real, spare: &mut Spare) {
        let particle = |a: &PointTriangle, b: &PointTriangle| a.particle == b.particle;
        let in_2d = |a: &PointSegment, b: &PointSegment| a.particle == b.particle;
        let points = [
            Buckets::sort(
                &mut self.point_triangle,
                width,
                |p| p.clearance,
                particle,
                &mut spare.point_triangle,
            ),
            Buckets::sort(
                &mut self.point_segment,
                width,
                |p| p.clearance,
                in_2d,
                &mut spare.point_segment,
            ),
        ];
        self.bucket_singles(width, points, spare);
    }

    /// [`ContactPairs::bucket`] for the lists of single pairs (of edges,
    /// of particles) only: the particle–element lists are in buckets
    /// already, where `points` say (triangles, segments), as the search
    /// puts them in order and in buckets in one sort
    /// ([`Buckets::by_particle`]).
    pub(crate) fn bucket_singles(&mut self, width: Real, points: [Buckets; 2], spare: &mut Spare) {
        let [triangles, segments] = points;
        self.buckets = [
            triangles,
            segments,
            Buckets::sort(
                &mut self.edge_edge,
                width,
                |p| p.clearance,
                |_, _| false,
                &mut spare.edge_edge,
            ),
            Buckets::sort(
                &mut self.point_point,
                width,
                |p| p.clearance,
                |_, _| false,
                &mut spare.point_point,
            ),
        ];
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

    /// Call `visit` with the particles each candidate pair that can touch
    /// in the step (its clearance within the allowance, as a measure reads
    /// them) may push. A particle meets each other body at one element
    /// only (its closest), so among a particle's pairs with one body's
    /// elements the particle itself is given with the first only.
    pub fn for_each_member(&self, mut visit: impl FnMut(&mut dyn Iterator<Item = u32>)) {
        let within = |clearance: Real| clearance <= self.allowance;
        point_members(
            &self.point_triangle,
            |p| (p.particle, p.body, within(p.clearance)),
            |p| p.triangle,
            &mut visit,
        );
        point_members(
            &self.point_segment,
            |p| (p.particle, p.body, within(p.clearance)),
            |p| p.segment,
            &mut visit,
        );
        for p in self.edge_edge.iter().filter(|p| within(p.clearance)) {
            visit(&mut p.first.into_iter().chain(p.second));
        }
        for p in self.point_point.iter().filter(|p| within(p.clearance)) {
            visit(&mut [p.first, p.second].into_iter());
        }
    }

    /// The number of pairs of `kind`.
    fn len_of(&self, kind: Kind) -> usize {
        let len = match kind {
            Kind::PointTriangle => self.point_triangle.len(),
            Kind::PointSegment => self.point_segment.len(),
            Kind::EdgeEdge => self.edge_edge.len(),
            Kind::PointPoint => self.point_point.len(),
        };
        self.buckets[kind as usize].reached(self.allowance, len)
    }

    /// Whether the pairs of `kind` may be cut before pair `i` (`0 < i <
    /// len`): not inside a particle's run of point–element pairs, whose
    /// closest element is picked among them.
    fn cut_before(&self, kind: Kind, i: usize) -> bool {
        match kind {
            Kind::PointTriangle => {
                self.point_triangle[i].particle != self.point_triangle[i - 1].particle
            }
            Kind::PointSegment => {
                self.point_segment[i].particle != self.point_segment[i - 1].particle
            }
            Kind::EdgeEdge | Kind::PointPoint => true,
        }
    }
}

/// The four lists of pairs, in the order their touches come.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    PointTriangle,
    PointSegment,
    EdgeEdge,
    PointPoint,
}

impl Kind {
    const ALL: [Kind; 4] = [
        Kind::PointTriangle,
        Kind::PointSegment,
        Kind::EdgeEdge,
        Kind::PointPoint,
    ];
}

/// [`ContactPairs::for_each_member`] over particle–element `pairs`: `key`
/// gives a pair's particle, the element's body and whether the pair can
/// touch in the step, `element` the element's particles.
fn point_members<P, const N: usize>(
    pairs: &[P],
    key: impl Fn(&P) -> (u32, u32, bool),
    element: impl Fn(&P) -> [u32; N],
    visit: &mut impl FnMut(&mut dyn Iterator<Item = u32>),
) {
    for (i, pair) in pairs.iter().enumerate() {
        let (particle, _, counts) = key(pair);
        if counts {
            let first = first_with_body(&pairs[..i], pair, &key);
            visit(&mut first.then_some(particle).into_iter().chain(element(pair)));
        }
    }
}

/// Whether `pair` is the first pair of its particle's run in `before` (the
/// pairs before it) with its body, among those `key` says count
/// (`(particle, body, counts)`): a particle's pairs come one after another.
fn first_with_body<P>(before: &[P], pair: &P, key: impl Fn(&P) -> (u32, u32, bool)) -> bool {
    let (particle, body, _) = key(pair);
    !before
        .iter()
        .rev()
        .map(&key)
        .take_while(|&(p, _, _)| p == particle)
        .any(|(_, b, counts)| counts && b == body)
}
