//! The detect stage: candidate pairs for one step from a uniform grid.

use super::buckets::{Buckets, ByParticle, CLEARANCE_BUCKETS};
use super::geometry::closest_between_segments;
use super::grid::Grid;
use super::links::Links;
use super::pairs::{beyond, Shape, Spare};
use super::{
    ContactSettings, Contacts, EdgeEdge, PointElement, PointPoint, PointSegment, PointTriangle,
};
use crate::body::{Body, BodyContact};
use crate::parallel;
use crate::springs::Springs;
use crate::{Real, Vec3};
use rayon::prelude::*;
use std::ops::Range;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Marks a particle of no colliding body.
const NONE: u32 = u32::MAX;

/// The detect stage's buffers, kept from step to step so that a step
/// allocates nothing once they have grown.
#[derive(Debug, Clone, Default)]
pub(super) struct Scratch {
    grid: Grid,
    /// Per particle, its body if that body collides.
    body_of: Vec<u32>,
    /// Surface elements of colliding bodies, with their body.
    triangles: Vec<([u32; 3], u32)>,
    segments: Vec<([u32; 2], u32)>,
    edges: Vec<([u32; 2], u32)>,
    /// Particles of colliding bodies without a surface, as one-point
    /// elements.
    loose: Vec<([u32; 1], u32)>,
    /// Particles that may touch another body (or their own): those that
    /// look for elements.
    querying: Vec<u32>,
    /// What the gathering found, per chunk of bodies, with the body.
    gathered: Vec<Vec<(Gathered, u32)>>,
    /// Per body, its bounding box grown by half the reach (colliding
    /// bodies only).
    body_box: Vec<(Vec3, Vec3)>,
    /// Per body, the centre of its box and the radius (m) of the ball
    /// about it that holds its particles, plus the reach: what comes
    /// within reach of the body meets that ball (tighter than the box for
    /// a round body, whose box corners are far from it).
    body_ball: Vec<(Vec3, Real)>,
    /// Per body, the bodies whose boxes overlap its own and whose balls
    /// meet its ball: `near[near_start[b]..near_start[b + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
    /// The grown bounding box of each element being searched.
    boxes: Vec<(Vec3, Vec3)>,
    /// Buffers to put the particle–element pairs in order.
    by_particle: ByParticle,
    /// Positions at the last search (empty before any).
    searched_at: Vec<Vec3>,
    /// The margin (m) beyond the thickness that search covered.
    searched_margin: Real,
    /// The contact settings and the bodies' contact flags of the last
    /// search.
    searched_settings: Option<ContactSettings>,
    searched_flags: Vec<BodyContact>,
    /// The velocities (m/s) and the step (s) of the last detect stage, to
    /// tell how much the velocities change in a step (empty before any).
    last_velocity: Vec<Vec3>,
    last_dt: Real,
}

/// What the pair search found per chunk of elements, before it is put in
/// order, by kind of pair: kept from step to step, so that a search
/// allocates nothing once they have grown.
#[derive(Debug, Clone, Default)]
pub(super) struct Found {
    point_triangle: Vec<Vec<PointTriangle>>,
    point_segment: Vec<Vec<PointSegment>>,
    edge_edge: Vec<Vec<EdgeEdge>>,
    point_point: Vec<Vec<PointPoint>>,
    /// Buffers to put the pairs in buckets of clearance.
    spare: Spare,
}

/// Something of a colliding body that may meet another body (or its own),
/// as [`Scratch::collect`] gathers it.
#[derive(Debug, Clone, Copy)]
enum Gathered {
    /// A particle that looks for elements.
    Querying(u32),
    /// A particle of a body without a surface.
    Loose(u32),
    /// A triangle of a surface.
    Triangle([u32; 3]),
    /// A segment of a 2D loop.
    Segment([u32; 2]),
    /// An edge of a surface.
    Edge([u32; 2]),
}

/// Bodies a thread takes at a time when gathering.
const BODY_CHUNK: usize = 8;

/// The bounding box of `points`, grown by `margin` (m) on every side.
fn bounds(points: impl Iterator<Item = Vec3>, margin: Real) -> (Vec3, Vec3) {
    let (low, high) = points.fold(
        (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY)),
        |(low, high), p| (low.min(p), high.max(p)),
    );
    (low - Vec3::splat(margin), high + Vec3::splat(margin))
}

/// Whether two boxes overlap.
fn overlap(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

/// How far apart a set of vectors (displacements, m; velocities, m/s) can
/// take two points: the distance between two elements changes by at most
/// the difference of their particles' vectors, which is at most twice the
/// largest distance of a vector from any common one. That common vector is
/// zero, or the centre of the vectors' box, whichever gives less: the
/// largest length, or half the box's diagonal. A cloth falling as one
/// piece moves far while its folds stay as they were.
#[derive(Debug, Clone, Copy)]
struct Spread {
    /// The largest squared length.
    longest: Real,
    /// The box of the vectors.
    low: Vec3,
    high: Vec3,
}

impl Spread {
    const NONE: Spread = Spread {
        longest: 0.0,
        low: Vec3::splat(Real::INFINITY),
        high: Vec3::splat(Real::NEG_INFINITY),
    };

    /// The spread of the `len` vectors `vector(i)`, taken in parallel.
    fn of(len: usize, vector: impl Fn(usize) -> Vec3 + Sync) -> Spread {
        parallel::merge_chunks(
            len,
            Spread::NONE,
            |range| range.fold(Spread::NONE, |s, i| s.with(vector(i))),
            Spread::merge,
        )
    }

    /// The spreads of `now` (m/s) and of its changes from `last` (m/s),
    /// taken in parallel; `last` becomes `now` on the way (one pass over
    /// both).
    fn of_change(last: &mut [Vec3], now: &[Vec3]) -> [Spread; 2] {
        let piece = |(last, now): (&mut [Vec3], &[Vec3])| {
            let mut spreads = [Spread::NONE; 2];
            for (last, &now) in last.iter_mut().zip(now) {
                spreads = [spreads[0].with(now), spreads[1].with(now - *last)];
                *last = now;
            }
            spreads
        };
        let both = |a: [Spread; 2], b: [Spread; 2]| [a[0].merge(b[0]), a[1].merge(b[1])];
        if now.len() <= parallel::CHUNK {
            return piece((last, now));
        }
        last.par_chunks_mut(parallel::CHUNK)
            .zip(now.par_chunks(parallel::CHUNK))
            .map(piece)
            .reduce(|| [Spread::NONE; 2], both)
    }

    /// The spread of these vectors and `v`.
    fn with(self, v: Vec3) -> Spread {
        Spread {
            longest: self.longest.max(v.length_squared()),
            low: self.low.min(v),
            high: self.high.max(v),
        }
    }

    /// The spread of the vectors of both.
    fn merge(self, other: Spread) -> Spread {
        Spread {
            longest: self.longest.max(other.longest),
            low: self.low.min(other.low),
            high: self.high.max(other.high),
        }
    }

    /// The largest distance of a vector from the common one (0 for none).
    fn bound(&self) -> Real {
        if self.low.x > self.high.x {
            return 0.0;
        }
        let half_diagonal = 0.5 * (self.high - self.low).length();
        self.longest.sqrt().min(half_diagonal)
    }
}

impl Scratch {
    /// The [`Spread`] bound of the colliding particles' velocities (m/s),
    /// and twice that of their changes (m/s) since the last detect stage,
    /// scaled from that stage's step to `dt` (s): `None` when there is no
    /// last stage for these particles. Remembers `velocity` (m/s) and `dt`
    /// for the next stage. One pass over the velocities.
    fn velocities(&mut self, bodies: &[Body], velocity: &[Vec3], dt: Real) -> (Real, Option<Real>) {
        let last = &mut self.last_velocity;
        let known = last.len() == velocity.len() && self.last_dt > 0.0;
        if !known {
            last.clear();
            last.extend_from_slice(velocity);
        }
        // The colliding particles' velocities and changes, and the others'
        // velocities remembered as they are.
        let [speed, change] = colliding_runs(bodies)
            .map(|run| Spread::of_change(&mut last[run.clone()], &velocity[run]))
            .fold([Spread::NONE; 2], |a, b| {
                [a[0].merge(b[0]), a[1].merge(b[1])]
            });
        for run in crate::body::runs_of(bodies, |b| !b.contact.collide) {
            last[run.clone()].copy_from_slice(&velocity[run]);
        }
        let change = known.then(|| 2.0 * change.bound() * dt / self.last_dt);
        self.last_dt = dt;
        (speed.bound(), change)
    }

    /// How much closer (m) two elements can have come since the last
    /// search by the end of a step whose closing distance is `closing` (m):
    /// twice the [`Spread`] of the particles' moves since, plus `closing`.
    /// `None` when that is more than the margin searched (the pairs of the
    /// last search may then miss one that touches), or the particles or
    /// settings are not those of the search.
    fn still_covers(
        &self,
        bodies: &[Body],
        position: &[Vec3],
        closing: Real,
        settings: &ContactSettings,
    ) -> Option<Real> {
        let same_bodies = self.searched_flags.len() == bodies.len()
            && self
                .searched_flags
                .iter()
                .zip(bodies)
                .all(|(flags, body)| *flags == body.contact);
        if !same_bodies
            || self.searched_at.len() != position.len()
            || self.searched_settings != Some(*settings)
        {
            return None;
        }
        let moved = Spread::of(position.len(), |i| position[i] - self.searched_at[i]).bound();
        let allowance = 2.0 * moved + closing;
        (allowance <= self.searched_margin).then_some(allowance)
    }

    /// The margin (m) and the positions (m) of the last search, if any.
    pub(super) fn last_search(&self) -> (Option<Real>, &[Vec3]) {
        let searched = self.searched_settings.is_some() && !self.searched_at.is_empty();
        (
            searched.then_some(self.searched_margin),
            if searched { &self.searched_at } else { &[] },
        )
    }

    /// Remember a search from `position` (m) with `margin` (m).
    pub(super) fn searched(
        &mut self,
        bodies: &[Body],
        position: &[Vec3],
        margin: Real,
        settings: &ContactSettings,
    ) {
        self.searched_flags.clear();
        self.searched_flags.extend(bodies.iter().map(|b| b.contact));
        self.searched_at.clear();
        self.searched_at.extend_from_slice(position);
        self.searched_margin = margin;
        self.searched_settings = Some(*settings);
    }

    /// The bodies whose boxes overlap the box of body `b`.
    fn near(&self, b: u32) -> &[u32] {
        &self.near[self.near_start[b as usize] as usize..self.near_start[b as usize + 1] as usize]
    }

    /// Whether a box of body `b` may meet another body's (or its own, if
    /// it collides with itself).
    fn may_touch(&self, bodies: &[Body], b: u32, low: Vec3, high: Vec3) -> bool {
        bodies[b as usize].contact.self_collision
            || self.near(b).iter().any(|&other| {
                let (centre, radius) = self.body_ball[other as usize];
                // The box's nearest point to the ball's centre.
                let nearest = centre.max(low).min(high);
                overlap((low, high), self.body_box[other as usize])
                    && nearest.distance_squared(centre) < radius * radius
            })
    }

    /// The broad phase between bodies: each colliding body's box (grown by
    /// half of `reach`, m) and ball, and the other bodies whose boxes it
    /// overlaps and whose balls it meets, from a grid of body boxes.
    fn near_bodies(&mut self, bodies: &[Body], position: &[Vec3], reach: Real) {
        let colliding = |b: &Body| b.contact.collide && !b.particles.is_empty();
        self.body_box.clear();
        self.body_box.extend(bodies.iter().map(|b| {
            if colliding(b) {
                bounds(position[b.particles.clone()].iter().copied(), 0.5 * reach)
            } else {
                (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY))
            }
        }));
        self.body_ball.clear();
        for (b, &(low, high)) in bodies.iter().zip(&self.body_box) {
            let centre = 0.5 * (low + high);
            let run = b.particles.clone();
            let radius = if colliding(b) {
                parallel::max(run.len(), |range| {
                    position[run.start + range.start..run.start + range.end]
                        .iter()
                        .map(|x| x.distance_squared(centre))
                        .fold(0.0, Real::max)
                })
                .sqrt()
            } else {
                0.0
            };
            self.body_ball.push((centre, radius + reach));
        }
        let extent = self
            .body_box
            .iter()
            .zip(bodies)
            .filter(|(_, b)| colliding(b))
            .map(|((low, high), _)| (*high - *low).max_element())
            .fold(0.0, Real::max);
        self.grid
            .build(extent.max(reach).max(1e-9), self.body_box.iter().copied());
        self.near_start.clear();
        self.near.clear();
        self.near_start.push(0);
        for (b, body) in bodies.iter().enumerate() {
            if colliding(body) {
                let (grid, near, boxes) = (&self.grid, &mut self.near, &self.body_box);
                let balls = &self.body_ball;
                // Each ball holds its body's particles, and so its
                // elements, with the reach to spare: a point of one body
                // within reach of a point of the other puts the centres
                // closer than the two radii less the reach.
                let (centre, radius) = balls[b];
                let balls_meet = |other: usize| {
                    let (other_centre, other_radius) = balls[other];
                    centre.distance(other_centre) < radius + other_radius
                };
                let start = near.len();
                grid.query(boxes[b].0, boxes[b].1, |other| {
                    let other_body = &bodies[other as usize];
                    if other as usize != b
                        && colliding(other_body)
                        && overlap(boxes[b], boxes[other as usize])
                        && balls_meet(other as usize)
                        && !near[start..].contains(&other)
                    {
                        near.push(other);
                    }
                });
            }
            self.near_start.push(self.near.len() as u32);
        }
    }

    /// Whether body `index` collides and may meet another body (or its
    /// own).
    fn considered(&self, index: usize, body: &Body) -> bool {
        body.contact.collide && (body.contact.self_collision || !self.near(index as u32).is_empty())
    }

    /// Gather the elements of colliding bodies that may meet another body
    /// (or their own), and the particles that may, in parallel over the
    /// bodies; edges only if `with_edges`.
    fn collect(&mut self, bodies: &[Body], position: &[Vec3], reach: Real, with_edges: bool) {
        self.near_bodies(bodies, position, reach);
        let mut body_of = std::mem::take(&mut self.body_of);
        body_of.clear();
        body_of.resize(position.len(), NONE);
        for (index, body) in bodies.iter().enumerate() {
            if self.considered(index, body) {
                body_of[body.particles.clone()].fill(index as u32);
            }
        }
        self.body_of = body_of;
        let mut gathered = std::mem::take(&mut self.gathered);
        let this = &*self;
        let x = |i: u32| position[i as usize];
        let margin = 0.5 * reach;
        // Few particles in all: one piece, on the calling thread.
        let chunk = if position.len() <= parallel::CHUNK {
            bodies.len().max(1)
        } else {
            BODY_CHUNK
        };
        parallel::collect_chunks(bodies.len(), chunk, &mut gathered, |range, out| {
            for index in range {
                let body = &bodies[index];
                if !this.considered(index, body) {
                    continue;
                }
                let index = index as u32;
                let touches = |low: Vec3, high: Vec3| this.may_touch(bodies, index, low, high);
                let loose = body.faces.is_empty() && body.segments.is_empty();
                // A particle, like an element, within the reach of another
                // body's box: its own box grown by half the reach.
                let grown = Vec3::splat(margin);
                for i in body.particles.clone() {
                    let p = position[i];
                    if touches(p - grown, p + grown) {
                        out.push((Gathered::Querying(i as u32), index));
                        if loose {
                            out.push((Gathered::Loose(i as u32), index));
                        }
                    }
                }
                let element_box = |e: &[u32]| bounds(e.iter().map(|&i| x(i)), margin);
                for &f in &body.faces {
                    let (low, high) = element_box(&f);
                    if touches(low, high) {
                        out.push((Gathered::Triangle(f), index));
                    }
                }
                for &s in &body.segments {
                    let (low, high) = element_box(&s);
                    if touches(low, high) {
                        out.push((Gathered::Segment(s), index));
                    }
                }
                for &e in body.edges.iter().filter(|_| with_edges) {
                    let (low, high) = element_box(&e);
                    if touches(low, high) {
                        out.push((Gathered::Edge(e), index));
                    }
                }
            }
        });
        self.triangles.clear();
        self.segments.clear();
        self.edges.clear();
        self.loose.clear();
        self.querying.clear();
        for &(element, body) in gathered.iter().flatten() {
            match element {
                Gathered::Querying(i) => self.querying.push(i),
                Gathered::Loose(i) => self.loose.push(([i], body)),
                Gathered::Triangle(f) => self.triangles.push((f, body)),
                Gathered::Segment(s) => self.segments.push((s, body)),
                Gathered::Edge(e) => self.edges.push((e, body)),
            }
        }
        self.gathered = gathered;
    }

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

/// Whether a body's edges meet other edges: an open surface's, or a
/// surface that collides with itself (two of its folds may cross edge
/// to edge).
fn edges_collide(body: &Body) -> bool {
    !body.closed || body.contact.self_collision
}

/// Elements a thread takes at a time in the pair search.
const QUERY_CHUNK: usize = 1024;

/// Picks a list of elements (with their bodies) out of the buffers.
type Elements<const N: usize> = fn(&Scratch) -> &[([u32; N], u32)];

/// What the pair search needs to know of the world.
struct Search<'a> {
    bodies: &'a [Body],
    position: &'a [Vec3],
    thickness: Real,
    reach: Real,
    /// Width (m) of the buckets of clearance the pairs are put in.
    bucket_width: Real,
    links: &'a Links,
    budget: &'a Budget,
}

/// The candidate pairs a search may find ([`pair_limit`]), counted as the
/// threads find them: a search that finds more stops, whatever the
/// number of threads (a count above the limit means the pairs are more).
struct Budget {
    found: AtomicUsize,
    limit: usize,
}

impl Budget {
    /// Count `more` pairs found; whether the limit is passed.
    fn spend(&self, more: usize) -> bool {
        self.found.fetch_add(more, Ordering::Relaxed) + more > self.limit
    }

    fn exceeded(&self) -> bool {
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
    fn particles_against<const N: usize>(
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
    fn among<const N: usize, P: Send + Copy>(
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

/// The particles of colliding bodies, as runs of consecutive bodies'
/// particles.
fn colliding_runs(bodies: &[Body]) -> impl Iterator<Item = Range<usize>> + '_ {
    crate::body::runs_of(bodies, |b| b.contact.collide)
}

/// The most distance (in contact thicknesses) two particles are searched
/// for closing in one step.
const MAX_CLOSING: Real = 4.0;

impl Contacts {
    /// The detect stage: make sure the candidate pairs hold every pair of
    /// elements of colliding bodies that can come within the thickness
    /// during a step of `dt` (s) from `position` (m) at `velocity` (m/s).
    ///
    /// Pairs are searched within the thickness plus a margin: twice the
    /// thickness plus the distance two particles can close in the step at
    /// the velocities they have now (at most four thicknesses: faster
    /// particles may pass through each other). They are kept for the
    /// following steps for as long as that margin still covers the motion
    /// (how much closer two elements can have come since, by the moves of
    /// their particles, plus the step's closing distance), so a slow scene
    /// searches every few steps, never missing a pair. Motion is counted
    /// from a common velocity and displacement: a body that falls or flies
    /// as one piece does not bring its own folds closer.
    pub fn detect(
        &mut self,
        bodies: &[Body],
        springs: &Springs,
        position: &[Vec3],
        velocity: &[Vec3],
        dt: Real,
    ) -> Result<(), TooManyPairs> {
        let colliding = bodies.iter().filter(|b| b.contact.collide).count();
        let self_colliding = bodies
            .iter()
            .any(|b| b.contact.collide && b.contact.self_collision);
        if !self.settings.enabled || (colliding < 2 && !self_colliding) {
            self.pairs.clear();
            self.scratch.searched_at.clear();
            self.scratch.last_velocity.clear();
            return Ok(());
        }
        // One common velocity for every colliding particle; how much the
        // velocities changed since the last step.
        let (speed, change) = self.scratch.velocities(bodies, velocity, dt);
        let speed = speed.min(1e6);
        // Beyond a few thicknesses a step, contact cannot catch a particle
        // anyway (its force acts within the thickness); searching further
        // would only gather every particle of a blowing-up scene.
        let closing = (2.0 * dt * speed).min(MAX_CLOSING * self.settings.thickness);
        // Within the step the particles' paths bend away from their
        // velocities now by what their velocities change (gravity against
        // a pinned body, springs, the iterates of an implicit solve): by
        // at most the change over the whole step times the step, taken as
        // twice the last step's (scaled to this step), counted from a
        // common change, for each of two particles. Unknown (nothing is
        // passed over) on the first step or after the particles changed.
        let bending = change.map(|change| 4.0 * dt * change);
        let covered = self
            .scratch
            .still_covers(bodies, position, closing, &self.settings);
        if let Some(allowance) = covered {
            self.pairs.allowance = bending.map_or(Real::INFINITY, |b| allowance + b);
            return Ok(());
        }
        self.pairs.clear();
        self.pairs.allowance = bending.map_or(Real::INFINITY, |b| closing + b);
        let Contacts {
            pairs,
            scratch,
            found,
            settings,
            links,
            ..
        } = self;
        let thickness = settings.thickness;
        let margin = thickness + closing;
        let reach = thickness + margin;
        scratch.searched(bodies, position, margin, settings);
        // Edges against edges only where a surface is open or meets
        // itself (closed ones are kept apart from each other by their
        // particles and triangles alone).
        let open = |b: &Body| b.contact.collide && edges_collide(b) && !b.faces.is_empty();
        scratch.collect(bodies, position, reach, bodies.iter().any(open));
        links.build(bodies, springs, position.len(), settings.thickness);
        let elements = scratch.querying.len()
            + scratch.triangles.len()
            + scratch.segments.len()
            + scratch.edges.len()
            + scratch.loose.len();
        let budget = Budget {
            found: AtomicUsize::new(0),
            limit: pair_limit(elements),
        };
        // Clearances lie within the margin.
        let bucket_width = margin / CLEARANCE_BUCKETS as Real;
        let search = Search {
            bodies,
            position,
            thickness,
            reach,
            bucket_width,
            links,
            budget: &budget,
        };
        let x = |i: u32| position[i as usize];
        let triangle_buckets = search.particles_against(
            scratch,
            |s| &s.triangles,
            (&mut found.point_triangle, &mut pairs.point_triangle),
        );
        let segment_buckets = search.particles_against(
            scratch,
            |s| &s.segments,
            (&mut found.point_segment, &mut pairs.point_segment),
        );
        search.among(
            scratch,
            |s| &s.edges,
            |body| edges_collide(&bodies[body as usize]),
            (&mut found.edge_edge, &mut pairs.edge_edge),
            |([p1, q1], body1), ([p2, q2], body2)| {
                let closed = |b: u32| bodies[b as usize].closed;
                if closed(body1) && closed(body2) && body1 != body2 {
                    return None;
                }
                if p1 == p2 || p1 == q2 || q1 == p2 || q1 == q2 {
                    return None;
                }
                let (s, t) = closest_between_segments(x(p1), x(q1), x(p2), x(q2));
                let gap = (x(p1) + s * (x(q1) - x(p1))) - (x(p2) + t * (x(q2) - x(p2)));
                let distance = gap.length();
                let direction = if distance > 0.0 {
                    gap / distance
                } else {
                    (x(q1) - x(p1)).cross(x(q2) - x(p2)).normalize_or_zero()
                };
                (distance < reach && direction != Vec3::ZERO).then_some(EdgeEdge {
                    first: [p1, q1],
                    second: [p2, q2],
                    direction,
                    clearance: beyond(distance, thickness),
                })
            },
        );
        search.among(
            scratch,
            |s| &s.loose,
            |_| true,
            (&mut found.point_point, &mut pairs.point_point),
            |([first], body1), ([second], body2)| {
                let gap = x(first) - x(second);
                let distance = gap.length();
                (body1 != body2 && distance < reach && distance > 0.0).then(|| PointPoint {
                    first,
                    second,
                    direction: gap / distance,
                    clearance: beyond(distance, thickness),
                })
            },
        );
        if budget.exceeded() {
            // Nothing of the search is kept: the next step searches again.
            pairs.clear();
            scratch.searched_at.clear();
            return Err(TooManyPairs {
                limit: budget.limit,
            });
        }
        pairs.bucket_singles(
            bucket_width,
            [triangle_buckets, segment_buckets],
            &mut found.spare,
        );
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spread_of_vectors_bounds_how_far_apart_they_take_two_points() {
        // Claim: any two of the vectors differ by at most twice the bound
        // (so two points moved by them come at most that much closer), and
        // for vectors near a common one far from zero (a body falling as
        // one piece) the bound is half the diagonal of their box (at most
        // 0.1 √3 for a box of side 0.2), not their length (over 5).
        let mut state = 0x2545_f491_u64;
        let mut random = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as Real / (1u64 << 53) as Real - 0.5
        };
        for centre in [Vec3::new(5.0, -3.0, 1.0), Vec3::ZERO] {
            let vectors: Vec<Vec3> = (0..1000)
                .map(|_| centre + 0.2 * Vec3::new(random(), random(), random()))
                .collect();
            let bound = Spread::of(vectors.len(), |i| vectors[i]).bound();
            assert!(bound <= 0.1 * Real::sqrt(3.0) + 1e-12, "{bound}");
            for a in &vectors {
                for b in &vectors {
                    assert!(a.distance(*b) <= 2.0 * bound + 1e-12);
                }
            }
        }
        assert_eq!(Spread::of(0, |_| Vec3::ONE).bound(), 0.0);
    }
}
