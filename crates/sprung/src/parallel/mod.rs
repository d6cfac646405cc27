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

mod loops;
mod schedule;

use std::cell::Cell;

pub(crate) use loops::{
    collect_chunks, find_first, for_each_aligned_share, for_each_piece, for_each_range,
    for_each_share, max, merge_chunks, piece_size,
};
pub use loops::{for_each_span, sum, SplitMut};
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::ops::Range;

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
