//! The CCD behind the penalty contacts (docs/physics.md §8): after
//! each (sub)step's forces, continuous collision detection over the motion
//! the step made, from where the particles were to where the integrator
//! (and the colliders, rods and rigid bodies) put them, so that no
//! crossing survives a step, at any speed or `dt`.
//!
//! **Method** (Bridson, Fedkiw and Anderson 2002; Harmon et al. 2008).
//! Each particle is taken to move on a straight line over the step. The
//! broad phase (`broad`) pairs the elements whose swept boxes overlap;
//! the narrow phase (`narrow`) finds the pairs that come within the gap
//! `δ` ([`GAP`] times the thickness) at some moment: a point and a
//! triangle or two edges where they become coplanar (3D), a point and a
//! segment (2D), two particles of bodies without surfaces, balls of radius
//! [`RADIUS`] times the thickness. Each collision gets an inelastic impulse
//! that leaves its two sides `2δ` apart along the normal of the side the
//! point started on, with Coulomb friction (the `[contact]` friction) on
//! the relative tangential motion, shared among the particles by their
//! weights and inverse masses, so momentum is kept exactly. The impulses
//! change where the particles end the step, and their velocities by the
//! same change over `dt`. The search runs again after each round of
//! impulses; after [`IMPULSE_ROUNDS`] rounds, colliding particles are
//! merged into impact zones that move rigidly (`zones`), merging again
//! until no collision is left between zones: a rigid motion has none
//! within a zone.
//!
//! The search and the impulses run in a fixed order, so the result is the
//! same bits on any number of threads.

mod broad;
mod colliders;
mod elements;
mod narrow;
mod search;
mod zones;

pub(crate) use broad::Runaway;
pub use broad::{kept_pairs_most, KEPT_PAIRS_PER_ELEMENT, MIN_KEPT_PAIRS, RUNAWAY_SIZES};
pub(crate) use colliders::sweep_colliders;

use crate::body::Body;
use crate::constrain::RigidBody;
use crate::units::{Real, Vec3};
use broad::Sweep;
use elements::{Element, Elements, Kind};
use narrow::{Hit, Moving};
use zones::Zones;

/// The gap `δ` (in contact thicknesses) within which the CCD counts
/// two elements as colliding; each collision is left `2δ` apart.
pub const GAP: Real = 1e-3;

/// The radius (in contact thicknesses) of the balls the particles of
/// bodies without surfaces are to the CCD: they never come closer
/// than twice it while closing.
pub const RADIUS: Real = 0.1;

/// The most an impulse may move a particle, in multiples of the push it
/// gives its collision's gap: a point and a free triangle, or a free
/// point and a pinned one, move at most once the push; only a collision
/// whose free particles carry little of its weight moves them more.
pub const MOST_LEVER: Real = 4.0;

/// Rounds of impulses before impact zones.
pub const IMPULSE_ROUNDS: usize = 4;

/// The most bytes the CCD's broad phase keeps for its pairs of
/// elements among `bodies` ([`kept_pairs_most`]): 0 where no body
/// collides.
pub(crate) fn kept_pairs_most_bytes(bodies: &[Body]) -> usize {
    let mut elements = Elements::default();
    if elements.gather(bodies) {
        Sweep::most_bytes(elements.list.len())
    } else {
        0
    }
}

/// The work a (sub)step's CCD may do, in narrow tests and particles
/// visited merging impact zones, per element that collides: the demos
/// take at most 1,425 (the bullet demo's ball at 100 m/s through a cloth,
/// 8.7 million in one step), most of them below 80 (`twist`: 78; `cover`:
/// 2).
pub const WORK_PER_ELEMENT: u64 = 4096;

/// The work any (sub)step's CCD may do, however few its elements:
/// about a tenth of a second.
pub const MIN_WORK: u64 = 1_000_000;

/// The work a (sub)step's CCD may do among `elements` elements:
/// [`WORK_PER_ELEMENT`] each, at least [`MIN_WORK`].
pub fn work_budget(elements: usize) -> u64 {
    (elements as u64)
        .saturating_mul(WORK_PER_ELEMENT)
        .max(MIN_WORK)
}

/// Why the CCD left a step's collisions as they were: the run must
/// stop on it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) enum Stopped {
    /// The motion ran away before the search ([`RUNAWAY_SIZES`]).
    Runaway(Runaway),
    /// The collisions would take more than the step's budget.
    OverBudget(OverBudget),
}

/// A step whose collisions the CCD could not clear within its
/// budget ([`work_budget`]).
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct OverBudget {
    /// The bodies of the collisions left (indices in the world).
    pub bodies: Vec<usize>,
    /// The work done, and the budget.
    pub work: u64,
    pub budget: u64,
    /// The rounds taken, and the collisions left.
    pub rounds: usize,
    pub collisions: usize,
}

/// What the CCD did in a step: its impulses and impact zones.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CcdReport {
    /// Collisions given an impulse (summed over the rounds and substeps).
    pub impulses: u64,
    /// Impact zones of more than one particle moved rigidly.
    pub zones: u64,
}

impl CcdReport {
    /// This report and `next` (a later substep's) together.
    pub fn then(self, next: CcdReport) -> CcdReport {
        CcdReport {
            impulses: self.impulses + next.impulses,
            zones: self.zones + next.zones,
        }
    }
}

/// The CCD's buffers, kept from step to step.
#[derive(Debug, Clone, Default)]
pub(crate) struct Ccd {
    elements: Elements,
    sweep: Sweep,
    hits: Vec<Hit>,
    zones: Zones,
    /// Where the particles ended the step before the CCD (m).
    before: Vec<Vec3>,
    /// Zone roots, and the particles of their zones (scratch).
    involved: Vec<u32>,
    members: Vec<u32>,
    /// The contact thickness (m) of this stage: the least margin of the
    /// broad phase.
    thickness: Real,
    /// The work of this (sub)step so far: narrow tests, and particles
    /// visited merging zones.
    work: u64,
    /// Searches (`find`s) so far, below 2³¹ ([`broad::Stamp`]), and the
    /// first of this (sub)step: a stamp from before it is stale.
    searches: u32,
    first_search: u32,
    /// Per particle, the search in which its end was last seen to have
    /// moved (this (sub)step), and where it ended then (m).
    moved_at: Vec<u32>,
    seen: Vec<Vec3>,
    /// Test every pair again at every round (the tests' reference).
    #[cfg(test)]
    retest_all: bool,
}

/// Searches counted before the stamps start again ([`broad::Stamp`]
/// keeps one bit for a collision).
const MOST_SEARCHES: u32 = 1 << 30;

/// The motion the CCD corrects: where each particle started the
/// (sub)step and ended it (m), their velocities (m/s) and inverse masses
/// (1/kg).
pub(crate) struct Motion<'a> {
    pub start: &'a [Vec3],
    pub position: &'a mut [Vec3],
    pub velocity: &'a mut [Vec3],
    pub inverse_mass: &'a [Real],
}

impl Ccd {
    /// Clear every collision of the step of `dt` (s) between `bodies`
    /// (contact `thickness` in m, Coulomb `friction`); `rigid` bodies
    /// move as one zone each. Refused, with the state left where the step
    /// took it, where the motion ran away ([`RUNAWAY_SIZES`]) or clearing
    /// the collisions would take more than the budget of the step
    /// ([`work_budget`]). Asked to stop ([`crate::interrupt`]),
    /// it takes its fail-safe: every particle that collides with another
    /// body or itself ends the step where it started it.
    pub fn resolve(
        &mut self,
        bodies: &[Body],
        rigid: &[RigidBody],
        motion: Motion<'_>,
        thickness: Real,
        friction: Real,
        dt: Real,
    ) -> Result<CcdReport, Stopped> {
        let mut report = CcdReport::default();
        self.work = 0;
        if !self.elements.gather(bodies) {
            return Ok(report);
        }
        let Motion {
            start,
            position,
            velocity,
            inverse_mass,
        } = motion;
        let gap = GAP * thickness;
        let radius = RADIUS * thickness;
        self.thickness = thickness;
        let budget = work_budget(self.elements.list.len());
        if self.searches >= MOST_SEARCHES {
            self.searches = 0;
            self.sweep.forget_stamps();
        }
        self.first_search = self.searches + 1;
        // Most steps find nothing: the ends are kept only for a step that
        // will move them.
        self.find(start, position, inverse_mass, gap, radius, false)?;
        if self.hits.is_empty() {
            return Ok(report);
        }
        self.before.clear();
        self.before.extend_from_slice(position);
        self.seen.clear();
        self.seen.extend_from_slice(position);
        self.moved_at.clear();
        self.moved_at.resize(position.len(), self.first_search);
        let mut zoned = false;
        for round in 0.. {
            if round > 0 {
                self.find(start, position, inverse_mass, gap, radius, zoned)?;
            }
            if self.work > budget {
                return Err(Stopped::OverBudget(self.over_budget(bodies, budget, round)));
            }
            if round >= IMPULSE_ROUNDS {
                if !zoned {
                    zoned = true;
                    self.start_zones(rigid, position.len());
                }
                // Collisions within a zone cannot happen but by rounding:
                // passed over, so that the merging ends.
                let zones = &mut self.zones;
                self.hits.retain(|hit| {
                    let first = zones.find(hit.particles[0]);
                    hit.particles
                        .iter()
                        .zip(hit.weights)
                        .any(|(&p, w)| w != 0.0 && zones.find(p) != first)
                });
            }
            if self.hits.is_empty() {
                break;
            }
            if crate::interrupt::requested() {
                self.keep_where_started(start, position);
                break;
            }
            if round < IMPULSE_ROUNDS {
                report.impulses += self.hits.len() as u64;
                for hit in &self.hits {
                    respond(hit, start, position, inverse_mass, friction);
                }
                if !rigid.is_empty() {
                    self.keep_rigid(rigid, start, position, inverse_mass);
                }
                continue;
            }
            report.zones += self.merge(start, position, inverse_mass);
        }
        for ((x, v), before) in position.iter().zip(velocity.iter_mut()).zip(&self.before) {
            if x != before {
                *v += (*x - *before) / dt;
            }
        }
        Ok(report)
    }

    /// The fail-safe: every particle of the bodies that collide (with
    /// each other or themselves) back where it started the step, which
    /// had no crossing. Their velocities then lose the step's motion.
    fn keep_where_started(&mut self, start: &[Vec3], position: &mut [Vec3]) {
        for span in &self.elements.span_particles {
            position[span.clone()].copy_from_slice(&start[span.clone()]);
        }
    }

    /// The refusal of a step whose collisions would take more work than
    /// `budget`, after `round` rounds: the bodies of its collisions left.
    fn over_budget(&self, bodies: &[Body], budget: u64, round: usize) -> OverBudget {
        let mut involved: Vec<usize> = self
            .hits
            .iter()
            .flat_map(|hit| hit.particles.iter().zip(hit.weights))
            .filter(|(_, w)| *w != 0.0)
            // The bodies hold the particles in runs, in order.
            .map(|(&p, _)| bodies.partition_point(|b| b.particles.end <= p as usize))
            .filter(|&b| b < bodies.len())
            .collect();
        involved.sort_unstable();
        involved.dedup();
        OverBudget {
            bodies: involved,
            work: self.work,
            budget,
            rounds: round,
            collisions: self.hits.len(),
        }
    }

    /// The collisions of the motion from `start` to `end` (m) into `hits`,
    /// in the sweep's order.
    /// A collision none of whose particles can move (all pinned, or of
    /// weight zero) is left out: nothing the CCD does changes it,
    /// and the pinned paths are the scene's own. Where `zoned`, a pair
    /// whose particles are all of one impact zone is not tested: a rigid
    /// motion has no collision within a zone (`zones`), and the rounds
    /// pass over any that rounding makes. Nor is a kept pair tested again
    /// whose test in an earlier round of this (sub)step found nothing
    /// and none of whose particles has moved since: the test would find
    /// the same.
    fn find(
        &mut self,
        start: &[Vec3],
        end: &[Vec3],
        inverse_mass: &[Real],
        gap: Real,
        radius: Real,
        zoned: bool,
    ) -> Result<(), Stopped> {
        self.searches += 1;
        let search = self.searches;
        if search > self.first_search {
            // The rounds after the first: which ends the last one moved.
            for (p, (seen, &x)) in self.seen.iter_mut().zip(end.iter()).enumerate() {
                if *seen != x {
                    *seen = x;
                    self.moved_at[p] = search;
                }
            }
        }
        let (first_search, moved_at) = (self.first_search, &self.moved_at);
        #[cfg(test)]
        let reuse = !self.retest_all;
        #[cfg(not(test))]
        let reuse = true;
        let elements = &self.elements;
        let hits = &mut self.hits;
        let work = &mut self.work;
        let zones = &mut self.zones;
        hits.clear();
        self.sweep
            .prepare(elements, start, end, self.thickness, gap, radius)
            .map_err(Stopped::Runaway)?;
        self.sweep.overlaps(elements, |a, b, stamp| {
            let (ea, eb) = (&elements.list[a], &elements.list[b]);
            let particles = || ea.particles().iter().chain(eb.particles());
            if zoned {
                let zone = zones.find(ea.particles[0]);
                if particles().all(|&p| zones.find(p) == zone) {
                    return;
                }
            }
            if let Some(&last) = stamp.as_deref() {
                // Tested this (sub)step, found nothing, nothing moved.
                let tested = last >> 1;
                let same = reuse
                    && last & 1 == 0
                    && tested >= first_search
                    && particles().all(|&p| moved_at[p as usize] <= tested);
                if same {
                    return;
                }
            }
            *work += 1;
            let found = test(ea, eb, start, end, gap, radius);
            if let Some(stamp) = stamp {
                *stamp = (search << 1) | found.is_some() as u32;
            }
            if let Some(hit) = found {
                let free = hit.particles.iter().zip(hit.weights);
                if free
                    .clone()
                    .any(|(&p, w)| w != 0.0 && inverse_mass[p as usize] > 0.0)
                {
                    hits.push(hit);
                }
            }
        });
        Ok(())
    }

    /// After a round of impulses, put the rigid bodies the impulses moved
    /// back on one rigid motion each.
    fn keep_rigid(
        &mut self,
        rigid: &[RigidBody],
        start: &[Vec3],
        position: &mut [Vec3],
        inverse_mass: &[Real],
    ) {
        for body in rigid {
            let hit = self.hits.iter().any(|h| {
                h.particles
                    .iter()
                    .any(|&p| body.particles.contains(&(p as usize)))
            });
            if hit {
                self.involved.clear();
                self.involved
                    .extend(body.particles.clone().map(|i| i as u32));
                zones::move_rigidly(&self.involved, start, position, inverse_mass);
            }
        }
    }

    /// Every particle its own zone but those of a rigid body, one each.
    fn start_zones(&mut self, rigid: &[RigidBody], particles: usize) {
        self.zones.reset(particles);
        for body in rigid {
            let first = body.particles.start as u32;
            for i in body.particles.clone() {
                self.zones.union(first, i as u32);
            }
        }
    }

    /// Merge the zones of this round's collisions and move each zone they
    /// touch rigidly (a rigid body's particles with their whole body);
    /// returns how many zones moved.
    fn merge(&mut self, start: &[Vec3], position: &mut [Vec3], inverse_mass: &[Real]) -> u64 {
        let mut roots = std::mem::take(&mut self.involved);
        roots.clear();
        for hit in &self.hits {
            let first = hit.particles[0];
            for (&p, w) in hit.particles.iter().zip(hit.weights) {
                if w != 0.0 {
                    self.zones.union(first, p);
                }
            }
        }
        for hit in &self.hits {
            roots.push(self.zones.find(hit.particles[0]));
        }
        roots.sort_unstable();
        roots.dedup();
        let mut members = std::mem::take(&mut self.members);
        members.clear();
        self.work += position.len() as u64;
        for p in 0..position.len() as u32 {
            if roots.binary_search(&self.zones.find(p)).is_ok() {
                members.push(p);
            }
        }
        self.work += (roots.len() * members.len()) as u64;
        for &root in &roots {
            self.zones
                .rigidify(root, &members, start, position, inverse_mass);
        }
        self.members = members;
        let moved = roots.len() as u64;
        self.involved = roots;
        moved
    }
}

/// The narrow test of a pair of elements (`a` a point, or an edge against
/// an edge).
fn test(
    a: &Element,
    b: &Element,
    start: &[Vec3],
    end: &[Vec3],
    gap: Real,
    radius: Real,
) -> Option<Hit> {
    let moving = |ids: &[u32]| -> ([Vec3; 4], [Vec3; 4]) {
        let mut s = [Vec3::ZERO; 4];
        let mut u = [Vec3::ZERO; 4];
        for (k, &i) in ids.iter().enumerate() {
            s[k] = start[i as usize];
            u[k] = end[i as usize] - start[i as usize];
        }
        (s, u)
    };
    let p = a.particles[0];
    match (a.kind, b.kind) {
        (Kind::Point(_), Kind::Triangle) => {
            let ids = [p, b.particles[0], b.particles[1], b.particles[2]];
            let (start, motion) = moving(&ids);
            narrow::point_triangle(&Moving { start, motion }, ids, gap)
        }
        (Kind::Point(_), Kind::Segment) => {
            let ids = [p, b.particles[0], b.particles[1]];
            let (s, u) = moving(&ids);
            let m = Moving {
                start: [s[0], s[1], s[2]],
                motion: [u[0], u[1], u[2]],
            };
            narrow::point_segment(&m, ids, gap)
        }
        (Kind::Point(_), Kind::Point(_)) => {
            let ids = [p, b.particles[0]];
            let (s, u) = moving(&ids);
            let m = Moving {
                start: [s[0], s[1]],
                motion: [u[0], u[1]],
            };
            narrow::point_point(&m, ids, radius)
        }
        (Kind::Edge, Kind::Edge) => {
            let ids = [
                a.particles[0],
                a.particles[1],
                b.particles[0],
                b.particles[1],
            ];
            let (start, motion) = moving(&ids);
            narrow::edge_edge(&Moving { start, motion }, ids, gap)
        }
        _ => None,
    }
}

/// The inelastic impulse of `hit`, with Coulomb friction `friction`: where
/// its sides end the step closer than its separation along its normal,
/// move them apart to it, each particle by its weight times its inverse
/// mass (the sum of mass times move is zero: momentum is kept), and slow
/// their relative tangential motion by up to `friction` times that.
fn respond(
    hit: &Hit,
    start: &[Vec3],
    position: &mut [Vec3],
    inverse_mass: &[Real],
    friction: Real,
) {
    let (mut gap, mut relative, mut share) = (0.0, Vec3::ZERO, 0.0);
    for (&p, w) in hit.particles.iter().zip(hit.weights) {
        let p = p as usize;
        gap += w * hit.normal.dot(position[p]);
        relative += w * (position[p] - start[p]);
        share += w * w * inverse_mass[p];
    }
    if gap >= hit.separation || share <= 0.0 {
        return;
    }
    // Where the particles free to move carry little of the weight (a
    // point near a pinned corner), clearing the gap would fling them far
    // (1e11 m seen): such a collision is left to the impact zones, whose
    // rigid motions never move a particle farther than its zone moves.
    let lever = hit
        .particles
        .iter()
        .zip(hit.weights)
        .map(|(&p, w)| w.abs() * inverse_mass[p as usize])
        .fold(0.0, Real::max)
        / share;
    if lever > MOST_LEVER {
        return;
    }
    let push = hit.separation - gap;
    let tangential = relative - relative.dot(hit.normal) * hit.normal;
    let slide = tangential.length();
    let slowed = (friction * push).min(slide);
    let change = push * hit.normal
        - if slide > 0.0 {
            slowed / slide * tangential
        } else {
            Vec3::ZERO
        };
    for (&p, w) in hit.particles.iter().zip(hit.weights) {
        let p = p as usize;
        if w != 0.0 {
            position[p] += (w * inverse_mass[p] / share) * change;
        }
    }
}

#[cfg(test)]
mod tests;
