//! Tests of the schedule: every element visited once, the same bits on
//! any number of threads, the blocks of a phase disjoint, the ways of
//! cutting chosen as documented, and the runs.

use super::*;
use std::ops::AddAssign;

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
fn scatter<const W: usize>(schedule: &Schedule<W>, particles: usize, threads: usize) -> Vec<f64> {
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
fn a_body_of_a_few_thousand_particles_is_cut_finer_than_a_chunk() {
    // 64² = one chunk of particles and 19 969 springs: a block a chunk
    // would leave one block, run on one thread; it gets FINE_BLOCKS of
    // 512 particles (wider than a spring's span of 2 rows, 128), two phases
    // of four. 128² = four chunks keeps its blocks of a chunk, and a
    // body of at most a chunk of springs (20², 1 841) its one block.
    for (side, blocks) in [(64, FINE_BLOCKS), (128, 4), (20, 1)] {
        let springs = grid(side);
        let particles = (side * side) as usize;
        let schedule = check(&springs, particles);
        assert_eq!(schedule.blocks.len(), blocks, "{side}²");
        assert_eq!(schedule.phases.len(), 2, "{side}²");
        assert_phases_disjoint(&schedule, particles);
    }
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
