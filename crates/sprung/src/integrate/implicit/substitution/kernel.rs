//! One supernode's forward and back substitution on dense columns.
//!
//! A supernode's columns share their rows below the diagonal block, so its
//! part of the right side (its own entries, then those of its rows below)
//! is copied once into [`Dense`], one array per axis, and the rows below
//! are gathered or scattered once per supernode, not once per column.
//! The columns are then taken [`BLOCK`] at a time: forwards, each block's
//! small triangle column by column, then one pass over the rows under it
//! subtracts the block's columns at once; backwards, one pass over the
//! rows after a block sums all of its columns' products, then its
//! triangle. Each value of the factor read serves three multiply-adds (x,
//! y, z), in the processor's widest vector unit ([`vectorised!`]). Only
//! the order of the sums differs from a substitution entry by entry (the
//! same result to rounding), and it is fixed ([`LANES`] partial sums, not
//! the vector unit's), so the bits are the same on any machine's threads.

use crate::units::{Real, Vec3};

/// Columns a pass over the rows below takes at once.
const BLOCK: usize = 4;

/// Partial sums of [`dot_block`]: a fixed number, so that its bits do not
/// depend on the vector unit.
const LANES: usize = 4;

/// A supernode's entries of the right side, one array per axis: its own
/// columns, then its rows below.
#[derive(Debug, Default, Clone)]
pub(super) struct Dense {
    x: Vec<Real>,
    y: Vec<Real>,
    z: Vec<Real>,
}

impl Dense {
    /// Room for supernodes of up to `height` rows (their width plus their
    /// rows below).
    pub fn with_height(height: usize) -> Dense {
        Dense {
            x: vec![0.0; height],
            y: vec![0.0; height],
            z: vec![0.0; height],
        }
    }

    /// The first `height` entries of each axis.
    fn axes(&mut self, height: usize) -> [&mut [Real]; 3] {
        [
            &mut self.x[..height],
            &mut self.y[..height],
            &mut self.z[..height],
        ]
    }
}

/// One supernode's values and rows.
pub(super) struct Supernode<'a> {
    /// Its width (columns).
    pub width: usize,
    /// Its rows below the diagonal block.
    pub rows: &'a [u32],
    /// How many of them are not the top's (they come first).
    pub inside: usize,
    /// Its values, column-major, `width + rows.len()` rows.
    pub values: &'a [Real],
}

impl Supernode<'_> {
    /// `L_s` forwards: its own entries `own` (its columns) solved, each
    /// push `L_rs v_s` on a row below subtracted from `below[row - end]`
    /// (`end` its last column + 1) or, for the top's rows, handed to
    /// `top(row, push)`.
    pub fn forward(
        &self,
        own: &mut [Vec3],
        (below, end): (&mut [Vec3], usize),
        mut top: impl FnMut(u32, Vec3),
        dense: &mut Dense,
    ) {
        let (width, height) = (self.width, self.width + self.rows.len());
        let [x, y, z] = dense.axes(height);
        for (k, o) in own[..width].iter().enumerate() {
            (x[k], y[k], z[k]) = (o.x, o.y, o.z);
        }
        for axis in [&mut *x, &mut *y, &mut *z] {
            axis[width..].fill(0.0);
        }
        forward_dense(self.values, width, [&mut *x, &mut *y, &mut *z]);
        let at = |k: usize| Vec3::new(x[k], y[k], z[k]);
        for (k, o) in own[..width].iter_mut().enumerate() {
            *o = at(k);
        }
        let (inside, outside) = self.rows.split_at(self.inside);
        for (k, &row) in inside.iter().enumerate() {
            below[row as usize - end] += at(width + k);
        }
        for (k, &row) in outside.iter().enumerate() {
            top(row, -at(width + self.inside + k));
        }
    }

    /// `L_sᵀ` backwards: its own entries solved, the rows below read from
    /// `below[row - end]` or, for the top's rows, by `top(row)`.
    pub fn backward(
        &self,
        own: &mut [Vec3],
        (below, end): (&[Vec3], usize),
        top: impl Fn(u32) -> Vec3,
        dense: &mut Dense,
    ) {
        let (width, height) = (self.width, self.width + self.rows.len());
        let [x, y, z] = dense.axes(height);
        let (inside, outside) = self.rows.split_at(self.inside);
        let entries = own[..width]
            .iter()
            .copied()
            .chain(inside.iter().map(|&row| below[row as usize - end]))
            .chain(outside.iter().map(|&row| top(row)));
        for (k, e) in entries.enumerate() {
            (x[k], y[k], z[k]) = (e.x, e.y, e.z);
        }
        backward_dense(self.values, width, [&mut *x, &mut *y, &mut *z]);
        for (k, o) in own[..width].iter_mut().enumerate() {
            *o = Vec3::new(x[k], y[k], z[k]);
        }
    }
}

vectorised! {
    /// Solve a supernode's `width` columns forwards in `axes` (its entries,
    /// as many as its rows), [`BLOCK`] columns at a time: each block's
    /// triangle column by column, then the rows under it take the block's
    /// columns at once (one pass over those rows a block, not a column).
    fn forward_dense(values: &[Real], width: usize, axes: [&mut [Real]; 3]) {
        let [x, y, z] = axes;
        let height = x.len();
        let mut j = 0;
        while j < width {
            let count = BLOCK.min(width - j);
            for c in j..j + count {
                let column = &values[c * height..(c + 1) * height];
                let d = column[c];
                (x[c], y[c], z[c]) = (x[c] / d, y[c] / d, z[c] / d);
                let v = [x[c], y[c], z[c]];
                for k in c + 1..j + count {
                    x[k] -= column[k] * v[0];
                    y[k] -= column[k] * v[1];
                    z[k] -= column[k] * v[2];
                }
            }
            let axes = [&mut *x, &mut *y, &mut *z];
            match count {
                4 => subtract_block::<4>(values, height, j, axes),
                3 => subtract_block::<3>(values, height, j, axes),
                2 => subtract_block::<2>(values, height, j, axes),
                _ => subtract_block::<1>(values, height, j, axes),
            }
            j += count;
        }
    }
}

vectorised! {
    /// Solve a supernode's `width` columns backwards in `axes` (as
    /// [`forward_dense`]), [`BLOCK`] columns at a time from the last: the
    /// block's columns' sums over the rows after it at once, then its
    /// triangle column by column.
    fn backward_dense(values: &[Real], width: usize, axes: [&mut [Real]; 3]) {
        let [x, y, z] = axes;
        let height = x.len();
        let mut end = width;
        while end > 0 {
            let count = BLOCK.min(end);
            let j = end - count;
            let after = [&x[end..], &y[end..], &z[end..]];
            let mut sums = [[0.0; 3]; BLOCK];
            match count {
                4 => sums = dot_block::<4>(values, height, j, after),
                3 => sums[..3].copy_from_slice(&dot_block::<3>(values, height, j, after)),
                2 => sums[..2].copy_from_slice(&dot_block::<2>(values, height, j, after)),
                _ => sums[..1].copy_from_slice(&dot_block::<1>(values, height, j, after)),
            }
            for c in (j..end).rev() {
                let column = &values[c * height..(c + 1) * height];
                let mut s = sums[c - j];
                for k in c + 1..end {
                    s[0] += column[k] * x[k];
                    s[1] += column[k] * y[k];
                    s[2] += column[k] * z[k];
                }
                let d = column[c];
                x[c] = (x[c] - s[0]) / d;
                y[c] = (y[c] - s[1]) / d;
                z[c] = (z[c] - s[2]) / d;
            }
            end = j;
        }
    }
}

/// The rows from `j + B` on less the pushes of the `B` solved columns
/// from `j`: `axis_k -= Σ_c L_kc v_c`, the sum in column order.
#[inline(always)]
fn subtract_block<const B: usize>(
    values: &[Real],
    height: usize,
    j: usize,
    axes: [&mut [Real]; 3],
) {
    let from = j + B;
    let [x, y, z] = axes;
    let v: [[Real; 3]; B] = std::array::from_fn(|c| [x[j + c], y[j + c], z[j + c]]);
    let rows = |c: usize| &values[(j + c) * height + from..(j + c + 1) * height];
    let (x, y, z) = (
        &mut x[from..height],
        &mut y[from..height],
        &mut z[from..height],
    );
    let along = x.iter_mut().zip(y.iter_mut()).zip(z.iter_mut());
    if B == 4 {
        let columns = rows(0).iter().zip(rows(1)).zip(rows(2)).zip(rows(3));
        for (((x, y), z), (((&a0, &a1), &a2), &a3)) in along.zip(columns) {
            *x -= a0 * v[0][0] + a1 * v[1][0] + a2 * v[2][0] + a3 * v[3][0];
            *y -= a0 * v[0][1] + a1 * v[1][1] + a2 * v[2][1] + a3 * v[3][1];
            *z -= a0 * v[0][2] + a1 * v[1][2] + a2 * v[2][2] + a3 * v[3][2];
        }
    } else {
        for (k, ((x, y), z)) in along.enumerate() {
            let a: [Real; B] = std::array::from_fn(|c| rows(c)[k]);
            let (mut px, mut py, mut pz) = (a[0] * v[0][0], a[0] * v[0][1], a[0] * v[0][2]);
            for c in 1..B {
                px += a[c] * v[c][0];
                py += a[c] * v[c][1];
                pz += a[c] * v[c][2];
            }
            *x -= px;
            *y -= py;
            *z -= pz;
        }
    }
}

/// `Σ_k L_kc axis_k` over the rows after the `B` columns from `j` (`after`
/// holds those rows' entries), for each column and axis, in [`LANES`]
/// partial sums added pairwise at the end.
#[inline(always)]
fn dot_block<const B: usize>(
    values: &[Real],
    height: usize,
    j: usize,
    after: [&[Real]; 3],
) -> [[Real; 3]; B] {
    let from = j + B;
    let n = height - from;
    let columns: [&[Real]; B] =
        std::array::from_fn(|c| &values[(j + c) * height + from..(j + c + 1) * height]);
    let [x, y, z] = after;
    let (x, y, z) = (&x[..n], &y[..n], &z[..n]);
    let mut sums = [[[0.0; LANES]; 3]; B];
    for c in 0..B {
        let [sx, sy, sz] = &mut sums[c];
        let chunks = chunk(columns[c]).zip(chunk(x)).zip(chunk(y)).zip(chunk(z));
        for (((a, x), y), z) in chunks {
            for lane in 0..LANES {
                sx[lane] += a[lane] * x[lane];
                sy[lane] += a[lane] * y[lane];
                sz[lane] += a[lane] * z[lane];
            }
        }
        let whole = n - n % LANES;
        for k in whole..n {
            let lane = k - whole;
            sx[lane] += columns[c][k] * x[k];
            sy[lane] += columns[c][k] * y[k];
            sz[lane] += columns[c][k] * z[k];
        }
    }
    let total = |s: [Real; LANES]| (s[0] + s[1]) + (s[2] + s[3]);
    sums.map(|[x, y, z]| [total(x), total(y), total(z)])
}

/// `v` in runs of [`LANES`] (the tail left out).
#[inline(always)]
fn chunk(v: &[Real]) -> impl Iterator<Item = [Real; LANES]> + '_ {
    v.chunks_exact(LANES)
        .map(|c| <[Real; LANES]>::try_from(c).unwrap_or_default())
}
