//! The forward and back substitutions of the factored `M + dt² L`
//! ([`Factor`](super::laplacian::Factor)) for particle vectors: the x, y
//! and z right sides together, over faer's supernodal factor, with its
//! elimination tree cut into subtrees that threads solve side by side.
//!
//! A substitution reads the whole factor once forwards and once back, and
//! at a few hundred thousand values and up that reading is its cost. The
//! three axes share the factor, so each value read serves three
//! multiply-adds here; faer's own solve, called per group of columns,
//! reads the factor again for each group.
//!
//! **Side by side, and the same bits.** A supernode's forward step writes
//! only to rows of its ancestors, and its backward step reads only them.
//! The supernodes near the root (the *top*) are set apart until the rest
//! falls into [`BINS`] groups of whole subtrees of about equal size, each a
//! range of columns. Forwards, each bin writes its own columns and adds
//! its pushes on the top's columns into a sum of its own; the top's rows
//! then take the bins' sums in bin order, and the top is solved in order.
//! Backwards, the top is solved first, then each bin reads it. The cut
//! depends on the factor's pattern alone, so every particle's arithmetic
//! is the same on any number of threads.

use std::ops::Range;

use faer::sparse::linalg::cholesky::simplicial::SymbolicSimplicialCholesky;
use faer::sparse::linalg::cholesky::supernodal::SymbolicSupernodalCholesky;

use crate::units::{Real, Vec3};

use kernel::{Dense, Supernode};

mod kernel;

/// Groups of subtrees solved side by side (fixed, not the threads', so that
/// the arithmetic does not depend on them).
pub const BINS: usize = 2;

/// The fewest values in the factor for its tree to be cut: below, one
/// thread's substitution takes little more than the threads would cost.
const SPLIT_VALUES: usize = 1 << 17;

/// Marks a column that is not the top's.
const NOT_TOP: u32 = u32::MAX;

/// The substitutions' plan: the factor's supernodes, the cut of its tree
/// and the buffers.
#[derive(Debug, Default)]
pub(super) struct Substitution {
    /// Supernode `s` holds the columns `column[s]..column[s + 1]`.
    column: Vec<usize>,
    /// Its rows below its diagonal block: `rows[row_start[s]..row_start[s + 1]]`.
    row_start: Vec<usize>,
    rows: Vec<u32>,
    /// How many of its rows below are not the top's: they come first, as
    /// the rows are in order and the top's columns are last on any path
    /// to the root.
    inside: Vec<usize>,
    /// Where its values start in the factor's values (column-major, its
    /// width's rows of the diagonal block, then `rows`).
    value_start: Vec<usize>,
    /// The groups of whole subtrees solved side by side.
    bins: Vec<Bin>,
    /// The supernodes above the bins, in order.
    top: Vec<u32>,
    /// Per column, its place among the top's columns, or [`NOT_TOP`].
    top_slot: Vec<u32>,
    /// The top's columns' values, read by the bins backwards.
    top_values: Vec<Vec3>,
    /// The top's scratch for one supernode's entries.
    top_dense: Dense,
}

/// A group of whole subtrees: their supernodes in order, over a range of
/// columns, with its sum of pushes on the top's columns.
#[derive(Debug, Default)]
struct Bin {
    supernodes: Vec<u32>,
    columns: Range<usize>,
    pushes: Vec<Vec3>,
    /// Scratch for one supernode's entries.
    dense: Dense,
}

impl Substitution {
    /// The plan for the factor `symbolic`. Its tree is cut only where each
    /// subtree is a range of supernodes (a postorder, which AMD's order
    /// gave on every cloth tried); else the plan is one serial group.
    pub fn new(symbolic: &SymbolicSupernodalCholesky<u32>) -> Substitution {
        Self::cut_from(symbolic, SPLIT_VALUES)
    }

    /// The plan for a simplicial factor (faer makes one where supernodes
    /// would not pay: few flops a column, as in a rope, a small cloth or a
    /// lone particle): a supernode per column, its diagonal value first.
    pub fn simplicial(symbolic: &SymbolicSimplicialCholesky<u32>) -> Substitution {
        let factor = symbolic.factor();
        let size = symbolic.nrows();
        let col_ptr: Vec<usize> = factor.col_ptr().iter().map(|&p| p as usize).collect();
        let mut plan = Substitution {
            column: (0..=size).collect(),
            row_start: Vec::with_capacity(size + 1),
            value_start: col_ptr.clone(),
            top_slot: vec![NOT_TOP; size],
            ..Substitution::default()
        };
        plan.row_start.push(0);
        for j in 0..size {
            let rows = &factor.row_idx()[col_ptr[j]..col_ptr[j + 1]];
            plan.rows.extend(rows.iter().filter(|&&r| r as usize != j));
            plan.row_start.push(plan.rows.len());
        }
        plan.cut(0, usize::MAX);
        plan
    }

    /// The plan, its tree cut when the factor has at least `split` values.
    fn cut_from(symbolic: &SymbolicSupernodalCholesky<u32>, split: usize) -> Substitution {
        let count = symbolic.n_supernodes();
        let mut plan = Substitution {
            column: Vec::with_capacity(count + 1),
            row_start: Vec::with_capacity(count + 1),
            value_start: symbolic.col_ptr_for_val()[..=count]
                .iter()
                .map(|&v| v as usize)
                .collect(),
            top_slot: vec![NOT_TOP; symbolic.nrows()],
            ..Substitution::default()
        };
        plan.row_start.push(0);
        for s in 0..count {
            let supernode = symbolic.supernode(s);
            plan.column.push(supernode.start());
            plan.rows.extend_from_slice(supernode.pattern());
            plan.row_start.push(plan.rows.len());
        }
        plan.column.push(symbolic.nrows());
        plan.cut(symbolic.len_val(), split);
        plan
    }

    /// Supernode `s` of the factor `values`.
    fn supernode<'a>(&'a self, s: usize, values: &'a [Real]) -> Supernode<'a> {
        Supernode {
            width: self.column[s + 1] - self.column[s],
            rows: &self.rows[self.row_start[s]..self.row_start[s + 1]],
            inside: self.inside[s],
            values: &values[self.value_start[s]..self.value_start[s + 1]],
        }
    }

    /// Cut the tree: the top and the bins (see the module's documentation);
    /// one bin of everything when the factor is small or its subtrees are
    /// not ranges of supernodes.
    fn cut(&mut self, values: usize, split: usize) {
        let count = self.column.len() - 1;
        let mut owner = vec![0; self.top_slot.len()];
        for s in 0..count {
            owner[self.column[s]..self.column[s + 1]].fill(s);
        }
        let parent: Vec<Option<usize>> = (0..count)
            .map(|s| {
                let (from, to) = (self.row_start[s], self.row_start[s + 1]);
                (from < to).then(|| owner[self.rows[from] as usize])
            })
            .collect();
        // Each subtree's values and first supernode.
        let mut weight: Vec<usize> = self.value_start.windows(2).map(|w| w[1] - w[0]).collect();
        let mut first: Vec<usize> = (0..count).collect();
        let mut size = vec![1; count];
        let mut ranges = true;
        for s in 0..count {
            if let Some(p) = parent[s] {
                ranges &= p > s;
                weight[p] += weight[s];
                first[p] = first[p].min(first[s]);
                size[p] += size[s];
            }
        }
        ranges &= (0..count).all(|s| size[s] == s - first[s] + 1);
        let mut roots: Vec<usize> = (0..count).filter(|&s| parent[s].is_none()).collect();
        let mut top = Vec::new();
        let split = ranges && values >= split;
        if split {
            let mut children = vec![Vec::new(); count];
            for (s, p) in parent.iter().enumerate() {
                if let Some(p) = *p {
                    children[p].push(s);
                }
            }
            // Set the heaviest subtree's root apart until the subtrees fall
            // into BINS runs of about equal weight.
            while let Some(&heaviest) = roots.iter().max_by_key(|&&r| (weight[r], r)) {
                let loads = runs(&roots, &weight).map(|run| run.iter().map(|&r| weight[r]).sum());
                let most = loads.into_iter().max().unwrap_or(0);
                let total: usize = roots.iter().map(|&r| weight[r]).sum();
                if 10 * most <= 11 * total.div_ceil(BINS) || weight[heaviest] * 8 * BINS < values {
                    break;
                }
                roots.retain(|&r| r != heaviest);
                roots.extend(&children[heaviest]);
                roots.sort_unstable();
                top.push(heaviest as u32);
            }
        }
        top.sort_unstable();
        let is_top = {
            let mut is_top = vec![false; count];
            top.iter().for_each(|&s| is_top[s as usize] = true);
            is_top
        };
        self.bins = if split {
            runs(&roots, &weight)
                .into_iter()
                .filter(|run| !run.is_empty())
                .map(|run| {
                    let (from, to) = (first[run[0]], run[run.len() - 1]);
                    Bin {
                        supernodes: (from..=to)
                            .filter(|&s| !is_top[s])
                            .map(|s| s as u32)
                            .collect(),
                        columns: self.column[from]..self.column[to + 1],
                        pushes: Vec::new(),
                        dense: Dense::default(),
                    }
                })
                .collect()
        } else {
            vec![Bin {
                supernodes: (0..count as u32).collect(),
                columns: 0..self.top_slot.len(),
                pushes: Vec::new(),
                dense: Dense::default(),
            }]
        };
        let mut slot = 0;
        for &s in &top {
            for c in self.column[s as usize]..self.column[s as usize + 1] {
                self.top_slot[c] = slot;
                slot += 1;
            }
        }
        self.inside = (0..count)
            .map(|s| {
                let rows = &self.rows[self.row_start[s]..self.row_start[s + 1]];
                match is_top[s] {
                    true => rows.len(),
                    false => rows.partition_point(|&r| self.top_slot[r as usize] == NOT_TOP),
                }
            })
            .collect();
        self.top = top;
        self.top_values = vec![Vec3::ZERO; slot as usize];
        let height = |s: usize| {
            self.column[s + 1] - self.column[s] + self.row_start[s + 1] - self.row_start[s]
        };
        let tallest = |supernodes: &[u32]| {
            supernodes
                .iter()
                .map(|&s| height(s as usize))
                .max()
                .unwrap_or(0)
        };
        self.top_dense = Dense::with_height(tallest(&self.top));
        for bin in &mut self.bins {
            bin.pushes = vec![Vec3::ZERO; slot as usize];
            bin.dense = Dense::with_height(tallest(&bin.supernodes));
        }
    }

    /// Solve `L Lᵀ y = b` in place (`y` holds `b`, in the factor's order of
    /// columns), `values` the factor's.
    pub fn solve(&mut self, values: &[Real], y: &mut [Vec3]) {
        // Forwards: the bins side by side, then the top.
        let mut bins = std::mem::take(&mut self.bins);
        let this = &*self;
        each_bin(&mut bins, y, 0, &|bin, own| {
            bin.pushes.fill(Vec3::ZERO);
            let offset = bin.columns.start;
            for &s in &bin.supernodes {
                let s = s as usize;
                let (start, end) = (this.column[s] - offset, this.column[s + 1] - offset);
                let (own_columns, below) = own.split_at_mut(end);
                let pushes = &mut bin.pushes;
                this.supernode(s, values).forward(
                    &mut own_columns[start..],
                    (below, end + offset),
                    |row, push| pushes[this.top_slot[row as usize] as usize] += push,
                    &mut bin.dense,
                );
            }
        });
        for (slot, c) in self.top_columns().enumerate() {
            for bin in &bins {
                y[c] -= bin.pushes[slot];
            }
        }
        let mut dense = std::mem::take(&mut self.top_dense);
        self.solve_top(values, y, &mut dense);
        self.top_dense = dense;
        // Backwards: the top, then the bins side by side reading it.
        let mut top_values = std::mem::take(&mut self.top_values);
        for (slot, c) in self.top_columns().enumerate() {
            top_values[slot] = y[c];
        }
        let this = &*self;
        each_bin(&mut bins, y, 0, &|bin, own| {
            let offset = bin.columns.start;
            for &s in bin.supernodes.iter().rev() {
                let s = s as usize;
                let (start, end) = (this.column[s] - offset, this.column[s + 1] - offset);
                let (own_columns, below) = own.split_at_mut(end);
                this.supernode(s, values).backward(
                    &mut own_columns[start..],
                    (&*below, end + offset),
                    |row| top_values[this.top_slot[row as usize] as usize],
                    &mut bin.dense,
                );
            }
        });
        self.bins = bins;
        self.top_values = top_values;
    }

    /// What one [`Substitution::solve`] reads of the factor and computes,
    /// forwards and back: the bytes of the values it reads (each column
    /// from its diagonal down) and of its supernodes' row indices, and its
    /// multiply-adds (three a value off the diagonal).
    pub fn cost(&self) -> (f64, f64) {
        let (mut read, mut products, mut rows) = (0.0, 0.0, 0.0);
        for s in 0..self.column.len() - 1 {
            let width = (self.column[s + 1] - self.column[s]) as f64;
            let below = (self.row_start[s + 1] - self.row_start[s]) as f64;
            let touched = width * (width + below) - width * (width - 1.0) / 2.0;
            read += touched;
            products += touched - width;
            rows += below;
        }
        let bytes = 2.0 * (read * size_of::<Real>() as f64 + rows * size_of::<u32>() as f64);
        (bytes, 2.0 * 3.0 * products)
    }

    /// The top's columns, in the order of their slots.
    fn top_columns(&self) -> impl Iterator<Item = usize> + '_ {
        self.top
            .iter()
            .flat_map(|&s| self.column[s as usize]..self.column[s as usize + 1])
    }

    /// The top's supernodes forwards then backwards, in order: their rows
    /// below are the top's own.
    fn solve_top(&self, values: &[Real], y: &mut [Vec3], dense: &mut Dense) {
        for &s in &self.top {
            let s = s as usize;
            let (start, end) = (self.column[s], self.column[s + 1]);
            let (head, below) = y.split_at_mut(end);
            self.supernode(s, values)
                .forward(&mut head[start..], (below, end), |_, _| (), dense);
        }
        for &s in self.top.iter().rev() {
            let s = s as usize;
            let (start, end) = (self.column[s], self.column[s + 1]);
            let (head, below) = y.split_at_mut(end);
            self.supernode(s, values).backward(
                &mut head[start..],
                (&*below, end),
                |_| Vec3::ZERO,
                dense,
            );
        }
    }
}

/// `f(bin, its columns of y)` for each bin, side by side on the pool
/// (`y` from column `at` on; the bins' columns are disjoint and in order).
fn each_bin(
    bins: &mut [Bin],
    y: &mut [Vec3],
    at: usize,
    f: &(impl Fn(&mut Bin, &mut [Vec3]) + Sync),
) {
    let Some((first, rest)) = bins.split_first_mut() else {
        return;
    };
    let (_, tail) = y.split_at_mut(first.columns.start - at);
    let (own, tail) = tail.split_at_mut(first.columns.len());
    let at = first.columns.end;
    if rest.is_empty() {
        f(first, own);
    } else if rayon::current_num_threads() > 1 {
        rayon::join(|| f(first, own), || each_bin(rest, tail, at, f));
    } else {
        f(first, own);
        each_bin(rest, tail, at, f);
    }
}

/// `roots` (in order) cut into [`BINS`] runs of consecutive roots, each run
/// closed once it reaches its share of the weight.
fn runs<'a>(roots: &'a [usize], weight: &[usize]) -> [&'a [usize]; BINS] {
    let total: usize = roots.iter().map(|&r| weight[r]).sum();
    let share = total.div_ceil(BINS).max(1);
    let mut out: [&[usize]; BINS] = [&[]; BINS];
    let (mut start, mut load, mut bin) = (0, 0, 0);
    for (k, &r) in roots.iter().enumerate() {
        load += weight[r];
        if load >= share && bin + 1 < BINS {
            out[bin] = &roots[start..=k];
            (start, load, bin) = (k + 1, 0, bin + 1);
        }
    }
    out[bin] = &roots[start..];
    out
}

#[cfg(test)]
mod tests;
