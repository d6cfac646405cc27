//! The engine's parallel loops, each with a result independent of the
//! number of threads: sums in a fixed tree ([`sum`]), loops over
//! particles in spans ([`for_each_span`]), shares and ranges of the
//! particles, and pieces whose results are put in order.

use std::cell::Cell;
use std::ops::Range;

use rayon::prelude::*;

use super::{threads, CHUNK, SPAN};
use crate::units::Real;

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
