//! A lattice ("jelly"): a 3D grid of particles with springs to all 26
//! neighbours (docs/physics.md §2). A 6-neighbour lattice has no resistance to
//! shear; the face and body diagonals make it hold its shape.

#[cfg(test)]
use super::MAX_SPRINGS;
use super::{check_count, check_length, check_springs, check_total};
use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// A lattice of `nx × ny × nz` particles (each at least 2) `spacing` (m)
/// apart, its corner at the origin. Particle `(x, y, z)` has index
/// `(z * ny + y) * nx + x`. Each particle is joined to its 26 neighbours
/// (13 springs per particle, each pair once).
///
/// # Examples
///
/// In a 2 × 2 × 2 lattice, every corner is a neighbour of every other: 28
/// springs, the longest the cube's diagonal. Inside a 3 × 3 × 3 one, the
/// centre particle has all 26 neighbours:
///
/// ```
/// use sprung::build;
///
/// let cube = build::lattice(2, 2, 2, 0.1).unwrap();
/// assert_eq!(cube.particle_count(), 8);
/// assert_eq!(cube.springs.len(), 8 * 7 / 2);
/// let longest = cube.springs.iter().map(|s| cube.rest_length(s)).fold(0.0, f64::max);
/// assert!((longest - 0.1 * 3_f64.sqrt()).abs() < 1e-16); // to rounding
/// let block = build::lattice(3, 3, 3, 0.1).unwrap();
/// let centre = (1 * 3 + 1) * 3 + 1; // (x, y, z) = (1, 1, 1)
/// let around = block.springs.iter().filter(|s| s.first == centre || s.second == centre);
/// assert_eq!(around.count(), 26);
/// ```
pub fn lattice(nx: usize, ny: usize, nz: usize, spacing: Real) -> Result<BodyData, BuildError> {
    for (field, n) in [("lattice.nx", nx), ("lattice.ny", ny), ("lattice.nz", nz)] {
        check_count(
            field,
            n,
            2,
            "a lattice needs at least 2 particles along each axis",
        )?;
    }
    check_total("lattice.nx", &[nx, ny, nz])?;
    check_length("lattice.spacing", spacing)?;
    let springs = spring_count(nx, ny, nz);
    check_springs("lattice.nx", springs)?;
    let offsets = forward_offsets();
    let id = |x: usize, y: usize, z: usize| (z * ny + y) * nx + x;
    let cells =
        || (0..nz).flat_map(move |z| (0..ny).flat_map(move |y| (0..nx).map(move |x| (x, y, z))));
    let position = cells()
        .map(|(x, y, z)| spacing * Vec3::new(x as Real, y as Real, z as Real))
        .collect();
    let mut body = BodyData::from_positions(position);
    body.springs.reserve(springs);
    for (x, y, z) in cells() {
        for &[dx, dy, dz] in &offsets {
            let (u, v, w) = (x as isize + dx, y as isize + dy, z as isize + dz);
            let inside = (0..nx as isize).contains(&u)
                && (0..ny as isize).contains(&v)
                && (0..nz as isize).contains(&w);
            if inside {
                body.springs.push(SpringData::between(
                    id(x, y, z),
                    id(u as usize, v as usize, w as usize),
                ));
            }
        }
    }
    Ok(body)
}

/// The 13 neighbour offsets that are lexicographically positive: each pair
/// of neighbours is visited from exactly one side.
fn forward_offsets() -> Vec<[isize; 3]> {
    (-1..=1)
        .flat_map(|dz| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dx| [dx, dy, dz])))
        .filter(|&[dx, dy, dz]| (dz, dy, dx) > (0, 0, 0))
        .collect()
}

/// How many springs [`lattice`] makes for `nx × ny × nz` particles (each
/// at least 2, at most [`super::MAX_PARTICLES`] in all): each offset joins
/// the particles whose neighbour along it is inside.
fn spring_count(nx: usize, ny: usize, nz: usize) -> usize {
    forward_offsets()
        .iter()
        .map(|d| {
            (nx - d[0].unsigned_abs()) * (ny - d[1].unsigned_abs()) * (nz - d[2].unsigned_abs())
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spring_count_is_that_of_the_lattice_built() {
        for [nx, ny, nz] in [[2, 2, 2], [3, 2, 4], [5, 4, 3]] {
            let body = lattice(nx, ny, nz, 0.1).expect("a small lattice");
            assert_eq!(spring_count(nx, ny, nz), body.springs.len());
        }
    }

    #[test]
    fn a_lattice_of_too_many_springs_is_refused_before_it_is_made() {
        // 200 × 100 × 100 = 2 000 000 particles (within the particle
        // limit) and about 13 springs each: over the 20 000 000 springs.
        let error = lattice(200, 100, 100, 0.01).expect_err("too many springs");
        assert!(
            matches!(error, BuildError::TooMany { field: "lattice.nx", what: "springs", count, .. }
                if count == spring_count(200, 100, 100) && count > MAX_SPRINGS),
            "{error}"
        );
    }
}
