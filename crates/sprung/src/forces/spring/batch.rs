//! The springs' force a batch at a time: the pulls of a batch of springs
//! computed in one loop the compiler vectorises, then added into the
//! particles in order. The whole kernel is `vectorised!`: compiled for
//! the widest vector unit the processor has, chosen at run time.
//!
//! Two kinds of batch:
//!
//! - **runs** (`springs::storage_order` stores them first): springs whose
//!   particles both step by one from spring to spring. Their particles are
//!   read as contiguous slices in the loop that computes the pulls, and
//!   the pulls added back the same way (`Block::add_run`), every loop
//!   vectorised: a builder's cloth, lattice and rope are almost all runs.
//! - **scattered** springs, any others: each spring's extension and
//!   relative velocity are gathered one by one first, then the pulls
//!   computed, and the pulls on the springs' first particles (stored by
//!   lowest particle, a particle is usually the first of several springs
//!   in a row) summed before being added. Gathering first takes the loads
//!   of scattered particles out of the arithmetic, so the square roots and
//!   divisions of a batch proceed side by side instead of waiting on each
//!   other's additions into shared particles.

use std::ops::Range;

use crate::parallel::{Block, Elements};
use crate::springs::{Springs, MIN_RUN};
use crate::units::{Real, Vec3};

/// Springs per batch: their data (12 arrays of `BATCH` reals, 6 KiB) stays
/// in the first-level cache.
pub const BATCH: usize = 64;

/// One batch of springs, structure of arrays: what the vectorised loop
/// reads and writes.
pub struct SpringBatch {
    /// `x_i - x_j` (m), per axis.
    delta: [[Real; BATCH]; 3],
    /// `v_i - v_j` (m/s), per axis.
    relative_velocity: [[Real; BATCH]; 3],
    /// Stiffness `k` (N/m).
    stiffness: [Real; BATCH],
    /// Damping `c` (N·s/m).
    damping: [Real; BATCH],
    /// Rest length `L0` (m).
    rest_length: [Real; BATCH],
    /// One-sided springs pull their second particle only.
    one_sided: [bool; BATCH],
    /// The pull on the second particle, `-` that on the first (N), per axis.
    pull: [[Real; BATCH]; 3],
}

impl Default for SpringBatch {
    fn default() -> Self {
        SpringBatch {
            delta: [[0.0; BATCH]; 3],
            relative_velocity: [[0.0; BATCH]; 3],
            stiffness: [0.0; BATCH],
            damping: [0.0; BATCH],
            rest_length: [0.0; BATCH],
            one_sided: [false; BATCH],
            pull: [[0.0; BATCH]; 3],
        }
    }
}

vectorised! {
    /// Add the force of every spring of `block` (a block of the springs'
    /// schedule) into `force` through the block, a batch at a time: each run
    /// of at least [`MIN_RUN`] springs (up to [`BATCH`]) as one batch, the
    /// springs between runs in batches of up to [`BATCH`].
    pub fn accumulate_block(
        springs: &Springs,
        position: &[Vec3],
        velocity: &[Vec3],
        block: &Block<'_, Vec3, 2>,
        batch: &mut SpringBatch,
    ) {
        let mut pending = Pending::default();
        let mut e = 0;
        while e < block.len() {
            // The schedule's entries four batches on, on their way while
            // this batch is computed: read only at a run's start, they
            // would otherwise miss the cache there and hold up each run.
            block.prefetch(e + 4 * BATCH);
            let run = block.run(e).min(BATCH);
            if run >= MIN_RUN {
                run_batch(springs, position, velocity, block, e, run, batch);
                e += run;
                continue;
            }
            // The scattered springs up to the next run, at most a batch.
            let start = e;
            while e < block.len() && e - start < BATCH && block.run(e) < MIN_RUN {
                e += 1;
            }
            scattered_batch(springs, position, velocity, block, start..e, batch, &mut pending);
        }
        pending.flush(block);
    }
}

/// The springs `e..e + count` of the block, a run ([`Block::run`]).
#[inline(always)]
fn run_batch(
    springs: &Springs,
    position: &[Vec3],
    velocity: &[Vec3],
    block: &Block<'_, Vec3, 2>,
    e: usize,
    count: usize,
    batch: &mut SpringBatch,
) {
    let [a, b] = block.members()[e].map(|p| p as usize);
    let (first_x, second_x) = (&position[a..a + count], &position[b..b + count]);
    let (first_v, second_v) = (&velocity[a..a + count], &velocity[b..b + count]);
    let s = block.element(e);
    let range = s..s + count;
    let stiffness = &springs.stiffness[range.clone()];
    let damping = &springs.damping[range.clone()];
    let rest_length = &springs.rest_length[range.clone()];
    // The particles are read straight from their slices, in the loop that
    // computes the pulls.
    let [px, py, pz] = &mut batch.pull;
    for m in 0..count {
        let delta = first_x[m] - second_x[m];
        let relative = first_v[m] - second_v[m];
        [px[m], py[m], pz[m]] = pull(
            delta.to_array(),
            relative.to_array(),
            [stiffness[m], damping[m], rest_length[m]],
        );
    }
    let one_sided = &springs.one_sided[range];
    let pull = &batch.pull;
    let pull_on = |m: usize| Vec3::new(pull[0][m], pull[1][m], pull[2][m]);
    block.add_run(e, 0, count, |m| {
        if one_sided[m] {
            Vec3::ZERO
        } else {
            -pull_on(m)
        }
    });
    block.add_run(e, 1, count, pull_on);
}

/// The springs `members` (a range of the block's, up to [`BATCH`]), their
/// particles gathered one by one; the pulls on their first particles
/// summed in `pending` while the particle stays the same.
#[inline(always)]
fn scattered_batch(
    springs: &Springs,
    position: &[Vec3],
    velocity: &[Vec3],
    block: &Block<'_, Vec3, 2>,
    range: Range<usize>,
    batch: &mut SpringBatch,
    pending: &mut Pending,
) {
    let members = &block.members()[range.clone()];
    for (b, &[i, j]) in members.iter().enumerate() {
        let delta = position[i as usize] - position[j as usize];
        let relative = velocity[i as usize] - velocity[j as usize];
        for axis in 0..3 {
            batch.delta[axis][b] = delta[axis];
            batch.relative_velocity[axis][b] = relative[axis];
        }
    }
    let count = members.len();
    let (stiffness, damping, rest_length, one_sided) = match block.elements(range.clone()) {
        Elements::Range(r) => (
            &springs.stiffness[r.clone()],
            &springs.damping[r.clone()],
            &springs.rest_length[r.clone()],
            &springs.one_sided[r],
        ),
        Elements::List(list) => {
            for (b, &s) in list.iter().enumerate() {
                let s = s as usize;
                batch.stiffness[b] = springs.stiffness[s];
                batch.damping[b] = springs.damping[s];
                batch.rest_length[b] = springs.rest_length[s];
                batch.one_sided[b] = springs.one_sided[s];
            }
            (
                &batch.stiffness[..count],
                &batch.damping[..count],
                &batch.rest_length[..count],
                &batch.one_sided[..count],
            )
        }
    };
    pulls(
        &batch.delta,
        &batch.relative_velocity,
        [stiffness, damping, rest_length],
        &mut batch.pull,
    );
    for (b, &[first, _]) in members.iter().enumerate() {
        let pull = Vec3::new(batch.pull[0][b], batch.pull[1][b], batch.pull[2][b]);
        if first != pending.particle {
            pending.flush(block);
            *pending = Pending {
                particle: first,
                element: range.start + b,
                sum: Vec3::ZERO,
            };
        }
        if !one_sided[b] {
            pending.sum -= pull;
        }
        block.add(range.start + b, 1, pull);
    }
}

/// The summed pulls on one first particle, not yet added.
struct Pending {
    /// The particle (`u32::MAX`: none).
    particle: u32,
    /// A block element whose first particle it is.
    element: usize,
    /// The sum (N).
    sum: Vec3,
}

impl Default for Pending {
    fn default() -> Self {
        Pending {
            particle: u32::MAX,
            element: 0,
            sum: Vec3::ZERO,
        }
    }
}

impl Pending {
    /// Add the sum into its particle, and clear it.
    fn flush(&mut self, block: &Block<'_, Vec3, 2>) {
        if self.particle != u32::MAX {
            block.add(self.element, 0, self.sum);
        }
        *self = Pending::default();
    }
}

vectorised! {
    /// The springs' pull formula alone, with nothing gathered or added:
    /// the pulls of `springs` springs (rounded up to whole batches of
    /// 64), one batch over and over, its data in the first-level
    /// cache, through the kernel's own vectorised loop. Returns a sum of
    /// pulls (N), so that no work can be skipped. `sprung bench` times it:
    /// the springs per second it reaches are the arithmetic bound of the
    /// force.
    pub fn pulls_alone(springs: usize) -> Real {
        let batches = springs.div_ceil(BATCH);
        let mut batch = SpringBatch::default();
        for b in 0..BATCH {
            // Springs 1 cm long give or take, moving apart or together.
            let spread = b as Real / BATCH as Real;
            batch.delta[0][b] = 0.01 + 0.001 * spread;
            batch.delta[1][b] = 0.002 * spread;
            batch.delta[2][b] = -0.001;
            batch.relative_velocity[0][b] = 0.1 - 0.2 * spread;
            batch.stiffness[b] = 1000.0;
            batch.damping[b] = 0.1;
            batch.rest_length[b] = 0.01;
        }
        let mut total = 0.0;
        for _ in 0..batches {
            pulls(
                &batch.delta,
                &batch.relative_velocity,
                [&batch.stiffness, &batch.damping, &batch.rest_length],
                &mut batch.pull,
            );
            total += batch.pull[0][0];
            // Feed a pull back, so that the batches depend on each other
            // no more than through one number.
            batch.delta[2][0] = -0.001 + 1e-12 * batch.pull[2][BATCH - 1];
        }
        total
    }
}

/// The pull of every spring of the batch ([`pull`]), in one loop the
/// compiler vectorises.
#[inline(always)]
fn pulls(
    delta: &[[Real; BATCH]; 3],
    relative_velocity: &[[Real; BATCH]; 3],
    [stiffness, damping, rest_length]: [&[Real]; 3],
    pull_out: &mut [[Real; BATCH]; 3],
) {
    let [dx, dy, dz] = delta;
    let [wx, wy, wz] = relative_velocity;
    let [px, py, pz] = pull_out;
    let count = stiffness.len().min(damping.len()).min(rest_length.len());
    for b in 0..count.min(BATCH) {
        [px[b], py[b], pz[b]] = pull(
            [dx[b], dy[b], dz[b]],
            [wx[b], wy[b], wz[b]],
            [stiffness[b], damping[b], rest_length[b]],
        );
    }
}

/// The pull of one spring on its second particle (N), `-` that on its
/// first: with `Δx` its extension `x_i - x_j` (m), `d = |Δx|` and the axis
/// `t = Δx / d`, the tension `k (d - L0) + c Δv·t` along `t`, for the
/// relative velocity `Δv = v_i - v_j` (m/s), stiffness `k` (N/m), damping
/// `c` (N·s/m) and rest length `L0` (m); zero for a spring of zero length
/// (no axis). Square roots and divisions are correctly rounded in every
/// vector width, and no product is fused into an addition, so each version
/// of the kernel gives the same bits.
#[inline(always)]
fn pull(
    [dx, dy, dz]: [Real; 3],
    [wx, wy, wz]: [Real; 3],
    [stiffness, damping, rest_length]: [Real; 3],
) -> [Real; 3] {
    let length_squared = dx * dx + dy * dy + dz * dz;
    let length = length_squared.sqrt();
    let inverse = if length_squared > 0.0 {
        1.0 / length
    } else {
        0.0
    };
    let closing = (wx * dx + wy * dy + wz * dz) * inverse;
    let tension = stiffness * (length - rest_length) + damping * closing;
    let along = tension * inverse;
    [along * dx, along * dy, along * dz]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pulls_alone_are_the_spring_formula() {
        // One batch: its first spring, Δx = (1, 0, -0.1) cm apart at rest
        // length 1 cm, Δv = (0.1, 0, 0) m/s, k = 1000 N/m, c = 0.1 N·s/m:
        // the pull `s Δx / d` with `s = k (d - L0) + c Δv·Δx / d`. The
        // kernel computes `(s / d) Δx` rather than `s (Δx / d)`: equal to
        // a few roundings (1e-14 relative).
        let delta = Vec3::new(0.01, 0.0, -0.001);
        let relative = Vec3::new(0.1, 0.0, 0.0);
        let d = delta.length();
        let s = 1000.0 * (d - 0.01) + 0.1 * relative.dot(delta) / d;
        let expected = s * delta.x / d;
        let pull = pulls_alone(BATCH);
        assert!(
            (pull - expected).abs() <= 1e-14 * expected.abs(),
            "{pull} against {expected}"
        );
        // Two batches: the second one's first spring as the first's, but
        // for the 1e-12 m times a pull fed back into its Δz (1e-9
        // relative).
        let twice = pulls_alone(BATCH + 1);
        assert!((twice - 2.0 * expected).abs() <= 1e-9 * expected.abs());
    }
}
