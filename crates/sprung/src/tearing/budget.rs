//! The give stage's movement budget: skip the search of the watched
//! springs while the particles have moved too little since the last one
//! for any spring to have reached a limit.
//!
//! A search finds the smallest slack (m), how far the nearest spring's
//! length is from its bounds, and keeps the particles' positions, packed
//! to 16 bits a coordinate on a grid over their bounding box. A spring's
//! length moves by at most the moves of its two ends, so while twice the
//! largest move since then stays below the slack, no spring can have
//! reached a limit. Each pass reads the positions and the packed copy:
//! 30 bytes a particle, against 48 for the 256² cloth's springs' ends,
//! bounds and two positions each, and in a flat pass the compiler
//! vectorises. Whatever moved the particles (an integrator, a collider, a
//! program setting positions by hand), the move is measured, not
//! reported.
//!
//! Where springs sit at their limits (a can yielding under a press, a cloth
//! tearing), every pass searches, and measuring the slack and packing the
//! positions would be wasted work: a search whose slack let no pass skip
//! makes the next one, two, four, ... (at most [`MAX_PAUSE`]) searches
//! leave them out. That choice changes what a step costs, never what it
//! gives.

use std::ops::Range;

use crate::parallel;
use crate::units::{Real, Vec3};

/// Coordinates a pass compares at a time: eight particles, so the lanes
/// of x, y and z repeat.
const LANES: usize = 24;

/// The most searches in a row that leave the slack unmeasured after
/// searches whose slack let no pass skip.
const MAX_PAUSE: u32 = 64;

/// The largest code of a packed coordinate.
const CODES: Real = u16::MAX as Real;

/// The positions of the last search, packed, and the slack found there.
#[derive(Debug, Clone, Default)]
pub(super) struct MoveBudget {
    /// The particles the watched springs join (their span).
    pub(super) particles: Range<usize>,
    /// Per particle of the span, its position at the last search as codes
    /// on the grid; empty: the next pass searches.
    codes: Vec<[u16; 3]>,
    /// Per lane (x, y, z repeated), the grid's origin (m).
    origin: [Real; LANES],
    /// Per lane, the grid's cell (m).
    cell: [Real; LANES],
    /// The largest distance (m) of a coordinate from its code's value.
    error: Real,
    /// The smallest slack at the last search (m).
    slack: Real,
    /// Whether the last search measured the slack.
    measured: bool,
    /// Passes skipped since the last search.
    skipped: u64,
    /// Searches to leave the slack unmeasured after the next fruitless one.
    pause: u32,
    /// Searches still to leave it unmeasured.
    waiting: u32,
}

impl MoveBudget {
    /// Forget the last search: the next pass searches.
    pub(super) fn clear(&mut self) {
        self.codes.clear();
    }

    /// Widen the span of particles to hold `particles`.
    pub(super) fn watch(&mut self, particles: Range<usize>) {
        self.particles = if self.particles.is_empty() {
            particles
        } else {
            self.particles.start.min(particles.start)..self.particles.end.max(particles.end)
        };
        self.clear();
    }

    /// A search begins: whether it should measure the slack and keep the
    /// positions (not for a while after measurements no pass could use).
    pub(super) fn plan(&mut self) -> bool {
        if self.measured {
            self.pause = if self.skipped == 0 {
                (self.pause * 2).clamp(1, MAX_PAUSE)
            } else {
                0
            };
            self.waiting = self.pause;
        }
        self.clear();
        self.skipped = 0;
        self.measured = self.waiting == 0;
        self.waiting = self.waiting.saturating_sub(1);
        self.measured
    }

    /// Keep `position` (the whole world's, m) as the last search's, where
    /// the smallest slack was `slack` (m).
    pub(super) fn keep(&mut self, position: &[Vec3], slack: Real) {
        self.clear();
        let span = &position[self.span(position)];
        if slack.is_nan() || slack <= 0.0 || span.is_empty() {
            return;
        }
        let (low, high) = span.iter().fold(
            (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY)),
            |(low, high), x| (low.min(*x), high.max(*x)),
        );
        let cell = (high - low) / CODES;
        if !(low.is_finite() && cell.is_finite()) {
            return;
        }
        for k in 0..LANES {
            self.origin[k] = low[k % 3];
            self.cell[k] = cell[k % 3];
        }
        let mut error: Real = 0.0;
        for x in span {
            let code = std::array::from_fn(|a| {
                let code = if cell[a] > 0.0 {
                    ((x[a] - low[a]) / cell[a]).round().clamp(0.0, CODES) as u16
                } else {
                    0
                };
                error = error.max((x[a] - (low[a] + Real::from(code) * cell[a])).abs());
                code
            });
            self.codes.push(code);
        }
        self.error = error;
        self.slack = slack;
    }

    /// Whether no spring can have reached a limit at `position`: twice the
    /// largest move of a particle since the last search is below the slack.
    /// A particle moved at most √3 times the largest change of a
    /// coordinate, itself at most its distance from the code's value plus
    /// the packing's error. The computed move errs by a few units of f64
    /// round-off relative to itself, and the slack is measured to the `f32`
    /// bounds, which lie inside the exact limits by more than 10⁷ times
    /// that: no spring past a limit is skipped.
    pub(super) fn allows(&mut self, position: &[Vec3]) -> bool {
        let span = self.span(position);
        if self.codes.len() != span.len() || self.codes.is_empty() {
            return false;
        }
        let now = &position[span];
        let coordinate = parallel::max(now.len(), |chunk| {
            largest_coordinate_move(
                &now[chunk.clone()],
                &self.codes[chunk],
                &self.origin,
                &self.cell,
            )
        });
        // 1e-9: far above the move's round-off, far below the f32 bounds'
        // margin.
        let moved = 3.0_f64.sqrt() * (coordinate + self.error);
        let allowed = 2.0 * moved * (1.0 + 1e-9) < self.slack;
        self.skipped += u64::from(allowed);
        allowed
    }

    /// The span of particles within `position`.
    fn span(&self, position: &[Vec3]) -> Range<usize> {
        self.particles.start.min(position.len())..self.particles.end.min(position.len())
    }
}

vectorised! {
    /// The largest distance (m) of a coordinate of `now` from the value of
    /// its code in `codes` (`origin + code cell`, per lane): one flat pass
    /// over the reals in [`LANES`] lanes, which the compiler vectorises.
    fn largest_coordinate_move(
        now: &[Vec3],
        codes: &[[u16; 3]],
        origin: &[Real; LANES],
        cell: &[Real; LANES],
    ) -> Real {
        let now: &[Real] = bytemuck::cast_slice(now);
        let codes: &[u16] = bytemuck::cast_slice(codes);
        let mut lanes: [Real; LANES] = [0.0; LANES];
        for (x, code) in now.chunks_exact(LANES).zip(codes.chunks_exact(LANES)) {
            for k in 0..LANES {
                let was = origin[k] + Real::from(code[k]) * cell[k];
                lanes[k] = lanes[k].max((x[k] - was).abs());
            }
        }
        let rest = now.len() / LANES * LANES;
        for (k, (x, code)) in now[rest..].iter().zip(&codes[rest..]).enumerate() {
            let was = origin[k] + Real::from(*code) * cell[k];
            lanes[0] = lanes[0].max((x - was).abs());
        }
        lanes.into_iter().fold(0.0, Real::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_of_half_the_slack_is_never_allowed() {
        // 1,000 particles spread over about 10 m, kept with a slack of
        // 0.1 m: standing still they are allowed; a particle moved by
        // exactly half the slack (in any direction, by any amount of
        // packing error) could have stretched a spring by the whole slack,
        // so it never is; a move of a tenth of it is (√3 (0.01 + ~1e-4) m,
        // twice that, stays below 0.1 m).
        let position: Vec<Vec3> = (0..1000)
            .map(|i| {
                let i = Real::from(i);
                Vec3::new((i * 0.37).sin() * 5.0, i * 0.01, (i * 0.11).cos() * 3.0)
            })
            .collect();
        let mut budget = MoveBudget::default();
        budget.watch(0..1000);
        budget.keep(&position, 0.1);
        assert!(budget.error <= 10.0 / CODES, "{}", budget.error);
        assert!(budget.allows(&position));
        for (p, direction) in [
            (0, Vec3::X),
            (517, Vec3::ONE),
            (999, Vec3::new(-1.0, 2.0, 0.5)),
        ] {
            let mut moved = position.clone();
            moved[p] += direction.normalize() * 0.05;
            assert!(!budget.allows(&moved), "{p}");
            moved[p] = position[p] + direction.normalize() * 0.01;
            assert!(budget.allows(&moved), "{p}");
        }
        // A particle added since: the span no longer matches, search.
        let mut more = position.clone();
        more.push(Vec3::ZERO);
        budget.watch(0..1001);
        assert!(!budget.allows(&more));
    }
}
