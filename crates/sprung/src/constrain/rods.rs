//! Rigid rods: `|x_j - x_i| = L` held by SHAKE and RATTLE.
//!
//! **Method.** After the integrator and the colliders, the positions are
//! corrected along each rod's direction at the *start* of the step,
//! `d⁰ = x⁰_j - x⁰_i`, in inverse proportion to the ends' masses (SHAKE):
//! `x_i += w_i λ d⁰`, `x_j -= w_j λ d⁰`, with `λ = (|d|² - L²) / (2 (w_i +
//! w_j) d·d⁰)` from the current `d = x_j - x_i` and `w` the inverse masses
//! (a pinned end, `w = 0`, does not move). Sweeps over the rods in order
//! (Gauss–Seidel) repeat until every rod is within the tolerance. The
//! velocities take the same correction over the step (`Δv = Δx / dt`),
//! then their relative velocity along each rod is removed, mass-weighted,
//! sweep after sweep (RATTLE's second half). So a rod does no work and its
//! impulses are equal and opposite (momentum is kept).
//!
//! Why the direction at the start: the correction then bends the velocity
//! onto the chord of the step without slowing it, and the projection onto
//! the new tangent turns it back, so a pendulum keeps its speed (its energy
//! stays in a band, as with RATTLE). Correcting along the new direction
//! instead would remove `1 - cos(ω dt)` of the speed every step (a 60°
//! pendulum at 1e-3 s loses 90 % of its energy in 100 periods). The stage
//! needs no constraint forces inside the integrator's trial states, so it
//! works unchanged after every integrator, RK4's stages and the implicit
//! solves included.

use crate::units::{Real, Vec3};

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
    /// The rod with that error (its index in the world's [`Rods`]; the
    /// first of equal ones).
    pub worst: usize,
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
        self.worst(position).1
    }

    /// The rod with the largest relative length error at `position` (m)
    /// (the first of equal ones; a rod whose error is not a number counts
    /// as the largest), and that error (0 for no rods).
    pub fn worst(&self, position: &[Vec3]) -> (usize, Real) {
        (0..self.len())
            .map(|r| (r, self.error_of(r, position)))
            .fold((0, 0.0), |(w, e), (r, error)| {
                if error > e || (error.is_nan() && !e.is_nan()) {
                    (r, error)
                } else {
                    (w, e)
                }
            })
    }

    fn error_of(&self, r: usize, position: &[Vec3]) -> Real {
        let (i, j) = (self.first[r] as usize, self.second[r] as usize);
        (position[j].distance(position[i]) - self.length[r]).abs() / self.length[r]
    }

    /// Project `position` (m) onto the rods along their directions at
    /// `before` (m, the positions at the start of the step), at most
    /// `iterations` sweeps or until every relative error is within
    /// `tolerance`; give the velocities (m/s) the correction over `dt`
    /// (s), then remove their relative velocity along each rod.
    /// `inverse_mass` (1/kg) weighs the ends; `start` (m) is scratch for
    /// the positions before the projection.
    #[allow(clippy::too_many_arguments)]
    pub fn project(
        &self,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        before: &[Vec3],
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
                let length = self.length[r];
                let d = position[j] - position[i];
                let distance = d.length();
                worst = worst.max((distance - length).abs() / length);
                // The start-of-step direction, unless the rod turned nearly
                // a right angle in the step (then the current one).
                let mut along = before[j] - before[i];
                if d.dot(along) <= 0.1 * distance * along.length() {
                    along = d;
                }
                let denominator = 2.0 * (wi + wj) * d.dot(along);
                if denominator == 0.0 {
                    continue;
                }
                let lambda = (distance * distance - length * length) / denominator;
                position[i] += wi * lambda * along;
                position[j] -= wj * lambda * along;
            }
            if worst <= tolerance {
                break;
            }
        }
        (report.worst, report.error) = self.worst(position);
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
