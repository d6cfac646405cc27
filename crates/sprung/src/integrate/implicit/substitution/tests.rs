//! The substitutions against faer's own solve of the same factor.

use super::*;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};

/// A cloth's `M + dt² L`: an `n × n` grid, springs to the 8 neighbours
/// and the second ones along the rows and columns, `dt² k = 5.6 kg`,
/// `m = 1e-5 kg` (the stiff 128² cloth's ratio).
fn cloth_matrix(n: usize) -> SparseColMat<u32, Real> {
    let (h2k, m) = (5.6, 1e-5);
    let at = |i: usize, j: usize| (i * n + j) as u32;
    let mut diagonal = vec![m; n * n];
    let mut entries = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let mut pairs = vec![];
            if j + 1 < n {
                pairs.push(at(i, j + 1));
            }
            if i + 1 < n {
                pairs.push(at(i + 1, j));
            }
            if i + 1 < n && j + 1 < n {
                pairs.push(at(i + 1, j + 1));
            }
            if i + 1 < n && j > 0 {
                pairs.push(at(i + 1, j - 1));
            }
            if j + 2 < n {
                pairs.push(at(i, j + 2));
            }
            if i + 2 < n {
                pairs.push(at(i + 2, j));
            }
            for b in pairs {
                let a = at(i, j);
                diagonal[a as usize] += h2k;
                diagonal[b as usize] += h2k;
                entries.push(Triplet::new(a.max(b), a.min(b), -h2k));
            }
        }
    }
    entries.extend(
        diagonal
            .iter()
            .enumerate()
            .map(|(r, &d)| Triplet::new(r as u32, r as u32, d)),
    );
    SparseColMat::try_new_from_triplets(n * n, n * n, &entries).unwrap()
}

/// The cut tree's substitutions give faer's own solve of the same
/// factor, to the rounding of the solve: the matrix's largest
/// eigenvalue is at most twice the 12 springs' `dt² k` of a particle
/// (Gershgorin, 134 kg), its smallest at least `m` (1e-5 kg), so its
/// condition number is at most 1.4e7, and two solves that order their
/// sums differently agree to about `1.4e7 · 1.1e-16 ≈ 1.5e-9` of the
/// solution's size; 1e-8 leaves a margin, and an entry misplaced or a
/// push lost would be off by order one.
#[test]
fn the_cut_substitution_is_faers_solve() {
    for threshold in [
        SupernodalThreshold::FORCE_SUPERNODAL,
        SupernodalThreshold::FORCE_SIMPLICIAL,
    ] {
        substitution_is_faers_solve(&cloth_matrix(40), threshold, true);
    }
}

/// A world of two cloths factors into a forest: two trees, cut into
/// the bins as whole trees when they weigh the same (two 25² cloths:
/// no top), the heavier one's root set apart when they do not
/// (40² and 12²). The same claim and tolerance as above (each block
/// is a cloth matrix of the same conditioning).
#[test]
fn a_forest_is_cut_into_whole_trees_and_solved_as_faer_does() {
    for (a, b, top) in [(25, 25, false), (40, 12, true)] {
        let (first, second) = (cloth_matrix(a), cloth_matrix(b));
        let offset = first.nrows() as u32;
        let mut entries = Vec::new();
        for (matrix, shift) in [(&first, 0), (&second, offset)] {
            for (column, rows) in (0..matrix.ncols()).map(|c| (c, matrix.row_idx_of_col(c))) {
                for (row, &value) in rows.zip(matrix.val_of_col(column)) {
                    entries.push(Triplet::new(
                        row as u32 + shift,
                        column as u32 + shift,
                        value,
                    ));
                }
            }
        }
        let size = first.nrows() + second.nrows();
        let forest = SparseColMat::try_new_from_triplets(size, size, &entries).unwrap();
        substitution_is_faers_solve(&forest, SupernodalThreshold::FORCE_SUPERNODAL, top);
    }
}

/// `matrix`'s factor (supernodal or simplicial as `threshold` says)
/// solved by the substitution, uncut and (supernodal) cut into
/// [`BINS`] bins, with a top or not as `top` says, against faer's own
/// solve, on 1, 2 and 3 threads.
fn substitution_is_faers_solve(
    matrix: &SparseColMat<u32, Real>,
    threshold: SupernodalThreshold,
    top: bool,
) {
    let size = matrix.nrows();
    let params = CholeskySymbolicParams {
        supernodal_flop_ratio_threshold: threshold,
        ..Default::default()
    };
    let symbolic = factorize_symbolic_cholesky(
        matrix.symbolic(),
        Side::Lower,
        SymmetricOrdering::Amd,
        params,
    )
    .unwrap();
    let mut values = vec![0.0; symbolic.len_val()];
    let mut scratch = MemBuffer::new(
        symbolic.factorize_numeric_llt_scratch::<Real>(Par::Seq, Default::default()),
    );
    symbolic
        .factorize_numeric_llt(
            &mut values,
            matrix.as_ref(),
            Side::Lower,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut scratch),
            Default::default(),
        )
        .unwrap();

    let right = |r: usize| {
        Vec3::new(
            (r % 7) as Real - 3.0,
            (r % 5) as Real,
            1.0 - (r % 3) as Real,
        )
    };
    let mut expected = Mat::<Real>::zeros(size, 3);
    for r in 0..size {
        for (axis, value) in right(r).to_array().into_iter().enumerate() {
            expected[(r, axis)] = value;
        }
    }
    let mut solve_scratch = MemBuffer::new(symbolic.solve_in_place_scratch::<Real>(3, Par::Seq));
    LltRef::new(&symbolic, &values).solve_in_place_with_conj(
        Conj::No,
        expected.as_mut(),
        Par::Seq,
        MemStack::new(&mut solve_scratch),
    );
    let order = symbolic.perm().unwrap().arrays().0.to_vec();
    let largest = (0..size)
        .flat_map(|r| (0..3).map(move |a| (r, a)))
        .map(|(r, a)| expected[(r, a)].abs())
        .fold(0.0, Real::max);
    let plans = match symbolic.raw() {
        SymbolicCholeskyRaw::Supernodal(supernodal) => vec![
            (usize::MAX, Substitution::cut_from(supernodal, usize::MAX)),
            (1, Substitution::cut_from(supernodal, 1)),
        ],
        SymbolicCholeskyRaw::Simplicial(simplicial) => {
            vec![(usize::MAX, Substitution::simplicial(simplicial))]
        }
    };
    for (split, mut plan) in plans {
        if split == 1 {
            assert_eq!(plan.bins.len(), BINS, "the tree is cut");
            assert_eq!(!plan.top.is_empty(), top);
        } else {
            assert_eq!((plan.bins.len(), plan.top.len()), (1, 0));
        }
        let mut y: Vec<Vec3> = order.iter().map(|&p| right(p as usize)).collect();
        let b = y.clone();
        plan.solve(&values, &mut y);
        // The same bits on 2 and 3 threads as on the one here.
        for threads in [2, 3] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut again = b.clone();
            pool.install(|| plan.solve(&values, &mut again));
            assert_eq!(again, y, "split {split}, {threads} threads");
        }
        for (k, &p) in order.iter().enumerate() {
            for (axis, value) in y[k].to_array().into_iter().enumerate() {
                let off = (value - expected[(p as usize, axis)]).abs();
                assert!(
                    off <= 1e-8 * largest,
                    "split {split}: row {p} axis {axis} off by {off}"
                );
            }
        }
    }
}
