//! The detect stage: candidate pairs for one step from a uniform grid.
//! The stage and its buffers are here; how far the particles have moved
//! since the last search (whether its pairs still cover a step) is in
//! `motion`, what of the bodies may meet (the broad phase) in `gather`,
//! and the pair search in `search`.

mod gather;
mod motion;
mod search;

pub use search::{pair_limit, TooManyPairs, MIN_PAIR_LIMIT, PAIRS_PER_ELEMENT};

use super::buckets::{ByParticle, CLEARANCE_BUCKETS};
use super::geometry::closest_between_segments;
use super::grid::Grid;
use super::pairs::{beyond, Spare};
use super::{ContactSettings, Contacts, EdgeEdge, PointPoint, PointSegment, PointTriangle};
use crate::body::{Body, BodyContact};
use crate::springs::Springs;
use crate::units::{Real, Vec3};
use gather::Gathered;
use search::{Budget, Search};
use std::sync::atomic::AtomicUsize;

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
    /// Per body, the last body (plus one) whose near bodies it was found
    /// among: each is listed once without searching the list (scratch).
    near_seen: Vec<u32>,
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

/// Whether a body's edges meet other edges: an open surface's, or a
/// surface that collides with itself (two of its folds may cross edge
/// to edge).
fn edges_collide(body: &Body) -> bool {
    !body.closed || body.contact.self_collision
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
