//! Candidate contact pairs, and how each is measured at a state: the
//! particles of its two sides with the weights of their closest points,
//! the normal, and how deep inside the thickness they are.

use super::buckets::Buckets;
use super::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use std::ops::Range;

use crate::parallel;
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

impl PointTriangle {
    /// The pair's clearance (m) at `position` (m) for the contact
    /// `thickness` (m), if it is within `reach` (m); zero beyond.
    pub(crate) fn clearance_at(&self, position: &[Vec3], thickness: Real, reach: Real) -> Real {
        self.touch(position, reach)
            .map_or(0.0, |t| beyond(reach - t.depth, thickness))
    }

    /// The touch of the pair at `position` (m) if the particle is within
    /// `thickness` (m) of the triangle in front of it, or anywhere behind
    /// it over its inside (a particle that got inside a closed surface is
    /// pushed out however deep).
    #[inline(always)]
    pub(crate) fn touch(&self, position: &[Vec3], thickness: Real) -> Option<Touch> {
        let x = |i: u32| position[i as usize];
        let [a, b, c] = self.triangle;
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

impl PointSegment {
    /// As [`PointTriangle::clearance_at`].
    pub(crate) fn clearance_at(&self, position: &[Vec3], thickness: Real, reach: Real) -> Real {
        self.touch(position, reach)
            .map_or(0.0, |t| beyond(reach - t.depth, thickness))
    }

    /// The touch of the pair at `position` (m): as
    /// [`PointTriangle::touch`], in 2D.
    #[inline(always)]
    pub(crate) fn touch(&self, position: &[Vec3], thickness: Real) -> Option<Touch> {
        let x = |i: u32| position[i as usize];
        let [a, b] = self.segment;
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

impl EdgeEdge {
    /// The distance (m) between the edges at `position` (m).
    pub(crate) fn distance_at(&self, position: &[Vec3]) -> Real {
        let x = |i: u32| position[i as usize];
        let ([p1, q1], [p2, q2]) = (self.first, self.second);
        let (s, t) = closest_between_segments(x(p1), x(q1), x(p2), x(q2));
        ((x(p1) + s * (x(q1) - x(p1))) - (x(p2) + t * (x(q2) - x(p2)))).length()
    }
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
        for kind in Kind::ALL {
            self.touches_in(kind, 0..self.len_of(kind), position, thickness, &mut touch);
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

    /// [`ContactPairs::for_each_touch`] over the pairs `range` of `kind`
    /// (whole runs of a particle's pairs).
    #[inline(always)]
    fn touches_in(
        &self,
        kind: Kind,
        range: Range<usize>,
        position: &[Vec3],
        thickness: Real,
        touch: &mut impl FnMut(Touch),
    ) {
        let x = |i: u32| position[i as usize];
        // Pairs that cannot have come within the thickness since they were
        // found are passed over without reading their positions.
        let within = |clearance: Real| clearance <= self.allowance;
        match kind {
            Kind::PointTriangle => closest_per_body(
                &self.point_triangle[range],
                |pair| (pair.particle, pair.body),
                |pair| {
                    let near = within(pair.clearance);
                    near.then(|| pair.touch(position, thickness)).flatten()
                },
                |pair| {
                    if within(pair.clearance) {
                        for i in pair.triangle {
                            if let Some(x) = position.get(i as usize) {
                                crate::cache::prefetch(x);
                            }
                        }
                    }
                },
                touch,
            ),
            Kind::PointSegment => closest_per_body(
                &self.point_segment[range],
                |pair| (pair.particle, pair.body),
                |pair| {
                    let near = within(pair.clearance);
                    near.then(|| pair.touch(position, thickness)).flatten()
                },
                |_| {},
                touch,
            ),
            Kind::EdgeEdge => {
                for pair in &self.edge_edge[range] {
                    if !within(pair.clearance) {
                        continue;
                    }
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
            }
            Kind::PointPoint => {
                for pair in &self.point_point[range] {
                    if !within(pair.clearance) {
                        continue;
                    }
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

/// How many touches ahead the normal forces' loop asks for their
/// particles' data ([`Touch::prefetch`]): a touch's particles lie
/// scattered over the arrays (a triangle of another body), and each touch
/// waited on memory without it (a 1000-ball pile's normal forces, one
/// thread: 0.34–0.43 ms a step without, 0.18–0.19 with; 8 and 16 ahead
/// measured alike). Friction's loop gained nothing from it.
pub(crate) const PREFETCH_TOUCHES: usize = 8;

/// Pairs a thread measures at a time (rounded up to whole runs).
const PAIR_CHUNK: usize = 2048;

/// The touches of the candidate pairs at a state, measured in parallel over
/// pieces of the pairs and kept in the order of
/// [`ContactPairs::for_each_touch`], so that whatever applies them in that
/// order gets the same bits on any number of threads. The buffers are kept
/// from step to step.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Touches {
    /// The pieces: a list and a range of whole runs in it.
    pieces: Vec<(Kind, Range<usize>)>,
    /// Per piece, its touches.
    found: Vec<Vec<Touch>>,
}

impl Touches {
    /// Measure every pair of `pairs` at `position` (m) with the contact
    /// `thickness` (m).
    pub fn measure(&mut self, pairs: &ContactPairs, position: &[Vec3], thickness: Real) {
        self.pieces.clear();
        for kind in Kind::ALL {
            let len = pairs.len_of(kind);
            let mut start = 0;
            while start < len {
                let mut end = (start + PAIR_CHUNK).min(len);
                while end < len && !pairs.cut_before(kind, end) {
                    end += 1;
                }
                self.pieces.push((kind, start..end));
                start = end;
            }
        }
        let pieces = &self.pieces;
        let measure = |range: Range<usize>, found: &mut Vec<Touch>| {
            measure_pieces(pairs, &pieces[range], position, thickness, found);
        };
        if pairs.len() <= parallel::CHUNK {
            // Too few to share: on the calling thread, into one buffer.
            self.found.iter_mut().for_each(Vec::clear);
            if self.found.is_empty() {
                self.found.push(Vec::new());
            }
            measure(0..pieces.len(), &mut self.found[0]);
        } else {
            parallel::collect_chunks(pieces.len(), 1, &mut self.found, measure);
        }
    }

    /// The touches of the last measure, in order, as pieces of a thread
    /// each (some may be empty).
    pub fn pieces(&self) -> &[Vec<Touch>] {
        &self.found
    }

    /// How many touches the last measure found.
    pub fn len(&self) -> usize {
        self.found.iter().map(Vec::len).sum()
    }
}

vectorised! {
    /// The touches of `pieces` of `pairs` at `position` (m), into `found`:
    /// the measure's loop, compiled for the widest vector unit (its
    /// geometry inlined into it). The wider units shorten the scalar
    /// arithmetic (three-operand instructions, fewer moves); no multiply
    /// and add are fused, so the bits are those of the baseline build.
    fn measure_pieces(
        pairs: &ContactPairs,
        pieces: &[(Kind, Range<usize>)],
        position: &[Vec3],
        thickness: Real,
        found: &mut Vec<Touch>,
    ) {
        for (kind, piece) in pieces {
            pairs.touches_in(*kind, piece.clone(), position, thickness, &mut |t| {
                found.push(t)
            });
        }
    }
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

/// How many pairs ahead [`closest_per_body`] asks for the particles' positions.
const PREFETCH_PAIRS: usize = 16;

/// Call `touch` with the deepest touch of each run of `pairs` that share a
/// particle and a body (`key`), measured by `measure`. The detect stage
/// writes a particle's pairs one after another, so a run is contiguous.
#[inline(always)]
fn closest_per_body<P>(
    pairs: &[P],
    key: impl Fn(&P) -> (u32, u32),
    measure: impl Fn(&P) -> Option<Touch>,
    prefetch: impl Fn(&P),
    touch: &mut impl FnMut(Touch),
) {
    let mut start = 0;
    let mut fetched = 0;
    while start < pairs.len() {
        let particle = key(&pairs[start]).0;
        let mut end = start;
        while end < pairs.len() && key(&pairs[end]).0 == particle {
            end += 1;
        }
        let ahead = (end + PREFETCH_PAIRS).min(pairs.len());
        for pair in &pairs[fetched.max(end)..ahead] {
            prefetch(pair);
        }
        fetched = ahead;
        // Within the particle's run, the deepest touch of each body, bodies
        // in the order they first appear.
        for (first, pair) in pairs[start..end].iter().enumerate() {
            let body = key(pair).1;
            if pairs[start..start + first].iter().any(|p| key(p).1 == body) {
                continue;
            }
            // Of equally deep touches, the first.
            let mut deepest: Option<Touch> = None;
            for p in &pairs[start + first..end] {
                if key(p).1 != body {
                    continue;
                }
                if let Some(t) = measure(p) {
                    if deepest.is_none_or(|b| t.depth > b.depth) {
                        deepest = Some(t);
                    }
                }
            }
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::buckets::CLEARANCE_BUCKETS;

    /// xorshift64*: numbers uniform in [-1, 1), the same on every run.
    struct Random(u64);

    impl Random {
        fn symmetric(&mut self) -> Real {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            2.0 * (bits as Real / (1u64 << 53) as Real) - 1.0
        }

        fn vector(&mut self, scale: Real) -> Vec3 {
            scale * Vec3::new(self.symmetric(), self.symmetric(), self.symmetric())
        }
    }

    /// The touches of `pairs` at `position` with `allowance`.
    fn touches(pairs: &mut ContactPairs, position: &[Vec3], allowance: Real) -> Vec<Touch> {
        pairs.allowance = allowance;
        let mut found = Vec::new();
        pairs.for_each_touch(position, THICKNESS, |t| found.push(t));
        found
    }

    const THICKNESS: Real = 0.01;

    #[test]
    fn a_pair_whose_clearance_exceeds_the_allowance_cannot_touch() {
        // Claim: after every particle has moved by at most `moved` from
        // where a pair was found, a pair whose clearance exceeds twice
        // that (the allowance of a step with no closing) touches nowhere,
        // so passing it over changes nothing. Random elements of 2 cm
        // around a particle within the search's reach (three thicknesses),
        // moved in random directions by up to the allowance's half, the
        // four kinds of pairs; each perturbed state measured with every
        // pair (infinite allowance) and with the allowance gives the same
        // touches. Some states are chosen near the edge cases: a particle
        // near the triangle's plane beyond an edge (which may end up
        // behind it), and nearly parallel edges.
        let mut random = Random(0x5eed);
        let reach = 3.0 * THICKNESS;
        let (mut skipped, mut measured) = (0, 0);
        for trial in 0..20_000 {
            let mut position: Vec<Vec3> = (0..4).map(|_| random.vector(0.02)).collect();
            if trial % 4 == 1 {
                // The particle just off the triangle's plane, beyond one of
                // its edges.
                let [a, b, c] = [position[1], position[2], position[3]];
                let normal = (b - a).cross(c - a).normalize();
                let out = a + 1.3 * (b - a) + 0.2 * (c - a);
                position[0] = out + 0.002 * random.symmetric() * normal;
            }
            if trial % 4 == 2 {
                // Nearly parallel edges 0–1 and 2–3.
                let along = random.vector(0.02);
                position[1] = position[0] + along;
                position[3] = position[2] + along + random.vector(0.001);
            }
            let side = if random.symmetric() > 0.0 { 1.0 } else { -1.0 };
            // The 3D pairs, and the 2D pair in the xy-plane.
            let (mut pairs, mut flat_pairs) = (ContactPairs::default(), ContactPairs::default());
            let triangle = PointTriangle {
                particle: 0,
                triangle: [1, 2, 3],
                body: 1,
                side,
                clearance: 0.0,
            };
            if triangle.touch(&position, reach).is_some() {
                pairs.point_triangle.push(PointTriangle {
                    clearance: triangle.clearance_at(&position, THICKNESS, reach),
                    ..triangle
                });
            }
            let segment = PointSegment {
                particle: 0,
                segment: [1, 2],
                body: 1,
                side,
                clearance: 0.0,
            };
            let flat: Vec<Vec3> = position.iter().map(|x| Vec3::new(x.x, x.y, 0.0)).collect();
            if segment.touch(&flat, reach).is_some() {
                flat_pairs.point_segment.push(PointSegment {
                    clearance: segment.clearance_at(&flat, THICKNESS, reach),
                    ..segment
                });
            }
            let mut edges = EdgeEdge {
                first: [0, 1],
                second: [2, 3],
                direction: Vec3::ZERO,
                clearance: 0.0,
            };
            let distance = edges.distance_at(&position);
            let (s, t) =
                closest_between_segments(position[0], position[1], position[2], position[3]);
            let gap = (position[0] + s * (position[1] - position[0]))
                - (position[2] + t * (position[3] - position[2]));
            if distance < reach && distance > 0.0 {
                edges.direction = gap / distance;
                edges.clearance = beyond(distance, THICKNESS);
                pairs.edge_edge.push(edges);
            }
            let gap = position[0] - position[3];
            if gap.length() < reach {
                pairs.point_point.push(PointPoint {
                    first: 0,
                    second: 3,
                    direction: gap.normalize(),
                    clearance: beyond(gap.length(), THICKNESS),
                });
            }
            let moved = 0.5 * THICKNESS * (random.symmetric() + 1.0);
            let allowance = 2.0 * moved;
            let shift = |random: &mut Random, x: Vec3, flat: bool| {
                let mut step = random.vector(1.0);
                if flat {
                    step.z = 0.0;
                }
                let length = step.length();
                if length > 1.0 || length == 0.0 {
                    x
                } else {
                    x + moved * step / length * random.symmetric().abs()
                }
            };
            for state in 0..8 {
                let flat_state = state % 2 == 1;
                let (from, pairs) = if flat_state {
                    (&flat, &mut flat_pairs)
                } else {
                    (&position, &mut pairs)
                };
                let at: Vec<Vec3> = if state < 2 {
                    from.clone()
                } else {
                    from.iter()
                        .map(|&x| shift(&mut random, x, flat_state))
                        .collect()
                };
                let all = touches(pairs, &at, Real::INFINITY);
                let some = touches(pairs, &at, allowance);
                assert_eq!(
                    all, some,
                    "trial {trial}, state {state}: {pairs:?} at {at:?}"
                );
            }
            let far = |c: Real| c > allowance;
            skipped += pairs
                .point_triangle
                .iter()
                .filter(|p| far(p.clearance))
                .count()
                + flat_pairs
                    .point_segment
                    .iter()
                    .filter(|p| far(p.clearance))
                    .count()
                + pairs.edge_edge.iter().filter(|p| far(p.clearance)).count()
                + pairs
                    .point_point
                    .iter()
                    .filter(|p| far(p.clearance))
                    .count();
            measured += pairs.len() + flat_pairs.len();
        }
        // The claim is not empty: many pairs are passed over.
        assert!(
            skipped > measured / 10,
            "{skipped} of {measured} passed over"
        );
    }

    #[test]
    fn buckets_of_clearance_hold_every_pair_an_allowance_reaches() {
        // Claim: after the pairs are put in buckets of clearance, the pairs
        // a measure reads for an allowance (a prefix of each list) hold
        // every pair whose clearance is within it; no pair is lost; the
        // pairs keep their order within a bucket; and a particle's run of
        // point–triangle pairs stays whole, in the bucket of its nearest.
        let mut random = Random(0xb0c5);
        let width = 0.02 / CLEARANCE_BUCKETS as Real;
        let mut clearance = move |i: u32| {
            if i.is_multiple_of(7) {
                0.0
            } else {
                0.01 * (random.symmetric() + 1.0)
            }
        };
        let mut pairs = ContactPairs::default();
        for i in 0..5000u32 {
            pairs.edge_edge.push(EdgeEdge {
                first: [i, i + 1],
                second: [i + 2, i + 3],
                direction: Vec3::X,
                clearance: clearance(i),
            });
            // Runs of one to four pairs a particle.
            pairs.point_triangle.push(PointTriangle {
                particle: i / 4 * 4 + (i % 4).min(i / 4 % 3),
                triangle: [i, i + 1, i + 2],
                body: 1,
                side: 1.0,
                clearance: clearance(i),
            });
        }
        let before = pairs.clone();
        pairs.bucket(width, &mut Spare::default());
        let buckets = &pairs.buckets;
        // Edges: nothing lost, buckets in order, order kept within one.
        let mut sorted = pairs.edge_edge.clone();
        sorted.sort_by_key(|p| p.first[0]);
        assert_eq!(sorted, before.edge_edge);
        let bucket = buckets[Kind::EdgeEdge as usize].clone();
        for w in pairs.edge_edge.windows(2) {
            let (a, b) = (bucket.of(w[0].clearance), bucket.of(w[1].clearance));
            assert!(a < b || (a == b && w[0].first[0] < w[1].first[0]));
        }
        // Triangles: each particle's run whole and in its original order.
        let mut sorted = pairs.point_triangle.clone();
        sorted.sort_by_key(|p| p.triangle[0]);
        assert_eq!(sorted, before.point_triangle);
        for w in pairs.point_triangle.windows(2) {
            if w[0].particle == w[1].particle {
                assert_eq!(w[0].triangle[0] + 1, w[1].triangle[0]);
            }
        }
        let runs = before
            .point_triangle
            .chunk_by(|a, b| a.particle == b.particle)
            .count();
        let kept = pairs
            .point_triangle
            .chunk_by(|a, b| a.particle == b.particle)
            .count();
        assert_eq!(runs, kept);
        for allowance in [0.0, 1e-4, 0.0025, 0.003, 0.01, 0.0199, 0.02, 1.0] {
            pairs.allowance = allowance;
            for (kind, list) in [
                (
                    Kind::EdgeEdge,
                    pairs
                        .edge_edge
                        .iter()
                        .map(|p| p.clearance)
                        .collect::<Vec<_>>(),
                ),
                (
                    Kind::PointTriangle,
                    pairs.point_triangle.iter().map(|p| p.clearance).collect(),
                ),
            ] {
                let reached = pairs.len_of(kind);
                assert!(list[reached..].iter().all(|&c| c > allowance), "{kind:?}");
            }
        }
        // Pairs added after the buckets were made are all read.
        pairs.edge_edge.push(before.edge_edge[1]);
        pairs.allowance = 0.0;
        assert_eq!(pairs.len_of(Kind::EdgeEdge), pairs.edge_edge.len());
    }

    #[test]
    fn members_count_a_particle_once_per_body_and_only_pairs_that_can_touch() {
        // Particle 0 with three triangles of body 1 (two within the
        // allowance of 1 mm, one beyond) and one of body 2; particle 9 with
        // one triangle of body 1, beyond. Claim: the stable step's members
        // are particle 0 once for body 1 and once for body 2, and the
        // vertices of the three triangles within the allowance; nothing of
        // the pairs beyond it.
        let pair = |particle, triangle, body, clearance| PointTriangle {
            particle,
            triangle,
            body,
            side: 1.0,
            clearance,
        };
        let pairs = ContactPairs {
            point_triangle: vec![
                pair(0, [1, 2, 3], 1, 0.0),
                pair(0, [2, 3, 4], 1, 0.002),
                pair(0, [3, 4, 5], 1, 0.0005),
                pair(0, [6, 7, 8], 2, 0.001),
                pair(9, [1, 2, 3], 1, 0.005),
            ],
            allowance: 0.001,
            ..ContactPairs::default()
        };
        let mut members = Vec::new();
        pairs.for_each_member(|particles| members.push(particles.collect::<Vec<_>>()));
        assert_eq!(
            members,
            vec![vec![0, 1, 2, 3], vec![3, 4, 5], vec![0, 6, 7, 8]]
        );
    }
}
