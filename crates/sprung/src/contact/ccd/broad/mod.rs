//! The broad phase of continuous collision detection: which pairs of
//! elements may come within the gap in a step, found rarely and checked
//! cheaply at every step.
//!
//! Each body has an *anchor*: where its particles were when its pairs were
//! last found, and a margin `h` (m). At every step each body's particles
//! are measured against their anchors: their mean move `T` (m), where the
//! step starts and where it ends, and the farthest any particle strays
//! from it at either end, `D` (m); on straight paths neither the strays
//! nor the parting of two bodies' mean moves is larger in between. Two
//! elements of bodies `a` and `b` can have come closer than they were at
//! the anchors by at most their particles' strays and `|T_a − T_b|`; so
//! while `D_a + D_b + |T_a − T_b| ≤ h_a + h_b` (within one body:
//! `D ≤ h`) only the pairs that were within `h_a + h_b` and the reach at
//! the anchors can meet, and those are kept, sorted by that distance (up
//! to an allowance, [`KEPT_PAIRS_PER_ELEMENT`]: past it, a pair of bodies
//! is searched again at each check instead). A
//! body that moves as one piece (a falling cloth) keeps its pairs; the
//! anchors of two bodies need not be from the same step.
//!
//! Per step, a sort and sweep over the bodies' swept boxes finds the pairs
//! of bodies that may meet at all; each such pair whose bound no longer
//! holds has its bodies anchored again where they start the step, and its
//! element pairs are found again through a uniform grid over the
//! elements' boxes about the anchors. Each step then hands on, from each
//! pair of bodies, the element pairs whose distance at the anchors, less
//! how far their particles strayed, is within the gap: the sorted list's
//! short front (or, for a pair of bodies past the allowance, the pairs of
//! a new search over the same anchors, in the grid's order).

use std::collections::BTreeMap;

use super::elements::{Elements, Kind};
use super::search::Anchored;
use crate::contact::grid::Grid;
use crate::units::{Real, Vec3};

/// The least margin `h` of a body, in contact thicknesses, and the most:
/// a larger one keeps pairs longer but finds more of them (a cloth folded
/// on itself at the thickness keeps none of its layers' pairs at a
/// quarter). A body starts at the least.
pub const MARGIN: (Real, Real) = (0.25, 2.0);

/// A body whose pairs held for fewer checks than this gets twice the
/// margin when anchored again (up to the most, unless it is crowded);
/// one whose pairs held for more than four times this, half of it.
const CHECKS_HELD: u64 = 64;

/// A body is crowded where its last search found more than this many
/// pairs per element: its margin no longer grows.
const CROWDED: usize = 4;

/// Each body's margin is at least this many times the farthest any of its
/// particles moved in the step it was anchored on, so that two bodies
/// anchored on the same step keep their pairs through it.
const MARGIN_PER_MOVE: Real = 3.0;

/// The pairs of elements the broad phase keeps, per element that
/// collides, over every pair of bodies, and at least [`MIN_KEPT_PAIRS`]
/// in all ([`kept_pairs_most`]): a search that would find more than the
/// rest of this allowance keeps none, and its two bodies' pairs are
/// searched again at each check instead, so that bodies pressed together
/// at speed cannot fill the memory. Those are the same pairs, handed on
/// in the grid's order rather than nearest first: the impulses, given in
/// that order, may differ in their last bits from a run that kept them
/// (the same on any number of threads), and the search, most of the
/// broad phase's work, runs every check. The demos stay well within it:
/// a cloth folded on itself keeps about 140 pairs per element at the
/// most, the bullet demo's ball at 100 m/s through a cloth about 300
/// (1.8 million pairs, within the 2 million).
pub const KEPT_PAIRS_PER_ELEMENT: usize = 256;

/// The fewest pairs the broad phase may keep, however few its elements.
pub const MIN_KEPT_PAIRS: usize = 2_000_000;

/// The most pairs the broad phase keeps among `elements` elements: no
/// more than there are pairs of them.
pub fn kept_pairs_most(elements: usize) -> usize {
    let pairs = elements.saturating_mul(elements.saturating_sub(1)) / 2;
    elements
        .saturating_mul(KEPT_PAIRS_PER_ELEMENT)
        .max(MIN_KEPT_PAIRS)
        .min(pairs)
}

/// How a body moved since its anchor.
#[derive(Debug, Clone, Copy, Default)]
struct Moved {
    /// Its margin `h` (m).
    half: Real,
    /// The check it was anchored on (a count of `prepare`s), and whether
    /// its last search was crowded.
    since: u64,
    crowded: bool,
    /// When it was anchored (a count of anchorings).
    epoch: u64,
    /// Its particles' mean move since the anchor `T` (m), where the step
    /// starts and where it ends.
    shift: [Vec3; 2],
    /// The farthest any particle strayed from it over the step, `D` (m).
    most: Real,
    /// The box its particles swept this step (m).
    low: Vec3,
    high: Vec3,
    /// The farthest any particle moved over the step against the body's
    /// mean move (m), which particle, and the size of the body where the
    /// step started (m: its box's diagonal).
    deformed: (Real, usize),
    size: Real,
}

/// How many times its own size (at the start of the step) a particle of a
/// colliding body may move against its body's mean move in one step before
/// the motion counts as run away. The CCD puts back motions of a few
/// sizes (a cloth particle flung by a deep penalty contact moved 2.9 m
/// against its 1.7 m cloth in one step of a 150 m/s ball's catch, and was
/// put back); an unstable ball of stiffness 2.1e9 N/m moved 340 times its
/// size in its first step.
pub const RUNAWAY_SIZES: Real = 100.0;

/// A step whose motion ran away ([`RUNAWAY_SIZES`]): found before the
/// search, whose work grows with the motion (to every pair in the scene).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Runaway {
    /// The particle (its index in the world), how far it moved against
    /// its body's mean move (m), and its body's size (m, or the contact
    /// thickness for a smaller body).
    pub particle: usize,
    pub stray: Real,
    pub size: Real,
}

/// How far apart the mean moves of two bodies part over the step (m): at
/// most the larger of where it starts and where it ends, as both move on
/// straight lines.
fn parting(a: &Moved, b: &Moved) -> Real {
    let start = (a.shift[0] - b.shift[0]).length();
    start.max((a.shift[1] - b.shift[1]).length())
}

/// The pairs of elements of two bodies (or of one with itself) found at
/// their anchors: `(point or first edge, other, distance in m)`, nearest
/// first.
#[derive(Debug, Clone, Default)]
struct Found {
    /// The bodies' epochs when found.
    epochs: (u64, u64),
    /// The pairs, or `None` where there were too many to keep
    /// ([`kept_pairs_most`]): then searched at each check.
    pairs: Option<Vec<(u32, u32, Real)>>,
    /// Per kept pair, what the narrow phase last made of it (its
    /// [`Stamp`]; 0: nothing yet).
    stamps: Vec<Stamp>,
}

/// What the narrow phase last made of a kept pair of elements, for it to
/// skip a test whose answer it has: the search it was tested in (a count
/// its caller keeps, below 2³¹) shifted up one bit, and in that bit
/// whether the test found a collision. 0: never tested.
pub(super) type Stamp = u32;

/// The broad phase's state, kept from step to step.
#[derive(Debug, Clone, Default)]
pub(super) struct Sweep {
    /// The generation of the elements the state was built on.
    generation: u64,
    /// The reach (m) of surface pairs (the gap) and of two loose
    /// particles (twice the radius); how far an element's box is grown
    /// beyond the margin (the gap, or the radius of a loose particle).
    reach: (Real, Real),
    grow: (Real, Real),
    /// Where each particle was at its body's anchor (m).
    anchor: Vec<Vec3>,
    /// Per element, its box about the anchor grown by its body's margin
    /// and its own reach (m).
    boxes: Vec<(Vec3, Vec3)>,
    /// Per particle, how far it strayed from its body's mean move (m).
    stray: Vec<Real>,
    /// Per body that collides (its span), how it moved.
    moved: Vec<Moved>,
    /// Anchorings so far, and checks (`prepare`s).
    clock: u64,
    checks: u64,
    /// The pairs of bodies that may meet this step (first ≤ second).
    near: Vec<(u32, u32)>,
    /// The element pairs of each pair of bodies, by the pair of spans.
    found: BTreeMap<(u32, u32), Found>,
    /// Scratch: the grid of a search; spans to anchor again; the spans
    /// sorted by their boxes.
    grid: Grid,
    again: Vec<bool>,
    order: Vec<u32>,
    /// The most pairs kept, where not [`kept_pairs_most`] (`None` but in
    /// the tests, which make it small to search at each check).
    allowance: Option<usize>,
}

impl Sweep {
    /// Ready the pairs for a step from `start` to `end` (m) among
    /// `elements`: measure each body's move, find the pairs of bodies
    /// that may meet, anchor again the bodies whose pairs no longer hold
    /// and find their pairs again (`thickness`, m, sets the least margin;
    /// `gap`, m, and `radius`, m, the reach).
    /// Refused, before any search, where a body's motion ran away
    /// ([`RUNAWAY_SIZES`]).
    #[allow(clippy::too_many_arguments)]
    pub fn prepare(
        &mut self,
        elements: &Elements,
        start: &[Vec3],
        end: &[Vec3],
        thickness: Real,
        gap: Real,
        radius: Real,
    ) -> Result<(), Runaway> {
        self.reach = (gap, 2.0 * radius);
        self.grow = (gap, radius);
        self.checks += 1;
        let spans = elements.spans.len();
        self.again.clear();
        let fresh = self.generation != elements.generation || self.anchor.len() != start.len();
        self.again.resize(spans, fresh);
        if fresh {
            self.generation = elements.generation;
            self.anchor.clear();
            self.anchor.extend_from_slice(start);
            self.stray.clear();
            self.stray.resize(start.len(), 0.0);
            self.boxes.clear();
            self.boxes
                .resize(elements.list.len(), (Vec3::ZERO, Vec3::ZERO));
            self.moved.clear();
            self.moved.resize(spans, Moved::default());
            self.found.clear();
        }
        for span in 0..spans {
            self.measure(elements, span, start, end);
            let moved = &self.moved[span];
            let ((stray, particle), size) = (moved.deformed, moved.size.max(thickness));
            if stray > RUNAWAY_SIZES * size {
                return Err(Runaway {
                    particle,
                    stray,
                    size,
                });
            }
        }
        self.find_near(elements);
        let before = self.clock;
        // Anchor again until every pair of bodies that may meet holds: a
        // body anchored on this step holds with any other anchored on it,
        // so each is anchored at most once and this ends.
        loop {
            for &(a, b) in &self.near {
                if !self.holds(a as usize, b as usize) {
                    for span in [a as usize, b as usize] {
                        self.again[span] = self.moved[span].epoch <= before;
                    }
                }
            }
            let mut anchored = false;
            for span in 0..spans {
                if self.again[span] {
                    self.again[span] = false;
                    anchored = true;
                    self.anchor_again(elements, span, start, end, thickness);
                }
            }
            if !anchored {
                break;
            }
        }
        let moved = &self.moved;
        self.found.retain(|&(a, b), found| {
            found.epochs == (moved[a as usize].epoch, moved[b as usize].epoch)
        });
        let allowance = self
            .allowance
            .unwrap_or_else(|| kept_pairs_most(elements.list.len()));
        let mut kept: usize = self
            .found
            .values()
            .filter_map(|f| f.pairs.as_ref())
            .map(Vec::len)
            .sum();
        for k in 0..self.near.len() {
            let (a, b) = self.near[k];
            if !self.found.contains_key(&(a, b)) {
                let (a, b) = (a as usize, b as usize);
                let anchored = Anchored {
                    elements,
                    boxes: &self.boxes,
                    anchor: &self.anchor,
                    reach: self.reach,
                };
                let within = self.moved[a].half + self.moved[b].half;
                let pairs = anchored.pairs(
                    &mut self.grid,
                    (a, b),
                    within,
                    allowance.saturating_sub(kept),
                );
                // Past the allowance counts as crowded: the margins stop
                // growing, which keeps the next searches smaller.
                let found = pairs.as_ref().map_or(usize::MAX, Vec::len);
                kept += pairs.as_ref().map_or(0, Vec::len);
                for span in [a, b] {
                    let count = elements.spans[span].len();
                    self.moved[span].crowded = found > CROWDED * count;
                }
                let epochs = (self.moved[a].epoch, self.moved[b].epoch);
                let stamps = vec![0; pairs.as_ref().map_or(0, Vec::len)];
                self.found.insert(
                    (a as u32, b as u32),
                    Found {
                        epochs,
                        pairs,
                        stamps,
                    },
                );
            }
        }
        Ok(())
    }

    /// The most bytes the pairs the broad phase keeps may take for
    /// `elements` elements that collide, at the peak of a search.
    pub fn most_bytes(elements: usize) -> usize {
        // A search's list grows by doubling up to the allowance left (the
        // one being grown and the one it grows from are held at once: less
        // than 3 times it), then is trimmed to its length and sorted (a
        // stable sort's buffer: at most its length).
        // The stamps: one per pair kept.
        let kept = kept_pairs_most(elements);
        3 * kept * size_of::<(u32, u32, Real)>() + kept * size_of::<Stamp>()
    }

    /// Forget every stamp ([`Stamp`]): for a caller whose count of
    /// searches starts again.
    pub fn forget_stamps(&mut self) {
        for found in self.found.values_mut() {
            found.stamps.fill(0);
        }
    }

    /// Call `meet(a, b)` on every pair of elements that may come within
    /// the gap (two loose particles: twice the radius) this step, pair of
    /// bodies by pair of bodies, nearest first within each (in the grid's
    /// order where their pairs were past the allowance): its distance
    /// at the anchors, less how far its particles strayed and how far its
    /// bodies' mean moves part, is within it. A pair of the kept lists
    /// comes with its [`Stamp`], for `meet` to read and write; a pair of
    /// a search at each check, with none.
    pub fn overlaps(
        &mut self,
        elements: &Elements,
        mut meet: impl FnMut(usize, usize, Option<&mut Stamp>),
    ) {
        let (gap, balls) = self.reach;
        let furthest = gap.max(balls);
        let stray = &self.stray;
        let slack = |e: u32| {
            elements.list[e as usize]
                .particles()
                .iter()
                .map(|&i| stray[i as usize])
                .fold(0.0, Real::max)
        };
        let anchored = Anchored {
            elements,
            boxes: &self.boxes,
            anchor: &self.anchor,
            reach: self.reach,
        };
        for &(a, b) in &self.near {
            let Some(found) = self.found.get_mut(&(a, b)) else {
                continue;
            };
            let (ma, mb) = (&self.moved[a as usize], &self.moved[b as usize]);
            let parting = if a == b { 0.0 } else { parting(ma, mb) };
            let bound = ma.most + mb.most + parting + furthest;
            let mut hand_on = |p: u32, q: u32, d: Real, stamp: Option<&mut Stamp>| {
                let closest = d - slack(p) - slack(q) - parting;
                let (ep, eq) = (&elements.list[p as usize], &elements.list[q as usize]);
                let reach =
                    if a != b && ep.kind == Kind::Point(true) && eq.kind == Kind::Point(true) {
                        balls
                    } else {
                        gap
                    };
                if closest <= reach {
                    meet(p as usize, q as usize, stamp);
                }
            };
            match &found.pairs {
                Some(pairs) => {
                    for (&(p, q, d), stamp) in pairs.iter().zip(&mut found.stamps) {
                        if d > bound {
                            break;
                        }
                        hand_on(p, q, d, Some(stamp));
                    }
                }
                None => {
                    let within = ma.half + mb.half;
                    let spans = (a as usize, b as usize);
                    anchored.each_pair(&mut self.grid, spans, within, |p, q, d| {
                        if d <= bound {
                            hand_on(p, q, d, None);
                        }
                        true
                    });
                }
            }
        }
    }

    /// Whether the pairs of bodies `a` and `b` found at their anchors
    /// still hold every pair that can meet (module docs).
    fn holds(&self, a: usize, b: usize) -> bool {
        let (ma, mb) = (&self.moved[a], &self.moved[b]);
        if a == b {
            ma.most <= ma.half
        } else {
            ma.most + mb.most + parting(ma, mb) <= ma.half + mb.half
        }
    }

    /// Measure how the particles of `span` moved since their anchors over
    /// the step from `start` to `end` (m), and the box they swept.
    fn measure(&mut self, elements: &Elements, span: usize, start: &[Vec3], end: &[Vec3]) {
        let particles = elements.span_particles[span].clone();
        let count = particles.len().max(1) as Real;
        let anchor = &self.anchor;
        let mean = |x: &[Vec3]| particles.clone().map(|i| x[i] - anchor[i]).sum::<Vec3>() / count;
        let shift = [mean(start), mean(end)];
        let (mut most, mut low, mut high): (Real, _, _) = (0.0, Vec3::INFINITY, Vec3::NEG_INFINITY);
        let (mut start_low, mut start_high) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
        let (mut deformed, mut worst) = (0.0, particles.start);
        let step_mean = shift[1] - shift[0];
        for i in particles {
            let (a, b) = (
                start[i] - anchor[i] - shift[0],
                end[i] - anchor[i] - shift[1],
            );
            let stray = a.length_squared().max(b.length_squared()).sqrt();
            self.stray[i] = stray;
            most = most.max(stray);
            low = low.min(start[i].min(end[i]));
            high = high.max(start[i].max(end[i]));
            start_low = start_low.min(start[i]);
            start_high = start_high.max(start[i]);
            let against = (end[i] - start[i] - step_mean).length_squared();
            if against > deformed {
                (deformed, worst) = (against, i);
            }
        }
        let moved = &mut self.moved[span];
        moved.shift = shift;
        moved.most = most;
        moved.low = low;
        moved.high = high;
        moved.deformed = (deformed.sqrt(), worst);
        moved.size = (start_high - start_low).length();
    }

    /// The pairs of bodies whose boxes swept this step, grown by the
    /// reach, overlap, and each body that collides with itself, in order:
    /// a sort and sweep along x.
    fn find_near(&mut self, elements: &Elements) {
        let grow = self.grow.0.max(self.grow.1);
        let moved = &self.moved;
        self.order.clear();
        self.order.extend(0..moved.len() as u32);
        self.order
            .sort_by(|&a, &b| moved[a as usize].low.x.total_cmp(&moved[b as usize].low.x));
        self.near.clear();
        for (k, &a) in self.order.iter().enumerate() {
            let ma = &moved[a as usize];
            if elements.span_own[a as usize] {
                self.near.push((a, a));
            }
            for &b in &self.order[k + 1..] {
                let mb = &moved[b as usize];
                if mb.low.x - grow > ma.high.x + grow {
                    break;
                }
                let overlap = (ma.low - grow).cmple(mb.high + grow).all()
                    && (mb.low - grow).cmple(ma.high + grow).all();
                if overlap {
                    self.near.push((a.min(b), a.max(b)));
                }
            }
        }
        self.near.sort_unstable();
    }

    /// Anchor `span` again where it starts the step from `start` to `end`
    /// (m), with a margin from `thickness` (m), how long its last pairs held
    /// and its move, and measure it again.
    fn anchor_again(
        &mut self,
        elements: &Elements,
        span: usize,
        start: &[Vec3],
        end: &[Vec3],
        thickness: Real,
    ) {
        let particles = elements.span_particles[span].clone();
        self.anchor[particles.clone()].copy_from_slice(&start[particles.clone()]);
        let moved = particles
            .map(|i| (end[i] - start[i]).length_squared())
            .fold(0.0, Real::max)
            .sqrt();
        let (least, most) = (MARGIN.0 * thickness, MARGIN.1 * thickness);
        let last = self.moved[span];
        let held = self.checks - last.since;
        let margin = if last.epoch == 0 {
            least
        } else if held < CHECKS_HELD && !last.crowded {
            (2.0 * last.half).min(most)
        } else if held > 4 * CHECKS_HELD {
            0.5 * last.half
        } else {
            last.half
        };
        let half = margin.max(least).max(MARGIN_PER_MOVE * moved);
        self.clock += 1;
        let anchored = &mut self.moved[span];
        anchored.half = half;
        anchored.epoch = self.clock;
        anchored.since = self.checks;
        let (gap, radius) = self.grow;
        let anchor = &self.anchor;
        for e in elements.spans[span].clone() {
            let element = &elements.list[e];
            let (mut lo, mut hi) = (Vec3::INFINITY, Vec3::NEG_INFINITY);
            for &i in element.particles() {
                lo = lo.min(anchor[i as usize]);
                hi = hi.max(anchor[i as usize]);
            }
            let grow = half
                + if element.kind == Kind::Point(true) {
                    radius
                } else {
                    gap
                };
            self.boxes[e] = (lo - grow, hi + grow);
        }
        self.measure(elements, span, start, end);
    }
}

#[cfg(test)]
mod tests;
