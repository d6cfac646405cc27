//! What of the bodies may meet in a step (the broad phase): each colliding
//! body's box and ball, the bodies near each other, and the elements and
//! particles of the bodies that may touch another body (or their own).

use super::Scratch;
use crate::body::Body;
use crate::parallel;
use crate::units::{Real, Vec3};

/// Marks a particle of no colliding body.
const NONE: u32 = u32::MAX;

/// Something of a colliding body that may meet another body (or its own),
/// as [`Scratch::collect`] gathers it.
#[derive(Debug, Clone, Copy)]
pub(super) enum Gathered {
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
#[inline]
pub(super) fn bounds(points: impl Iterator<Item = Vec3>, margin: Real) -> (Vec3, Vec3) {
    let (low, high) = points.fold(
        (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY)),
        |(low, high), p| (low.min(p), high.max(p)),
    );
    (low - Vec3::splat(margin), high + Vec3::splat(margin))
}

/// Whether two boxes overlap.
#[inline]
pub(super) fn overlap(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> bool {
    a.0.cmple(b.1).all() && b.0.cmple(a.1).all()
}

impl Scratch {
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
        self.near_seen.clear();
        self.near_seen.resize(bodies.len(), 0);
        for (b, body) in bodies.iter().enumerate() {
            if colliding(body) {
                let (grid, near, boxes) = (&self.grid, &mut self.near, &self.body_box);
                let seen = &mut self.near_seen;
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
                // A body is listed once, where the grid first gives it
                // (it may come once per cell the two share).
                let mark = b as u32 + 1;
                grid.query(boxes[b].0, boxes[b].1, |other| {
                    if other as usize == b || seen[other as usize] == mark {
                        return;
                    }
                    seen[other as usize] = mark;
                    if colliding(&bodies[other as usize])
                        && overlap(boxes[b], boxes[other as usize])
                        && balls_meet(other as usize)
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
    pub(super) fn collect(
        &mut self,
        bodies: &[Body],
        position: &[Vec3],
        reach: Real,
        with_edges: bool,
    ) {
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
}
