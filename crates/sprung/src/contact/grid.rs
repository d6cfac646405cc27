//! The broad phase: a uniform grid of cubic cells over space, stored in
//! compressed rows (counting sort), rebuilt once per step. An element (a
//! triangle, an edge, a particle grown by the contact distance) is entered
//! in every cell its bounding box overlaps; a query visits the elements of
//! the cells a box overlaps. Building and querying cost time linear in the
//! number of entries; the buffers are kept, so a step allocates nothing
//! once they have grown. Entries keep the order of the elements, so the
//! candidates come out in the same order whatever the layout.
//!
//! Two layouts, chosen at each build. Where the cells the elements cover
//! fit in a box of at most four cells per entry (or 4096 cells: a pile of
//! bodies, a cloth), every cell of that box has its row, in order along
//! `z` within each `(x, y)` column: a query reads each column's cells as
//! one slice, with no hashing and no other cell's entries. Elsewhere
//! (bodies far apart, whose box of cells would be mostly empty) the cells
//! are hashed into buckets, a power of two at least twice the entries.
//! Both visit the same elements in the same order (unless two cells' 64-bit
//! hashes are equal, when the hashed layout also visits the other cell's
//! elements: candidates that the callers' own tests turn away). An empty
//! box (its low corner above its high one on some axis, or NaN) is
//! entered in no cell.

use crate::units::{Real, Vec3};

/// Most cells one box may cover along an axis: a larger box is entered in,
/// and queries, only the first this many, so the elements beyond them are
/// not found through it ([`Grid::query_unless_capped`] tells when; a
/// caller that must find them looks at every element instead).
const MAX_CELLS_PER_AXIS: i64 = 16;

/// Most cells per entry for the dense layout (a box of cells this many
/// times the entries or fewer, or [`DENSE_CELLS_MIN`]).
const DENSE_CELLS_PER_ENTRY: usize = 4;

/// The dense layout may always have this many cells.
const DENSE_CELLS_MIN: usize = 4096;

/// The box of cells of the dense layout: its lowest cell and its cells per
/// axis.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Dense {
    origin: [i64; 3],
    size: [i64; 3],
}

impl Dense {
    /// The row of cell `(i, j, k)` (inside the box).
    fn row(&self, i: i64, j: i64, k: i64) -> u64 {
        let [x, y, z] = [i - self.origin[0], j - self.origin[1], k - self.origin[2]];
        ((x * self.size[1] + y) * self.size[2] + z) as u64
    }

    /// The part of the cells `lo..=hi` of an axis inside the box.
    fn clamp(&self, axis: usize, lo: i64, hi: i64) -> (i64, i64) {
        let last = self.origin[axis] + self.size[axis] - 1;
        (lo.max(self.origin[axis]), hi.min(last))
    }
}

/// A uniform grid over boxes, in compressed rows.
#[derive(Debug, Clone, Default)]
pub struct Grid {
    /// Cell side (m).
    cell: Real,
    /// The dense layout's box of cells; `None`: hashed.
    dense: Option<Dense>,
    /// Per row (a bucket of hashed cells, or a cell of the dense layout),
    /// the start of its entries (one more than the rows).
    start: Vec<u32>,
    /// Entries `(cell key, element)`, grouped by row (the key is the
    /// cell's hash, or its row in the dense layout).
    entries: Vec<(u64, u32)>,
    /// Scratch: the entries before grouping.
    scratch: Vec<(u64, u32)>,
    /// Scratch: the next free place of each bucket while filling.
    fill: Vec<u32>,
    /// Per element, the lowest cell it was entered in, and the highest.
    lowest: Vec<[i64; 3]>,
    highest: Vec<[i64; 3]>,
}

/// The integer cell of coordinate `x` (m) in cells of side `cell`: the
/// floor of `x / cell`, within ±10¹⁵ (0 for NaN). Rounded by a cast and a
/// correction: `floor` itself is a call into the system's maths library
/// on the baseline x86-64 the engine is built for, and it was a tenth of
/// the pair search.
fn cell_of(x: Real, cell: Real) -> i64 {
    let ratio = (x / cell).clamp(-1e15, 1e15);
    let toward_zero = ratio as i64;
    if (toward_zero as Real) > ratio {
        toward_zero - 1
    } else {
        toward_zero
    }
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
        self.highest.clear();
        let (mut least, mut most) = ([i64::MAX; 3], [i64::MIN; 3]);
        let mut entered = 0usize;
        for (low, high) in boxes {
            if !low.cmple(high).all() {
                // Empty: no cell (the loops below run over none).
                self.lowest.push([0; 3]);
                self.highest.push([-1; 3]);
                continue;
            }
            let (lo, hi) = cell_range(low, high, cell);
            self.lowest.push(lo);
            self.highest.push(hi);
            entered += (0..3)
                .map(|a| (hi[a] - lo[a] + 1) as usize)
                .product::<usize>();
            for axis in 0..3 {
                least[axis] = least[axis].min(lo[axis]);
                most[axis] = most[axis].max(hi[axis]);
            }
        }
        self.dense = dense_box(least, most, entered);
        let dense = self.dense;
        for (element, (lo, hi)) in self.lowest.iter().zip(&self.highest).enumerate() {
            for i in lo[0]..=hi[0] {
                for j in lo[1]..=hi[1] {
                    for k in lo[2]..=hi[2] {
                        let key = dense.map_or_else(|| key(i, j, k), |d| d.row(i, j, k));
                        self.scratch.push((key, element as u32));
                    }
                }
            }
        }
        let buckets = match dense {
            Some(d) => d.size.iter().product::<i64>() as usize,
            None => (2 * self.scratch.len()).max(1).next_power_of_two(),
        };
        // A dense layout's keys are its rows.
        let bucket = |key: u64| match dense {
            Some(_) => key as usize,
            None => bucket(key, buckets),
        };
        self.start.clear();
        self.start.resize(buckets + 1, 0);
        for &(key, _) in &self.scratch {
            self.start[bucket(key) + 1] += 1;
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
            let b = bucket(key);
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

    /// Like [`Grid::query`], if the box `(low, high)` (m) spans at most as
    /// many cells along each axis as one query visits (16): `false`, and
    /// nothing visited, if it spans more.
    pub fn query_unless_capped(&self, low: Vec3, high: Vec3, mut visit: impl FnMut(u32)) -> bool {
        let (lo, hi) = (self.cell_of(low), self.cell_of(high));
        if (0..3).any(|axis| hi[axis] - lo[axis] >= MAX_CELLS_PER_AXIS) {
            return false;
        }
        self.visit_cells(lo, hi, |_, element| visit(element));
        true
    }

    /// The cell of point `x` (m).
    fn cell_of(&self, x: Vec3) -> [i64; 3] {
        x.to_array().map(|x| cell_of(x, self.cell))
    }

    /// Call `visit(cell, element)` for each element entered in a cell of
    /// the box `(low, high)` (m), with that cell.
    fn query_cells(&self, low: Vec3, high: Vec3, visit: impl FnMut([i64; 3], u32)) {
        let (lo, hi) = cell_range(low, high, self.cell);
        self.visit_cells(lo, hi, visit);
    }

    /// Call `visit(cell, element)` for each element entered in a cell of
    /// `lo..=hi`, with that cell.
    fn visit_cells(&self, lo: [i64; 3], hi: [i64; 3], mut visit: impl FnMut([i64; 3], u32)) {
        let buckets = self.start.len().saturating_sub(1);
        if buckets == 0 || self.entries.is_empty() {
            return;
        }
        if let Some(dense) = self.dense {
            let ([i0, j0, k0], [i1, j1, k1]) = (lo, hi);
            let (i0, i1) = dense.clamp(0, i0, i1);
            let (j0, j1) = dense.clamp(1, j0, j1);
            let (k0, k1) = dense.clamp(2, k0, k1);
            if k0 > k1 {
                return;
            }
            for i in i0..=i1 {
                for j in j0..=j1 {
                    // The column's cells k0..=k1 are consecutive rows.
                    let first = dense.row(i, j, k0);
                    let rows = first as usize..first as usize + (k1 - k0) as usize + 1;
                    let range = self.start[rows.start] as usize..self.start[rows.end] as usize;
                    for &(row, element) in &self.entries[range] {
                        visit([i, j, k0 + (row - first) as i64], element);
                    }
                }
            }
            return;
        }
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

/// The dense layout over the cells `least..=most` holding `entered`
/// entries, if its box of cells is small enough.
fn dense_box(least: [i64; 3], most: [i64; 3], entered: usize) -> Option<Dense> {
    let limit = entered
        .saturating_mul(DENSE_CELLS_PER_ENTRY)
        .max(DENSE_CELLS_MIN);
    let mut size = [0i64; 3];
    let mut cells = 1usize;
    for axis in 0..3 {
        // No element: no box.
        let span = most[axis].checked_sub(least[axis])?.checked_add(1)?;
        if span <= 0 {
            return None;
        }
        size[axis] = span;
        cells = cells.checked_mul(usize::try_from(span).ok()?)?;
        if cells > limit {
            return None;
        }
    }
    Some(Dense {
        origin: least,
        size,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `boxes` as they are (a dense layout), and with one more box far
    /// away, which makes the box of cells too large for it (hashed).
    fn both_layouts(boxes: &[(Vec3, Vec3)], cell: Real) -> [Grid; 2] {
        let far = (Vec3::splat(1e4), Vec3::splat(1e4 + cell));
        let mut dense = Grid::default();
        dense.build(cell, boxes.iter().copied());
        let mut hashed = Grid::default();
        hashed.build(cell, boxes.iter().copied().chain([far]));
        assert!(dense.dense.is_some() && hashed.dense.is_none());
        [dense, hashed]
    }

    #[test]
    fn every_overlapping_box_is_found_and_far_ones_are_not() {
        let boxes: Vec<(Vec3, Vec3)> = (0..50)
            .map(|i| {
                let low = Vec3::new(i as Real * 0.3, (i % 7) as Real * 0.2, 0.0);
                (low, low + Vec3::splat(0.25))
            })
            .collect();
        let overlaps =
            |a: (Vec3, Vec3), b: (Vec3, Vec3)| a.0.cmple(b.1).all() && b.0.cmple(a.1).all();
        for grid in both_layouts(&boxes, 0.25) {
            for (q, query) in boxes.iter().enumerate() {
                let mut found = vec![false; boxes.len() + 1];
                grid.query(query.0, query.1, |e| found[e as usize] = true);
                for (e, other) in boxes.iter().enumerate() {
                    if overlaps(*query, *other) {
                        assert!(found[e], "box {q} misses its overlap with {e}");
                    }
                }
                assert!(found[q]);
            }
            // A box far from everything finds nothing, also beyond the
            // dense layout's cells.
            for at in [100.0, -100.0] {
                let mut any = false;
                grid.query(Vec3::splat(at), Vec3::splat(at + 0.1), |_| any = true);
                assert!(!any);
            }
        }
    }

    #[test]
    fn a_cell_is_the_floor_of_the_coordinate_over_the_side() {
        // Claim: the cast-and-correct rounding of `cell_of` is the floor,
        // clamped to ±1e15: on whole and half multiples of the side, on
        // both sides of zero, next to whole multiples, far out, and NaN.
        let cell = 0.1;
        let mut values = vec![0.0, -0.0, 1e300, -1e300, Real::NAN, Real::INFINITY];
        for k in -50..=50 {
            let x = Real::from(k) * cell;
            values.extend([x, x + 0.5 * cell, x.next_up(), x.next_down()]);
        }
        for x in values {
            let floor = (x / cell).floor().clamp(-1e15, 1e15) as i64;
            assert_eq!(cell_of(x, cell), floor, "{x}");
        }
    }

    #[test]
    fn both_layouts_visit_the_same_elements_in_the_same_order() {
        // Claim: the dense layout and the hashed one give every query the
        // same sequence of (cell, element) visits, so the pairs found, and
        // the bits of a run, do not depend on the layout. Boxes of many
        // sizes, some spanning more cells than a query visits (capped),
        // queried by each box and by boxes reaching past the grid.
        let boxes: Vec<(Vec3, Vec3)> = (0..200)
            .map(|i| {
                let low = Vec3::new(
                    (i % 13) as Real * 0.07 - 0.3,
                    (i % 5) as Real * 0.11,
                    (i % 7) as Real * -0.05,
                );
                let size = 0.02 + 0.3 * ((i * 37) % 11) as Real / 10.0;
                (low, low + Vec3::new(size, 0.5 * size, 2.0 * size))
            })
            .collect();
        let [dense, hashed] = both_layouts(&boxes, 0.05);
        let mut queries = boxes.clone();
        queries.push((Vec3::new(-0.35, -0.05, -0.4), Vec3::new(0.4, 0.5, 0.3)));
        queries.push((Vec3::new(0.5, -0.2, -0.1), Vec3::new(0.6, 0.4, 0.0)));
        for query in &queries {
            let visits = |grid: &Grid| {
                let mut seen = Vec::new();
                grid.query_cells(query.0, query.1, |cell, e| seen.push((cell, e)));
                seen
            };
            let seen = visits(&dense);
            assert!(!seen.is_empty(), "query {query:?} found nothing");
            assert_eq!(seen, visits(&hashed), "query {query:?}");
        }
    }

    #[test]
    fn a_query_unless_capped_is_a_query_or_refuses_a_box_too_wide() {
        // Claim: on both layouts, a box spanning at most 16 cells along
        // each axis is visited exactly as `query` visits it, and a box
        // spanning more is refused (false) with nothing visited, where
        // `query` would have missed the elements beyond its 16 cells. An
        // empty box is entered in no cell.
        let cell = 0.1;
        let mut boxes: Vec<(Vec3, Vec3)> = (0..40)
            .map(|i| {
                let low = Vec3::new((i % 10) as Real * 0.15, (i / 10) as Real * 0.2, 0.0);
                (low, low + Vec3::splat(0.12))
            })
            .collect();
        boxes.push((Vec3::splat(0.5), Vec3::splat(0.4)));
        let empty = boxes.len() as u32 - 1;
        for grid in both_layouts(&boxes, cell) {
            for query in &boxes[..boxes.len() - 1] {
                let (mut all, mut unless) = (Vec::new(), Vec::new());
                grid.query(query.0, query.1, |e| all.push(e));
                assert!(grid.query_unless_capped(query.0, query.1, |e| unless.push(e)));
                assert_eq!(all, unless);
                assert!(!all.contains(&empty));
            }
            // 15 cells wide: still a query; 17 wide: refused.
            let low = Vec3::new(0.0, 0.0, 0.0);
            let mut seen = 0;
            let fits = (low, low + Vec3::new(1.45, 0.05, 0.05));
            assert!(grid.query_unless_capped(fits.0, fits.1, |_| seen += 1));
            assert!(seen > 0);
            let wide = (low, low + Vec3::new(1.65, 0.05, 0.05));
            assert!(!grid.query_unless_capped(wide.0, wide.1, |_| seen = 0));
            assert!(seen > 0);
        }
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
        for grid in both_layouts(&boxes, 0.1) {
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
}
