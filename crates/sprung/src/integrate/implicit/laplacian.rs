//! The matrix `M + dt² L` of the fast mass-spring solver, factored once by
//! a sparse Cholesky decomposition (faer), over the free particles: `M`
//! the masses, `L = Σ k A Aᵀ` the stiffness-weighted graph Laplacian of the
//! springs (Liu, Bargteil, O'Brien and Kavan, SIGGRAPH Asia 2013). It is the
//! same for the x, y and z components, so one scalar factor solves all
//! three. Pinned particles are left out (their rows and columns removed,
//! their springs' pull on free particles kept on the diagonal). It is
//! factored again only when the springs, the masses, the pins or `dt`
//! change (the viewer's stiffness slider, say), and only numerically when
//! the pattern stays.

use std::fmt;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};

use crate::error::SolverError;
use crate::integrate::Derivative;
use crate::parallel::Schedule;
use crate::springs::Springs;
use crate::{Real, Vec3};

/// Marks a pinned particle in [`Factor::unknown`].
const PINNED: u32 = u32::MAX;

/// What the factored matrix was built from: when any of it changes, the
/// matrix is factored again.
#[derive(Debug, Clone, PartialEq)]
struct FactorKey {
    dt: Real,
    /// The springs' endpoints ([`Springs::topology`]).
    topology: u64,
    stiffness: Vec<Real>,
    mass: Vec<Real>,
    inverse_mass: Vec<Real>,
}

impl FactorKey {
    fn matches(&self, dt: Real, springs: &Springs, mass: &[Real], inverse_mass: &[Real]) -> bool {
        self.dt == dt
            && self.topology == springs.topology()
            && self.stiffness == springs.stiffness
            && self.mass == mass
            && self.inverse_mass == inverse_mass
    }

    /// Same sparsity pattern and pinned set: only the numbers differ.
    fn same_pattern(&self, springs: &Springs, inverse_mass: &[Real]) -> bool {
        self.topology == springs.topology()
            && self.inverse_mass.len() == inverse_mass.len()
            && self
                .inverse_mass
                .iter()
                .zip(inverse_mass)
                .all(|(&a, &b)| (a == 0.0) == (b == 0.0))
    }
}

/// The Cholesky factor of `M + dt² L` over the free particles.
pub(super) struct Factor {
    key: FactorKey,
    /// Per particle, its row in the matrix, or [`PINNED`].
    unknown: Vec<u32>,
    /// Per row, the particle.
    particle: Vec<u32>,
    symbolic: SymbolicCholesky<u32>,
    values: Vec<Real>,
    /// Scratch of the back-substitutions: x and y together, and z.
    solve_scratch: [MemBuffer; 2],
    /// The right side of a solve, one column per axis.
    right_side: Mat<Real>,
    /// The springs in blocks, for the Laplacian's products.
    springs: Schedule<2>,
}

impl fmt::Debug for Factor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Factor")
            .field("unknowns", &self.particle.len())
            .field("values", &self.values.len())
            .finish()
    }
}

/// `M + dt² L` over the free particles, lower triangle, in `unknown` order.
fn global_matrix(
    dt: Real,
    springs: &Springs,
    mass: &[Real],
    unknown: &[u32],
    size: usize,
) -> Result<SparseColMat<u32, Real>, SolverError> {
    let h2 = dt * dt;
    let mut diagonal = vec![0.0; size];
    for (i, &row) in unknown.iter().enumerate() {
        if row != PINNED {
            diagonal[row as usize] = mass[i];
        }
    }
    let mut entries = Vec::with_capacity(size + springs.len());
    for s in 0..springs.len() {
        let k = h2 * springs.stiffness[s];
        let (a, b) = (
            unknown[springs.first()[s] as usize],
            unknown[springs.second()[s] as usize],
        );
        for row in [a, b] {
            if row != PINNED {
                diagonal[row as usize] += k;
            }
        }
        if a != PINNED && b != PINNED {
            entries.push(Triplet::new(a.max(b), a.min(b), -k));
        }
    }
    entries.extend(
        diagonal
            .iter()
            .enumerate()
            .map(|(row, &d)| Triplet::new(row as u32, row as u32, d)),
    );
    SparseColMat::try_new_from_triplets(size, size, &entries)
        .map_err(|e| SolverError::Factorization(format!("{e:?}")))
}

impl Factor {
    /// Build and factor `M + dt² L`, reusing `previous`'s symbolic analysis
    /// when the pattern is the same.
    fn new(
        dt: Real,
        springs: &Springs,
        mass: &[Real],
        inverse_mass: &[Real],
        previous: Option<Factor>,
    ) -> Result<Factor, SolverError> {
        let key = FactorKey {
            dt,
            topology: springs.topology(),
            stiffness: springs.stiffness.clone(),
            mass: mass.to_vec(),
            inverse_mass: inverse_mass.to_vec(),
        };
        let (unknown, particle, symbolic) = match previous {
            Some(p) if p.key.same_pattern(springs, inverse_mass) => {
                (p.unknown, p.particle, p.symbolic)
            }
            _ => {
                let mut unknown = vec![PINNED; mass.len()];
                let mut particle = Vec::new();
                for (i, &w) in inverse_mass.iter().enumerate() {
                    if w != 0.0 {
                        unknown[i] = particle.len() as u32;
                        particle.push(i as u32);
                    }
                }
                let matrix = global_matrix(dt, springs, mass, &unknown, particle.len())?;
                let symbolic = factorize_symbolic_cholesky(
                    matrix.symbolic(),
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    CholeskySymbolicParams::default(),
                )
                .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
                (unknown, particle, symbolic)
            }
        };
        let matrix = global_matrix(dt, springs, mass, &unknown, particle.len())?;
        let mut values = vec![0.0; symbolic.len_val()];
        let mut scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_llt_scratch::<Real>(Par::Seq, Default::default()),
        )
        .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
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
            .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        let scratch = |columns| {
            MemBuffer::try_new(symbolic.solve_in_place_scratch::<Real>(columns, Par::Seq))
                .map_err(|e| SolverError::Factorization(format!("{e:?}")))
        };
        let solve_scratch = [scratch(2)?, scratch(1)?];
        let right_side = Mat::zeros(particle.len(), 3);
        let members = springs.first().iter().zip(springs.second());
        let springs = Schedule::new(members.map(|(&i, &j)| [i, j]), mass.len());
        Ok(Factor {
            springs,
            key,
            unknown,
            particle,
            symbolic,
            values,
            solve_scratch,
            right_side,
        })
    }

    /// Add `scale L p` over the free rows (`L_ff p_f`) to `out`: per
    /// spring, `k (p_i - p_j)` to `i` and its opposite to `j`, pinned ends
    /// counted as zero; springs added block by block ([`Schedule`]).
    pub(super) fn add_laplacian_product(
        &self,
        springs: &Springs,
        scale: Real,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        let free = |i: usize| self.unknown[i] != PINNED;
        self.springs.scatter(out, |s, w| {
            let (i, j) = (w.particle(0), w.particle(1));
            let (pi, pj) = (
                if free(i) { p[i] } else { Vec3::ZERO },
                if free(j) { p[j] } else { Vec3::ZERO },
            );
            let pull = scale * springs.stiffness[s] * (pi - pj);
            if free(i) {
                w.add(0, pull);
            }
            if free(j) {
                w.add(1, -pull);
            }
        });
    }

    /// `z = (M + dt² L)⁻¹ r` over the free particles; zero for pinned ones.
    pub(super) fn solve(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        for (row, &i) in self.particle.iter().enumerate() {
            for (axis, value) in r[i as usize].to_array().into_iter().enumerate() {
                self.right_side[(row, axis)] = value;
            }
        }
        // The three axes are independent back-substitutions with the one
        // factor, each serial. x and y go through it together (the factor,
        // which bounds a substitution, read once for both: two columns cost
        // little more than one), z beside them on the pool. The grouping is
        // fixed, not chosen by the number of threads: faer's arithmetic on
        // a column depends on how many columns go with it (measured on the
        // 128² cloth), and the bits must not depend on the threads.
        let factor = LltRef::new(&self.symbolic, &self.values);
        let solve = |column: faer::MatMut<'_, Real>, scratch: &mut MemBuffer| {
            factor.solve_in_place_with_conj(Conj::No, column, Par::Seq, MemStack::new(scratch));
        };
        let (xy, z_axis) = self.right_side.as_mut().split_at_col_mut(2);
        let [sxy, sz] = &mut self.solve_scratch;
        rayon::join(|| solve(xy, sxy), || solve(z_axis, sz));
        z.fill(Vec3::ZERO);
        for (row, &i) in self.particle.iter().enumerate() {
            z[i as usize] = Vec3::new(
                self.right_side[(row, 0)],
                self.right_side[(row, 1)],
                self.right_side[(row, 2)],
            );
        }
    }
}

/// The factor in `slot`, factored again if springs, masses, pins or `dt`
/// changed since it was made.
pub(super) fn refreshed<'a>(
    slot: &'a mut Option<Factor>,
    dt: Real,
    system: &dyn Derivative,
) -> Result<&'a mut Factor, SolverError> {
    let (springs, mass, inverse_mass) = (system.springs(), system.mass(), system.inverse_mass());
    let current = slot
        .as_ref()
        .is_some_and(|f| f.key.matches(dt, springs, mass, inverse_mass));
    if !current {
        let previous = slot.take();
        *slot = Some(Factor::new(dt, springs, mass, inverse_mass, previous)?);
    }
    slot.as_mut()
        .ok_or_else(|| SolverError::Factorization("no factor".into()))
}
