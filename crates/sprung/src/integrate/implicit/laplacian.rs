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
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Par, Side};

use super::substitution::Substitution;
use crate::error::SolverError;
use crate::integrate::Derivative;
use crate::parallel::Schedule;
use crate::springs::Springs;
use crate::units::{Real, Vec3};

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
    /// Per column of the factor (its order of the rows), the particle.
    column_particle: Vec<u32>,
    /// The substitutions' plan and buffers.
    substitution: Substitution,
    /// A solve's vector, in the factor's order.
    work: Vec<Vec3>,
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
    pub(super) fn new(
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
        let (unknown, particle, symbolic, column_particle, substitution) = match previous {
            Some(p) if p.key.same_pattern(springs, inverse_mass) => (
                p.unknown,
                p.particle,
                p.symbolic,
                p.column_particle,
                p.substitution,
            ),
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
                let params = CholeskySymbolicParams::default();
                let symbolic = factorize_symbolic_cholesky(
                    matrix.symbolic(),
                    Side::Lower,
                    SymmetricOrdering::Amd,
                    params,
                )
                .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
                let substitution = match symbolic.raw() {
                    SymbolicCholeskyRaw::Supernodal(supernodal) => Substitution::new(supernodal),
                    SymbolicCholeskyRaw::Simplicial(simplicial) => {
                        Substitution::simplicial(simplicial)
                    }
                };
                let column_particle = match symbolic.perm() {
                    Some(perm) => perm
                        .arrays()
                        .0
                        .iter()
                        .map(|&row| particle[row as usize])
                        .collect(),
                    None => particle.clone(),
                };
                (unknown, particle, symbolic, column_particle, substitution)
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
        let work = vec![Vec3::ZERO; particle.len()];
        let members = springs.first().iter().zip(springs.second());
        let springs = Schedule::new(members.map(|(&i, &j)| [i, j]), mass.len());
        Ok(Factor {
            springs,
            key,
            unknown,
            particle,
            symbolic,
            values,
            column_particle,
            substitution,
            work,
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

    /// The values the factor stores, and what one [`Factor::solve`] reads
    /// of them and computes ([`Substitution::cost`]).
    pub(super) fn cost(&self) -> (usize, f64, f64) {
        let (bytes, multiply_adds) = self.substitution.cost();
        (self.values.len(), bytes, multiply_adds)
    }

    /// `z = (M + dt² L)⁻¹ r` over the free particles; zero for pinned ones
    /// (the x, y and z axes at once, [`Substitution`]).
    pub(super) fn solve(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        for (y, &i) in self.work.iter_mut().zip(&self.column_particle) {
            *y = r[i as usize];
        }
        self.substitution.solve(&self.values, &mut self.work);
        z.fill(Vec3::ZERO);
        for (y, &i) in self.work.iter().zip(&self.column_particle) {
            z[i as usize] = *y;
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
