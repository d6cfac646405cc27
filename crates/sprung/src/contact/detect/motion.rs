//! How far the particles have moved, and how fast, since the last search:
//! the [`Spread`] of a set of vectors, whether the pairs of the last search
//! still cover a step, and the velocities remembered from one detect stage
//! to the next.

use super::Scratch;
use crate::body::Body;
use crate::contact::ContactSettings;
use crate::parallel;
use crate::units::{Real, Vec3};
use rayon::prelude::*;
use std::ops::Range;

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
    pub(super) fn velocities(
        &mut self,
        bodies: &[Body],
        velocity: &[Vec3],
        dt: Real,
    ) -> (Real, Option<Real>) {
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
    pub(super) fn still_covers(
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
    pub(in crate::contact) fn last_search(&self) -> (Option<Real>, &[Vec3]) {
        let searched = self.searched_settings.is_some() && !self.searched_at.is_empty();
        (
            searched.then_some(self.searched_margin),
            if searched { &self.searched_at } else { &[] },
        )
    }

    /// Remember a search from `position` (m) with `margin` (m).
    pub(in crate::contact) fn searched(
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
}

/// The particles of colliding bodies, as runs of consecutive bodies'
/// particles.
fn colliding_runs(bodies: &[Body]) -> impl Iterator<Item = Range<usize>> + '_ {
    crate::body::runs_of(bodies, |b| b.contact.collide)
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
