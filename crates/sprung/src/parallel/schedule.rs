//! Elements that share particles (springs, triangles), in blocks that
//! threads can add into side by side without meeting.

use std::cell::Cell;
use std::marker::PhantomData;
use std::ops::{AddAssign, Range};

use rayon::prelude::*;

use super::CHUNK;

/// Elements (springs, triangles) of `W` particles each, in blocks that can
/// add into their particles' entries from several threads at once
/// ([`Schedule::for_each_block`]), with their own copy of their particles.
///
/// The blocks run in phases: the blocks of a phase share no particle and
/// run side by side; the phases run one after the other, and each block
/// takes its elements in order. Every particle thus receives its
/// contributions in the same order whatever the number of threads. Two
/// ways of cutting the blocks, chosen by the elements alone:
///
/// - **by neighbourhood**, when the particles are numbered along the body
///   (the builders' cloths, ropes and lattices): block `b` holds the
///   elements whose lowest particle is in `[b B, (b + 1) B)`, with `B`
///   larger than the widest span of particle indices of an element, so its
///   writes stay in `[b B, (b + 2) B)`; the even blocks form one phase, the
///   odd ones the next. A thread streams through neighbouring particles.
/// - **by colour**, when that gives fewer than [`MIN_BLOCKS`] blocks over
///   more than two chunks of particles (a mesh whose vertices are numbered
///   in no local order; a smaller scene keeps its one or two blocks, run
///   in order on one thread, faster than colours). Greedy colouring: each
///   *piece* of [`COLOUR_PIECE`] elements in a row, in order, takes the
///   first of 64 colours that none of its particles has yet; a colour is a
///   phase, each of its pieces a block, so the elements keep their order
///   and a thread reads them as stored. When the pieces need more than 64
///   colours or leave fewer than [`MIN_BLOCKS`] pieces a colour on
///   average (a numbering with no locality at all), single elements are
///   coloured instead, each colour cut into blocks of [`COLOUR_BLOCK`]
///   elements, and the elements left without a colour make a last phase
///   of one block.
///
/// Since the writes go by the schedule's own copy of the particles, no
/// change made to the elements afterwards can make two threads meet.
#[derive(Debug, Clone, PartialEq)]
pub struct Schedule<const W: usize> {
    /// The elements' particles, block by block.
    members: Vec<[u32; W]>,
    /// The elements' own indices, in the same order; empty when that order
    /// is theirs already (cut by neighbourhood with the elements stored by
    /// lowest block, as `World::add_body` stores a body's springs, or
    /// coloured by pieces, which keep the elements in place).
    element: Vec<u32>,
    /// Each block's elements (a range of `members`), phase by phase.
    blocks: Vec<Range<usize>>,
    /// Each phase's blocks (a range of `blocks`).
    phases: Vec<Range<usize>>,
    /// One more than the highest particle of any element (0 for none): the
    /// shortest slice the blocks may add into.
    reach: usize,
    /// Per element in schedule order, how many elements from it on (itself
    /// included, within its block, at most [`MAX_RUN`]) form a *run*: each
    /// one's particles and own index one more than the last's.
    run: Vec<u8>,
    /// Cut by colouring single elements: the numbering of the particles
    /// has no locality at all.
    singles: bool,
}

/// The longest run [`Block::run`] reports.
pub const MAX_RUN: usize = u8::MAX as usize;

/// Elements per block of a colour: a colour of a mesh of some ten
/// thousand vertices holds a few thousand elements, cut small enough to
/// share among threads.
pub const COLOUR_BLOCK: usize = 1024;

/// The fewest blocks cut by neighbourhood for the schedule to use them
/// rather than colours.
pub const MIN_BLOCKS: usize = 4;

/// Elements coloured together (in their order) when the schedule is cut by
/// colour: a few pages of their particles and parameters, which a thread
/// streams through as stored instead of gathering a colour's elements from
/// all over the body.
pub const COLOUR_PIECE: usize = 512;

/// The colour of the elements that found none free among 64 (a colour is
/// a bit of a `u64` per particle).
const LEFT: usize = u64::BITS as usize;

/// Greedy colours of `groups` (ranges of `members`, elements of particles
/// below `particles`): each group takes the first of 64 colours that none
/// of its particles has yet, [`LEFT`] when none is free.
fn greedy_colours<const W: usize>(
    members: &[[u32; W]],
    groups: &[Range<usize>],
    particles: usize,
) -> Vec<usize> {
    let mut used = vec![0u64; particles];
    groups
        .iter()
        .map(|group| {
            let group = &members[group.clone()];
            let taken = group
                .iter()
                .flatten()
                .fold(0, |acc, &p| acc | used[p as usize]);
            let c = (!taken).trailing_zeros() as usize;
            if c < LEFT {
                group
                    .iter()
                    .flatten()
                    .for_each(|&p| used[p as usize] |= 1 << c);
            }
            c
        })
        .collect()
}

/// How many groups took each colour (the last entry: [`LEFT`]).
fn colour_counts(colour: &[usize]) -> [usize; LEFT + 1] {
    let mut count = [0; LEFT + 1];
    colour.iter().for_each(|&c| count[c] += 1);
    count
}

impl<const W: usize> Default for Schedule<W> {
    fn default() -> Self {
        Schedule {
            members: Vec::new(),
            element: Vec::new(),
            blocks: Vec::new(),
            phases: Vec::new(),
            reach: 0,
            run: Vec::new(),
            singles: false,
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
        if members.len() <= CHUNK || blocks >= MIN_BLOCKS || particles <= 2 * CHUNK {
            let block_of = |m: &[u32; W]| (lowest(m) / block).min(blocks - 1);
            let keys: Vec<usize> = members.iter().map(block_of).collect();
            let even = (0..blocks).step_by(2).chain((1..blocks).step_by(2));
            let phases = vec![0..blocks.div_ceil(2), blocks.div_ceil(2)..blocks];
            Self::sorted(members, &keys, even.collect(), phases)
        } else {
            Self::coloured(members, particles)
        }
    }

    /// Cut by colour (see the type's documentation): pieces of
    /// [`COLOUR_PIECE`] elements in their order when that leaves enough of
    /// them side by side, else single elements.
    fn coloured(members: Vec<[u32; W]>, particles: usize) -> Self {
        let pieces: Vec<Range<usize>> = (0..members.len())
            .step_by(COLOUR_PIECE)
            .map(|start| start..(start + COLOUR_PIECE).min(members.len()))
            .collect();
        let colour = greedy_colours(&members, &pieces, particles);
        let colours = colour.iter().max().map_or(0, |&c| c + 1);
        if colours <= LEFT && pieces.len() >= MIN_BLOCKS * colours {
            // Block `p` is piece `p`, a phase a colour's pieces: the
            // elements stay in place.
            let key: Vec<usize> = (0..members.len()).map(|e| e / COLOUR_PIECE).collect();
            let mut order: Vec<usize> = (0..pieces.len()).collect();
            order.sort_by_key(|&p| colour[p]);
            // Greedy colours leave no colour below the highest unused.
            let phases = colour_counts(&colour)[..colours]
                .iter()
                .scan(0, |start, &count| {
                    *start += count;
                    Some(*start - count..*start)
                })
                .collect();
            return Self::sorted(members, &key, order, phases);
        }
        let singles: Vec<Range<usize>> = (0..members.len()).map(|e| e..e + 1).collect();
        let colour = greedy_colours(&members, &singles, particles);
        let count = colour_counts(&colour);
        // Blocks: each colour cut into COLOUR_BLOCK elements, the leftovers
        // one.
        let mut blocks = 0;
        let mut phases = Vec::new();
        let mut first_block_of = [0usize; LEFT + 1];
        for (c, &n) in count.iter().enumerate() {
            if n == 0 {
                continue;
            }
            first_block_of[c] = blocks;
            let pieces = if c == LEFT {
                1
            } else {
                n.div_ceil(COLOUR_BLOCK)
            };
            phases.push(blocks..blocks + pieces);
            blocks += pieces;
        }
        let mut seen = [0usize; LEFT + 1];
        let slot: Vec<usize> = colour
            .iter()
            .map(|&c| {
                let piece = if c == LEFT { 0 } else { seen[c] / COLOUR_BLOCK };
                seen[c] += 1;
                first_block_of[c] + piece
            })
            .collect();
        Self {
            singles: true,
            ..Self::sorted(members, &slot, (0..blocks).collect(), phases)
        }
    }

    /// Sort the elements into blocks (stably) by `key` (each element's
    /// block); `order` lists the blocks phase by phase, `phases` cuts that
    /// list.
    fn sorted(
        members: Vec<[u32; W]>,
        key: &[usize],
        order: Vec<usize>,
        phases: Vec<Range<usize>>,
    ) -> Self {
        let reach = members
            .iter()
            .flatten()
            .map(|&p| p as usize + 1)
            .max()
            .unwrap_or(0);
        let keys = order.len();
        let mut starts = vec![0usize; keys + 1];
        key.iter().for_each(|&k| starts[k + 1] += 1);
        for k in 0..keys {
            starts[k + 1] += starts[k];
        }
        let blocks = order.iter().map(|&k| starts[k]..starts[k + 1]).collect();
        if key.windows(2).all(|pair| pair[0] <= pair[1]) {
            return Schedule {
                members,
                element: Vec::new(),
                blocks,
                phases,
                reach,
                run: Vec::new(),
                singles: false,
            }
            .with_runs();
        }
        let mut fill = starts;
        let mut sorted = vec![[0u32; W]; members.len()];
        let mut element = vec![0u32; members.len()];
        for (e, (m, &k)) in members.iter().zip(key).enumerate() {
            let at = fill[k];
            fill[k] += 1;
            element[at] = e as u32;
            sorted[at] = *m;
        }
        Schedule {
            members: sorted,
            element,
            blocks,
            phases,
            reach,
            run: Vec::new(),
            singles: false,
        }
        .with_runs()
    }

    /// Measure the runs (see `run`), block by block, from the last element
    /// back.
    fn with_runs(mut self) -> Self {
        let mut run = vec![1u8; self.members.len()];
        for block in &self.blocks {
            for e in block.clone().rev().skip(1) {
                let (this, next) = (self.members[e], self.members[e + 1]);
                let steps = this
                    .iter()
                    .zip(&next)
                    .all(|(&a, &b)| a.checked_add(1) == Some(b));
                let index = |e: usize| self.element.get(e).map_or(e, |&i| i as usize);
                if steps && index(e + 1) == index(e) + 1 {
                    run[e] = run[e + 1].saturating_add(1);
                }
            }
        }
        self.run = run;
        self
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.members.len()
    }

    /// Whether the schedule colours single elements: their particles are
    /// numbered with no locality at all (see the type's documentation).
    pub fn colours_single_elements(&self) -> bool {
        self.singles
    }

    /// True when there are no elements.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
    }

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

/// A [`Schedule`] kept for a list of elements that may change (a body's
/// faces): made again whenever the list differs from the one it was made
/// for (a comparison, a small part of a pass over the elements).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ScheduleCache<const W: usize> {
    /// The elements the schedule was made for.
    members: Vec<[u32; W]>,
    schedule: Schedule<W>,
}

impl<const W: usize> ScheduleCache<W> {
    /// The schedule of `members` (particles below `particles`).
    pub fn get(&mut self, members: &[[u32; W]], particles: usize) -> &Schedule<W> {
        if self.members != members || self.schedule.len() != members.len() {
            self.members = members.to_vec();
            self.schedule = Schedule::new(members.iter().copied(), particles);
        }
        &self.schedule
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

    /// True when the block has no elements.
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
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
    /// [`MAX_RUN`]) form a run: each one's particles, and its index among
    /// all the elements, one more than the last's.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Springs of a `side × side` grid (right, down and the two-apart
    /// bending neighbours), numbered along rows.
    fn grid(side: u32) -> Vec<[u32; 2]> {
        let mut springs = Vec::new();
        for row in 0..side {
            for column in 0..side {
                let i = row * side + column;
                for (dr, dc) in [(0, 1), (1, 0), (0, 2), (2, 0), (1, 1)] {
                    if row + dr < side && column + dc < side {
                        springs.push([i, i + dr * side + dc]);
                    }
                }
            }
        }
        springs
    }

    /// A pseudo-random shuffle of `0..n` (the numbering of a mesh with no
    /// local order).
    fn shuffled(n: u32) -> Vec<u32> {
        let mut order: Vec<u32> = (0..n).collect();
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        for i in (1..order.len()).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            order.swap(i, (state % (i as u64 + 1)) as usize);
        }
        order
    }

    /// Each element's contribution, a value with many significant bits so
    /// that a change of the order of additions changes the sum's rounding.
    fn contribution(e: usize, k: usize) -> f64 {
        ((e * 2 + k) as f64 * 0.618_033_988_749_895).sin() * 1e3 + 1e-7 * e as f64
    }

    /// Add every element's contributions through the schedule, on a pool
    /// of `threads`.
    fn scatter<const W: usize>(
        schedule: &Schedule<W>,
        particles: usize,
        threads: usize,
    ) -> Vec<f64> {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool");
        let mut out = vec![0.0; particles];
        pool.install(|| {
            schedule.scatter(&mut out, |e, w| {
                for k in 0..W {
                    w.add(k, contribution(e, k));
                }
            })
        });
        out
    }

    /// Every element is visited once, the sums are right (to rounding),
    /// and they are the same bits on 1, 2 and 3 threads.
    fn check<const W: usize>(members: &[[u32; W]], particles: usize) -> Schedule<W> {
        let schedule = Schedule::new(members.iter().copied(), particles);
        assert_eq!(schedule.len(), members.len());
        let mut serial = vec![0.0; particles];
        for (e, m) in members.iter().enumerate() {
            for (k, &p) in m.iter().enumerate() {
                serial[p as usize] += contribution(e, k);
            }
        }
        let one = scatter(&schedule, particles, 1);
        for (a, b) in one.iter().zip(&serial) {
            // The same terms in another order: a few roundings of 1e3-sized
            // terms, fewer than 20 per particle.
            assert!((a - b).abs() < 1e-9, "{a} vs {b}");
        }
        for threads in [2, 3] {
            let many = scatter(&schedule, particles, threads);
            assert!(
                one.iter()
                    .zip(&many)
                    .all(|(a, b)| a.to_bits() == b.to_bits()),
                "{threads} threads give other bits than one"
            );
        }
        schedule
    }

    /// The blocks of each phase share no particle.
    fn assert_phases_disjoint<const W: usize>(schedule: &Schedule<W>, particles: usize) {
        for phase in &schedule.phases {
            let mut owner = vec![usize::MAX; particles];
            for b in phase.clone() {
                for m in &schedule.members[schedule.blocks[b].clone()] {
                    for &p in m {
                        let p = p as usize;
                        assert!(
                            owner[p] == usize::MAX || owner[p] == b,
                            "blocks meet at {p}"
                        );
                        owner[p] = b;
                    }
                }
            }
        }
    }

    #[test]
    fn in_order_each_element_adds_into_its_own_particles_one_after_another() {
        // Claim: `scatter_in_order` gives each element its own particles
        // and adds into them in the elements' order. Each spring of a
        // shuffled grid multiplies an accumulator of its particles by a
        // fixed odd number and adds its index (a sum that depends on the
        // order, exact in integers that wrap), and the same is computed
        // element by element here.
        #[derive(Clone, Copy, Default)]
        struct Chain(u64);
        impl AddAssign for Chain {
            fn add_assign(&mut self, other: Chain) {
                self.0 = self
                    .0
                    .wrapping_mul(0x9e37_79b9_7f4a_7c15)
                    .wrapping_add(other.0);
            }
        }
        let side = 30;
        let relabel = shuffled(side * side);
        let springs: Vec<[u32; 2]> = grid(side)
            .into_iter()
            .map(|[i, j]| [relabel[i as usize], relabel[j as usize]])
            .collect();
        let mut expected = vec![Chain::default(); (side * side) as usize];
        for (s, [i, j]) in springs.iter().enumerate() {
            expected[*i as usize] += Chain(2 * s as u64 + 1);
            expected[*j as usize] += Chain(2 * s as u64 + 2);
        }
        let mut out = vec![Chain::default(); expected.len()];
        scatter_in_order(&springs, &mut out, 0, |s, w| {
            assert_eq!(
                [w.particle(0), w.particle(1)],
                springs[s].map(|p| p as usize)
            );
            w.add(0, Chain(2 * s as u64 + 1));
            w.add(1, Chain(2 * s as u64 + 2));
        });
        let bits = |v: &[Chain]| v.iter().map(|c| c.0).collect::<Vec<_>>();
        assert_eq!(bits(&out), bits(&expected));
        // The same springs numbered from particle 7 on, added into entries
        // that start there.
        let moved: Vec<[u32; 2]> = springs.iter().map(|s| s.map(|p| p + 7)).collect();
        let mut out = vec![Chain::default(); expected.len()];
        scatter_in_order(&moved, &mut out, 7, |s, w| {
            assert_eq!(w.particle(0), moved[s][0] as usize);
            w.add(0, Chain(2 * s as u64 + 1));
            w.add(1, Chain(2 * s as u64 + 2));
        });
        assert_eq!(bits(&out), bits(&expected));
    }

    #[test]
    fn a_grid_numbered_along_rows_is_cut_by_neighbourhood_in_place() {
        let side = 160;
        let springs = grid(side);
        let particles = (side * side) as usize;
        let schedule = check(&springs, particles);
        assert!(
            schedule.element.is_empty(),
            "stored in order: no permutation"
        );
        assert_eq!(schedule.phases.len(), 2);
        assert!(schedule.blocks.len() >= MIN_BLOCKS);
        assert_phases_disjoint(&schedule, particles);
    }

    #[test]
    fn a_shuffled_numbering_is_cut_by_colour() {
        let side = 160;
        let relabel = shuffled(side * side);
        let springs: Vec<[u32; 2]> = grid(side)
            .into_iter()
            .map(|[i, j]| [relabel[i as usize], relabel[j as usize]])
            .collect();
        let particles = (side * side) as usize;
        let schedule = check(&springs, particles);
        assert!(schedule.phases.len() > 2, "colours expected");
        assert_phases_disjoint(&schedule, particles);
        // The springs stored in no order either: a piece of them in a row
        // reaches particles all over the grid, every piece meets every
        // other, so single springs are coloured (and permuted).
        let order = shuffled(springs.len() as u32);
        let scattered: Vec<[u32; 2]> = order.iter().map(|&s| springs[s as usize]).collect();
        let schedule = check(&scattered, particles);
        assert!(!schedule.element.is_empty(), "single elements expected");
        assert_phases_disjoint(&schedule, particles);
        // Triangles of the same shuffled grid.
        let mut triangles = Vec::new();
        for row in 0..side - 1 {
            for column in 0..side - 1 {
                let i = row * side + column;
                let r = |p: u32| relabel[p as usize];
                triangles.push([r(i), r(i + 1), r(i + side)]);
                triangles.push([r(i + 1), r(i + side + 1), r(i + side)]);
            }
        }
        let schedule = check(&triangles, particles);
        assert_phases_disjoint(&schedule, particles);
    }

    #[test]
    fn a_local_numbering_with_one_long_spring_is_coloured_by_pieces_in_place() {
        // A grid numbered along rows, and one spring from the first
        // particle to the last: too wide for blocks of neighbours, so the
        // springs are coloured, a piece of them in a row at a time, and
        // keep their order.
        let side = 160;
        let mut springs = grid(side);
        springs.push([0, side * side - 1]);
        let particles = (side * side) as usize;
        let schedule = check(&springs, particles);
        assert!(schedule.element.is_empty(), "pieces keep the order");
        assert!(schedule.phases.len() > 2, "colours expected");
        assert!(schedule.blocks.len() >= MIN_BLOCKS * schedule.phases.len());
        assert!(schedule
            .blocks
            .iter()
            .all(|block| block.len() == COLOUR_PIECE || block.end == springs.len()));
        assert_phases_disjoint(&schedule, particles);
    }

    #[test]
    fn more_than_64_elements_on_one_particle_still_add_up() {
        // A star: 5000 springs from particle 0 need 5000 colours; the ones
        // beyond 64 run in a last phase of one block.
        let particles = 5001;
        let star: Vec<[u32; 2]> = (1..particles as u32).map(|j| [j, 0]).collect();
        let schedule = check(&star, particles);
        assert_phases_disjoint(&schedule, particles);
    }

    #[test]
    fn no_elements_and_few_elements() {
        let schedule = check::<2>(&[], 10);
        assert!(schedule.is_empty());
        check(&[[3, 1], [1, 2], [0, 3]], 4);
    }

    #[test]
    fn runs_are_measured_within_blocks_and_added_as_slices() {
        // A run of ten springs [p, p + 1], a spring that breaks it, then a
        // run of three [p, p + 2] and springs stepping in particles but not
        // in index order (a run needs both).
        let mut springs: Vec<[u32; 2]> = (0..10).map(|p| [p, p + 1]).collect();
        springs.push([0, 5]);
        springs.extend((0..3).map(|p| [p, p + 2]));
        let schedule = Schedule::new(springs.iter().copied(), 12);
        let runs: Vec<usize> = (0..springs.len())
            .map(|e| usize::from(schedule.run[e]))
            .collect();
        assert_eq!(runs, [10, 9, 8, 7, 6, 5, 4, 3, 2, 1, 1, 3, 2, 1]);
        // Adding a run as a slice reaches each element's own particle.
        let mut out = vec![0.0; 12];
        schedule.for_each_block(&mut out, |block| {
            block.add_run(0, 1, 10, |m| (m + 1) as f64);
            block.add_run(11, 0, 3, |m| 100.0 * (m + 1) as f64);
        });
        let expected = [
            100.0, 201.0, 302.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 0.0,
        ];
        assert_eq!(out, expected);
        // A run needs the elements' own indices to step by one too (their
        // parameters are then contiguous): cut into blocks of 4096
        // particles, elements 0 and 3 follow each other in block 1 with
        // particles stepping by one, but are no run; elements 1 and 2 in
        // block 0 are.
        let springs = [[5000u32, 5001], [0, 1], [1, 2], [5001, 5002]];
        let schedule = Schedule::new(springs.iter().copied(), 20_000);
        assert_eq!(schedule.element, [1, 2, 0, 3]);
        assert_eq!(schedule.run, [2, 1, 1, 1]);
    }

    #[test]
    #[should_panic(expected = "not a run")]
    fn adding_what_is_not_a_run_as_one_panics() {
        let springs = [[0u32, 1], [1, 2], [5, 6]];
        let schedule = Schedule::new(springs.iter().copied(), 7);
        let mut out = vec![0.0; 7];
        schedule.for_each_block(&mut out, |block| block.add_run(0, 0, 3, |_| 1.0));
    }
}
