//! The springs' own Newton matrix `M - dt D_s - dt² K_s`, factored by a
//! sparse Cholesky decomposition (faer) at each linearisation: the
//! preconditioner [`Preconditioner::Stiffness`](super::Preconditioner).
//!
//! Each spring adds the 3×3 block `a t tᵀ + b I` (`t` its axis; `a`, `b`
//! from [`SpringJacobian::coefficients`], with `α = dt²`, `β = dt`) to its
//! particles' own blocks and its opposite between them: the very blocks of
//! the springs' Jacobian products, so for a world of springs alone the
//! factor is the solve's matrix and conjugate gradients converge in one
//! iteration. Unlike the Laplacian `M + dt² L`, which is as stiff across a
//! spring as along it, it follows the springs' directions: a cloth swings
//! out of its plane almost freely (its springs are stiff only along
//! themselves), and the factor knows it. Other forces (drag, contacts,
//! gas) are left to the conjugate gradients.
//!
//! The matrix is `3 × 3` blocks over the free particles (pinned ones left
//! out, as in the Laplacian factor). Their order (approximate minimum
//! degree over the particles' graph, each particle's three unknowns
//! together), the pattern and the symbolic analysis are made once per set
//! of springs and pins; each linearisation fills the values in place and
//! factors them again, serially (faer's sequential factorisation: the same
//! bits on any number of threads), allocating nothing.
//!
//! Where `preconditioner = "auto"` (the default) implicit Euler tries the
//! Jacobi preconditioner first, within the number of its iterations that
//! cost as much as a step with this factor ([`Pattern::budget`]), and
//! takes this factor from the first solve that needs more. It then keeps
//! the factor across steps: a cloth hung in its plane, or coming to rest,
//! changes its springs' directions little, and the factor of an earlier
//! state converges in a few iterations. A solve that needs more than a
//! new factorisation costs ([`StiffnessFactor::refactor_after`]) factors
//! at the state it is at and goes on from there.

use std::fmt;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::perm::PermRef;
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};

use crate::error::SolverError;
use crate::forces::{JacobianScale, SpringJacobian};
use crate::integrate::Derivative;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

/// Marks a pinned particle in [`Pattern::unknown`], and a block with a
/// pinned end in [`Numeric::between`].
const NONE: u32 = u32::MAX;

/// The cost model of [`Pattern::budget`], measured on the stiff cloths of
/// `sprung bench` (2-core AMD EPYC VM): nanoseconds per multiply-add of the
/// numeric factorisation (3 × 3 blocks: 27 per scalar one of the particles'
/// graph)…
const FACTOR_NS: Real = 0.25;
/// … per entry of the factor in a back-substitution (9 per scalar entry) …
const SOLVE_NS: Real = 3.0;
/// … and per spring and per particle in a Jacobi iteration (a Jacobian
/// product and the vector updates).
const JACOBI_NS: (Real, Real) = (10.0, 5.0);

fn factorization(error: impl fmt::Debug) -> SolverError {
    SolverError::Factorization(format!("{error:?}"))
}

/// The free particles, their order and the springs between them.
#[derive(Debug)]
struct Pattern {
    /// The springs' endpoints it was made for ([`Springs::topology`]).
    topology: u64,
    /// Per particle, its block row, or [`NONE`] for a pinned one.
    unknown: Vec<u32>,
    /// Per block row, the particle.
    particle: Vec<u32>,
    /// The order of the block rows' unknowns, and its inverse.
    order: (Vec<u32>, Vec<u32>),
    /// Jacobi iterations that cost as much as a solve with the factor.
    budget: u32,
    /// Iterations with a kept factor that cost as much as factoring again.
    refactor_after: u32,
}

impl Pattern {
    fn new(springs: &Springs, inverse_mass: &[Real]) -> Result<Pattern, SolverError> {
        let mut unknown = vec![NONE; inverse_mass.len()];
        let mut particle = Vec::new();
        for (i, &w) in inverse_mass.iter().enumerate() {
            if w != 0.0 {
                unknown[i] = particle.len() as u32;
                particle.push(i as u32);
            }
        }
        let rows = particle.len();
        let mut entries: Vec<Triplet<u32, u32, Real>> =
            (0..rows as u32).map(|r| Triplet::new(r, r, 0.0)).collect();
        for s in 0..springs.len() {
            if let Some((high, low)) = ends(springs, &unknown, s) {
                entries.push(Triplet::new(high, low, 0.0));
            }
        }
        let graph =
            SparseColMat::try_new_from_triplets(rows, rows, &entries).map_err(factorization)?;
        let (mut order, mut inverse) = (vec![0u32; rows], vec![0u32; rows]);
        let mut scratch = MemBuffer::try_new(amd::order_scratch::<u32>(rows, graph.val().len()))
            .map_err(factorization)?;
        let flops = amd::order(
            &mut order,
            &mut inverse,
            graph.symbolic(),
            Default::default(),
            MemStack::new(&mut scratch),
        )
        .map_err(factorization)?;
        let step_ns =
            27.0 * FACTOR_NS * flops.n_mult_subs_ldl + 9.0 * SOLVE_NS * (flops.n_div + rows as f64);
        let iteration_ns = JACOBI_NS.0 * springs.len() as Real + JACOBI_NS.1 * rows as Real;
        let budget = (step_ns / iteration_ns.max(1.0)).clamp(1.0, u32::MAX as Real) as u32;
        let factor_ns = 27.0 * FACTOR_NS * flops.n_mult_subs_ldl;
        let kept_ns = 9.0 * SOLVE_NS * (flops.n_div + rows as f64) + iteration_ns;
        let refactor_after = (factor_ns / kept_ns.max(1.0)).clamp(2.0, u32::MAX as Real) as u32;
        let blocks = |p: &[u32]| {
            p.iter()
                .flat_map(|&r| [3 * r, 3 * r + 1, 3 * r + 2])
                .collect()
        };
        Ok(Pattern {
            topology: springs.topology(),
            order: (blocks(&order), blocks(&inverse)),
            unknown,
            particle,
            budget,
            refactor_after,
        })
    }

    /// Whether it is the pattern of `springs` with these pins.
    fn fits(&self, springs: &Springs, inverse_mass: &[Real]) -> bool {
        self.topology == springs.topology()
            && self.unknown.len() == inverse_mass.len()
            && self
                .unknown
                .iter()
                .zip(inverse_mass)
                .all(|(&row, &w)| (row == NONE) == (w == 0.0))
    }
}

/// Spring `s`'s block rows `(high, low)` where both its ends are free and
/// it couples them (not one-sided).
fn ends(springs: &Springs, unknown: &[u32], s: usize) -> Option<(u32, u32)> {
    let (a, b) = (
        unknown[springs.first()[s] as usize],
        unknown[springs.second()[s] as usize],
    );
    (a != NONE && b != NONE && a != b && !springs.one_sided[s]).then(|| (a.max(b), a.min(b)))
}

/// The matrix, its symbolic analysis and factor.
struct Numeric {
    /// The lower triangle of the matrix, unknown `3 r + axis` for block row
    /// `r`.
    matrix: SparseColMat<u32, Real>,
    /// Per spring, the index in the matrix's values of its block between
    /// its ends, entry `(3 high, 3 low + β)` for `β = 0, 1, 2` (the three
    /// rows of each column follow): [`NONE`] where it has none.
    between: Vec<[u32; 3]>,
    symbolic: SymbolicCholesky<u32>,
    /// The factor's values.
    values: Vec<Real>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    /// The right side of a solve, one column of `3 ×` block rows.
    right_side: Mat<Real>,
}

impl Numeric {
    fn new(springs: &Springs, pattern: &Pattern) -> Result<Numeric, SolverError> {
        let rows = pattern.particle.len() as u32;
        let size = 3 * rows as usize;
        let mut entries = Vec::with_capacity(6 * rows as usize + 9 * springs.len());
        for row in 0..rows {
            for beta in 0..3 {
                for alpha in beta..3 {
                    entries.push(Triplet::new(3 * row + alpha, 3 * row + beta, 0.0));
                }
            }
        }
        for s in 0..springs.len() {
            if let Some((high, low)) = ends(springs, &pattern.unknown, s) {
                for beta in 0..3 {
                    for alpha in 0..3 {
                        entries.push(Triplet::new(3 * high + alpha, 3 * low + beta, 0.0));
                    }
                }
            }
        }
        let matrix =
            SparseColMat::try_new_from_triplets(size, size, &entries).map_err(factorization)?;
        drop(entries);
        let (column_start, row_index) = (matrix.symbolic().col_ptr(), matrix.symbolic().row_idx());
        let find = |row: u32, column: u32| -> u32 {
            let (start, end) = (
                column_start[column as usize] as usize,
                column_start[column as usize + 1] as usize,
            );
            // The pattern holds every entry searched for: it was made from them.
            let found = row_index[start..end].binary_search(&row);
            debug_assert!(found.is_ok(), "entry ({row}, {column}) in the pattern");
            let offset = found.unwrap_or(0);
            (start + offset) as u32
        };
        let between = (0..springs.len())
            .map(|s| match ends(springs, &pattern.unknown, s) {
                Some((high, low)) => [0, 1, 2].map(|beta| find(3 * high, 3 * low + beta)),
                None => [NONE; 3],
            })
            .collect();
        let (order, inverse) = &pattern.order;
        let symbolic = factorize_symbolic_cholesky(
            matrix.symbolic(),
            Side::Lower,
            SymmetricOrdering::Custom(PermRef::new_checked(order, inverse, size)),
            CholeskySymbolicParams::default(),
        )
        .map_err(factorization)?;
        let values = vec![0.0; symbolic.len_val()];
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<Real>(Par::Seq, Default::default()),
        )
        .map_err(factorization)?;
        let solve_scratch =
            MemBuffer::try_new(symbolic.solve_in_place_scratch::<Real>(1, Par::Seq))
                .map_err(factorization)?;
        Ok(Numeric {
            matrix,
            between,
            symbolic,
            values,
            factor_scratch,
            solve_scratch,
            right_side: Mat::zeros(size, 1),
        })
    }

    /// Fill the matrix at `position` (m) for a step of `dt` (s) and factor
    /// it.
    fn factor(
        &mut self,
        pattern: &Pattern,
        (dt, springs, mass): (Real, &Springs, &[Real]),
        position: &[Vec3],
    ) -> Result<(), SolverError> {
        let scale = JacobianScale {
            position: dt * dt,
            velocity: dt,
        };
        let unknown = &pattern.unknown;
        let (structure, values) = self.matrix.parts_mut();
        let column_start = structure.col_ptr();
        values.fill(0.0);
        // Entry (3 r + α, 3 r + β), α ≥ β, of block row r's own block: the
        // diagonal leads each column of the lower triangle.
        let own = |row: u32, alpha: usize, beta: usize| {
            column_start[3 * row as usize + beta] as usize + (alpha - beta)
        };
        for (row, &i) in pattern.particle.iter().enumerate() {
            for axis in 0..3 {
                values[own(row as u32, axis, axis)] = mass[i as usize];
            }
        }
        for s in 0..springs.len() {
            let jacobian = SpringJacobian::at(springs, s, position);
            let (a, b) = jacobian.coefficients(springs.stiffness[s], springs.damping[s], scale);
            let t = jacobian.axis.to_array();
            let block = |alpha: usize, beta: usize| {
                a * t[alpha] * t[beta] + if alpha == beta { b } else { 0.0 }
            };
            let (first, second) = (springs.first()[s] as usize, springs.second()[s] as usize);
            let ends: &[usize] = if springs.one_sided[s] {
                &[second]
            } else {
                &[first, second]
            };
            for &end in ends {
                let row = unknown[end];
                if row == NONE {
                    continue;
                }
                for beta in 0..3 {
                    for alpha in beta..3 {
                        values[own(row, alpha, beta)] += block(alpha, beta);
                    }
                }
            }
            let between = self.between[s];
            if between[0] != NONE {
                for (beta, &start) in between.iter().enumerate() {
                    for alpha in 0..3 {
                        values[start as usize + alpha] -= block(alpha, beta);
                    }
                }
            }
        }
        self.symbolic
            .factorize_numeric_llt(
                &mut self.values,
                self.matrix.as_ref(),
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(factorization)?;
        Ok(())
    }
}

/// The springs' Newton matrix over the free particles: its pattern, and
/// its factor once one is asked for.
pub(super) struct StiffnessFactor {
    pattern: Pattern,
    numeric: Option<Numeric>,
}

impl fmt::Debug for StiffnessFactor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("StiffnessFactor")
            .field("particles", &self.pattern.particle.len())
            .field("budget", &self.pattern.budget)
            .field("factored", &self.numeric.is_some())
            .finish()
    }
}

impl StiffnessFactor {
    /// The Jacobi iterations that cost about as much as a step with the
    /// factor (its numeric factorisation and one back-substitution), from
    /// the flops of the particles' order and a fixed cost model.
    pub(super) fn budget(&self) -> u32 {
        self.pattern.budget
    }

    /// The iterations a solve with a factor kept from an earlier state may
    /// take before factoring again pays (as many as cost a factorisation,
    /// in the same cost model; at least 2).
    pub(super) fn refactor_after(&self) -> u32 {
        self.pattern.refactor_after
    }

    /// Whether it holds a factor (of some earlier state).
    pub(super) fn is_factored(&self) -> bool {
        self.numeric.is_some()
    }

    /// Fill the matrix at `position` (m) for a step of `dt` (s) and factor
    /// it.
    pub(super) fn factor(
        &mut self,
        dt: Real,
        system: &dyn Derivative,
        position: &[Vec3],
    ) -> Result<(), SolverError> {
        self.factor_with(dt, (system.springs(), system.mass()), position)
    }

    /// [`StiffnessFactor::factor`] with these springs (the world's ends,
    /// their parameters as they were when a kept factor was made) and
    /// masses (kg).
    pub(super) fn factor_with(
        &mut self,
        dt: Real,
        (springs, mass): (&Springs, &[Real]),
        position: &[Vec3],
    ) -> Result<(), SolverError> {
        if self.numeric.is_none() {
            self.numeric = Some(Numeric::new(springs, &self.pattern)?);
        }
        if let Some(numeric) = &mut self.numeric {
            numeric.factor(&self.pattern, (dt, springs, mass), position)?;
        }
        Ok(())
    }

    /// `z = P⁻¹ r` over the free particles; zero for pinned ones. Only
    /// after [`StiffnessFactor::factor`].
    pub(super) fn solve(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        z.fill(Vec3::ZERO);
        let Some(numeric) = &mut self.numeric else {
            return;
        };
        let particles = &self.pattern.particle;
        for (row, &i) in particles.iter().enumerate() {
            for (axis, value) in r[i as usize].to_array().into_iter().enumerate() {
                numeric.right_side[(3 * row + axis, 0)] = value;
            }
        }
        LltRef::new(&numeric.symbolic, &numeric.values).solve_in_place_with_conj(
            Conj::No,
            numeric.right_side.as_mut(),
            Par::Seq,
            MemStack::new(&mut numeric.solve_scratch),
        );
        for (row, &i) in particles.iter().enumerate() {
            z[i as usize] = Vec3::new(
                numeric.right_side[(3 * row, 0)],
                numeric.right_side[(3 * row + 1, 0)],
                numeric.right_side[(3 * row + 2, 0)],
            );
        }
    }
}

/// The factor in `slot` for the world's springs and pins, its pattern made
/// again where they changed (not yet factored).
pub(super) fn prepared<'a>(
    slot: &'a mut Option<StiffnessFactor>,
    system: &dyn Derivative,
) -> Result<&'a mut StiffnessFactor, SolverError> {
    let (springs, inverse_mass) = (system.springs(), system.inverse_mass());
    if !slot
        .as_ref()
        .is_some_and(|f| f.pattern.fits(springs, inverse_mass))
    {
        *slot = Some(StiffnessFactor {
            pattern: Pattern::new(springs, inverse_mass)?,
            numeric: None,
        });
    }
    slot.as_mut()
        .ok_or_else(|| SolverError::Factorization("no factor".into()))
}
