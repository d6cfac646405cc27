//! Rigid rods: `|x_j - x_i| = L` held by iterative projection.
//!
//! **Method.** After the integrator and the colliders, each sweep visits
//! the rods in order (Gauss–Seidel) and moves the two ends along the rod,
//! in inverse proportion to their masses, to the rod's length:
//! `Δx_i = w_i C n / (w_i + w_j)`, `Δx_j = -w_j C n / (w_i + w_j)`, with
//! `C = |d| - L`, `n = d / |d|` and `w` the inverse masses (a pinned end,
//! `w = 0`, does not move). Sweeps repeat until every rod is within the
//! tolerance. The velocities then take the same correction over the step
//! (`Δv = Δx / dt`, as in RATTLE) and are projected onto the rods'
//! tangent space the same way: the relative velocity along each rod is
//! removed, mass-weighted, sweep after sweep. So a rod does no work, the
//! momentum of the particles it joins is kept (its impulses are equal and
//! opposite), and it works unchanged after any integrator.
//!
//! This is SHAKE/RATTLE with the constraint direction taken at the
//! projected positions rather than the previous ones: the same fixed point
//! (the rod lengths exact), simpler, and it needs no constraint forces
//! inside the integrator's trial states, so RK4's and the implicit
//! solvers' stages stay as they are.

use crate::{Real, Vec3};

/// The world's rods, structure of arrays, world particle indices.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Rods {
    /// First particle of each rod.
    pub first: Vec<u32>,
    /// Second particle of each rod.
    pub second: Vec<u32>,
    /// Length of each rod (m).
    pub length: Vec<Real>,
}

/// What the last projection did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RodReport {
    /// Sweeps over the rods the positions took.
    pub sweeps: u32,
    /// Largest relative length error left, `|d - L| / L`.
    pub error: Real,
}

impl Rods {
    /// Number of rods.
    pub fn len(&self) -> usize {
        self.length.len()
    }

    /// True when there are none.
    pub fn is_empty(&self) -> bool {
        self.length.is_empty()
    }

    /// Add a rod of `length` (m) between particles `i` and `j`.
    pub fn push(&mut self, i: u32, j: u32, length: Real) {
        self.first.push(i);
        self.second.push(j);
        self.length.push(length);
    }

    /// Largest relative length error `|d - L| / L` at `position` (m).
    pub fn largest_error(&self, position: &[Vec3]) -> Real {
        (0..self.len())
            .map(|r| self.error_of(r, position))
            .fold(0.0, Real::max)
    }

    fn error_of(&self, r: usize, position: &[Vec3]) -> Real {
        let (i, j) = (self.first[r] as usize, self.second[r] as usize);
        (position[j].distance(position[i]) - self.length[r]).abs() / self.length[r]
    }

    /// Project `position` (m) onto the rods, at most `iterations` sweeps
    /// or until every relative error is within `tolerance`; give the
    /// velocities (m/s) the correction over `dt` (s), then remove their
    /// relative velocity along each rod. `inverse_mass` (1/kg) weighs the
    /// ends; `start` (m) is scratch for the positions before.
    #[allow(clippy::too_many_arguments)]
    pub fn project(
        &self,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        inverse_mass: &[Real],
        dt: Real,
        tolerance: Real,
        iterations: u32,
        start: &mut Vec<Vec3>,
    ) -> RodReport {
        if self.is_empty() {
            return RodReport::default();
        }
        start.clear();
        start.extend_from_slice(position);
        let mut report = RodReport::default();
        for sweep in 1..=iterations {
            report.sweeps = sweep;
            let mut worst: Real = 0.0;
            for r in 0..self.len() {
                let (i, j) = (self.first[r] as usize, self.second[r] as usize);
                let (wi, wj) = (inverse_mass[i], inverse_mass[j]);
                if wi + wj == 0.0 {
                    continue;
                }
                let d = position[j] - position[i];
                let distance = d.length();
                if distance == 0.0 {
                    continue;
                }
                let error = distance - self.length[r];
                worst = worst.max(error.abs() / self.length[r]);
                let shift = error / ((wi + wj) * distance) * d;
                position[i] += wi * shift;
                position[j] -= wj * shift;
            }
            if worst <= tolerance {
                break;
            }
        }
        report.error = self.largest_error(position);
        for ((v, x), x0) in velocity.iter_mut().zip(&*position).zip(&*start) {
            *v += (*x - *x0) / dt;
        }
        // The velocities: the same sweeps on the relative speed along each
        // rod, until it is below the tolerance's length per step.
        for _ in 0..iterations {
            let mut worst: Real = 0.0;
            for r in 0..self.len() {
                let (i, j) = (self.first[r] as usize, self.second[r] as usize);
                let (wi, wj) = (inverse_mass[i], inverse_mass[j]);
                let d = position[j] - position[i];
                let distance = d.length();
                if wi + wj == 0.0 || distance == 0.0 {
                    continue;
                }
                let n = d / distance;
                let along = (velocity[j] - velocity[i]).dot(n);
                worst = worst.max(along.abs() * dt / self.length[r]);
                let kick = along / (wi + wj) * n;
                velocity[i] += wi * kick;
                velocity[j] -= wj * kick;
            }
            if worst <= tolerance {
                break;
            }
        }
        report
    }
}
