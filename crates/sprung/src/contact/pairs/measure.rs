//! The candidate pairs measured at a state: every pair closer than the
//! thickness, a particle's closest element of each other body only, in a
//! fixed order, in parallel over pieces of the pairs.

use std::ops::Range;

use super::touch::{apart, Shape, Touch};
use super::{ContactPairs, Kind, PointElement};
use crate::contact::geometry::closest_between_segments;
use crate::parallel;
use crate::units::{Real, Vec3};

impl ContactPairs {
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
                within,
                position,
                thickness,
                |pair| {
                    if within(pair.clearance) {
                        for i in pair.element {
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
                within,
                position,
                thickness,
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

/// How many pairs ahead [`closest_per_body`] asks for the particles' positions.
const PREFETCH_PAIRS: usize = 16;

/// Call `touch` with the deepest touch of each run of particle–element
/// `pairs` that share a particle and a body, measured at `position` (m)
/// with `thickness` (m) where their clearance is `within` the allowance;
/// `prefetch` asks for a pair's data ahead. The detect stage writes a
/// particle's pairs one after another, so a run is contiguous.
#[inline(always)]
fn closest_per_body<const N: usize>(
    pairs: &[PointElement<N>],
    within: impl Fn(Real) -> bool,
    position: &[Vec3],
    thickness: Real,
    prefetch: impl Fn(&PointElement<N>),
    touch: &mut impl FnMut(Touch),
) where
    PointElement<N>: Shape,
{
    let measure = |pair: &PointElement<N>| {
        let near = within(pair.clearance);
        near.then(|| pair.touch(position, thickness)).flatten()
    };
    let mut start = 0;
    let mut fetched = 0;
    while start < pairs.len() {
        let particle = pairs[start].particle;
        let mut end = start;
        while end < pairs.len() && pairs[end].particle == particle {
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
            let body = pair.body;
            if pairs[start..start + first].iter().any(|p| p.body == body) {
                continue;
            }
            // Of equally deep touches, the first.
            let mut deepest: Option<Touch> = None;
            for p in &pairs[start + first..end] {
                if p.body != body {
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
