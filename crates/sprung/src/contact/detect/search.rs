//! The pair search: the querying particles within reach of each surface
//! element, and the elements within reach of each other, found through a
//! grid in parallel over chunks of elements, in an order that does not
//! depend on the threads, within a budget of pairs.

use super::gather::{bounds, overlap};
use super::Scratch;
use crate::body::Body;
use crate::contact::buckets::Buckets;
use crate::contact::links::Links;
use crate::contact::pairs::{beyond, Shape};
use crate::contact::PointElement;
use crate::parallel;
use crate::units::{Real, Vec3};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Whether a particle of `particle` against an element of body `body`
/// pushes along the element's outward normal, whatever side the particle
/// is on: against a closed surface of another body (a particle that got
/// inside is pushed out). Against an open surface, or its own closed one
/// (a hollow ball collapsing onto itself: its particles meet their own
/// surface from inside), it pushes to the side the particle was on when
/// the pair was found.
fn pushes_outward(bodies: &[Body], particle: u32, body: u32) -> bool {
    let body = &bodies[body as usize];
    body.closed && !body.particles.contains(&(particle as usize))
}

/// Elements a thread takes at a time in the pair search.
const QUERY_CHUNK: usize = 1024;

/// Picks a list of elements (with their bodies) out of the buffers.
type Elements<const N: usize> = fn(&Scratch) -> &[([u32; N], u32)];

/// What the pair search needs to know of the world.
pub(super) struct Search<'a> {
    pub(super) bodies: &'a [Body],
    pub(super) position: &'a [Vec3],
    pub(super) thickness: Real,
    pub(super) reach: Real,
    /// Width (m) of the buckets of clearance the pairs are put in.
    pub(super) bucket_width: Real,
    pub(super) links: &'a Links,
    pub(super) budget: &'a Budget,
}

/// The candidate pairs a search may find ([`pair_limit`]), counted as the
/// threads find them: a search that finds more stops, whatever the
/// number of threads (a count above the limit means the pairs are more).
pub(super) struct Budget {
    pub(super) found: AtomicUsize,
    pub(super) limit: usize,
}

impl Budget {
    /// Count `more` pairs found; whether the limit is passed.
    fn spend(&self, more: usize) -> bool {
        self.found.fetch_add(more, Ordering::Relaxed) + more > self.limit
    }

    pub(super) fn exceeded(&self) -> bool {
        self.found.load(Ordering::Relaxed) > self.limit
    }

    /// Whether a chunk that has found `found` pairs may go on: what it
    /// found since it last counted (`counted`) is counted every
    /// [`BUDGET_STRIDE`] pairs, and the limit looked at in between.
    fn may_go_on(&self, found: usize, counted: &mut usize) -> bool {
        if found - *counted >= BUDGET_STRIDE {
            let over = self.spend(found - *counted);
            *counted = found;
            !over
        } else {
            !self.exceeded()
        }
    }
}

/// Candidate pairs a search may find per element that looks for them or
/// is looked for (a querying particle, a triangle, a segment, an edge, a
/// loose particle), and at least [`MIN_PAIR_LIMIT`] in all: a pile of gas
/// balls has well under one, a cloth lying in folds about ten. A contact
/// thickness many times the spacing of the particles finds hundreds each,
/// and the memory of the pairs would grow with its square.
pub const PAIRS_PER_ELEMENT: usize = 64;

/// The fewest candidate pairs a search may find, however few its elements.
pub const MIN_PAIR_LIMIT: usize = 2_000_000;

/// Pairs found per chunk of the search between two counts in the budget.
const BUDGET_STRIDE: usize = 1024;

/// The most candidate pairs a search among `elements` may find.
pub fn pair_limit(elements: usize) -> usize {
    elements
        .saturating_mul(PAIRS_PER_ELEMENT)
        .max(MIN_PAIR_LIMIT)
}

/// A search that found more candidate pairs than [`pair_limit`] allows
/// (how many more depends on when the threads noticed: not kept).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooManyPairs {
    /// The limit.
    pub limit: usize,
}

impl Search<'_> {
    fn x(&self, i: u32) -> Vec3 {
        self.position[i as usize]
    }

    /// May an element of `first` touch one of `second`?
    fn allowed(&self, first: u32, second: u32) -> bool {
        first != second || self.bodies[first as usize].contact.self_collision
    }

    /// Whether `particle` (of body `body`) may touch `element` of
    /// `element_body`: not one of its particles, nor joined to one by a
    /// spring, and allowed between the bodies.
    fn may_pair<const N: usize>(
        &self,
        particle: u32,
        body: u32,
        element: [u32; N],
        element_body: u32,
    ) -> bool {
        self.allowed(body, element_body)
            && !element.contains(&particle)
            && !(body == element_body && element.iter().any(|&v| self.links.linked(particle, v)))
    }

    /// The pair of `particle` with `element` of body `body`, or nothing
    /// when it cannot touch within the reach: pushed along the outward
    /// normal of another body's closed surface ([`pushes_outward`]), else
    /// to the side the particle is on.
    fn point_pair<const N: usize>(
        &self,
        particle: u32,
        element: [u32; N],
        body: u32,
    ) -> Option<PointElement<N>>
    where
        PointElement<N>: Shape,
    {
        let pair = PointElement {
            particle,
            element,
            body,
            side: 1.0,
            clearance: 0.0,
        };
        let side = if pushes_outward(self.bodies, particle, body) {
            1.0
        } else {
            pair.side_at(self.position)
        };
        let pair = PointElement { side, ..pair };
        let distance = self.reach - pair.touch(self.position, self.reach)?.depth;
        Some(PointElement {
            clearance: beyond(distance, self.thickness),
            ..pair
        })
    }

    /// The pairs of every querying particle with the surface elements of
    /// `elements` (triangles or segments) within reach
    /// ([`Search::point_pair`]), into `out` in buckets of clearance, each
    /// particle's pairs together in the order of the elements, the
    /// particles in ascending order within a bucket
    /// ([`Buckets::by_particle`]); returns where the buckets start. The
    /// particles go into a grid (one cell each) and each element's box,
    /// grown by the reach, asks it for the particles inside, in parallel
    /// over chunks of elements.
    pub(super) fn particles_against<const N: usize>(
        &self,
        scratch: &mut Scratch,
        elements: Elements<N>,
        (chunks, out): (&mut Vec<Vec<PointElement<N>>>, &mut Vec<PointElement<N>>),
    ) -> Buckets
    where
        PointElement<N>: Shape,
    {
        out.clear();
        if elements(scratch).is_empty() || scratch.querying.is_empty() {
            return Buckets::empty(self.bucket_width);
        }
        let extent = scratch.element_boxes(elements, self.position, self.reach);
        let Scratch { grid, querying, .. } = scratch;
        let points = querying.iter().map(|&i| (self.x(i), self.x(i)));
        grid.build((extent + 2.0 * self.reach).max(1e-9), points);
        let built = &*scratch;
        let list = elements(built);
        parallel::collect_chunks(
            list.len(),
            parallel::piece_size(list.len(), QUERY_CHUNK),
            chunks,
            |range, found| {
                let mut counted = 0;
                for e in range {
                    if !self.budget.may_go_on(found.len(), &mut counted) {
                        return;
                    }
                    let (element, element_body) = list[e];
                    let (low, high) = built.boxes[e];
                    let mut visit = |q: u32| {
                        let particle = built.querying[q as usize];
                        let p = self.x(particle);
                        let inside = p.cmpge(low).all() && p.cmple(high).all();
                        let body = built.body_of[particle as usize];
                        if inside && self.may_pair(particle, body, element, element_body) {
                            found.extend(self.point_pair(particle, element, element_body));
                        }
                    };
                    // An element far larger than the cells (a ground of two
                    // triangles under a fine cloth) covers more cells than a
                    // query visits: it looks at every particle instead.
                    if !built.grid.query_unless_capped(low, high, &mut visit) {
                        (0..built.querying.len() as u32).for_each(visit);
                    }
                }
                self.budget.spend(found.len() - counted);
            },
        );
        if self.budget.exceeded() {
            out.clear();
            return Buckets::empty(self.bucket_width);
        }
        Buckets::by_particle(
            chunks,
            |pair| pair.particle,
            |pair| pair.clearance,
            self.bucket_width,
            self.position.len(),
            &mut scratch.by_particle,
            out,
        )
    }

    /// The pairs of elements of `elements` with each other within reach
    /// (each pair once) into `out`, in parallel over chunks of elements;
    /// `pair` gets both, with their bodies, and keeps the pair or not. Only
    /// elements whose body `asks` look for partners (the others are found
    /// by them): edges of closed surfaces need no partner among themselves.
    pub(super) fn among<const N: usize, P: Send + Copy>(
        &self,
        scratch: &mut Scratch,
        elements: Elements<N>,
        asks: impl Fn(u32) -> bool + Sync,
        (chunks, out): (&mut Vec<Vec<P>>, &mut Vec<P>),
        pair: impl Fn(([u32; N], u32), ([u32; N], u32)) -> Option<P> + Sync,
    ) {
        out.clear();
        let count = elements(scratch).len();
        if count < 2 {
            return;
        }
        let extent = scratch.element_boxes(elements, self.position, 0.5 * self.reach);
        let Scratch { grid, boxes, .. } = scratch;
        grid.build(extent.max(self.reach).max(1e-9), boxes.iter().copied());
        let built = &*scratch;
        let list = elements(built);
        parallel::collect_chunks(
            count,
            parallel::piece_size(count, QUERY_CHUNK),
            chunks,
            |range, found| {
                let mut counted = 0;
                for first in range {
                    if !self.budget.may_go_on(found.len(), &mut counted) {
                        return;
                    }
                    if !asks(list[first].1) {
                        continue;
                    }
                    let (low, high) = built.boxes[first];
                    // Each pair once: from the lower index, unless only the
                    // higher one asks.
                    let once = |second: u32| {
                        let second = second as usize;
                        second > first || (second != first && !asks(list[second].1))
                    };
                    built.grid.query_once(low, high, once, |second| {
                        let second = second as usize;
                        let (a, b) = (list[first], list[second]);
                        let own_neighbours = || {
                            a.1 == b.1
                                && a.0
                                    .iter()
                                    .any(|&p| b.0.iter().any(|&q| self.links.linked(p, q)))
                        };
                        if overlap((low, high), built.boxes[second])
                            && self.allowed(a.1, b.1)
                            && !own_neighbours()
                        {
                            found.extend(pair(a, b));
                        }
                    });
                }
                self.budget.spend(found.len() - counted);
            },
        );
        if !self.budget.exceeded() {
            out.extend(chunks.iter().flatten().copied());
        }
    }
}

impl Scratch {
    /// The boxes of `elements`, each grown by `margin` (m), into
    /// `self.boxes`; returns the elements' average extent (m, the largest
    /// side of a box before growing).
    fn element_boxes<const N: usize>(
        &mut self,
        elements: Elements<N>,
        position: &[Vec3],
        margin: Real,
    ) -> Real {
        let mut boxes = std::mem::take(&mut self.boxes);
        boxes.clear();
        let list = elements(self);
        let grown =
            |(e, _): &([u32; N], u32)| bounds(e.iter().map(|&i| position[i as usize]), margin);
        if list.len() <= parallel::CHUNK {
            boxes.extend(list.iter().map(grown));
        } else {
            boxes.par_extend(list.par_iter().with_min_len(QUERY_CHUNK).map(grown));
        }
        let extent = parallel::sum(boxes.len(), |range| {
            boxes[range]
                .iter()
                .map(|(low, high)| (*high - *low).max_element() - 2.0 * margin)
                .sum()
        }) / boxes.len().max(1) as Real;
        self.boxes = boxes;
        extent
    }
}
