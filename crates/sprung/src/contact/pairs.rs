//! Candidate contact pairs: the four kinds, the lists of a step in
//! buckets of clearance, and the particles they may push. How one pair is
//! measured at a state is in `touch`; measuring them all, in `measure`.

mod measure;
mod touch;

#[cfg(test)]
mod tests;

pub(crate) use measure::{Touches, PREFETCH_TOUCHES};
pub(crate) use touch::{Shape, Touch};

use super::buckets::Buckets;
use crate::units::{Real, Vec3};

/// A particle against a surface element of `N` particles: a triangle of a
/// surface ([`PointTriangle`], 3D) or a segment of a 2D loop
/// ([`PointSegment`]). Their geometry, which differs, is in their touch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointElement<const N: usize> {
    /// The particle.
    pub particle: u32,
    /// The element's particles.
    pub element: [u32; N],
    /// The element's body.
    pub body: u32,
    /// +1 or -1: the side of the element the particle is pushed to, along
    /// its normal (a triangle's `(b - a) × (c - a)`, a segment's
    /// `(Δy, -Δx)`): the outside of a closed surface; for an open one, the
    /// side it was on when the pair was found.
    pub side: Real,
    /// How far (m) beyond the thickness the particle was from the element
    /// when the pair was found (zero within it, or behind).
    pub clearance: Real,
}

/// A particle against a triangle of a surface (3D).
pub type PointTriangle = PointElement<3>;

/// A particle against a segment of a 2D loop.
pub type PointSegment = PointElement<2>;

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
        let points = [
            Buckets::sort(
                &mut self.point_triangle,
                width,
                |p| p.clearance,
                same_particle,
                &mut spare.point_triangle,
            ),
            Buckets::sort(
                &mut self.point_segment,
                width,
                |p| p.clearance,
                same_particle,
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
        point_members(&self.point_triangle, within, &mut visit);
        point_members(&self.point_segment, within, &mut visit);
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
                !same_particle(&self.point_triangle[i - 1], &self.point_triangle[i])
            }
            Kind::PointSegment => {
                !same_particle(&self.point_segment[i - 1], &self.point_segment[i])
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

/// Whether two particle–element pairs are of one particle's run.
fn same_particle<const N: usize>(a: &PointElement<N>, b: &PointElement<N>) -> bool {
    a.particle == b.particle
}

/// [`ContactPairs::for_each_member`] over particle–element `pairs`, those
/// whose clearance is `within` the allowance only.
fn point_members<const N: usize>(
    pairs: &[PointElement<N>],
    within: impl Fn(Real) -> bool,
    visit: &mut impl FnMut(&mut dyn Iterator<Item = u32>),
) {
    for (i, pair) in pairs.iter().enumerate() {
        if within(pair.clearance) {
            let first = first_with_body(&pairs[..i], pair, &within);
            visit(
                &mut first
                    .then_some(pair.particle)
                    .into_iter()
                    .chain(pair.element),
            );
        }
    }
}

/// Whether `pair` is the first pair of its particle's run in `before` (the
/// pairs before it) with its body, among those whose clearance is `within`
/// the allowance: a particle's pairs come one after another.
fn first_with_body<const N: usize>(
    before: &[PointElement<N>],
    pair: &PointElement<N>,
    within: impl Fn(Real) -> bool,
) -> bool {
    !before
        .iter()
        .rev()
        .take_while(|p| p.particle == pair.particle)
        .any(|p| within(p.clearance) && p.body == pair.body)
}
