//! The machine's bounds: the memory bandwidth, by a STREAM-style triad
//! `a = b + s c` over arrays far larger than the caches (bytes per spring
//! update times spring updates per second cannot exceed it), and the
//! springs' arithmetic alone (`sprung::forces::pulls_alone`).

use std::time::Instant;

use sprung::parallel;

/// Entries per array: 8 Mi f64 (64 MiB), twice the largest caches of the
/// machines we run on.
const LENGTH: usize = 8 << 20;

/// Bytes per second the triad moves on `pool`'s threads (24 bytes an
/// entry: two read, one written; the best of five passes).
pub fn triad_bytes_per_second(pool: &parallel::Pool) -> f64 {
    let b = vec![1.0f64; LENGTH];
    let c = vec![2.0f64; LENGTH];
    let mut a = vec![0.0f64; LENGTH];
    let scale = 3.0;
    let best = pool.install(|| {
        (0..5)
            .map(|_| {
                let start = Instant::now();
                parallel::for_each_span(&mut a[..], |first, a| {
                    for (k, a) in a.iter_mut().enumerate() {
                        *a = b[first + k] + scale * c[first + k];
                    }
                });
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    });
    std::hint::black_box(&a);
    (24 * LENGTH) as f64 / best
}

/// Springs whose pulls one thread computes per timed pass of
/// [`pulls_per_second`].
const PULLS: usize = 1 << 24;

/// Springs per second whose pulls `pool`'s threads compute together, the
/// formula alone on data in the first-level cache of each (the best of
/// five passes): the arithmetic bound of the springs' force.
pub fn pulls_per_second(pool: &parallel::Pool) -> f64 {
    let threads = pool.threads();
    let best = pool.install(|| {
        (0..5)
            .map(|_| {
                let start = Instant::now();
                // One piece of the engine's parallel sum per thread.
                let sum = parallel::sum(threads * parallel::CHUNK, |_| {
                    sprung::forces::pulls_alone(PULLS)
                });
                std::hint::black_box(sum);
                start.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min)
    });
    (threads * PULLS) as f64 / best
}
