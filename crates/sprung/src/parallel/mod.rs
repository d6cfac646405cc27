//! Threads, with results that do not depend on how many there are.
//!
//! The engine runs its long loops on rayon's thread pool: the current one
//! (`ThreadPool::install`), else the global one, sized by [`configure`]
//! (`sprung --threads N`), else by `SPRUNG_THREADS` when set, else by
//! rayon's own default (every core). Whatever the number of threads, a run writes the same bits:
//!
//! - a loop over particles writes each particle's entries only, so the
//!   threads never meet;
//! - a sum (an energy, a volume, a dot product of the solvers) is taken
//!   over fixed pieces of at most [`CHUNK`] elements, each summed in order,
//!   then the pieces' sums pairwise in a tree fixed by the length ([`sum`]),
//!   so its rounding is that of the length, not of the threads;
//! - forces of elements that share particles (springs, faces) are added
//!   block by block (`Schedule`): blocks of neighbouring particles that
//!   share none run at once, so each particle receives its contributions
//!   in the same order whatever thread computes them.
//!
//! Loops shorter than [`CHUNK`] run on the calling thread: a small scene
//! pays nothing for the threads.

mod schedule;

use std::cell::Cell;
use std::ops::Range;

use rayon::prelude::*;

use crate::units::Real;

pub use schedule::particle_span;
pub(crate) use schedule::{scatter_in_order, Block, Elements, Schedule, ScheduleCache, Writer};

/// The number of elements a thread takes at a time, and the chunk of the
/// fixed-order sums.
pub const CHUNK: usize = 4096;

thread_local! {
    /// The most entries of a piece of [`for_each_span`] on this thread
    /// ([`with_span`]).
    static SPAN: Cell<usize> = const { Cell::new(CHUNK) };
}

/// Run `job` with the per-particle loops it starts on this thread
/// ([`for_each_span`]) cut into pieces of at most `span` entries (at
/// least 8, at most [`CHUNK`]) instead of [`CHUNK`]: a world whose springs
/// are cut finer than a chunk ([`particle_span`]) updates each particle on
/// the thread that added its forces. The pieces change no result, only
/// which thread computes it.
pub fn with_span<R>(span: usize, job: impl FnOnce() -> R) -> R {
    /// Puts the span back however `job` ends.
    struct Restore(usize);
    impl Drop for Restore {
        fn drop(&mut self) {
            SPAN.with(|s| s.set(self.0));
        }
    }
    let _restore = Restore(SPAN.with(|s| s.replace(span.clamp(8, CHUNK))));
    job()
}

/// The most threads the engine runs on: far beyond any machine it is
/// made for; each thread costs a stack, and tens of thousands of them took
/// minutes to start.
pub const MAX_THREADS: usize = 1024;

/// The threads a failed start of the global pool asked for (0: none
/// failed). Rayon then has no global pool, and asking its size would panic.
static GLOBAL_START_REFUSED: std::sync::atomic::AtomicUsize =
    std::sync::atomic::AtomicUsize::new(0);

/// Why the engine's threads could not be set.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ThreadsError {
    /// `SPRUNG_THREADS` is not a positive whole number.
    #[error("SPRUNG_THREADS={0:?}: expected a positive whole number of threads")]
    BadVariable(String),
    /// A count of zero.
    #[error("--threads 0: the engine needs at least one thread")]
    Zero,
    /// More threads than [`MAX_THREADS`].
    #[error("{0} threads: at most {max} (more only start threads that wait)", max = MAX_THREADS)]
    TooMany(usize),
    /// The pool could not be built (it was built already, with another size,
    /// or the system refused the threads).
    #[error("cannot run on {threads} threads: {reason}")]
    Start {
        /// The threads asked for.
        threads: usize,
        /// The reason rayon gave.
        reason: String,
    },
}

/// Size rayon's global pool, which the engine runs on: `threads` if given,
/// else `SPRUNG_THREADS` if set, else rayon's default (`RAYON_NUM_THREADS`,
/// else every core). Call it before the first step; returns the threads the
/// pool has.
pub fn configure(threads: Option<usize>) -> Result<usize, ThreadsError> {
    let threads = match threads {
        Some(0) => return Err(ThreadsError::Zero),
        Some(n) => Some(n),
        None => match std::env::var("SPRUNG_THREADS") {
            Ok(text) => match text.trim().parse::<usize>() {
                Ok(n) if n > 0 => Some(n),
                _ => return Err(ThreadsError::BadVariable(text)),
            },
            Err(_) => None,
        },
    };
    use std::sync::atomic::Ordering::Relaxed;
    if let Some(threads) = threads {
        if threads > MAX_THREADS {
            return Err(ThreadsError::TooMany(threads));
        }
        let built = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build_global();
        if let Err(error) = built {
            // Built already (by an earlier call): fine if of this size.
            // The system refused the threads: rayon has no global pool.
            let refused = GLOBAL_START_REFUSED.load(Relaxed) != 0
                || !error.to_string().contains("already been initialized");
            if refused {
                let _ = GLOBAL_START_REFUSED.compare_exchange(0, threads, Relaxed, Relaxed);
            }
            if refused || rayon::current_num_threads() != threads {
                return Err(ThreadsError::Start {
                    threads,
                    reason: error.to_string(),
                });
            }
        }
    }
    match GLOBAL_START_REFUSED.load(Relaxed) {
        0 => {}
        refused => {
            return Err(ThreadsError::Start {
                threads: refused,
                reason: "the system refused the threads".into(),
            })
        }
    }
    Ok(rayon::current_num_threads())
}

/// [`configure`] from `SPRUNG_THREADS`, once per process, for a library
/// user who did not call it ([`World::new`](crate::World::new) does); a
/// malformed variable leaves rayon's default.
pub fn configure_from_env() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = configure(None);
    });
}

/// A pool of threads of its own, to run the engine's loops on a chosen
/// number of threads in one process (the bench compares 1 and all). Kept
/// for as long as it is used: a pool's threads exit when it is dropped,
/// and building one per call would count their start and exit in every
/// measurement.
#[derive(Debug)]
pub struct Pool(rayon::ThreadPool);

impl Pool {
    /// Start a pool of `threads` threads.
    pub fn new(threads: usize) -> Result<Self, ThreadsError> {
        if threads == 0 {
            return Err(ThreadsError::Zero);
        }
        if threads > MAX_THREADS {
            return Err(ThreadsError::TooMany(threads));
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .map(Pool)
            .map_err(|e| ThreadsError::Start {
                threads,
                reason: e.to_string(),
            })
    }

    /// The pool's number of threads.
    pub fn threads(&self) -> usize {
        self.0.current_num_threads()
    }

    /// Run `f` with the engine's loops inside it on this pool.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        self.0.install(f)
    }
}

/// Run `f` on a pool of its own of `threads` threads, started for the
/// call and stopped after it (see [`Pool`] to keep one).
pub fn with_threads<R: Send>(
    threads: usize,
    f: impl FnOnce() -> R + Send,
) -> Result<R, ThreadsError> {
    Ok(Pool::new(threads)?.install(f))
}

/// Run `job` on a thread of the current pool (the caller waits for it), so
/// that the engine's parallel loops inside it start from the pool itself
/// instead of each being handed over from an outside thread, which waits
/// for it (a few microseconds a loop). A job already on the pool runs at
/// once.
pub fn in_pool<R: Send>(job: impl FnOnce() -> R + Send) -> R {
    rayon::join(job, || ()).0
}

/// The threads the engine's loops run on here (the current pool's).
pub fn threads() -> usize {
    rayon::current_num_threads()
}

/// `Σ f(piece)` over pieces of `0..len` of at most [`CHUNK`] indices, cut
/// at multiples of it and added pairwise in a tree that depends on `len`
/// only: the same bits whatever the number of threads, and nothing
/// allocated.
#[doc(hidden)]
pub fn sum(len: usize, f: impl Fn(Range<usize>) -> Real + Sync) -> Real {
    fn run(range: Range<usize>, f: &(impl Fn(Range<usize>) -> Real + Sync)) -> Real {
        let len = range.len();
        if len <= CHUNK {
            f(range)
        } else {
            let mid = range.start + len.div_ceil(CHUNK).div_ceil(2) * CHUNK;
            let (left, right) = rayon::join(|| run(range.start..mid, f), || run(mid..range.end, f));
            left + right
        }
    }
    run(0..len, &f)
}

/// `max f(chunk)` over the chunks of `0..len`, in parallel (0 for none; a
/// maximum does not depend on the order it is taken in).
pub(crate) fn max(len: usize, f: impl Fn(Range<usize>) -> Real + Sync) -> Real {
    if len <= CHUNK {
        return f(0..len).max(0.0);
    }
    (0..len.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| f(c * CHUNK..((c + 1) * CHUNK).min(len)))
        .reduce(|| 0.0, Real::max)
}

/// `f(chunk)` over the chunks of `0..len`, in parallel, combined by
/// `merge` from `empty` (which must not depend on the order it is taken
/// in: a maximum, a bounding box), so the same whatever the threads.
pub(crate) fn merge_chunks<T: Send + Sync + Clone>(
    len: usize,
    empty: T,
    f: impl Fn(Range<usize>) -> T + Sync,
    merge: impl Fn(T, T) -> T + Sync + Send,
) -> T {
    if len <= CHUNK {
        return merge(empty, f(0..len));
    }
    (0..len.div_ceil(CHUNK))
        .into_par_iter()
        .map(|c| f(c * CHUNK..((c + 1) * CHUNK).min(len)))
        .reduce(|| empty.clone(), merge)
}

/// The lowest `i < len` for which `f(i)` is something, with it: the same
/// one whatever the number of threads.
pub(crate) fn find_first<T: Send>(
    len: usize,
    f: impl Fn(usize) -> Option<T> + Sync,
) -> Option<(usize, T)> {
    let in_chunk = |range: Range<usize>| range.into_iter().find_map(|i| f(i).map(|t| (i, t)));
    if len <= CHUNK {
        return in_chunk(0..len);
    }
    (0..len.div_ceil(CHUNK))
        .into_par_iter()
        .find_map_first(|c| in_chunk(c * CHUNK..((c + 1) * CHUNK).min(len)))
}

/// The size of the pieces [`collect_chunks`] should cut `0..len` into:
/// `chunk`, or all of it (one piece, on the calling thread) up to [`CHUNK`]
/// indices, where sharing the work costs more than it saves.
pub(crate) fn piece_size(len: usize, chunk: usize) -> usize {
    if len <= CHUNK {
        len.max(1)
    } else {
        chunk
    }
}

/// Call `f(piece, buffer)` on the pieces of `0..len` of at most `chunk`
/// indices, in parallel, each piece writing into a buffer of its own
/// (emptied first): `buffers[c]` holds what piece `c` wrote, so reading the
/// buffers in order gives the same sequence whatever the number of
/// threads. The buffers are kept for the next call, so once they have
/// grown nothing is allocated. Buffers past the last piece are left empty.
/// One piece runs on the calling thread (see [`piece_size`]).
pub(crate) fn collect_chunks<T: Send>(
    len: usize,
    chunk: usize,
    buffers: &mut Vec<Vec<T>>,
    f: impl Fn(Range<usize>, &mut Vec<T>) + Sync,
) {
    buffers.iter_mut().for_each(Vec::clear);
    for_each_piece(len, chunk, buffers, f);
}

/// Call `f(piece, buffer)` on the pieces of `0..len` of at most `chunk`
/// indices, in parallel, each with a buffer of its own that `f` fills
/// (`buffers[c]` for piece `c`, grown to the count of pieces and kept for
/// the next call); returns the count of pieces. One piece runs on the
/// calling thread.
pub(crate) fn for_each_piece<B: Send + Default>(
    len: usize,
    chunk: usize,
    buffers: &mut Vec<B>,
    f: impl Fn(Range<usize>, &mut B) + Sync,
) -> usize {
    let chunk = chunk.max(1);
    let pieces = len.div_ceil(chunk);
    if buffers.len() < pieces {
        buffers.resize_with(pieces, B::default);
    }
    let run = |(c, buffer): (usize, &mut B)| f(c * chunk..((c + 1) * chunk).min(len), buffer);
    if pieces <= 1 {
        buffers.iter_mut().take(pieces).enumerate().for_each(run);
    } else {
        buffers[..pieces].par_iter_mut().enumerate().for_each(run);
    }
    pieces
}

/// Call `f(first, share)` on consecutive shares of `out`, one per thread,
/// in parallel; `first` is the index of the share's first entry. For a
/// scatter whose items are few beside the entries they add into (the
/// contacts' forces): every thread reads all the items in order and adds
/// those that land in its share, so each entry receives its additions in
/// the items' order, the same bits whatever the number of threads. With
/// one thread, or at most [`CHUNK`] entries, one share on the calling
/// thread.
pub(crate) fn for_each_share<T: Send>(out: &mut [T], f: impl Fn(usize, &mut [T]) + Sync) {
    let threads = threads();
    if threads <= 1 || out.len() <= CHUNK {
        f(0, out);
        return;
    }
    let share = out.len().div_ceil(threads);
    out.par_chunks_mut(share)
        .enumerate()
        .for_each(|(i, entries)| f(i * share, entries));
}

/// Call `f(first, shares)` on consecutive shares of `slices`, one per
/// thread, in parallel, cut only at indices `offset + k align` (`k`
/// whole); `first` is the index of the share's first entry. For a loop
/// whose items each write within a window `[g align/2, (g + 2) align/2)`
/// that starts at a cut (the friction's groups of particles): each window
/// lies in one share. With one thread, or at most [`CHUNK`] entries, one
/// share on the calling thread.
pub(crate) fn for_each_aligned_share<S: SplitMut>(
    slices: S,
    align: usize,
    offset: usize,
    f: impl Fn(usize, S) + Sync,
) {
    /// Cut `slices` (entries `first..`) for `threads` threads: at the
    /// cut nearest past its middle share, halving the threads.
    fn run<S: SplitMut>(
        slices: S,
        first: usize,
        threads: usize,
        (align, offset): (usize, usize),
        f: &(impl Fn(usize, S) + Sync),
    ) {
        let len = slices.len();
        let left = threads / 2;
        let target = first + (len * left).div_ceil(threads.max(1));
        // No cut where it would not fit in an index.
        let cut = if target <= offset {
            Some(offset)
        } else {
            (target - offset)
                .div_ceil(align)
                .checked_mul(align)
                .and_then(|k| k.checked_add(offset))
        };
        let Some(cut) = cut.filter(|&cut| left > 0 && cut > first && cut < first + len) else {
            f(first, slices);
            return;
        };
        let (before, after) = slices.split_at(cut - first);
        rayon::join(
            || run(before, first, left, (align, offset), f),
            || run(after, cut, threads - left, (align, offset), f),
        );
    }
    let threads = threads();
    if threads <= 1 || slices.len() <= CHUNK || align == 0 {
        f(0, slices);
        return;
    }
    run(slices, 0, threads, (align, offset), &f);
}

/// Slices of equal length (one, or a tuple of them) that can be cut at an
/// index into two sets of slices; [`for_each_span`] hands the pieces to
/// threads.
#[doc(hidden)]
pub trait SplitMut: Sized + Send {
    /// Length of the slices (the shortest, for a tuple).
    fn len(&self) -> usize;
    /// True when the slices are empty.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The slices cut at `mid`: `[..mid]` and `[mid..]`.
    fn split_at(self, mid: usize) -> (Self, Self);
}

impl<T: Send> SplitMut for &mut [T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        self.split_at_mut(mid)
    }
}

impl<T: Sync> SplitMut for &[T] {
    fn len(&self) -> usize {
        <[T]>::len(self)
    }
    fn split_at(self, mid: usize) -> (Self, Self) {
        <[T]>::split_at(self, mid)
    }
}

macro_rules! split_mut_tuple {
    ($($name:ident),+) => {
        impl<$($name: SplitMut),+> SplitMut for ($($name,)+) {
            fn len(&self) -> usize {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                [$($name.len()),+].into_iter().min().unwrap_or(0)
            }
            fn split_at(self, mid: usize) -> (Self, Self) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                #[allow(non_snake_case)]
                let ($($name,)+) = ($($name.split_at(mid),)+);
                (($($name.0,)+), ($($name.1,)+))
            }
        }
    };
}

split_mut_tuple!(A, B);
split_mut_tuple!(A, B, C);
split_mut_tuple!(A, B, C, D);
split_mut_tuple!(A, B, C, D, E);

/// Call `f(item, entries)` for each item of `0..count` with its own
/// entries `out[range(item)]` (a body and its particles), in parallel over
/// pieces of consecutive items of about [`CHUNK`] entries. Each item writes
/// its own entries only, so the result does not depend on the threads.
/// The ranges must follow each other without overlapping, within `out`;
/// when they do not, nothing is called and `false` is returned.
pub(crate) fn for_each_range<T: Send>(
    out: &mut [T],
    count: usize,
    range: impl Fn(usize) -> Range<usize> + Sync,
    f: impl Fn(usize, &mut [T]) + Sync,
) -> bool {
    fn run<T: Send>(
        out: &mut [T],
        base: usize,
        items: Range<usize>,
        range: &(impl Fn(usize) -> Range<usize> + Sync),
        f: &(impl Fn(usize, &mut [T]) + Sync),
    ) {
        let entries = range(items.end - 1).end - range(items.start).start;
        if items.len() == 1 || entries <= CHUNK {
            for item in items {
                let r = range(item);
                f(item, &mut out[r.start - base..r.end - base]);
            }
        } else {
            let mid = items.start + items.len() / 2;
            let split = range(mid).start - base;
            let (left, right) = out.split_at_mut(split);
            rayon::join(
                || run(left, base, items.start..mid, range, f),
                || run(right, base + split, mid..items.end, range, f),
            );
        }
    }
    let in_order = (0..count).all(|item| {
        let r = range(item);
        r.start <= r.end && r.end <= out.len() && (item == 0 || range(item - 1).end <= r.start)
    });
    if in_order && count > 0 {
        run(out, 0, 0..count, &range, &f);
    }
    in_order
}

/// Call `f(start, spans)` on pieces of `slices` (of at most [`CHUNK`]
/// entries, cut at multiples of it, or of the span [`with_span`] set on
/// this thread), in parallel; `start` is the index of the piece's first
/// entry. A loop over particles that writes each particle's own entries:
/// the result does not depend on the threads.
#[doc(hidden)]
pub fn for_each_span<S: SplitMut>(slices: S, f: impl Fn(usize, S) + Sync) {
    fn run<S: SplitMut>(slices: S, start: usize, span: usize, f: &(impl Fn(usize, S) + Sync)) {
        let len = slices.len();
        if len <= span {
            f(start, slices);
        } else {
            let mid = len.div_ceil(span).div_ceil(2) * span;
            let (left, right) = slices.split_at(mid);
            rayon::join(
                || run(left, start, span, f),
                || run(right, start + mid, span, f),
            );
        }
    }
    run(slices, 0, SPAN.with(Cell::get), &f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shares_cover_every_entry_once_whatever_the_threads() {
        // Claim: `for_each_share` hands out consecutive shares that cover
        // `out` exactly once, each with the index of its first entry: on 1,
        // 2, 3 and 7 threads every entry of 10 007 (not a multiple of any
        // of them) is written once with its own index, and a slice of at
        // most `CHUNK` entries is one share.
        for threads in [1, 2, 3, 7] {
            let mut out = vec![(0, 0); 10_007];
            Pool::new(threads).expect("a pool").install(|| {
                for_each_share(&mut out, |first, share| {
                    for (k, entry) in share.iter_mut().enumerate() {
                        *entry = (entry.0 + 1, first + k);
                    }
                });
            });
            assert!(
                out.iter().enumerate().all(|(i, &e)| e == (1, i)),
                "{threads} threads"
            );
            let mut shares = 0;
            let mut short = vec![0; CHUNK];
            Pool::new(threads).expect("a pool").install(|| {
                let count = std::sync::atomic::AtomicUsize::new(0);
                for_each_share(&mut short, |_, _| {
                    count.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                });
                shares = count.into_inner();
            });
            assert_eq!(shares, 1);
        }
    }

    #[test]
    fn a_span_cuts_the_particle_loops_into_its_pieces_and_is_put_back() {
        // Claim: under `with_span(1024, ..)` `for_each_span` hands out
        // pieces of 4 000 entries of at most 1 024, starting at multiples
        // of 1 024, that cover every entry once with its own index (4 000:
        // four pieces, the last short); without a span, or after one (even
        // one left by a panic), a slice of a chunk is one piece.
        let pieces = |out: &mut [usize]| {
            let starts = std::sync::Mutex::new(Vec::new());
            for_each_span(out, |start, piece: &mut [usize]| {
                starts
                    .lock()
                    .expect("not poisoned")
                    .push((start, piece.len()));
                for (k, entry) in piece.iter_mut().enumerate() {
                    *entry += start + k + 1;
                }
            });
            let mut starts = starts.into_inner().expect("not poisoned");
            starts.sort_unstable();
            starts
        };
        for threads in [1, 2, 3] {
            Pool::new(threads).expect("a pool").install(|| {
                let mut out = vec![0; 4000];
                let cut = with_span(1024, || pieces(&mut out));
                assert_eq!(cut, [(0, 1024), (1024, 1024), (2048, 1024), (3072, 928)]);
                assert!(out.iter().enumerate().all(|(i, &e)| e == i + 1));
                assert_eq!(pieces(&mut vec![0; CHUNK]), [(0, CHUNK)]);
                let panicked = std::panic::catch_unwind(|| with_span(8, || panic!("inside")));
                assert!(panicked.is_err());
                assert_eq!(pieces(&mut vec![0; CHUNK]), [(0, CHUNK)], "put back");
            });
        }
    }

    #[test]
    fn the_particle_loops_are_cut_finer_only_where_the_springs_are() {
        // Claim: a 64² cloth's 19 969 springs (cut into eight blocks of
        // 512 particles) give its loops pieces of two blocks; a 128² cloth
        // (four chunks), a rope of 3 000 particles and 2 999 springs (one
        // block) and a 20² cloth (too few springs) keep pieces of a chunk.
        assert_eq!(particle_span(19_969, 64 * 64), 1024);
        assert_eq!(particle_span(80_000, 128 * 128), CHUNK);
        assert_eq!(particle_span(2_999, 3_000), CHUNK);
        assert_eq!(particle_span(1_841, 400), CHUNK);
    }

    #[test]
    fn aligned_shares_cover_every_entry_once_and_are_cut_only_where_asked() {
        // Claim: `for_each_aligned_share` hands out consecutive shares that
        // cover two slices of 10 007 entries exactly once, each with the
        // index of its first entry, every cut at `offset + k align`: on 1,
        // 2, 3 and 7 threads, with cuts every 512 from 0 and from 256 (the
        // friction's even and odd groups of 256), and every 3000 from 1000
        // (cuts far coarser than the shares), and every usize::MAX from 5
        // (no cut fits in an index: one share, where the sum used to
        // wrap around to a cut at 4); more than one share only where there
        // are threads to take them.
        for threads in [1, 2, 3, 7] {
            let huge = (usize::MAX, 5);
            for (align, offset) in [(512, 0), (512, 256), (3000, 1000), huge] {
                let (mut a, mut b) = (vec![0; 10_007], vec![0; 10_007]);
                let firsts = std::sync::Mutex::new(Vec::new());
                Pool::new(threads).expect("a pool").install(|| {
                    for_each_aligned_share(
                        (&mut a[..], &mut b[..]),
                        align,
                        offset,
                        |first, (a, b)| {
                            firsts.lock().expect("not poisoned").push(first);
                            for (k, (a, b)) in a.iter_mut().zip(b).enumerate() {
                                *a += 1;
                                *b = first + k;
                            }
                        },
                    );
                });
                let case = format!("{threads} threads, cuts at {offset} + k {align}");
                assert!(a.iter().all(|&n| n == 1), "{case}");
                assert!(b.iter().enumerate().all(|(i, &j)| i == j), "{case}");
                let firsts = firsts.into_inner().expect("not poisoned");
                assert!(firsts.len() <= threads, "{case}: {firsts:?}");
                // Cuts beyond the entries (or beyond any index): one share.
                let cuts = (align, offset) != huge;
                assert!(
                    threads == 1 || firsts.len() > 1 || !cuts,
                    "{case}: one share"
                );
                assert!(cuts || firsts == [0], "{case}: {firsts:?}");
                assert!(
                    firsts
                        .iter()
                        .all(|&f| f == 0 || (f >= offset && (f - offset) % align == 0)),
                    "{case}: {firsts:?}"
                );
            }
        }
    }

    #[test]
    fn each_item_gets_its_own_entries_in_parallel_or_not() {
        // Claim: `for_each_range` hands item `i` exactly `out[range(i)]`:
        // 300 items of 1 to 60 entries with gaps (some 18 000 entries, so
        // they split over two threads), each writing its index and the
        // entry's offset; entries of no item stay untouched. The same
        // ranges listed out of order, or with one beyond `out`, are
        // refused and nothing is touched.
        let sizes: Vec<usize> = (0..300).map(|i| 1 + (i * 37) % 60).collect();
        let mut ranges = Vec::new();
        let mut at = 0;
        for &size in &sizes {
            at += 3;
            ranges.push(at..at + size);
            at += size;
        }
        let expected = |ranges: &[Range<usize>]| {
            let mut out = vec![(usize::MAX, 0); at + 5];
            for (i, r) in ranges.iter().enumerate() {
                for (k, entry) in out[r.clone()].iter_mut().enumerate() {
                    *entry = (i, k);
                }
            }
            out
        };
        let pool = Pool::new(2).expect("two threads");
        let mut beyond = ranges.clone();
        beyond.push(at..at + 6);
        let reversed: Vec<_> = ranges.iter().rev().cloned().collect();
        for (ranges, runs) in [(&ranges, true), (&reversed, false), (&beyond, false)] {
            let mut out = vec![(usize::MAX, 0); at + 5];
            let ran = pool.install(|| {
                for_each_range(
                    &mut out,
                    ranges.len(),
                    |i| ranges[i].clone(),
                    |i, own| {
                        for (k, entry) in own.iter_mut().enumerate() {
                            *entry = (i, k);
                        }
                    },
                )
            });
            assert_eq!(ran, runs);
            let untouched = vec![(usize::MAX, 0); at + 5];
            assert_eq!(out, if runs { expected(ranges) } else { untouched });
        }
    }
}
