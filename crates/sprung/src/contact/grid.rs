//! The broad phase: a uniform grid of cubic cells over space, stored as a
//! hash table in compressed rows (counting sort), rebuilt once per step.
//! An element (a triangle, an edge, a particle grown by the contact
//! distance) is entered in every cell its bounding box overlaps; a query
//! visits the elements of the cells a box overlaps. Building and querying
//! cost time linear in the number of entries; the buffers are kept, so a
//! step allocates nothing once they have grown. Entries keep the order of
//! the elements, so the candidates come out in the same order whatever the
//! hashing.

use crate::{Real, Vec3};

/// Most cells one box may cover along an axis: a larger box is entered in,
/// and queries, only the first this many, so the elements beyond them are
/// not found through it ([`Grid::capped`] tells when; a caller that must
/// find them looks at every element instead).
const MAX_CELLS_PER_AXIS: i64 = 16;

/// A uniform grid over boxes, hashed into compressed rows.
#[derive(Debug, Clone, Default)]
pub struct Grid {
    /// Cell side (m).
    cell: Real,
    /// Per bucket, the start of its entries (one more than the buckets).
    start: Vec<u32>,
    /// Entries `(cell key, element)`, grouped by bucket.
    entries: Vec<(u64, u32)>,
    /// Scratch: the entries before grouping.
    scratch: Vec<(u64, u32)>,
    /// Scratch: the next free place of each bucket while filling.
    fill: Vec<u32>,
    /// Per element, the lowest cell it was entered in.
    lowest: Vec<[i64; 3]>,
}

/// The integer cell of coordinate `x` (m) in cells of side `cell`.
fn cell_of(x: Real, cell: Real) -> i64 {
    (x / cell).floor().clamp(-1e15, 1e15) as i64
}

/// A key for cell `(i, j, k)`: the three coordinates folded into 64 bits
/// and mixed (the finaliser of SplitMix64), so that neighbouring cells land
/// in unrelated buckets.
fn key(i: i64, j: i64, k: i64) -> u64 {
    let mut h = (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (j as u64)
            .wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
            .rotate_left(21)
        ^ (k as u64)
            .wrapping_mul(0x1656_67B1_9E37_79F9)
            .rotate_left(42);
    h ^= h >> 30;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 27;
    h = h.wrapping_mul(0x94D0_49BB_1331_11EB);
    h ^ (h >> 31)
}

/// The cell ranges `[lo, hi]` a box covers, capped per axis.
fn cell_range(low: Vec3, high: Vec3, cell: Real) -> ([i64; 3], [i64; 3]) {
    let lo = [
        cell_of(low.x, cell),
        cell_of(low.y, cell),
        cell_of(low.z, cell),
    ];
    let mut hi = [
        cell_of(high.x, cell),
        cell_of(high.y, cell),
        cell_of(high.z, cell),
    ];
    for axis in 0..3 {
        hi[axis] = hi[axis].clamp(lo[axis], lo[axis] + MAX_CELLS_PER_AXIS - 1);
    }
    (lo, hi)
}

impl Grid {
    /// Rebuild the grid with cells of side `cell` (m) over `boxes`: element
    /// `e` (its index in the iterator) covers the box `(low, high)` (m).
    pub fn build(&mut self, cell: Real, boxes: impl Iterator<Item = (Vec3, Vec3)>) {
        self.cell = cell;
        self.scratch.clear();
        self.lowest.clear();
        for (element, (low, high)) in boxes.enumerate() {
            let (lo, hi) = cell_range(low, high, cell);
            self.lowest.push(lo);
            for i in lo[0]..=hi[0] {
                for j in lo[1]..=hi[1] {
                    for k in lo[2]..=hi[2] {
                        self.scratch.push((key(i, j, k), element as u32));
                    }
                }
            }
        }
        let buckets = (2 * self.scratch.len()).max(1).next_power_of_two();
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for &(key, _) in &self.scratch {
            self.start[bucket(key, buckets) + 1] += 1;
        }
        for b in 0..buckets {
            self.start[b + 1] += self.start[b];
        }
        self.entries.clear();
        self.entries.resize(self.scratch.len(), (0, 0));
        // Fill each bucket in element order (a stable counting sort).
        self.fill.clear();
        self.fill.extend_from_slice(&self.start);
        for &(key, element) in &self.scratch {
            let b = bucket(key, buckets);
            self.entries[self.fill[b] as usize] = (key, element);
            self.fill[b] += 1;
        }
    }

    /// Call `visit` with each element entered in a cell that the box
    /// `(low, high)` (m) overlaps; an element may come more than once (one
    /// per shared cell), and an element of another cell that hashes to the
    /// same bucket never does.
    pub fn query(&self, low: Vec3, high: Vec3, mut visit: impl FnMut(u32)) {
        self.query_cells(low, high, |_, element| visit(element));
    }

    /// Like [`Grid::query`], but only the elements `wanted` says, each at
    /// most once: in the lowest cell (per axis) that it shares with the box
    /// `(low, high)` (m), which is the first such cell the query visits.
    /// The elements come in the same order as the first visits of
    /// [`Grid::query`].
    pub fn query_once(
        &self,
        low: Vec3,
        high: Vec3,
        wanted: impl Fn(u32) -> bool,
        mut visit: impl FnMut(u32),
    ) {
        let lo = cell_range(low, high, self.cell).0;
        self.query_cells(low, high, |cell, element| {
            if !wanted(element) {
                return;
            }
            let own = self.lowest[element as usize];
            if (0..3).all(|axis| cell[axis] == lo[axis].max(own[axis])) {
                visit(element);
            }
        });
    }

    /// Whether the box `(low, high)` (m) spans more cells along an axis than
    /// one query visits (16).
    pub fn capped(&self, low: Vec3, high: Vec3) -> bool {
        let (low, high) = (low.to_array(), high.to_array());
        (0..3).any(|axis| {
            cell_of(high[axis], self.cell) - cell_of(low[axis], self.cell) >= MAX_CELLS_PER_AXIS
        })
    }

    /// Call `visit(cell, element)` for each element entered in a cell of
    /// the box `(low, high)` (m), with that cell.
    fn query_cells(&self, low: Vec3, high: Vec3, mut visit: impl FnMut([i64; 3], u32)) {
        let buckets = self.start.len().saturating_sub(1);
        if buckets == 0 || self.entries.is_empty() {
            return;
        }
        let (lo, hi) = cell_range(low, high, self.cell);
        for i in lo[0]..=hi[0] {
            for j in lo[1]..=hi[1] {
                for k in lo[2]..=hi[2] {
                    let wanted = key(i, j, k);
                    let b = bucket(wanted, buckets);
                    let range = self.start[b] as usize..self.start[b + 1] as usize;
                    for &(entry_key, element) in &self.entries[range] {
                        if entry_key == wanted {
                            visit([i, j, k], element);
                        }
                    }
                }
            }
        }
    }
}

/// The bucket of `key` in a table of `buckets` (a power of two).
fn bucket(key: u64, buckets: usize) -> usize {
    (key & (buckets as u64 - 1)) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_overlapping_box_is_found_and_far_ones_are_not() {
        let boxes: Vec<(Vec3, Vec3)> = (0..50)
            .map(|i| {
                let low = Vec3::new(i as Real * 0.3, (i % 7) as Real * 0.2, 0.0);
                (low, low + Vec3::splat(0.25))
            })
            .collect();
        let mut grid = Grid::default();
        grid.build(0.25, boxes.iter().copied());
        let overlaps =
            |a: (Vec3, Vec3), b: (Vec3, Vec3)| a.0.cmple(b.1).all() && b.0.cmple(a.1).all();
        for (q, query) in boxes.iter().enumerate() {
            let mut found = vec![false; boxes.len()];
            grid.query(query.0, query.1, |e| found[e as usize] = true);
            for (e, other) in boxes.iter().enumerate() {
                if overlaps(*query, *other) {
                    assert!(found[e], "box {q} misses its overlap with {e}");
                }
            }
            assert!(found[q]);
        }
        // A box far from everything finds nothing.
        let mut any = false;
        grid.query(Vec3::splat(100.0), Vec3::splat(100.1), |_| any = true);
        assert!(!any);
    }

    #[test]
    fn query_once_visits_each_element_once_in_first_visit_order() {
        // Boxes spanning several cells, so that pairs share many cells.
        let boxes: Vec<(Vec3, Vec3)> = (0..60)
            .map(|i| {
                let low = Vec3::new(
                    i as Real * 0.07,
                    (i % 5) as Real * 0.11,
                    (i % 3) as Real * 0.05,
                );
                (low, low + Vec3::new(0.3, 0.2, 0.25))
            })
            .collect();
        let mut grid = Grid::default();
        grid.build(0.1, boxes.iter().copied());
        for query in &boxes {
            let mut first_visits = Vec::new();
            grid.query(query.0, query.1, |e| {
                if !first_visits.contains(&e) {
                    first_visits.push(e);
                }
            });
            let mut once = Vec::new();
            grid.query_once(query.0, query.1, |_| true, |e| once.push(e));
            assert_eq!(once, first_visits);
        }
    }
}
