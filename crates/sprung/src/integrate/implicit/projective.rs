//! The fast mass-spring solver (Liu, Bargteil, O'Brien and Kavan, "Fast
//! simulation of mass-spring systems", SIGGRAPH Asia 2013): backward Euler
//! by local/global iterations over a matrix that does not change.
//!
//! Backward Euler is the minimum of
//! `g(x) = 1/(2 dt²) (x - y)ᵀ M (x - y) + E(x)`, `y = x_n + dt v_n`. Each
//! spring's energy `½ k (|x_i - x_j| - L0)²` is the least, over vectors `d`
//! of length `L0`, of `½ k |x_i - x_j - d|²`: the **local step** projects
//! each spring onto its rest length (`d = L0 t`), the **global step** solves
//! the linear system `(M + dt² L) x = M y + dt² J d`, with `L = Σ k A Aᵀ`
//! the stiffness-weighted graph Laplacian of the springs. That matrix is
//! the same at every iteration and every step while springs, masses, pins
//! and `dt` stay, so it is factored once by a sparse Cholesky decomposition
//! (faer) and each iteration is one forward and back substitution.
//!
//! **Every other force.** Since `L x - J d(x) = -f_springs(x)` (the elastic
//! spring force), the iteration can be written with the world's whole force
//! list. Backward Euler is `F(x) = M (x - y) - dt² f(x, v) = 0` with
//! `v = (x - x_n) / dt`, and Liu et al.'s iteration is the correction
//! `x_{k+1} = x_k + δ`, `(M + dt² L) δ = M (y - x_k) + dt² f(x_k, v_k)`:
//! `M + dt² L` stands in for the Jacobian of `F`. For springs alone this is
//! exactly the local/global iteration (the projection onto the rest length
//! happens inside the spring force). Forces that are not springs can be
//! much stiffer than `M / dt²` (a penalty floor), and a fixed-point
//! iteration on them diverges, so their Jacobians join the matrix:
//! `(M + dt² L - dt² K_o - dt D_o) δ = M (y - x_k) + dt² f(x_k, v_k)`, with
//! `K_o`, `D_o` the Jacobians of every force but the springs (see
//! [`Jacobians::AllButSprings`]). That system is solved by conjugate
//! gradients preconditioned with the factored `M + dt² L`: when the other
//! forces have no Jacobian (gravity, wind) the first iteration is exact, one
//! back-substitution, as in the paper; penalty contacts and the gas add a
//! few. A converged iteration is the exact backward-Euler step for every
//! force. The correction is small next to the positions, so its round-off
//! is too, and since the internal forces and the rows of `L` sum to zero,
//! the step conserves momentum.
//!
//! Projection colliders are constraints of each global solve (see
//! [`ContactConstraint`]): a particle reaching one has its end position
//! along the normal prescribed. Pinned particles are left out of the unknowns (their rows and columns
//! removed, their springs' pull on free particles kept), not given large
//! masses. The iteration starts from the inertial guess `y` and takes a
//! fixed number of iterations (`iterations`, default 10), as in the paper.

use std::fmt;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::{SparseColMat, Triplet};
use faer::{Conj, Mat, Par, Side};

use super::cg::{ConjugateGradient, Limits, Operator};
use super::SolverSettings;
use crate::collide::ContactConstraint;
use crate::error::SolverError;
use crate::forces::{JacobianScale, Jacobians};
use crate::integrate::{fit, Derivative, Integrator, IntegratorKind, State, StepReport};
use crate::springs::Springs;
use crate::{Real, Vec3};

/// Marks a pinned particle in [`Factor::unknown`].
const PINNED: u32 = u32::MAX;

/// The projective solver with its factored matrix and buffers.
#[derive(Debug, Default)]
pub struct Projective {
    factor: Option<Factor>,
    start_position: Vec<Vec3>,
    inertial: Vec<Vec3>,
    force: Vec<Vec3>,
    residual: Vec<Vec3>,
    correction: Vec<Vec3>,
    contacts: Vec<ContactConstraint>,
    impulses: Vec<Real>,
    cg: ConjugateGradient,
}

/// What the factored matrix was built from: when any of it changes, the
/// matrix is factored again.
#[derive(Debug, Clone, PartialEq)]
struct FactorKey {
    dt: Real,
    first: Vec<u32>,
    second: Vec<u32>,
    stiffness: Vec<Real>,
    mass: Vec<Real>,
    inverse_mass: Vec<Real>,
}

impl FactorKey {
    fn matches(&self, dt: Real, springs: &Springs, mass: &[Real], inverse_mass: &[Real]) -> bool {
        self.dt == dt
            && self.first == springs.first
            && self.second == springs.second
            && self.stiffness == springs.stiffness
            && self.mass == mass
            && self.inverse_mass == inverse_mass
    }

    /// Same sparsity pattern and pinned set: only the numbers differ.
    fn same_pattern(&self, springs: &Springs, inverse_mass: &[Real]) -> bool {
        self.first == springs.first
            && self.second == springs.second
            && self.inverse_mass.len() == inverse_mass.len()
            && self
                .inverse_mass
                .iter()
                .zip(inverse_mass)
                .all(|(&a, &b)| (a == 0.0) == (b == 0.0))
    }
}

/// The Cholesky factor of `M + dt² L` over the free particles.
struct Factor {
    key: FactorKey,
    /// Per particle, its row in the matrix, or [`PINNED`].
    unknown: Vec<u32>,
    /// Per row, the particle.
    particle: Vec<u32>,
    symbolic: SymbolicCholesky<u32>,
    values: Vec<Real>,
    solve_scratch: MemBuffer,
    /// The right side of a solve, one column per axis.
    right_side: Mat<Real>,
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
            unknown[springs.first[s] as usize],
            unknown[springs.second[s] as usize],
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
            first: springs.first.clone(),
            second: springs.second.clone(),
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
        let solve_scratch =
            MemBuffer::try_new(symbolic.solve_in_place_scratch::<Real>(3, Par::Seq))
                .map_err(|e| SolverError::Factorization(format!("{e:?}")))?;
        let right_side = Mat::zeros(particle.len(), 3);
        Ok(Factor {
            key,
            unknown,
            particle,
            symbolic,
            values,
            solve_scratch,
            right_side,
        })
    }

    /// `z = (M + dt² L)⁻¹ r` over the free particles; zero for pinned ones.
    fn solve(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        for (row, &i) in self.particle.iter().enumerate() {
            for (axis, value) in r[i as usize].to_array().into_iter().enumerate() {
                self.right_side[(row, axis)] = value;
            }
        }
        LltRef::new(&self.symbolic, &self.values).solve_in_place_with_conj(
            Conj::No,
            self.right_side.as_mut(),
            Par::Seq,
            MemStack::new(&mut self.solve_scratch),
        );
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

/// Add `scale L p` over the free rows (`L_ff p_f`) to `out`: per spring,
/// `k (p_i - p_j)` to `i` and its opposite to `j`, pinned ends counted as
/// zero.
fn add_laplacian_product(
    springs: &Springs,
    unknown: &[u32],
    scale: Real,
    p: &[Vec3],
    out: &mut [Vec3],
) {
    let free = |i: usize| unknown[i] != PINNED;
    for s in 0..springs.len() {
        let (i, j) = (springs.first[s] as usize, springs.second[s] as usize);
        let (pi, pj) = (
            if free(i) { p[i] } else { Vec3::ZERO },
            if free(j) { p[j] } else { Vec3::ZERO },
        );
        let pull = scale * springs.stiffness[s] * (pi - pj);
        if free(i) {
            out[i] += pull;
        }
        if free(j) {
            out[j] -= pull;
        }
    }
}

/// The global step's matrix `M + dt² L - dt² K_o - dt D_o` at a state,
/// preconditioned by the factored `M + dt² L`.
struct GlobalMatrix<'a> {
    system: &'a dyn Derivative,
    state: State<'a>,
    factor: &'a mut Factor,
    dt: Real,
}

impl Operator for GlobalMatrix<'_> {
    fn apply(&mut self, p: &[Vec3], out: &mut [Vec3]) {
        let dt = self.dt;
        let scale = JacobianScale {
            position: dt * dt,
            velocity: dt,
        };
        self.system
            .jacobian_products(self.state, Jacobians::AllButSprings, scale, p, out);
        for ((o, p), &m) in out.iter_mut().zip(p).zip(self.system.mass()) {
            *o = m * *p - *o;
        }
        add_laplacian_product(self.system.springs(), &self.factor.unknown, dt * dt, p, out);
    }

    fn precondition(&mut self, r: &[Vec3], z: &mut [Vec3]) {
        self.factor.solve(r, z);
    }
}

impl Projective {
    /// The factor of the current matrix, factored again if springs,
    /// masses, pins or `dt` changed since the last step.
    fn refresh(&mut self, dt: Real, system: &dyn Derivative) -> Result<(), SolverError> {
        let (springs, mass, inverse_mass) =
            (system.springs(), system.mass(), system.inverse_mass());
        let current = self
            .factor
            .as_ref()
            .is_some_and(|f| f.key.matches(dt, springs, mass, inverse_mass));
        if !current {
            let previous = self.factor.take();
            self.factor = Some(Factor::new(dt, springs, mass, inverse_mass, previous)?);
        }
        Ok(())
    }
}

/// Most times the first global solve is done again after releasing
/// contacts that pulled.
const RELEASE_PASSES: usize = 3;

impl Integrator for Projective {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Projective
    }

    fn step(
        &mut self,
        time: Real,
        dt: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        system: &mut dyn Derivative,
        solver: &SolverSettings,
    ) -> Result<StepReport, SolverError> {
        let n = position.len();
        for buffer in [
            &mut self.start_position,
            &mut self.inertial,
            &mut self.force,
            &mut self.residual,
            &mut self.correction,
        ] {
            fit(buffer, n);
        }
        self.refresh(dt, system)?;
        let Some(factor) = self.factor.as_mut() else {
            return Err(SolverError::Factorization("no factor".into()));
        };
        let start = State {
            time,
            position,
            velocity,
        };
        system.contact_constraints(start, dt, &mut self.contacts);
        self.start_position.copy_from_slice(position);
        for i in 0..n {
            self.inertial[i] = position[i] + dt * velocity[i];
            position[i] = self.inertial[i];
        }
        let mut report = StepReport {
            iterations: Some(solver.iterations),
            residual: Some(0.0),
            unconverged: false,
        };
        let time = time + dt;
        for iteration in 0..solver.iterations {
            for i in 0..n {
                velocity[i] = (position[i] - self.start_position[i]) / dt;
            }
            system.force(time, position, velocity, &mut self.force);
            let mass = system.mass();
            for i in 0..n {
                self.residual[i] =
                    mass[i] * (self.inertial[i] - position[i]) + dt * dt * self.force[i];
            }
            let state = State {
                time,
                position,
                velocity,
            };
            system.linearize(state, Jacobians::AllButSprings);
            let mass = system.mass();
            let mut matrix = GlobalMatrix {
                system: &*system,
                state,
                factor: &mut *factor,
                dt,
            };
            // The first iteration decides which contacts hold: those that
            // pulled are released and the system solved again.
            let passes = if iteration == 0 { RELEASE_PASSES } else { 1 };
            for pass in 0..passes {
                self.correction.fill(Vec3::ZERO);
                for c in &self.contacts {
                    let i = c.particle;
                    let reached = self.start_position[i] + dt * c.normal_velocity() * c.normal;
                    self.correction[i] = (reached - position[i]).dot(c.normal) * c.normal;
                }
                let limits = Limits {
                    inverse_mass: system.inverse_mass(),
                    contacts: &self.contacts,
                    tolerance: solver.tolerance,
                    max_iterations: solver.max_iterations,
                };
                let outcome =
                    self.cg
                        .solve(&mut matrix, &self.residual, &mut self.correction, limits);
                report.residual = Some(outcome.residual);
                report.unconverged |= !outcome.converged;
                self.cg.contact_impulses(
                    &mut matrix,
                    &self.residual,
                    &self.correction,
                    &self.contacts,
                    &mut self.impulses,
                );
                let pulled = self.impulses.iter().any(|&j| j < 0.0);
                if !pulled || pass + 1 == passes {
                    break;
                }
                let mut index = 0;
                let impulses = &self.impulses;
                self.contacts.retain(|_| {
                    index += 1;
                    impulses[index - 1] >= 0.0
                });
            }
            // The impulse of a position-level solve is in kg·m: over m dt,
            // the velocity change.
            for (c, &impulse) in self.contacts.iter_mut().zip(&self.impulses) {
                c.normal_change = impulse.max(0.0) / (mass[c.particle] * dt);
            }
            for (x, d) in position.iter_mut().zip(&self.correction) {
                *x += *d;
            }
        }
        for i in 0..n {
            velocity[i] = (position[i] - self.start_position[i]) / dt;
        }
        for c in &self.contacts {
            let i = c.particle;
            c.apply_friction(&mut velocity[i]);
            position[i] = self.start_position[i] + dt * velocity[i];
        }
        Ok(report)
    }
}
