//! The detect stage: candidate pairs for one step from a uniform grid.

use super::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use super::grid::Grid;
use super::{
    ContactPairs, ContactSettings, Contacts, EdgeEdge, PointPoint, PointSegment, PointTriangle,
};
use crate::body::{Body, BodyContact};
use crate::springs::Springs;
use crate::{Real, Vec3};

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
    /// Per body, its bounding box grown by half the reach (colliding
    /// bodies only).
    body_box: Vec<(Vec3, Vec3)>,
    /// Per body, the bodies whose boxes overlap its own:
    /// `near[near_start[b]..near_start[b + 1]]`.
    near_start: Vec<u32>,
    near: Vec<u32>,
    /// The grown bounding box of each element of the current grid.
    boxes: Vec<(Vec3, Vec3)>,
    /// Per element, the last query that visited it (plus one).
    seen: Vec<u32>,
    /// Positions at the last search (empty before any).
    searched_at: Vec<Vec3>,
    /// The margin (m) beyond the thickness that search covered.
    searched_margin: Real,
    /// The contact settings and the bodies' contact flags of the last
    /// search.
    searched_settings: Option<ContactSettings>,
    searched_flags: Vec<BodyContact>,
}

/// The bounding box of `points`, grown by `margin` (m) on every side.
fn bounds(points: impl Iterator<Item = Vec3>, margin: Real) -> (Vec3, Vec3) {
    let (low, high) = points.fold(
        (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY)),
        |(low, high), p| (low.min(p), high.max(p)),
    );
    (low - Vec3::splat(margin), high + Vec3::splat(margin))
}

/// The side (+1 or -1) of `offset` along `face`, +1 when in the plane.
fn side_of(offset: Vec3, face: Vec3) -> Real {
    if offset.dot(face) < 0.0 {
        -1.0
    } else {
        1.0
    }
}

/// Whether two boxes overlap.
fn overlap(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

impl Scratch {
    /// Whether the pairs of the last search still hold every pair that can
    /// touch in a step whose closing distance is `closing` (m): same
    /// particles and settings, and twice the largest distance moved since,
    /// plus `closing`, within the margin searched.
    fn still_covers(
        &self,
        bodies: &[Body],
        position: &[Vec3],
        closing: Real,
        settings: &ContactSettings,
    ) -> bool {
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
            return false;
        }
        let moved = position
            .iter()
            .zip(&self.searched_at)
            .map(|(x, x0)| x.distance_squared(*x0))
            .fold(0.0, Real::max)
            .sqrt();
        2.0 * moved + closing <= self.searched_margin
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
            || self
                .near(b)
                .iter()
                .any(|&other| overlap((low, high), self.body_box[other as usize]))
    }

    /// The broad phase between bodies: each colliding body's box (grown by
    /// half of `reach`, m) and the other bodies it overlaps, from a grid of
    /// body boxes.
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
                let start = near.len();
                grid.query(boxes[b].0, boxes[b].1, |other| {
                    let other_body = &bodies[other as usize];
                    if other as usize != b
                        && colliding(other_body)
                        && overlap(boxes[b], boxes[other as usize])
                        && !near[start..].contains(&other)
                    {
                        near.push(other);
                    }
                });
            }
            self.near_start.push(self.near.len() as u32);
        }
    }

    /// Gather the elements of colliding bodies that may meet another body
    /// (or their own), and the particles that may.
    fn collect(&mut self, bodies: &[Body], position: &[Vec3], reach: Real) {
        self.near_bodies(bodies, position, reach);
        self.body_of.clear();
        self.body_of.resize(position.len(), NONE);
        self.triangles.clear();
        self.segments.clear();
        self.edges.clear();
        self.loose.clear();
        self.querying.clear();
        let x = |i: u32| position[i as usize];
        for (index, body) in bodies.iter().enumerate() {
            let index = index as u32;
            if !body.contact.collide
                || (!body.contact.self_collision && self.near(index).is_empty())
            {
                continue;
            }
            for i in body.particles.clone() {
                self.body_of[i] = index;
                if self.may_touch(bodies, index, position[i], position[i]) {
                    self.querying.push(i as u32);
                }
            }
            let margin = 0.5 * reach;
            for &f in &body.faces {
                let (low, high) = bounds(f.iter().map(|&i| x(i)), margin);
                if self.may_touch(bodies, index, low, high) {
                    self.triangles.push((f, index));
                }
            }
            for &s in &body.segments {
                let (low, high) = bounds(s.iter().map(|&i| x(i)), margin);
                if self.may_touch(bodies, index, low, high) {
                    self.segments.push((s, index));
                }
            }
            for &e in &body.edges {
                let (low, high) = bounds(e.iter().map(|&i| x(i)), margin);
                if self.may_touch(bodies, index, low, high) {
                    self.edges.push((e, index));
                }
            }
            if body.faces.is_empty() && body.segments.is_empty() {
                for i in body.particles.clone() {
                    if self.may_touch(bodies, index, position[i], position[i]) {
                        self.loose.push(([i as u32], index));
                    }
                }
            }
        }
    }

    /// Build the grid over `elements`, each box grown by `margin` (m), with
    /// cells about the size of the average element and at least `reach`.
    fn build<const N: usize>(
        &mut self,
        elements: impl Fn(&Scratch) -> &[([u32; N], u32)],
        position: &[Vec3],
        margin: Real,
        reach: Real,
    ) {
        let mut boxes = std::mem::take(&mut self.boxes);
        boxes.clear();
        boxes.extend(
            elements(self)
                .iter()
                .map(|(e, _)| bounds(e.iter().map(|&i| position[i as usize]), margin)),
        );
        let extent = boxes
            .iter()
            .map(|(low, high)| (*high - *low).max_element() - 2.0 * margin)
            .sum::<Real>()
            / boxes.len().max(1) as Real;
        self.grid
            .build(extent.max(reach).max(1e-9), boxes.iter().copied());
        self.seen.clear();
        self.seen.resize(boxes.len(), 0);
        self.boxes = boxes;
    }
}

/// Picks a list of elements (with their bodies) out of the buffers.
type Elements<const N: usize> = fn(&Scratch) -> &[([u32; N], u32)];

/// The particles joined to each particle by a spring, for the particles of
/// self-colliding bodies: a particle does not collide with an element of
/// its own body that holds one of them (they are kept at their distance by
/// the spring already, and would otherwise be found within reach of each
/// other at rest).
#[derive(Debug, Clone, Default)]
pub(super) struct Links {
    start: Vec<u32>,
    list: Vec<u32>,
    /// What they were built from: the springs' topology, the particles,
    /// the bodies' flags.
    built_for: Option<(u64, usize, Vec<BodyContact>)>,
}

impl Links {
    /// Rebuild from the springs of the self-colliding bodies, unless those
    /// are what they were built from.
    fn build(&mut self, bodies: &[Body], springs: &Springs, particles: usize) {
        let unchanged = self
            .built_for
            .as_ref()
            .is_some_and(|(topology, count, flags)| {
                *topology == springs.topology()
                    && *count == particles
                    && flags.iter().eq(bodies.iter().map(|b| &b.contact))
            });
        if unchanged {
            return;
        }
        self.built_for = Some((
            springs.topology(),
            particles,
            bodies.iter().map(|b| b.contact).collect(),
        ));
        self.start.clear();
        self.list.clear();
        let selfish = |i: u32, b: &Body| b.particles.contains(&(i as usize));
        let wanted: Vec<&Body> = bodies
            .iter()
            .filter(|b| b.contact.collide && b.contact.self_collision)
            .collect();
        if wanted.is_empty() {
            return;
        }
        let mut count = vec![0u32; particles + 1];
        let mut kept = Vec::new();
        for body in &wanted {
            for s in body.springs.clone() {
                let (i, j) = (springs.first()[s], springs.second()[s]);
                if selfish(i, body) && selfish(j, body) {
                    count[i as usize + 1] += 1;
                    count[j as usize + 1] += 1;
                    kept.push((i, j));
                }
            }
        }
        for i in 0..particles {
            count[i + 1] += count[i];
        }
        self.list.resize(count[particles] as usize, 0);
        let mut fill = count.clone();
        for (i, j) in kept {
            self.list[fill[i as usize] as usize] = j;
            fill[i as usize] += 1;
            self.list[fill[j as usize] as usize] = i;
            fill[j as usize] += 1;
        }
        self.start = count;
    }

    /// Whether particles `a` and `b` are the same or joined by a spring.
    fn linked(&self, a: u32, b: u32) -> bool {
        a == b
            || self.start.get(a as usize + 1).is_some_and(|&end| {
                self.list[self.start[a as usize] as usize..end as usize].contains(&b)
            })
    }
}

/// What the pair search needs to know of the world.
struct Search<'a> {
    bodies: &'a [Body],
    position: &'a [Vec3],
    reach: Real,
    links: &'a Links,
}

impl Search<'_> {
    fn x(&self, i: u32) -> Vec3 {
        self.position[i as usize]
    }

    /// May an element of `first` touch one of `second`?
    fn allowed(&self, first: u32, second: u32) -> bool {
        first != second || self.bodies[first as usize].contact.self_collision
    }

    /// Pairs of every colliding particle with the surface elements of
    /// `elements` (triangles or segments) within reach; `pair` makes the
    /// pair from the particle, the element and the element's body.
    fn particles_against<const N: usize>(
        &self,
        scratch: &mut Scratch,
        elements: Elements<N>,
        mut pair: impl FnMut(u32, [u32; N], u32),
    ) {
        if elements(scratch).is_empty() {
            return;
        }
        scratch.build(elements, self.position, self.reach, self.reach);
        let scratch = &*scratch;
        for &particle in &scratch.querying {
            let body = scratch.body_of[particle as usize];
            let p = self.x(particle);
            scratch.grid.query(p, p, |e| {
                let (element, element_body) = elements(scratch)[e as usize];
                let (low, high) = scratch.boxes[e as usize];
                let inside = p.cmpge(low).all() && p.cmple(high).all();
                let own_neighbour =
                    body == element_body && element.iter().any(|&v| self.links.linked(particle, v));
                if inside
                    && self.allowed(body, element_body)
                    && !element.contains(&particle)
                    && !own_neighbour
                {
                    pair(particle, element, element_body);
                }
            });
        }
    }

    /// Pairs of elements of `elements` with each other within reach (each
    /// pair once); `pair` gets both, with their bodies. Only elements whose
    /// body `asks` look for partners (the others are found by them): edges
    /// of closed surfaces need no partner among themselves.
    fn among<const N: usize>(
        &self,
        scratch: &mut Scratch,
        elements: Elements<N>,
        asks: impl Fn(u32) -> bool,
        mut pair: impl FnMut(([u32; N], u32), ([u32; N], u32)),
    ) {
        let count = elements(scratch).len();
        if count < 2 {
            return;
        }
        scratch.build(elements, self.position, 0.5 * self.reach, self.reach);
        let mut seen = std::mem::take(&mut scratch.seen);
        let built = &*scratch;
        let list = elements(built);
        for first in 0..count {
            if !asks(list[first].1) {
                continue;
            }
            let (low, high) = built.boxes[first];
            built.grid.query(low, high, |second| {
                let second = second as usize;
                // Each pair once: from the lower index, unless only the
                // higher one asks.
                let once = second > first || !asks(list[second].1);
                if !once || second == first || seen[second] == first as u32 + 1 {
                    return;
                }
                seen[second] = first as u32 + 1;
                let (a, b) = (list[first], list[second]);
                let own_neighbours = a.1 == b.1
                    && a.0
                        .iter()
                        .any(|&p| b.0.iter().any(|&q| self.links.linked(p, q)));
                if self.allowed(a.1, b.1)
                    && !own_neighbours
                    && overlap((low, high), built.boxes[second])
                {
                    pair(a, b);
                }
            });
        }
        scratch.seen = seen;
    }
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
    /// thickness plus the distance two particles at the fastest speed now
    /// close in the step (at most four thicknesses: faster particles may
    /// pass through each other). They are kept for the following steps for as long
    /// as that margin still covers the motion (twice the largest distance a
    /// particle has moved since, plus the step's closing distance), so a
    /// slow scene searches every few steps, never missing a pair.
    pub fn detect(
        &mut self,
        bodies: &[Body],
        springs: &Springs,
        position: &[Vec3],
        velocity: &[Vec3],
        dt: Real,
    ) {
        let colliding = bodies.iter().filter(|b| b.contact.collide).count();
        let self_colliding = bodies
            .iter()
            .any(|b| b.contact.collide && b.contact.self_collision);
        if !self.settings.enabled || (colliding < 2 && !self_colliding) {
            self.pairs.clear();
            self.scratch.searched_at.clear();
            return;
        }
        let speed = bodies
            .iter()
            .filter(|b| b.contact.collide)
            .flat_map(|b| velocity[b.particles.clone()].iter())
            .map(|v| v.length())
            .fold(0.0, Real::max)
            .min(1e6);
        // Beyond a few thicknesses a step, contact cannot catch a particle
        // anyway (its force acts within the thickness); searching further
        // would only gather every particle of a blowing-up scene.
        let closing = (2.0 * dt * speed).min(MAX_CLOSING * self.settings.thickness);
        if self
            .scratch
            .still_covers(bodies, position, closing, &self.settings)
        {
            return;
        }
        self.pairs.clear();
        let Contacts {
            pairs,
            scratch,
            settings,
            links,
            ..
        } = self;
        let margin = settings.thickness + closing;
        let reach = settings.thickness + margin;
        scratch.searched(bodies, position, margin, settings);
        scratch.collect(bodies, position, reach);
        links.build(bodies, springs, position.len());
        let search = Search {
            bodies,
            position,
            reach,
            links,
        };
        let x = |i: u32| position[i as usize];
        let ContactPairs {
            point_triangle,
            point_segment,
            edge_edge,
            point_point,
        } = pairs;
        search.particles_against(
            scratch,
            |s| &s.triangles,
            |particle, [a, b, c], body| {
                let closed = bodies[body as usize].closed;
                let p = x(particle);
                let w = closest_on_triangle(p, x(a), x(b), x(c));
                let q = w[0] * x(a) + w[1] * x(b) + w[2] * x(c);
                let face = (x(b) - x(a)).cross(x(c) - x(a));
                point_triangle.push(PointTriangle {
                    particle,
                    triangle: [a, b, c],
                    body,
                    side: if closed { 1.0 } else { side_of(p - q, face) },
                });
            },
        );
        search.particles_against(
            scratch,
            |s| &s.segments,
            |particle, [a, b], body| {
                let closed = bodies[body as usize].closed;
                let p = x(particle);
                let d = x(b) - x(a);
                let q = x(a) + closest_on_segment(p, x(a), x(b)) * d;
                point_segment.push(PointSegment {
                    particle,
                    segment: [a, b],
                    body,
                    side: if closed {
                        1.0
                    } else {
                        side_of(p - q, Vec3::new(d.y, -d.x, 0.0))
                    },
                });
            },
        );
        let reach = search.reach;
        // Edges against edges only where a surface is open (closed ones
        // are kept apart by their particles and triangles alone).
        let open = |b: &Body| b.contact.collide && !b.closed && !b.faces.is_empty();
        if !bodies.iter().any(open) {
            scratch.edges.clear();
        }
        search.among(
            scratch,
            |s| &s.edges,
            |body| !bodies[body as usize].closed,
            |([p1, q1], body1), ([p2, q2], body2)| {
                if bodies[body1 as usize].closed && bodies[body2 as usize].closed {
                    return;
                }
                if p1 == p2 || p1 == q2 || q1 == p2 || q1 == q2 {
                    return;
                }
                let (s, t) = closest_between_segments(x(p1), x(q1), x(p2), x(q2));
                let gap = (x(p1) + s * (x(q1) - x(p1))) - (x(p2) + t * (x(q2) - x(p2)));
                let distance = gap.length();
                let direction = if distance > 0.0 {
                    gap / distance
                } else {
                    (x(q1) - x(p1)).cross(x(q2) - x(p2)).normalize_or_zero()
                };
                if distance < reach && direction != Vec3::ZERO {
                    edge_edge.push(EdgeEdge {
                        first: [p1, q1],
                        second: [p2, q2],
                        direction,
                    });
                }
            },
        );
        search.among(
            scratch,
            |s| &s.loose,
            |_| true,
            |([first], body1), ([second], body2)| {
                let gap = x(first) - x(second);
                let distance = gap.length();
                if body1 != body2 && distance < reach && distance > 0.0 {
                    point_point.push(PointPoint {
                        first,
                        second,
                        direction: gap / distance,
                    });
                }
            },
        );
    }
}
