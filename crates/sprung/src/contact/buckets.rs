//! Candidate pairs kept nearest first, in buckets of clearance, so that a
//! measure reads only the buckets the step's allowance reaches: a cloth
//! lying in folds has hundreds of thousands of candidates, nearly all
//! farther than the allowance, and reading them alone would cost more than
//! its springs.

use std::ops::Range;

use crate::Real;

/// How many buckets of clearance each list of pairs is kept in.
pub(crate) const CLEARANCE_BUCKETS: usize = 8;

/// Where the pairs of each bucket of clearance start in their list.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Buckets {
    /// Width (m) of a bucket; zero when the list is not in buckets.
    width: Real,
    /// The pairs of bucket `b` are `start[b]..start[b + 1]`.
    start: [usize; CLEARANCE_BUCKETS + 1],
}

impl Buckets {
    /// The bucket of a clearance (m).
    pub(crate) fn of(&self, clearance: Real) -> usize {
        ((clearance / self.width) as usize).min(CLEARANCE_BUCKETS - 1)
    }

    /// How many of the `len` pairs of the list a measure with `allowance`
    /// (m) must read: the buckets up to that of the allowance (all of
    /// them when the list is not in buckets, or has changed since). A
    /// pair whose clearance is within the allowance is in a bucket no
    /// later than the allowance's, as both are rounded down alike.
    pub(crate) fn reached(&self, allowance: Real, len: usize) -> usize {
        if self.width <= 0.0 || self.width.is_nan() || self.start[CLEARANCE_BUCKETS] != len {
            return len;
        }
        match (allowance / self.width) as usize {
            b if b < CLEARANCE_BUCKETS => self.start[b + 1],
            _ => len,
        }
    }

    /// Sort `pairs` into buckets of clearance `width` (m) wide, nearest
    /// first, keeping their order within a bucket, and return where the
    /// buckets start. Neighbours for which `same_run` holds form a run
    /// that stays whole, in the bucket of its nearest pair (a particle's
    /// pairs, among which its closest element is picked). `spare` is a
    /// buffer.
    pub(crate) fn sort<P: Copy>(
        pairs: &mut Vec<P>,
        width: Real,
        clearance: impl Fn(&P) -> Real,
        same_run: impl Fn(&P, &P) -> bool,
        spare: &mut Vec<P>,
    ) -> Buckets {
        if width <= 0.0 || width.is_nan() {
            return Buckets::default();
        }
        let mut buckets = Buckets {
            width,
            start: [0; CLEARANCE_BUCKETS + 1],
        };
        let sizing = Buckets {
            width,
            start: [0; CLEARANCE_BUCKETS + 1],
        };
        let bucket_of_run = |run: &Range<usize>| {
            let nearest = pairs[run.clone()]
                .iter()
                .map(&clearance)
                .fold(Real::INFINITY, Real::min);
            sizing.of(nearest)
        };
        for run in runs(pairs, &same_run) {
            buckets.start[bucket_of_run(&run) + 1] += run.len();
        }
        for b in 0..CLEARANCE_BUCKETS {
            buckets.start[b + 1] += buckets.start[b];
        }
        let mut next = buckets.start;
        spare.clear();
        spare.extend_from_slice(pairs);
        for run in runs(pairs, &same_run) {
            let b = bucket_of_run(&run);
            spare[next[b]..next[b] + run.len()].copy_from_slice(&pairs[run.clone()]);
            next[b] += run.len();
        }
        std::mem::swap(pairs, spare);
        buckets
    }
}

/// The runs of `pairs`: neighbours for which `same_run` holds.
fn runs<'a, P>(
    pairs: &'a [P],
    same_run: &'a impl Fn(&P, &P) -> bool,
) -> impl Iterator<Item = Range<usize>> + 'a {
    let mut start = 0;
    std::iter::from_fn(move || {
        if start == pairs.len() {
            return None;
        }
        let mut end = start + 1;
        while end < pairs.len() && same_run(&pairs[end - 1], &pairs[end]) {
            end += 1;
        }
        let run = start..end;
        start = end;
        Some(run)
    })
}
