//! Springs as a structure of arrays: endpoints, rest length, stiffness and
//! damping in parallel `Vec`s.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::units::Real;

/// The next number [`Springs::topology`] hands out.
static NEXT_TOPOLOGY: AtomicU64 = AtomicU64::new(1);

/// The damped springs of a world (docs/physics.md §1), stored as parallel arrays.
///
/// Spring `s` joins particles `first()[s]` and `second()[s]`. A *one-sided*
/// spring pushes and pulls only its `second` (child) particle: rope builders
/// use it to keep segment lengths equal under load, at the price of momentum
/// conservation.
///
/// The endpoints change only through [`Springs::push`] and
/// [`Springs::set_endpoints`], which give the springs a new
/// [`Springs::topology`]: what is built from the endpoints (the force's
/// thread schedule, the projective solver's factor, the contact exclusions)
/// knows by that number when to build again. Rest lengths, stiffnesses and
/// damping may be changed in place.
#[derive(Debug, Clone, Default)]
pub struct Springs {
    /// Index of the first (parent) particle of each spring.
    first: Vec<u32>,
    /// Index of the second (child) particle of each spring.
    second: Vec<u32>,
    /// Rest length of each spring (m), positive.
    pub rest_length: Vec<Real>,
    /// Stiffness of each spring (N/m), non-negative.
    pub stiffness: Vec<Real>,
    /// Damping along each spring (N·s/m), non-negative.
    pub damping: Vec<Real>,
    /// Whether each spring acts on its second particle only.
    pub one_sided: Vec<bool>,
    /// Whether each spring has broken ([`Springs::break_spring`]).
    broken: Vec<bool>,
    /// Which endpoints these are (see [`Springs::topology`]).
    topology: u64,
}

impl Springs {
    /// Number of springs.
    pub fn len(&self) -> usize {
        self.first.len()
    }

    /// True when there are no springs.
    pub fn is_empty(&self) -> bool {
        self.first.is_empty()
    }

    /// Append one spring between particles `first` and `second` with rest
    /// length (m), stiffness (N/m) and damping (N·s/m).
    pub fn push(
        &mut self,
        first: u32,
        second: u32,
        rest_length: Real,
        stiffness: Real,
        damping: Real,
        one_sided: bool,
    ) {
        self.first.push(first);
        self.second.push(second);
        self.topology = NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed);
        self.rest_length.push(rest_length);
        self.stiffness.push(stiffness);
        self.damping.push(damping);
        self.one_sided.push(one_sided);
        self.broken.push(false);
    }

    /// Index of the first (parent) particle of each spring.
    pub fn first(&self) -> &[u32] {
        &self.first
    }

    /// Index of the second (child) particle of each spring.
    pub fn second(&self) -> &[u32] {
        &self.second
    }

    /// The particles spring `s` joins, `[first, second]`.
    pub fn endpoints(&self, s: usize) -> [u32; 2] {
        [self.first[s], self.second[s]]
    }

    /// Join spring `s` to particles `first` and `second` instead.
    pub fn set_endpoints(&mut self, s: usize, first: u32, second: u32) {
        self.first[s] = first;
        self.second[s] = second;
        self.topology = NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed);
    }

    /// Break spring `s` for good: its stiffness and damping go to zero and
    /// it joins nothing from now on, so the springs get a new
    /// [`Springs::topology`] (what is built from them, the thread
    /// schedule, the implicit solvers' factor and the contact exclusions,
    /// is built again). Breaking a broken spring changes nothing.
    pub fn break_spring(&mut self, s: usize) {
        if self.broken[s] {
            return;
        }
        self.broken[s] = true;
        self.stiffness[s] = 0.0;
        self.damping[s] = 0.0;
        self.topology = NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed);
    }

    /// Whether spring `s` has broken ([`Springs::break_spring`]).
    pub fn is_broken(&self, s: usize) -> bool {
        self.broken[s]
    }

    /// Whether each spring has broken, in spring order.
    pub fn broken(&self) -> &[bool] {
        &self.broken
    }

    /// A number that changes whenever the endpoints do, and that no other
    /// set of endpoints has had in this process (a clone keeps it: its
    /// endpoints are the same); 0 for none ever pushed.
    pub fn topology(&self) -> u64 {
        self.topology
    }
}

/// The fewest springs in a row, each joining the particles one after its
/// predecessor's, that [`storage_order`] keeps together as a run: a vector
/// of the widest unit (8 reals).
pub const MIN_RUN: usize = 8;

/// The order a body's springs (`[first, second]` each) are stored in: first
/// the *runs* (in the body's own numbering), then every other spring by
/// lowest particle (then highest), the particles taken by `number` where
/// the body has one (a numbering for locality, `order::locality_numbering`:
/// the springs then come in the order the spring force reads its
/// particles in).
///
/// A run is at least [`MIN_RUN`] springs whose particles both step by one
/// from spring to spring (`[a, b]`, `[a + 1, b + 1]`, ...): a cloth's or a
/// lattice's springs of one direction along a row, a rope's. Runs are
/// listed by the offset `b - a`, then by first particle. The force reads a
/// run's particles as contiguous slices and adds into them the same way,
/// vectorised (`forces/spring/batch.rs`); the springs after the runs share
/// particles with their neighbours in the list, which the force sums
/// before adding them.
pub fn storage_order(ends: &[[u32; 2]], number: Option<&[u32]>) -> Vec<usize> {
    let offset = |[a, b]: [u32; 2]| i64::from(b) - i64::from(a);
    let renumber = |p: u32| number.map_or(p, |number| number[p as usize]);
    let lowest = |[a, b]: [u32; 2]| {
        let (a, b) = (renumber(a), renumber(b));
        (a.min(b), a.max(b))
    };
    // By offset, then first particle: a run's springs come one after the
    // other.
    let mut by_offset: Vec<usize> = (0..ends.len()).collect();
    by_offset.sort_by_key(|&s| (offset(ends[s]), ends[s][0], ends[s][1]));
    let mut in_run = vec![false; ends.len()];
    let mut start = 0;
    while start < by_offset.len() {
        let [a, b] = ends[by_offset[start]];
        let mut length = 1;
        while let Some(&next) = by_offset.get(start + length) {
            let step = length as u32;
            if ends[next] != [a.wrapping_add(step), b.wrapping_add(step)] {
                break;
            }
            length += 1;
        }
        if length >= MIN_RUN {
            by_offset[start..start + length]
                .iter()
                .for_each(|&s| in_run[s] = true);
        }
        start += length;
    }
    let mut rest: Vec<usize> = (0..ends.len()).filter(|&s| !in_run[s]).collect();
    rest.sort_by_key(|&s| lowest(ends[s]));
    by_offset.retain(|&s| in_run[s]);
    by_offset.extend(rest);
    by_offset
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn runs_come_first_by_offset_then_the_rest_by_lowest_particle() {
        // A row of 10 particles with its 9 neighbour springs (a run of
        // offset 1), its 8 two-apart springs (a run of offset 2), a spring
        // turned the other way in the middle of a third row that is too
        // short, and a lone far spring.
        let mut ends: Vec<[u32; 2]> = Vec::new();
        ends.push([9, 0]);
        ends.extend((0..8).map(|a| [a, a + 2]));
        ends.extend((0..9).rev().map(|a| [a, a + 1]));
        ends.extend([[0, 5], [1, 6], [7, 2], [3, 8]]);
        let order = storage_order(&ends, None);
        let stored: Vec<[u32; 2]> = order.iter().map(|&s| ends[s]).collect();
        let mut expected: Vec<[u32; 2]> = (0..9).map(|a| [a, a + 1]).collect();
        expected.extend((0..8).map(|a| [a, a + 2]));
        // The rest by (lowest, highest): [0, 5], [0, 9], [1, 6], [2, 7],
        // [3, 8].
        expected.extend([[0, 5], [9, 0], [1, 6], [7, 2], [3, 8]]);
        assert_eq!(stored, expected);
        // A permutation of the springs.
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..ends.len()).collect::<Vec<_>>());
    }
}
