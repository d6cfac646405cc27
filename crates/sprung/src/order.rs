//! A numbering of the particles that keeps each spring's two ends close,
//! for meshes whose own numbering does not: reverse Cuthill–McKee over the
//! graph of the springs.
//!
//! Breadth-first from a particle of low degree at the edge of each
//! connected piece, neighbours taken by increasing degree, the whole order
//! then reversed: every spring joins two particles of the same or
//! neighbouring levels, so a spring's ends are at most about two levels'
//! widths apart. A grid
//! comes out numbered along its diagonals, a shuffled grid as well.
//!
//! [`locality_numbering`] renumbers only where the spring schedule finds no
//! locality at all in the numbering, and only the pieces where that pays (their
//! springs' ends far apart in their own numbering, four times closer in
//! the new one), each within the numbers it had: the builders' cloths,
//! ropes and lattices, numbered along their rows, keep their numbers and
//! the runs of springs the force reads fastest. The world stores a
//! renumbered piece's springs in the new order (`springs::storage_order`)
//! and the spring force works in it (`forces::spring`); nothing a user
//! sees is renumbered.

use crate::parallel::{Schedule, CHUNK};

/// The particles (`0..particles`) in reverse Cuthill–McKee order of the
/// graph whose edges are `ends`: `order[k]` is the particle numbered `k`.
/// Particles of no edge come last, in their own order. Deterministic: ties
/// go to the lower particle.
pub fn reverse_cuthill_mckee(ends: &[[u32; 2]], particles: usize) -> Vec<u32> {
    let (start, neighbours) = adjacency(ends, particles);
    let degree = |p: usize| start[p + 1] - start[p];
    let mut order: Vec<u32> = Vec::with_capacity(particles);
    let mut placed = vec![false; particles];
    // Roots by increasing degree: a piece is entered at one of its
    // particles of least degree (a corner of a grid, an end of a rope).
    let mut roots: Vec<u32> = (0..particles as u32)
        .filter(|&p| degree(p as usize) > 0)
        .collect();
    roots.sort_by_key(|&p| (degree(p as usize), p));
    let mut level: Vec<u32> = Vec::new();
    for root in roots {
        if placed[root as usize] {
            continue;
        }
        placed[root as usize] = true;
        let first = order.len();
        order.push(root);
        let mut next = first;
        while next < order.len() {
            let p = order[next] as usize;
            next += 1;
            level.clear();
            level.extend(
                neighbours[start[p]..start[p + 1]]
                    .iter()
                    .copied()
                    .filter(|&q| !placed[q as usize]),
            );
            level.sort_by_key(|&q| (degree(q as usize), q));
            level.dedup();
            for &q in &level {
                placed[q as usize] = true;
                order.push(q);
            }
        }
    }
    order.reverse();
    order.extend((0..particles as u32).filter(|&p| !placed[p as usize]));
    order
}

/// A new number for each particle (`0..particles`) of a body whose springs
/// join `ends` and are stored in the order `stored` (indices into `ends`,
/// `springs::storage_order` in the body's own numbering), or `None` when
/// no piece needs one: each connected piece of the graph of `ends` whose
/// springs' ends are far apart ([`pays`]) takes its own numbers again in
/// reverse Cuthill–McKee order; every other particle keeps its number.
pub fn locality_numbering(
    ends: &[[u32; 2]],
    stored: &[usize],
    particles: usize,
) -> Option<Vec<u32>> {
    // Only a numbering the spring schedule finds no locality in at all: it
    // reads any other well enough in its own ways (a mesh refined by
    // subdivision steps 20 % slower a step renumbered, measured on the
    // 10 242-vertex icosphere), and the schedule keeps a body of at most
    // two chunks of particles in neighbouring blocks in any order (small
    // enough to stay in the caches).
    let schedule = Schedule::new(stored.iter().map(|&s| ends[s]), particles);
    if !schedule.colours_single_elements() {
        return None;
    }
    renumber_pieces(ends, particles)
}

/// [`locality_numbering`] without asking the schedule: each piece that
/// pays renumbered, `None` if none does.
fn renumber_pieces(ends: &[[u32; 2]], particles: usize) -> Option<Vec<u32>> {
    let order = reverse_cuthill_mckee(ends, particles);
    // The pieces, as runs of `order`: a piece is placed whole, and a
    // particle of no spring is a piece of its own.
    let (start, neighbours) = adjacency(ends, particles);
    let mut piece = vec![u32::MAX; particles];
    let mut pieces: Vec<std::ops::Range<usize>> = Vec::new();
    let mut k = 0;
    while k < particles {
        let first = k;
        let id = pieces.len() as u32;
        let mut stack = vec![order[k]];
        piece[order[k] as usize] = id;
        let mut size = 0;
        while let Some(p) = stack.pop() {
            size += 1;
            for &q in &neighbours[start[p as usize]..start[p as usize + 1]] {
                if piece[q as usize] == u32::MAX {
                    piece[q as usize] = id;
                    stack.push(q);
                }
            }
        }
        k = first + size;
        pieces.push(first..k);
    }
    // Each piece's particles, by number, take its numbers in that order.
    let mut number: Vec<u32> = (0..particles as u32).collect();
    let mut renumbered = false;
    let mut spans = vec![(0u64, 0u64, 0u64); pieces.len()];
    let mut candidate = vec![0u32; particles];
    for range in &pieces {
        let mut own: Vec<u32> = order[range.clone()].to_vec();
        own.sort_unstable();
        for (&p, &n) in order[range.clone()].iter().zip(&own) {
            candidate[p as usize] = n;
        }
    }
    for &[a, b] in ends {
        let s = &mut spans[piece[a as usize] as usize];
        s.0 += u64::from(a.abs_diff(b));
        s.1 += u64::from(candidate[a as usize].abs_diff(candidate[b as usize]));
        s.2 += 1;
    }
    for (range, &(before, after, count)) in pieces.iter().zip(&spans) {
        if count == 0 {
            continue;
        }
        let mean = |total: u64| total as f64 / count as f64;
        if pays(mean(before), mean(after)) {
            renumbered = true;
            for &p in &order[range.clone()] {
                number[p as usize] = candidate[p as usize];
            }
        }
    }
    renumbered.then_some(number)
}

/// The graph of `ends` in compressed rows: the neighbours of particle `p`
/// are `neighbours[start[p]..start[p + 1]]` (repeated edges repeated,
/// loops left out).
fn adjacency(ends: &[[u32; 2]], particles: usize) -> (Vec<usize>, Vec<u32>) {
    let mut start = vec![0usize; particles + 1];
    for &[a, b] in ends.iter().filter(|[a, b]| a != b) {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for p in 0..particles {
        start[p + 1] += start[p];
    }
    let mut fill = start.clone();
    let mut neighbours = vec![0u32; start[particles]];
    for &[a, b] in ends.iter().filter(|[a, b]| a != b) {
        neighbours[fill[a as usize]] = b;
        fill[a as usize] += 1;
        neighbours[fill[b as usize]] = a;
        fill[b as usize] += 1;
    }
    (start, neighbours)
}

/// Whether renumbering pays: the springs' ends are, on average, more than
/// an eighth of a chunk (the particles a thread takes at a time) apart,
/// and the new numbering brings them at least four times closer.
pub fn pays(before: f64, after: f64) -> bool {
    before > CHUNK as f64 / 8.0 && after * 4.0 <= before
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean distance between the numbers of a spring's two ends (0 for no
    /// springs), under `number` (each particle's number).
    fn mean_span(ends: &[[u32; 2]], number: impl Fn(u32) -> u32) -> f64 {
        if ends.is_empty() {
            return 0.0;
        }
        let total: u64 = ends
            .iter()
            .map(|&[a, b]| u64::from(number(a).abs_diff(number(b))))
            .sum();
        total as f64 / ends.len() as f64
    }

    /// A fixed random numbering of `n` particles (xorshift, Fisher–Yates):
    /// `shuffled(n, seed)[p]` is particle `p`'s new number.
    fn shuffled(n: usize, seed: u64) -> Vec<usize> {
        let mut state = seed;
        let mut number: Vec<usize> = (0..n).collect();
        for k in (1..n).rev() {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            number.swap(k, (state % (k as u64 + 1)) as usize);
        }
        number
    }

    /// The springs of a `width × height` grid (right and down neighbours),
    /// particle `(i, j)` numbered `number(j * width + i)`.
    fn grid(width: u32, height: u32, number: impl Fn(u32) -> u32) -> Vec<[u32; 2]> {
        let mut ends = Vec::new();
        for j in 0..height {
            for i in 0..width {
                let p = j * width + i;
                if i + 1 < width {
                    ends.push([number(p), number(p + 1)]);
                }
                if j + 1 < height {
                    ends.push([number(p), number(p + width)]);
                }
            }
        }
        ends
    }

    #[test]
    fn a_shuffled_grid_gets_its_springs_short_again() {
        // A 60 × 40 grid numbered at random: its springs span a third of
        // the 2400 particles on average (the mean distance of two random
        // numbers). Numbered by rows, they span (1 + 60) / 2 = 30.5; along
        // diagonals, at most the 41 particles of the longest diagonal
        // between a particle and its neighbour on the next one.
        let (width, height) = (60u32, 40u32);
        let particles = (width * height) as usize;
        let shuffled = shuffled(particles, 0x9e37_79b9);
        let ends = grid(width, height, |p| shuffled[p as usize] as u32);
        let before = mean_span(&ends, |p| p);
        assert!(before > 600.0, "{before}");
        let order = reverse_cuthill_mckee(&ends, particles);
        // A permutation of the particles.
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..particles as u32).collect::<Vec<_>>());
        let mut number = vec![0u32; particles];
        for (k, &p) in order.iter().enumerate() {
            number[p as usize] = k as u32;
        }
        let widest = ends
            .iter()
            .map(|&[a, b]| number[a as usize].abs_diff(number[b as usize]))
            .max()
            .unwrap_or(0);
        assert!(widest <= 2 * height + 1, "widest span {widest}");
        let after = mean_span(&ends, |p| number[p as usize]);
        assert!(after <= 41.0, "{after}");
        assert!(pays(before, after));
        // The grid numbered by rows already is local: no gain worth it.
        let rows = grid(width, height, |p| p);
        assert!(!pays(mean_span(&rows, |p| p), 20.0));
        // Far apart, but brought less than four times closer: not either.
        assert!(!pays(1000.0, 251.0));
        assert!(pays(1000.0, 250.0));
    }

    #[test]
    fn repeated_springs_loops_and_lone_particles_are_all_placed() {
        // Two pieces (0-1-2 and 4-5), a repeated spring, a loop on 3, and
        // particle 6 in no spring: each particle once, the lone ones last.
        let ends = [[0, 1], [1, 2], [2, 1], [3, 3], [5, 4]];
        let order = reverse_cuthill_mckee(&ends, 7);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..7).collect::<Vec<_>>());
        assert_eq!(&order[5..], &[3, 6]);
    }

    #[test]
    fn only_a_body_numbered_with_no_locality_is_renumbered() {
        use crate::build::{self, ClothSprings, SurfaceSprings};
        use crate::{integrate::IntegratorKind, world::World};
        // A 100 × 100 cloth (10 000 particles, past the two chunks a world
        // reads in any order): numbered at random, its springs are read in
        // a numbering of their own; numbered along its rows (the runs the
        // force reads fastest), and the 10 242-vertex icosphere (its
        // subdivision order is read faster than a renumbering), not.
        let side = 100;
        let cloth = build::cloth(side, side, 1.0, 1.0, ClothSprings::default()).expect("cloth");
        let number = shuffled(side * side, 0x2545_f491);
        let shuffled = cloth.renumbered(&number).expect("a numbering");
        let ball = build::icosphere(1.0, 5, SurfaceSprings::default()).expect("icosphere");
        for (body, renumbered) in [(shuffled, true), (cloth, false), (ball, false)] {
            let mut world = World::new(IntegratorKind::SymplecticEuler);
            world.add_body("body", body).expect("valid body");
            assert_eq!(world.bodies[0].spring_numbering.is_some(), renumbered);
        }
    }
}
