//! How a [`Schedule`] cuts its elements into blocks and phases: by
//! neighbourhood where the particles are numbered along the body, else by
//! greedy colours of pieces of elements or of single elements; and the
//! runs of elements within each block.

use std::ops::Range;

use super::{cut_finer, Schedule, COLOUR_BLOCK, COLOUR_PIECE, FINE_BLOCKS, MIN_BLOCKS};
use crate::parallel::CHUNK;

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
        // Blocks of a chunk of particles; where that leaves fewer than
        // MIN_BLOCKS, and there are elements enough for FINE_BLOCKS blocks
        // of FINE_ELEMENTS (a body of a few thousand particles), that many
        // blocks, so that two threads still share its phases.
        let coarse = (span + 1).max(CHUNK);
        let block = if cut_finer(members.len(), particles, coarse) {
            (span + 1).max(particles.div_ceil(FINE_BLOCKS))
        } else {
            coarse
        };
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
}
