//! Elements that share particles (springs, triangles), in blocks that
//! threads can add into side by side without meeting.

use std::marker::PhantomData;
use std::ops::{AddAssign, Range};

use rayon::prelude::*;

use super::CHUNK;

/// Elements (springs, triangles) of `W` particles each, sorted into blocks
/// by the lowest particle they touch, with their own copy of their
/// particles, so that they can add into their particles' entries from
/// several threads at once ([`Schedule::for_each_block`]).
///
/// Block `b` holds the elements whose lowest particle is in
/// `[b B, (b + 1) B)`, with `B` larger than the widest span of particle
/// indices of an element (`D`): its writes stay in `[b B, (b + 2) B)`, so
/// blocks two apart never meet. The even blocks run in parallel, then the
/// odd ones, each block in the elements' own order: every particle receives
/// its contributions in the same order whatever the number of threads, and
/// a thread streams through neighbouring particles (builders number them
/// along the body, so `D` is small: a row and a bit for a cloth). Since the
/// writes go by the schedule's own copy of the particles, no change made to
/// the elements afterwards can make two threads meet.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule<const W: usize> {
    /// The elements' particles, block by block.
    members: Vec<[u32; W]>,
    /// The elements' own indices, in the same order; empty when that order
    /// is theirs already (elements stored by lowest particle, as
    /// `World::add_body` stores springs).
    element: Vec<u32>,
    /// Where each block starts in `members` (one more than the blocks).
    starts: Vec<u32>,
}

impl<const W: usize> Default for Schedule<W> {
    fn default() -> Self {
        Schedule {
            members: Vec::new(),
            element: Vec::new(),
            starts: vec![0],
        }
    }
}

impl<const W: usize> Schedule<W> {
    /// Schedule elements (each one's particles, all below `particles`).
    pub fn new(members: impl ExactSizeIterator<Item = [u32; W]>, particles: usize) -> Self {
        let members: Vec<[u32; W]> = members.collect();
        let lowest = |m: &[u32; W]| m.iter().copied().min().unwrap_or(0) as usize;
        let highest = |m: &[u32; W]| m.iter().copied().max().unwrap_or(0) as usize;
        let span = members
            .iter()
            .map(|m| highest(m) - lowest(m))
            .max()
            .unwrap_or(0);
        let block = (span + 1).max(CHUNK);
        let blocks = particles.div_ceil(block).max(1);
        let block_of = |m: &[u32; W]| (lowest(m) / block).min(blocks - 1);
        let mut starts = vec![0u32; blocks + 1];
        for m in &members {
            starts[block_of(m) + 1] += 1;
        }
        for b in 0..blocks {
            starts[b + 1] += starts[b];
        }
        if members
            .windows(2)
            .all(|w| block_of(&w[0]) <= block_of(&w[1]))
        {
            return Schedule {
                members,
                element: Vec::new(),
                starts,
            };
        }
        let mut fill = starts.clone();
        let mut sorted = vec![[0u32; W]; members.len()];
        let mut element = vec![0u32; members.len()];
        for (e, m) in members.iter().enumerate() {
            let b = block_of(m);
            let at = fill[b] as usize;
            fill[b] += 1;
            element[at] = e as u32;
            sorted[at] = *m;
        }
        Schedule {
            members: sorted,
            element,
            starts,
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when there are no elements.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

    /// Call `f(element, writer)` for every element: the even blocks in
    /// parallel, then the odd ones, each block in order; the writer adds
    /// into `out` at the element's own particles, and nowhere else.
    pub fn scatter<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(usize, &Writer<'_, T, W>) + Sync,
    ) {
        self.for_each_block(out, |block| {
            for e in 0..block.len() {
                let writer = Writer { block: &block, e };
                f(block.element(e), &writer);
            }
        });
    }

    /// Call `f(block)` for every block: the even blocks in parallel, then
    /// the odd ones. A [`Block`] lists its elements in order and adds into
    /// `out` at their particles only; a kernel that takes its elements in
    /// batches (the springs' force) works on a block at a time.
    pub fn for_each_block<T: Send + Copy + AddAssign>(
        &self,
        out: &mut [T],
        f: impl Fn(Block<'_, T, W>) + Sync,
    ) {
        assert!(
            self.members
                .iter()
                .flatten()
                .all(|&p| (p as usize) < out.len()),
            "a scheduled element's particle is beyond the slice"
        );
        let shared = Disjoint {
            pointer: out.as_mut_ptr(),
            _slice: PhantomData,
        };
        let blocks = self.starts.len() - 1;
        let run = |b: usize| {
            let range = self.starts[b] as usize..self.starts[b + 1] as usize;
            f(Block {
                members: &self.members[range.clone()],
                element: self.element.get(range.clone()),
                first: range.start,
                shared: &shared,
            });
        };
        if blocks <= 2 || self.len() <= CHUNK {
            (0..blocks)
                .step_by(2)
                .chain((1..blocks).step_by(2))
                .for_each(run);
        } else {
            for parity in 0..2 {
                (parity..blocks).into_par_iter().step_by(2).for_each(run);
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
    shared: &'a Disjoint<'a, T>,
}

impl<T: Copy + AddAssign, const W: usize> Block<'_, T, W> {
    /// Number of elements in the block.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// True when the block has no elements.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
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
// parity and write through their `Block`, which reaches only the particles
// of the block's own elements. Block `b`'s elements have their lowest
// particle in `[b B, (b + 1) B)` and span fewer than `B` particles
// (`Schedule::new`), so its writes stay in `[b B, (b + 2) B)`; blocks of one
// parity are two or more apart, so no two threads ever touch the same
// entry; every particle is within the slice (checked in `for_each_block`).
// `T: Send` lets the values move between threads.
#[allow(unsafe_code)]
unsafe impl<T: Send> Sync for Disjoint<'_, T> {}

/// What one element's computation may write: additions to its own
/// particles' entries.
pub struct Writer<'a, T, const W: usize> {
    block: &'a Block<'a, T, W>,
    e: usize,
}

impl<T: Copy + AddAssign, const W: usize> Writer<'_, T, W> {
    /// The element's `k`-th particle.
    pub fn particle(&self, k: usize) -> usize {
        self.block.members[self.e][k] as usize
    }

    /// Add `value` to the entry of the element's `k`-th particle.
    pub fn add(&self, k: usize, value: T) {
        self.block.add(self.e, k, value);
    }
}
