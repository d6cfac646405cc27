//! What `projective`'s substitution costs on a world, for `sprung bench`:
//! the factor of `M + dt² L`, what one substitution reads and computes,
//! and how long it takes.

use std::time::Instant;

use super::laplacian::Factor;
use crate::error::SolverError;
use crate::model::Model;
use crate::units::{Real, Vec3};

/// One substitution (forwards and back) with the factor of `M + dt² L`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SubstitutionFigures {
    /// Values the factor stores (faer's supernodal layout: each
    /// supernode's dense columns).
    pub values: usize,
    /// Bytes of the factor one substitution reads (B): each column's
    /// values from its diagonal down and the supernodes' row indices,
    /// forwards and back.
    pub bytes: f64,
    /// Multiply-adds of one substitution, x, y and z (three a value off the
    /// diagonal, forwards and back).
    pub multiply_adds: f64,
    /// Wall-clock time of one substitution on the calling thread pool (s).
    pub seconds: f64,
}

/// Factor `M + dt² L` for `model`'s springs, masses and pins at the step
/// `dt` (s), and time its substitution on the calling thread pool: as many
/// as fill `least_seconds` (s), at least ten, after two untimed.
pub fn measure_substitution(
    model: &Model,
    dt: Real,
    least_seconds: f64,
) -> Result<SubstitutionFigures, SolverError> {
    let mut factor = Factor::new(dt, model.springs, model.mass, model.inverse_mass, None)?;
    let (values, bytes, multiply_adds) = factor.cost();
    let right = vec![Vec3::ONE; model.mass.len()];
    let mut solution = vec![Vec3::ZERO; model.mass.len()];
    for _ in 0..2 {
        factor.solve(&right, &mut solution);
    }
    let start = Instant::now();
    let mut count = 0u32;
    while count < 10 || start.elapsed().as_secs_f64() < least_seconds {
        factor.solve(&right, &mut solution);
        count += 1;
    }
    Ok(SubstitutionFigures {
        values,
        bytes,
        multiply_adds,
        seconds: start.elapsed().as_secs_f64() / f64::from(count),
    })
}
