//! A [`Schedule`] run: the blocks of each phase side by side on the
//! threads, each adding into its own elements' particles' entries
//! ([`Block`], [`Writer`]), the one place that writes through a shared
//! pointer; and [`scatter_in_order`] for lists too short to share.

use std::cell::Cell;
use std::marker::PhantomData;
use std::ops::{AddAssign, Range};

use rayon::prelude::*;

use super::Schedule;
use crate::parallel::CHUNK;

impl<const W: usize> Schedule<W> {
    /// Call `f(element, writer)` for every element, phase by phase, the
    /// blocks of a phase in parallel, each block in order; the writer adds
    /// into `out` at the element's own particles, and nowhere else.
    pub fn scatter<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(usize, &Writer<'_, T, W>) + Sync,
    ) {
        self.for_each_block(out, |block| {
            for e in 0..block.len() {
                let writer = Writer {
                    particles: block.members[e],
                    into: Entries::Block { block: &block, e },
                };
                f(block.element(e), &writer);
            }
        });
    }

    /// Call `f(block)` for every block, phase by phase, the blocks of a
    /// phase in parallel. A [`Block`] lists its elements in order and adds
    /// into `out` at their particles only; a kernel that takes its elements
    /// in batches (the springs' force) works on a block at a time.
    pub fn for_each_block<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(Block<'_, T, W>) + Sync,
    ) {
        // Checked once here rather than at each addition: `members` is
        // private and never changed after `new`, which measured `reach`.
        assert!(
            self.reach <= out.len(),
            "a scheduled element's particle is beyond the slice"
        );
        let shared = Disjoint {
            pointer: out.as_mut_ptr(),
            _slice: PhantomData,
        };
        let run = |b: usize| {
            let range = self.blocks[b].clone();
            f(Block {
                members: &self.members[range.clone()],
                element: self.element.get(range.clone()),
                first: range.start,
                run: &self.run[range.clone()],
                shared: &shared,
                _one_thread: PhantomData,
            });
        };
        for phase in &self.phases {
            if self.len() <= CHUNK || phase.len() < 2 {
                phase.clone().for_each(run);
            } else {
                phase.clone().into_par_iter().for_each(run);
            }
        }
    }
}

/// One block of a [`Schedule`]: its elements in order, and additions into
/// their particles' entries (from one thread; blocks running at once share
/// no particle).
pub struct Block<'a, T, const W: usize> {
    /// The block's elements' particles.
    members: &'a [[u32; W]],
    /// The elements' own indices, when they are not `first..`.
    element: Option<&'a [u32]>,
    /// The first element's index, when they are in order.
    first: usize,
    /// The elements' runs (`Schedule::run`).
    run: &'a [u8],
    shared: &'a Disjoint<'a, T>,
    /// A block is used by the one thread that runs it: not `Sync`, so no
    /// code can hand it to two threads that would add into one entry.
    _one_thread: PhantomData<Cell<()>>,
}

impl<T: Copy + AddAssign, const W: usize> Block<'_, T, W> {
    /// Number of elements in the block.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Ask the processor to bring the schedule's entries for the block's
    /// `e`-th element (its particle indices, run length and own index)
    /// into the cache ahead of their use; nothing past the block.
    #[inline(always)]
    pub fn prefetch(&self, e: usize) {
        if let Some(members) = self.members.get(e) {
            crate::cache::prefetch(members);
            crate::cache::prefetch(&self.run[e]);
            if let Some(element) = self.element.and_then(|element| element.get(e)) {
                crate::cache::prefetch(element);
            }
        }
    }

    /// The block's elements' particles, in order.
    pub fn members(&self) -> &[[u32; W]] {
        self.members
    }

    /// The indices (among all the elements) of the block's elements
    /// `range`: a range when the elements are stored in schedule order,
    /// else a list.
    pub fn elements(&self, range: Range<usize>) -> Elements<'_> {
        match self.element {
            None => Elements::Range(self.first + range.start..self.first + range.end),
            Some(element) => Elements::List(&element[range]),
        }
    }

    /// How many of the block's elements from its `e`-th on (at most
    /// 255) form a run: each one's particles, and
    /// its index among all the elements, one more than the last's.
    pub fn run(&self, e: usize) -> usize {
        usize::from(self.run[e])
    }

    /// The index (among all the elements) of the block's `e`-th element.
    pub fn element(&self, e: usize) -> usize {
        self.element
            .map_or(self.first + e, |element| element[e] as usize)
    }

    /// Add `value` to the entry of the `k`-th particle of the block's `e`-th
    /// element.
    #[allow(unsafe_code)]
    pub fn add(&self, e: usize, k: usize, value: T) {
        let index = self.members[e][k] as usize;
        // SAFETY: `index` is a particle of one of this block's elements,
        // within the slice (checked in `for_each_block`), and no thread but
        // this block's writes it while this block runs (see the `Sync` impl
        // of `Disjoint`).
        unsafe { *self.shared.pointer.add(index) += value };
    }

    /// Add `value(m)` to the entry of the `k`-th particle of the block's
    /// element `e + m`, for `m < count`, where those particles follow each
    /// other: elements `e..e + count` are a run ([`Block::run`], checked).
    /// One pass over neighbouring entries, which the compiler vectorises.
    ///
    /// # Panics
    /// If the elements are not a run.
    #[allow(unsafe_code)]
    #[inline(always)]
    pub fn add_run(&self, e: usize, k: usize, count: usize, value: impl Fn(usize) -> T) {
        if count == 0 {
            return;
        }
        assert!(
            count <= self.run(e),
            "elements {e}..{} of a block are not a run",
            e + count
        );
        let start = self.members[e][k] as usize;
        // SAFETY: particles `start..start + count` are the `k`-th particles
        // of this block's elements `e..e + count` (a run, checked above:
        // `with_runs` measured it on the very members, without wrapping
        // around), within the slice and written by no other thread while
        // this block runs, as for `add`. Each value is computed before its
        // entry is borrowed, so no reference to an entry is alive while
        // `value` runs, whatever it does.
        unsafe {
            let entries = self.shared.pointer.add(start);
            for m in 0..count {
                let addition = value(m);
                *entries.add(m) += addition;
            }
        }
    }
}

/// Indices of elements: a range of them, or a list.
#[derive(Debug, Clone)]
pub enum Elements<'a> {
    /// Elements `start..end`.
    Range(Range<usize>),
    /// These elements.
    List(&'a [u32]),
}

/// The entries of a slice that the blocks of one parity add into from
/// several threads.
struct Disjoint<'a, T> {
    pointer: *mut T,
    _slice: PhantomData<&'a mut [T]>,
}

// SAFETY: a `Disjoint` is made and used only inside
// `Schedule::for_each_block`, whose threads each run whole blocks of one
// phase and write through their `Block`, which reaches only the particles
// of the block's own elements. The blocks of a phase share no particle
// (`Schedule::new`): cut by neighbourhood, block `b`'s elements have their
// lowest particle in `[b B, (b + 1) B)` and span fewer than `B` particles,
// so its writes stay in `[b B, (b + 2) B)`, and the blocks of a phase are
// all even or all odd, two or more apart; cut by colour, the blocks of a
// phase are pieces of one colour, which share no particle with each other
// (the elements within a piece may share particles: a block runs in
// order on one thread), or single elements of one colour, which share
// none, and the elements left without one run as a phase of a single
// block. So no two threads ever touch the same entry;
// every particle is within the slice (checked in `for_each_block`).
// `T: Send` lets the values move between threads.
#[allow(unsafe_code)]
unsafe impl<T: Send> Sync for Disjoint<'_, T> {}

/// What one element's computation may write: additions to its own
/// particles' entries.
pub struct Writer<'a, T, const W: usize> {
    /// The element's particles.
    particles: [u32; W],
    /// Where the additions go.
    into: Entries<'a, T, W>,
}

/// The entries a [`Writer`] adds into.
enum Entries<'a, T, const W: usize> {
    /// Through a block of a schedule, as its element `e`.
    Block {
        block: &'a Block<'a, T, W>,
        e: usize,
    },
    /// Straight into the entries, from the one thread that holds them:
    /// particle `i`'s entry is `entries[i - first]`.
    Own {
        entries: &'a [Cell<T>],
        first: usize,
    },
}

impl<T: Copy + AddAssign, const W: usize> Writer<'_, T, W> {
    /// The element's `k`-th particle.
    #[inline(always)]
    pub fn particle(&self, k: usize) -> usize {
        self.particles[k] as usize
    }

    /// Add `value` to the entry of the element's `k`-th particle.
    #[inline(always)]
    pub fn add(&self, k: usize, value: T) {
        match &self.into {
            Entries::Block { block, e } => block.add(*e, k, value),
            Entries::Own { entries, first } => {
                let entry = &entries[self.particles[k] as usize - first];
                let mut sum = entry.get();
                sum += value;
                entry.set(sum);
            }
        }
    }
}

/// Call `f(element, writer)` for every element of `members` (each `W`
/// particles), in their order, on the calling thread: the writer adds into
/// `out` at the element's own particles, particle `i` at `out[i - first]`
/// (`out` holds the entries of particles `first..`). For lists too short
/// to share among threads (at most [`CHUNK`] elements, which a
/// [`Schedule`] would run on one thread as well), without making or
/// checking a schedule.
///
/// # Panics
/// If an element's particle is outside `first..first + out.len()`.
#[inline(always)]
pub fn scatter_in_order<T: Copy + AddAssign, const W: usize>(
    members: &[[u32; W]],
    out: &mut [T],
    first: usize,
    f: impl Fn(usize, &Writer<'_, T, W>),
) {
    let entries = Cell::from_mut(out).as_slice_of_cells();
    for (e, &particles) in members.iter().enumerate() {
        let writer = Writer {
            particles,
            into: Entries::Own { entries, first },
        };
        f(e, &writer);
    }
}
