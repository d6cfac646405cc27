//! Candidate pairs kept nearest first, in buckets of clearance, so that a
//! measure reads only the buckets the step's allowance reaches: a cloth
//! lying in folds has hundreds of thousands of candidates, nearly all
//! farther than the allowance, and reading them alone would cost more than
//! its springs.

use std::ops::Range;

use rayon::prelude::*;

use crate::parallel;
use crate::units::Real;

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
    /// The buckets of an empty list sorted with buckets `width` (m) wide
    /// (none where the width is not positive), as [`Buckets::sort`] and
    /// [`Buckets::by_particle`] give them.
    pub(crate) fn empty(width: Real) -> Buckets {
        if width > 0.0 && !width.is_nan() {
            Buckets {
                width,
                start: [0; CLEARANCE_BUCKETS + 1],
            }
        } else {
            Buckets::default()
        }
    }

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
        let mut buckets = Buckets::empty(width);
        if buckets.width == 0.0 {
            return buckets;
        }
        let sizing = Buckets::empty(width);
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

/// A particle's pairs in [`Buckets::by_particle`]: how many, the bucket of
/// the nearest, and then where the next one goes in its bucket's share.
#[derive(Debug, Clone, Copy)]
struct Tally {
    count: u32,
    bucket: u8,
    nearest: Real,
}

const NO_PAIRS: Tally = Tally {
    count: 0,
    bucket: 0,
    nearest: Real::INFINITY,
};

/// Buffers of [`Buckets::by_particle`], kept from search to search.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct ByParticle {
    /// Per particle, its [`Tally`].
    tally: Vec<Tally>,
    /// Per share of the particles, its pairs in each bucket, then where
    /// they start.
    shares: Vec<[usize; CLEARANCE_BUCKETS]>,
}

impl PartialEq for Tally {
    fn eq(&self, other: &Self) -> bool {
        (self.count, self.bucket) == (other.count, other.bucket)
            && self.nearest.to_bits() == other.nearest.to_bits()
    }
}

/// One slice of the output per bucket.
type PerBucket<'a, P> = [&'a mut [P]; CLEARANCE_BUCKETS];

impl Buckets {
    /// Put the pairs of `chunks` (in their order) into `out` in buckets of
    /// clearance `width` (m) wide, nearest first, each particle's pairs
    /// (`particle_of`, below `particles`) together as a run in the bucket
    /// of its nearest one (`clearance_of`), in the order they were found,
    /// the particles ascending within a bucket; return where the buckets
    /// start. The same as grouping the pairs by particle and then
    /// [`Buckets::sort`] with runs of a particle, in one counting sort by
    /// bucket and particle. Many pairs are sorted in parallel over shares
    /// of the particles, each thread reading every pair and taking those of
    /// its own particles: the same order whatever the number of threads.
    /// Where `width` is not positive, in no buckets (grouped by particle).
    /// A pair whose particle is not below `particles` is left out.
    pub(crate) fn by_particle<P: Copy + Send + Sync>(
        chunks: &[Vec<P>],
        particle_of: fn(&P) -> u32,
        clearance_of: fn(&P) -> Real,
        width: Real,
        particles: usize,
        buffers: &mut ByParticle,
        out: &mut Vec<P>,
    ) -> Buckets {
        out.clear();
        let mut buckets = Buckets::empty(width);
        let Some(&filler) = chunks.iter().find_map(|c| c.first()) else {
            return buckets;
        };
        let in_buckets = buckets.width > 0.0;
        let total: usize = chunks.iter().map(Vec::len).sum();
        let sizing = Buckets::empty(width);
        let bucket_of = |nearest: Real| if in_buckets { sizing.of(nearest) } else { 0 };
        let threads = if total <= parallel::CHUNK || particles <= parallel::CHUNK {
            1
        } else {
            parallel::threads()
        };
        let share = particles.div_ceil(threads).max(1);
        let shares = particles.div_ceil(share).max(1);
        let ByParticle {
            tally,
            shares: counts,
        } = buffers;
        tally.clear();
        tally.resize(particles, NO_PAIRS);
        counts.clear();
        counts.resize(shares, [0; CLEARANCE_BUCKETS]);
        // Count each particle's pairs and find its bucket, then each
        // share's pairs per bucket.
        let count =
            |(s, (tally, counts)): (usize, (&mut [Tally], &mut [usize; CLEARANCE_BUCKETS]))| {
                let first = s * share;
                for pair in chunks.iter().flatten() {
                    let own = (particle_of(pair) as usize).wrapping_sub(first);
                    if let Some(t) = tally.get_mut(own) {
                        t.count += 1;
                        t.nearest = t.nearest.min(clearance_of(pair));
                    }
                }
                for t in tally.iter_mut().filter(|t| t.count > 0) {
                    t.bucket = bucket_of(t.nearest) as u8;
                    counts[t.bucket as usize] += t.count as usize;
                }
            };
        if shares == 1 {
            count((0, (&mut tally[..], &mut counts[0])));
        } else {
            tally
                .par_chunks_mut(share)
                .zip(counts.par_iter_mut())
                .enumerate()
                .for_each(count);
        }
        for b in 0..CLEARANCE_BUCKETS {
            buckets.start[b + 1] = buckets.start[b] + counts.iter().map(|c| c[b]).sum::<usize>();
        }
        // Pairs of particles beyond `particles` (none from the search)
        // were counted nowhere, and are left out.
        out.resize(buckets.start[CLEARANCE_BUCKETS], filler);
        // The output cut into its buckets, each share then takes its own
        // part of each.
        let mut rest = &mut out[..];
        let mut per_bucket: PerBucket<'_, P> = Default::default();
        for (b, slice) in per_bucket.iter_mut().enumerate() {
            let (this, after) = rest.split_at_mut(buckets.start[b + 1] - buckets.start[b]);
            *slice = this;
            rest = after;
        }
        let place = |s: usize, tally: &mut [Tally], mut slices: PerBucket<'_, P>| {
            let first = s * share;
            let mut next = [0u32; CLEARANCE_BUCKETS];
            for t in tally.iter_mut().filter(|t| t.count > 0) {
                let b = t.bucket as usize;
                (next[b], t.count) = (next[b] + t.count, next[b]);
            }
            for pair in chunks.iter().flatten() {
                let own = (particle_of(pair) as usize).wrapping_sub(first);
                if let Some(t) = tally.get_mut(own) {
                    slices[t.bucket as usize][t.count as usize] = *pair;
                    t.count += 1;
                }
            }
            // Every slot written: the slices are used up.
            slices.iter_mut().for_each(|slice| *slice = &mut []);
        };
        split_shares(per_bucket, 0..shares, share, tally, counts, &place);
        if in_buckets {
            buckets
        } else {
            Buckets::default()
        }
    }
}

/// Call `place(s, tally, slices)` for each share `s` of `shares` with its
/// particles' tallies (`share` particles a share) and its part of each
/// bucket's slice (its pairs per bucket are `counts[s]`), halving the
/// shares between two threads at a time.
fn split_shares<P: Send>(
    slices: PerBucket<'_, P>,
    shares: Range<usize>,
    share: usize,
    tally: &mut [Tally],
    counts: &[[usize; CLEARANCE_BUCKETS]],
    place: &(impl Fn(usize, &mut [Tally], PerBucket<'_, P>) + Sync),
) {
    if shares.len() == 1 {
        place(shares.start, tally, slices);
        return;
    }
    let mid = shares.start + shares.len() / 2;
    let mut left: PerBucket<'_, P> = Default::default();
    let mut right: PerBucket<'_, P> = Default::default();
    for (b, slice) in slices.into_iter().enumerate() {
        let before: usize = counts[shares.start..mid].iter().map(|c| c[b]).sum();
        (left[b], right[b]) = slice.split_at_mut(before);
    }
    let (low, high) = tally.split_at_mut(((mid - shares.start) * share).min(tally.len()));
    rayon::join(
        || split_shares(left, shares.start..mid, share, low, counts, place),
        || split_shares(right, mid..shares.end, share, high, counts, place),
    );
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The order [`Buckets::by_particle`] must give, the plain way: the
    /// pairs grouped by particle (a stable sort), then each particle's run
    /// put in the bucket of its nearest pair by [`Buckets::sort`].
    fn grouped_then_sorted(
        chunks: &[Vec<(u32, Real, usize)>],
        width: Real,
    ) -> (Vec<(u32, Real, usize)>, Buckets) {
        let mut pairs: Vec<_> = chunks.iter().flatten().copied().collect();
        pairs.sort_by_key(|p| p.0);
        let buckets = Buckets::sort(
            &mut pairs,
            width,
            |p| p.1,
            |a, b| a.0 == b.0,
            &mut Vec::new(),
        );
        (pairs, buckets)
    }

    #[test]
    fn one_counting_sort_gives_the_order_of_grouping_then_bucketing_on_any_threads() {
        // Claim: pairs (particle, clearance, the order found) in chunks of
        // uneven sizes, particles in random order with several pairs each,
        // come out of `by_particle` exactly as grouping them by particle and
        // then bucketing the particles' runs puts them, with the same
        // bucket starts, on 1, 2 and 3 threads (enough pairs and particles
        // to be shared among threads), for bucket widths that do and do not
        // make buckets (0 and NaN: grouped by particle only), and for no
        // pairs at all.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let particles = 3 * parallel::CHUNK + 17;
        let mut found = 0;
        let chunks: Vec<Vec<(u32, Real, usize)>> = (0..40)
            .map(|c| {
                (0..(c * 37) % 700)
                    .map(|_| {
                        found += 1;
                        let particle = (next() % particles as u64) as u32;
                        let clearance = (next() % 1000) as Real * 1e-5;
                        (particle, clearance, found)
                    })
                    .collect()
            })
            .collect();
        assert!(found > parallel::CHUNK);
        for width in [1e-3, 2.5e-4, 0.0, Real::NAN] {
            let (expected, expected_buckets) = grouped_then_sorted(&chunks, width);
            for threads in [1, 2, 3] {
                let mut out = Vec::new();
                let buckets = parallel::Pool::new(threads).expect("a pool").install(|| {
                    Buckets::by_particle(
                        &chunks,
                        |p| p.0,
                        |p| p.1,
                        width,
                        particles,
                        &mut ByParticle::default(),
                        &mut out,
                    )
                });
                assert!(out == expected, "width {width}, {threads} threads");
                assert_eq!(
                    buckets, expected_buckets,
                    "width {width}, {threads} threads"
                );
            }
        }
        // A pair of a particle beyond `particles` is left out (not a copy
        // of another pair in its place).
        let mut out = Vec::new();
        let beyond = vec![vec![(5, 0.0, 1), (100, 0.0, 2), (5, 1e-4, 3)]];
        let buckets = Buckets::by_particle(
            &beyond,
            |p| p.0,
            |p| p.1,
            1e-3,
            10,
            &mut ByParticle::default(),
            &mut out,
        );
        assert_eq!(out, vec![(5, 0.0, 1), (5, 1e-4, 3)]);
        assert_eq!(buckets.start[CLEARANCE_BUCKETS], 2);
        let mut out = vec![(0, 0.0, 0)];
        let none = Buckets::by_particle(
            &[Vec::new()],
            |p: &(u32, Real, usize)| p.0,
            |p| p.1,
            1e-3,
            10,
            &mut ByParticle::default(),
            &mut out,
        );
        assert!(out.is_empty());
        assert_eq!(none, grouped_then_sorted(&[], 1e-3).1);
    }
}
