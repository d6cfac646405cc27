//! The detect stage: candidate pairs for one step from a uniform grid.

use super::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use super::grid::Grid;
use super::{ContactPairs, Contacts, EdgeEdge, PointPoint, PointSegment, PointTriangle};
use crate::body::Body;
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
    /// The grown bounding box of each element of the current grid.
    boxes: Vec<(Vec3, Vec3)>,
    /// Per element, the last query that visited it (plus one).
    seen: Vec<u32>,
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

impl Scratch {
    /// Gather the colliding bodies' elements.
    fn collect(&mut self, bodies: &[Body], particles: usize) {
        self.body_of.clear();
        self.body_of.resize(particles, NONE);
        self.triangles.clear();
        self.segments.clear();
        self.edges.clear();
        self.loose.clear();
        for (index, body) in bodies.iter().enumerate() {
            if !body.contact.collide {
                continue;
            }
            let index = index as u32;
            for i in body.particles.clone() {
                self.body_of[i] = index;
            }
            self.triangles
                .extend(body.faces.iter().map(|&f| (f, index)));
            self.segments
                .extend(body.segments.iter().map(|&s| (s, index)));
            self.edges.extend(body.edges.iter().map(|&e| (e, index)));
            if body.faces.is_empty() && body.segments.is_empty() {
                self.loose
                    .extend(body.particles.clone().map(|i| ([i as u32], index)));
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

/// What the pair search needs to know of the world.
struct Search<'a> {
    bodies: &'a [Body],
    position: &'a [Vec3],
    reach: Real,
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
        for particle in 0..self.position.len() as u32 {
            let body = scratch.body_of[particle as usize];
            if body == NONE {
                continue;
            }
            let p = self.x(particle);
            scratch.grid.query(p, p, |e| {
                let (element, element_body) = elements(scratch)[e as usize];
                let (low, high) = scratch.boxes[e as usize];
                let inside = p.cmpge(low).all() && p.cmple(high).all();
                if inside && self.allowed(body, element_body) && !element.contains(&particle) {
                    pair(particle, element, element_body);
                }
            });
        }
    }

    /// Pairs of elements of `elements` with each other within reach (each
    /// pair once); `pair` gets both, with their bodies.
    fn among<const N: usize>(
        &self,
        scratch: &mut Scratch,
        elements: Elements<N>,
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
            let (low, high) = built.boxes[first];
            built.grid.query(low, high, |second| {
                let second = second as usize;
                if second <= first || seen[second] == first as u32 + 1 {
                    return;
                }
                seen[second] = first as u32 + 1;
                let (a, b) = (list[first], list[second]);
                if self.allowed(a.1, b.1) {
                    pair(a, b);
                }
            });
        }
        scratch.seen = seen;
    }
}

impl Contacts {
    /// The detect stage: find every pair of elements of colliding bodies
    /// within the thickness plus the distance two particles moving at the
    /// fastest speed now can close in a step of `dt` (s), as candidate pairs
    /// for the step's force evaluations.
    pub fn detect(&mut self, bodies: &[Body], position: &[Vec3], velocity: &[Vec3], dt: Real) {
        self.pairs.clear();
        let colliding = bodies.iter().filter(|b| b.contact.collide).count();
        let self_colliding = bodies
            .iter()
            .any(|b| b.contact.collide && b.contact.self_collision);
        if !self.settings.enabled || (colliding < 2 && !self_colliding) {
            return;
        }
        let Contacts {
            pairs,
            scratch,
            settings,
        } = self;
        scratch.collect(bodies, position.len());
        let speed = (0..position.len())
            .filter(|&i| scratch.body_of[i] != NONE)
            .map(|i| velocity[i].length())
            .fold(0.0, Real::max);
        let search = Search {
            bodies,
            position,
            reach: settings.thickness + 2.0 * dt * speed.min(1e6),
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
        search.among(
            scratch,
            |s| &s.edges,
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
