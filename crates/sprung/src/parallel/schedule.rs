//! Elements that share particles (springs, triangles), in blocks that
//! threads can add into side by side without meeting. The schedule is
//! here; how it cuts its elements into blocks and phases is in `cut`, how
//! the blocks run and add into their particles' entries in `blocks`.

mod blocks;
mod cut;

#[cfg(test)]
mod tests;

pub use blocks::{scatter_in_order, Block, Elements, Writer};

use std::ops::Range;

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
///   `B` is a chunk of particles, or, where that leaves fewer than
///   [`MIN_BLOCKS`] blocks and there are at least [`FINE_BLOCKS`] ×
///   [`FINE_ELEMENTS`] elements, an eighth of the particles (a body of a
///   few thousand, shared by two threads).
/// - **by colour**, when that still gives fewer than [`MIN_BLOCKS`] blocks
///   over more than two chunks of particles (a mesh whose vertices are
///   numbered in no local order; a smaller scene keeps its one or two
///   blocks, run in order on one thread, faster than colours). Greedy colouring: each
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
    /// included, within its block, at most 255: a run length is a `u8`) form a *run*: each
    /// one's particles and own index one more than the last's.
    run: Vec<u8>,
    /// Cut by colouring single elements: the numbering of the particles
    /// has no locality at all.
    singles: bool,
}

/// Elements per block of a colour: a colour of a mesh of some ten
/// thousand vertices holds a few thousand elements, cut small enough to
/// share among threads.
pub const COLOUR_BLOCK: usize = 1024;

/// The fewest blocks cut by neighbourhood for the schedule to use them
/// rather than colours.
pub const MIN_BLOCKS: usize = 4;

/// Blocks cut by neighbourhood where a chunk of particles a block would
/// leave fewer than [`MIN_BLOCKS`]: two phases of four, enough for two
/// threads to share a body of a few thousand particles.
pub const FINE_BLOCKS: usize = 8;

/// The fewest elements a block cut finer ([`FINE_BLOCKS`]) holds on
/// average: below, a phase's work is too short to pay for sharing it
/// (the 32² cloth's 5 800 springs in 8 blocks took 1.3 times as long on
/// two threads as on one).
pub const FINE_ELEMENTS: usize = 1024;

/// Whether `elements` over `particles` are cut into [`FINE_BLOCKS`]
/// blocks: blocks of `coarse` particles would be fewer than
/// [`MIN_BLOCKS`], and there are at least [`FINE_ELEMENTS`] elements a
/// fine block.
pub(crate) fn cut_finer(elements: usize, particles: usize, coarse: usize) -> bool {
    elements >= FINE_BLOCKS * FINE_ELEMENTS && particles.div_ceil(coarse) < MIN_BLOCKS
}

/// The particles a piece of a per-particle loop holds
/// ([`super::for_each_span`], [`super::with_span`]) in a world of
/// `springs` springs over `particles` particles: where the springs are cut
/// into the eight finer blocks of neighbouring particles (a body of a few
/// thousand particles and at least 8192 springs), two blocks' worth
/// (the particles a thread writes in both phases when four share them, or
/// two of its pieces when two do), so that each thread updates the
/// particles whose forces it added, still in its cache; else
/// [`super::CHUNK`]. A hint of speed only: a per-particle loop writes the
/// same bits whatever its pieces.
pub fn particle_span(springs: usize, particles: usize) -> usize {
    if cut_finer(springs, particles, super::CHUNK) {
        (2 * particles.div_ceil(FINE_BLOCKS)).next_multiple_of(8)
    } else {
        super::CHUNK
    }
}

/// Elements coloured together (in their order) when the schedule is cut by
/// colour: a few pages of their particles and parameters, which a thread
/// streams through as stored instead of gathering a colour's elements from
/// all over the body.
pub const COLOUR_PIECE: usize = 512;

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
    #[cfg(test)]
    pub fn is_empty(&self) -> bool {
        self.members.is_empty()
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
