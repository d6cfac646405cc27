//! Tearing: the springs and joins that give way (docs/physics.md §11).
//! Past its yield strain a spring's rest length moves (plasticity, or
//! yielding); past its break strain it breaks for good, and a surface
//! opens along it (a cloth tears, a ball bursts). Joins between bodies
//! ([`join`]) are springs and rods like any other, and break the same way.
//! Here are the limits and their search (this file, with the move budget
//! of `budget.rs`) and the joins (`join.rs`); the world's side, the give
//! stage ([`Stage::Give`](crate::Stage::Give): adding joins, the surfaces
//! that open, what a saved state holds), is `world/tearing.rs`, as every
//! stage's is in `world/`.
//!
//! The strain of a spring of rest length `L0` at length `L` is
//! `ε = (L − L0) / L0`. At the end of each (sub)step, in spring order:
//!
//! - `ε > B` (the break strain): the spring breaks
//!   ([`Springs::break_spring`]); the energy it held, `½ k (L − L0)²`,
//!   leaves with it;
//! - else `ε > Y` (the yield strain now): the rest length moves to
//!   `L / (1 + Y)`, so the strain stays on the yield limit; `ε < −Y` (for
//!   `Y < 1`) moves it to `L / (1 − Y)`. The spring's potential energy drops
//!   by `½ k [(L − L0)² − (L − L0')²] ≥ 0`. With a hardening `H`, the yield
//!   strain then grows by `H |L0' − L0| / L0`.
//!
//! The energy taken out both ways is summed in [`SpringLimits::plastic_work`]
//! (the `plastic` energy column), so the energy balance of a run still
//! closes. Springs with neither limit cost nothing: the stage walks only
//! the ranges of springs that have one.
//!
//! A full search reads every watched spring's two ends; between searches
//! a budget of the particles' moves (`tearing/budget.rs`) tells when the
//! next one is due.

mod budget;
pub mod join;

use std::ops::Range;

use crate::error::BuildError;
use crate::parallel;
use crate::springs::Springs;
use crate::units::{Real, Vec3};
use budget::MoveBudget;
pub use join::{Join, JoinData, JoinEnd, JoinLink};

/// How a body's (or a join's) springs give way: the scene keys
/// `break_strain`, `yield_strain` and `hardening`.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StrainLimits {
    /// Strain `(L − L0) / L0` past which a spring breaks (dimensionless,
    /// positive); `None`: never.
    pub break_strain: Option<Real>,
    /// Strain (in tension or compression) past which a spring's rest
    /// length moves (dimensionless, positive, below `break_strain`);
    /// `None`: never.
    pub yield_strain: Option<Real>,
    /// Linear hardening `H` (dimensionless, non-negative): each yield
    /// raises the spring's yield strain by `H` times the relative move of
    /// its rest length. Default 0.
    pub hardening: Real,
}

impl StrainLimits {
    /// Whether a spring with these limits can give at all.
    pub fn any(&self) -> bool {
        self.break_strain.is_some() || self.yield_strain.is_some()
    }

    /// Refuse a strain that is not positive and finite, a negative or
    /// non-finite hardening, and a yield strain at or above the break
    /// strain.
    ///
    /// ```
    /// use sprung::tearing::StrainLimits;
    /// use sprung::BuildError;
    ///
    /// let limits = StrainLimits { break_strain: Some(0.2), yield_strain: Some(0.3), hardening: 0.0 };
    /// assert!(matches!(limits.validate(), Err(BuildError::YieldAboveBreak { .. })));
    /// let limits = StrainLimits { break_strain: Some(f64::NAN), ..StrainLimits::default() };
    /// assert!(limits.validate().unwrap_err().to_string().starts_with("`break_strain` = NaN"));
    /// ```
    pub fn validate(&self) -> Result<(), BuildError> {
        let positive = |field, value: Option<Real>| match value {
            Some(value) if !(value.is_finite() && value > 0.0) => Err(BuildError::OutOfRange {
                field,
                value,
                reason: "a strain (L - L0) / L0 must be positive and finite",
            }),
            _ => Ok(()),
        };
        positive("break_strain", self.break_strain)?;
        positive("yield_strain", self.yield_strain)?;
        if !(self.hardening.is_finite() && self.hardening >= 0.0) {
            return Err(BuildError::OutOfRange {
                field: "hardening",
                value: self.hardening,
                reason: "must be non-negative and finite",
            });
        }
        if let (Some(break_strain), Some(yield_strain)) = (self.break_strain, self.yield_strain) {
            if yield_strain >= break_strain {
                return Err(BuildError::YieldAboveBreak {
                    yield_strain,
                    break_strain,
                });
            }
        }
        Ok(())
    }
}

/// What the springs of a world may do past their limits, and what they
/// have done: per spring its break strain, yield strain (grown by
/// hardening) and hardening; the count of springs broken and the work
/// taken out.
#[derive(Debug, Clone, Default)]
pub struct SpringLimits {
    /// Per spring, its break strain (∞: never). Springs past the end have
    /// none.
    break_strain: Vec<Real>,
    /// Per spring, its yield strain now (∞: never).
    yield_strain: Vec<Real>,
    /// Per spring, its hardening.
    hardening: Vec<Real>,
    /// Per spring, the squared lengths (m²) outside which it may give,
    /// `[(L0 (1 + min(B, Y)))², (L0 (1 - Y))²]`, rounded inward to `f32`:
    /// the search reads 8 bytes a spring besides its ends, and checks the
    /// few it finds exactly. `[∞, 0]` for none (or broken).
    trigger: Vec<[f32; 2]>,
    /// The ranges of springs with a limit, in order, not overlapping.
    watched: Vec<Range<usize>>,
    /// Springs broken so far (the `broken` column).
    broken: u64,
    /// Energy taken out by yielding and breaking so far (J).
    plastic_work: Real,
    /// Scratch: per chunk, the springs past a limit and how near the
    /// others are.
    found: Vec<Found>,
    /// When the next search is due.
    budget: MoveBudget,
    /// Full searches run so far (the rest were skipped on the budget).
    searches: u64,
}

/// What the search of one chunk of springs found.
#[derive(Debug, Clone, Default)]
struct Found {
    /// The springs past (or within a rounding of) a limit, in order.
    springs: Vec<u32>,
    /// The smallest slack of the chunk's springs (m): a bound below on
    /// how far each length is from its bounds; negative where one was
    /// found.
    slack: Real,
}

/// What one pass of [`SpringLimits::give`] did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Given {
    /// The springs that broke, in order.
    pub broken: Vec<usize>,
    /// How many springs yielded.
    pub yielded: usize,
}

impl SpringLimits {
    /// Give springs `range` of `springs` the limits `limits` (from a body
    /// or a join).
    pub fn set(&mut self, springs: &Springs, range: Range<usize>, limits: StrainLimits) {
        if !limits.any() || range.is_empty() {
            return;
        }
        if self.break_strain.len() < range.end {
            self.break_strain.resize(range.end, Real::INFINITY);
            self.yield_strain.resize(range.end, Real::INFINITY);
            self.hardening.resize(range.end, 0.0);
            self.trigger.resize(range.end, NEVER);
        }
        self.break_strain[range.clone()].fill(limits.break_strain.unwrap_or(Real::INFINITY));
        self.yield_strain[range.clone()].fill(limits.yield_strain.unwrap_or(Real::INFINITY));
        self.hardening[range.clone()].fill(limits.hardening);
        match self.watched.last_mut() {
            Some(last) if last.end == range.start => last.end = range.end,
            _ => self.watched.push(range.clone()),
        }
        // Bodies and joins add their springs in order, so the ranges stay
        // sorted as they come: sorting them again for each body was
        // quadratic in the bodies.
        let n = self.watched.len();
        if n > 1 && self.watched[n - 1].start < self.watched[n - 2].start {
            self.watched.sort_by_key(|r| r.start);
        }
        let ends = springs.first()[range.clone()]
            .iter()
            .chain(&springs.second()[range.clone()]);
        let (low, high) = ends.fold((usize::MAX, 0), |(low, high), &p| {
            (low.min(p as usize), high.max(p as usize + 1))
        });
        self.budget.watch(low..high);
        self.refresh(springs, range);
    }

    /// Compute again the search's bounds of springs `range` from their
    /// rest lengths now: after they changed other than by yielding (a
    /// muscle's drive, a restored state, a spring added). The world calls
    /// it for every new spring and for its muscles' springs every step; a
    /// program that sets the rest lengths of springs with limits by hand
    /// calls it for them.
    pub fn refresh(&mut self, springs: &Springs, range: Range<usize>) {
        let end = range.end.min(self.trigger.len()).min(springs.len());
        for s in range.start..end {
            self.trigger[s] = self.bounds(springs, s);
        }
        // The slack was measured from the old bounds: search next time.
        self.budget.clear();
    }

    /// Spring `s`'s squared lengths outside which it may give, rounded
    /// inward to `f32` by two steps (down above, up below).
    fn bounds(&self, springs: &Springs, s: usize) -> [f32; 2] {
        if springs.is_broken(s) {
            return NEVER;
        }
        let rest = springs.rest_length[s];
        let yield_strain = self.yield_strain[s];
        let longest = rest * (1.0 + self.break_strain[s].min(yield_strain));
        let shortest = rest * (1.0 - yield_strain).max(0.0);
        // Inward, and one more f32 step for the roundings of L² and of the
        // exact check: every spring past a limit is found (a few near it
        // too, checked exactly and left).
        [
            step_down(below(longest * longest)),
            step_up(above(shortest * shortest)),
        ]
    }

    /// Whether any spring has a limit (the `broken` and `plastic` columns
    /// are written then).
    pub fn enabled(&self) -> bool {
        !self.watched.is_empty()
    }

    /// Full searches of the watched springs run so far; the other passes
    /// of [`Self::give`] were skipped on the movement budget.
    pub fn searches(&self) -> u64 {
        self.searches
    }

    /// Springs broken so far.
    pub fn broken_count(&self) -> u64 {
        self.broken
    }

    /// Energy taken out by yielding and breaking so far (J).
    pub fn plastic_work(&self) -> Real {
        self.plastic_work
    }

    /// Whether spring `s` has a limit (may yield or break): its stiffness,
    /// damping and rest length may change as it runs.
    pub fn can_give(&self, s: usize) -> bool {
        self.break_strain(s).is_finite() || self.yield_strain(s).is_finite()
    }

    /// Spring `s`'s yield strain now (∞ for none).
    pub fn yield_strain(&self, s: usize) -> Real {
        self.yield_strain.get(s).copied().unwrap_or(Real::INFINITY)
    }

    /// Spring `s`'s break strain (∞ for none).
    pub fn break_strain(&self, s: usize) -> Real {
        self.break_strain.get(s).copied().unwrap_or(Real::INFINITY)
    }

    /// Yield and break the springs past their limits at `position`, in
    /// spring order (the search runs in parallel chunks, their findings
    /// taken in order: the same on any number of threads). Skipped while
    /// the particles have moved too little since the last search for any
    /// spring to have reached a limit (the module's movement budget).
    pub fn give(&mut self, springs: &mut Springs, position: &[Vec3]) -> Given {
        if self.budget.allows(position) {
            return Given::default();
        }
        self.searches += 1;
        let mut found = std::mem::take(&mut self.found);
        let mut given = Given::default();
        let measure = self.budget.plan();
        let mut slack = Real::INFINITY;
        for w in 0..self.watched.len() {
            let range = self.watched[w].start..self.watched[w].end.min(springs.len());
            let this = &*self;
            let springs_now = &*springs;
            let pieces =
                parallel::for_each_piece(range.len(), parallel::CHUNK, &mut found, |chunk, out| {
                    let chunk = range.start + chunk.start..range.start + chunk.end;
                    if measure {
                        this.past_limits::<true>(springs_now, position, chunk, out);
                    } else {
                        this.past_limits::<false>(springs_now, position, chunk, out);
                    }
                });
            for piece in &found[..pieces] {
                slack = slack.min(piece.slack);
            }
            for &s in found[..pieces].iter().flat_map(|piece| &piece.springs) {
                self.give_one(springs, position, s as usize, &mut given);
            }
        }
        self.found = found;
        // Where a spring was found, it is on (or near) a bound: its slack is
        // at most zero and the next pass searches again.
        if measure {
            self.budget.keep(position, slack);
        }
        given
    }

    /// Push the springs of `chunk` past a limit at `position` onto `out`:
    /// `L² > T = (L0 (1 + min(B, Y)))²` or `L² < S = (L0 (1 − Y))²`, without
    /// a square root of `L²`; and, with `SLACK`, the smallest slack of the
    /// others (else infinity).
    ///
    /// A spring's slack is at least `min(T − L², L² − S) / (2 √T)` (m; the
    /// lower side only where `S > 0`): `T − L² = (√T − L)(√T + L)` and
    /// `L² − S = (L − √S)(L + √S)`, where `√S ≤ L ≤ √T` for a spring not
    /// found. `√T` is taken in `f32` (a vector unit's eight lanes at once)
    /// and rounded up by far more than its error.
    fn past_limits<const SLACK: bool>(
        &self,
        springs: &Springs,
        position: &[Vec3],
        chunk: Range<usize>,
        out: &mut Found,
    ) {
        let first = &springs.first()[chunk.clone()];
        let second = &springs.second()[chunk.clone()];
        let trigger = &self.trigger[chunk.clone()];
        let ends = first.iter().zip(second).zip(trigger);
        out.springs.clear();
        let mut slack = Real::INFINITY;
        for (k, ((&a, &b), &[upper, lower])) in ends.enumerate() {
            let length_squared = (position[b as usize] - position[a as usize]).length_squared();
            let (upper_f32, upper, lower) = (upper, Real::from(upper), Real::from(lower));
            if length_squared > upper || length_squared < lower {
                out.springs.push((chunk.start + k) as u32);
            }
            if SLACK {
                let longest = Real::from(upper_f32.sqrt()) * (1.0 + 1e-6);
                let gap_below = if lower > 0.0 {
                    length_squared - lower
                } else {
                    Real::INFINITY
                };
                // A broken spring (T = ∞) gives ∞ / ∞, NaN, which `min` passes over.
                slack = slack.min((upper - length_squared).min(gap_below) / (2.0 * longest));
            }
        }
        out.slack = slack;
    }

    /// Break or yield spring `s`, found near a limit (checked exactly
    /// here), and bound it anew.
    fn give_one(&mut self, springs: &mut Springs, position: &[Vec3], s: usize, given: &mut Given) {
        self.give_exactly(springs, position, s, given);
        self.trigger[s] = self.bounds(springs, s);
    }

    /// Break or yield spring `s` if it is past a limit.
    fn give_exactly(
        &mut self,
        springs: &mut Springs,
        position: &[Vec3],
        s: usize,
        given: &mut Given,
    ) {
        if springs.is_broken(s) {
            return;
        }
        let [a, b] = springs.endpoints(s);
        let length = position[a as usize].distance(position[b as usize]);
        let rest = springs.rest_length[s];
        let stiffness = springs.stiffness[s];
        let strain = (length - rest) / rest;
        let energy = |rest: Real| 0.5 * stiffness * (length - rest) * (length - rest);
        if strain > self.break_strain[s] {
            self.plastic_work += energy(rest);
            springs.break_spring(s);
            self.broken += 1;
            given.broken.push(s);
            return;
        }
        let yield_strain = self.yield_strain[s];
        let moved = if strain > yield_strain {
            length / (1.0 + yield_strain)
        } else if strain < -yield_strain && yield_strain < 1.0 {
            length / (1.0 - yield_strain)
        } else {
            return;
        };
        self.plastic_work += energy(rest) - energy(moved);
        springs.rest_length[s] = moved;
        self.yield_strain[s] += self.hardening[s] * (moved - rest).abs() / rest;
        given.yielded += 1;
    }

    /// Add `energy` (J) to the work taken out (a burst body's gas).
    pub(crate) fn add_work(&mut self, energy: Real) {
        self.plastic_work += energy;
    }

    /// Set the count of broken springs and the work taken out (J), from a
    /// saved state.
    pub(crate) fn restore_totals(&mut self, broken: u64, plastic_work: Real) {
        self.broken = broken;
        self.plastic_work = plastic_work;
    }

    /// Every spring's yield strain now, for a saved state (empty without
    /// limits).
    pub(crate) fn yield_strains(&self) -> &[Real] {
        &self.yield_strain
    }

    /// Set every spring's yield strain from a saved state; false when the
    /// count disagrees.
    pub(crate) fn restore_yield_strains(&mut self, values: &[Real]) -> bool {
        if values.len() != self.yield_strain.len() {
            return false;
        }
        self.yield_strain.copy_from_slice(values);
        true
    }
}

/// The search's bounds of a spring that never gives.
const NEVER: [f32; 2] = [f32::INFINITY, 0.0];

/// The smallest `f32` at least `x` (≥ 0): a bound above.
fn above(x: Real) -> f32 {
    let rounded = x as f32;
    if f64::from(rounded) < x {
        f32::from_bits(rounded.to_bits() + 1)
    } else {
        rounded
    }
}

/// The next `f32` below `f` (≥ 0): `f32::MAX` below infinity, 0 stays.
fn step_down(f: f32) -> f32 {
    if f == f32::INFINITY {
        f32::MAX
    } else if f > 0.0 {
        f32::from_bits(f.to_bits() - 1)
    } else {
        f
    }
}

/// The next `f32` above `f` (≥ 0, finite; infinity stays).
fn step_up(f: f32) -> f32 {
    if f.is_finite() {
        f32::from_bits(f.to_bits() + 1)
    } else {
        f
    }
}

/// The largest `f32` at most `x` (≥ 0): a bound below.
fn below(x: Real) -> f32 {
    let rounded = x as f32;
    if f64::from(rounded) > x {
        f32::from_bits(rounded.to_bits() - 1)
    } else {
        rounded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bounds_round_inward_so_every_spring_past_a_limit_is_found() {
        for x in [1e-300, 0.1, 1.0 / 3.0, 2.5, 1e30, 1e39, 1e300] {
            assert!(f64::from(step_down(below(x))) < x, "{x}");
            assert!(f64::from(step_up(above(x))) > x, "{x}");
        }
        assert_eq!(below(1e300), f32::MAX);
        assert_eq!(step_down(f32::INFINITY), f32::MAX);
        assert_eq!((step_down(0.0), f64::from(below(0.5))), (0.0, 0.5));
        // A spring 1 m at rest breaking past 0.1: found at any length a
        // rounding past 1.1 m, where the exact check breaks it.
        let mut springs = Springs::default();
        springs.push(0, 1, 1.0, 1.0, 0.0, false);
        let mut limits = SpringLimits::default();
        let strain = StrainLimits {
            break_strain: Some(0.1),
            ..StrainLimits::default()
        };
        limits.set(&springs, 0..1, strain);
        let past = 1.1 * (1.0 + 4.0 * Real::EPSILON);
        let position = [Vec3::ZERO, Vec3::new(past, 0.0, 0.0)];
        let mut found = Found::default();
        limits.past_limits::<true>(&springs, &position, 0..1, &mut found);
        assert_eq!(found.springs, [0]);
        assert!(found.slack < 0.0);
        let given = limits.give(&mut springs, &position);
        assert_eq!(given.broken, [0]);
    }

    /// The ranges of springs with limits stay in order, one per run of
    /// neighbouring ranges, whether they come in order (bodies with and
    /// without limits in turn, then joins: not sorted again) or not.
    #[test]
    fn watched_ranges_stay_in_order_and_joined() {
        let mut springs = Springs::default();
        for s in 0..40 {
            springs.push(s, s + 1, 1.0, 1.0, 0.0, false);
        }
        let strain = StrainLimits {
            break_strain: Some(0.5),
            ..StrainLimits::default()
        };
        let mut limits = SpringLimits::default();
        for body in (0..10).step_by(2) {
            limits.set(&springs, 2 * body..2 * body + 2, strain);
        }
        limits.set(&springs, 20..21, strain);
        limits.set(&springs, 21..22, strain);
        let expected = [0..2, 4..6, 8..10, 12..14, 16..18, 20..22];
        assert_eq!(limits.watched, expected);
        // Out of order (a program setting limits by hand): sorted.
        limits.set(&springs, 30..31, strain);
        limits.set(&springs, 2..3, strain);
        let expected = [0..2, 2..3, 4..6, 8..10, 12..14, 16..18, 20..22, 30..31];
        assert_eq!(limits.watched, expected);
    }
}
