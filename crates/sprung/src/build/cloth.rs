//! A cloth: an `nx × ny` grid of particles in the xy-plane with structural,
//! shear and bending springs (docs/physics.md §2), and its triangles.

use super::{check_count, check_length, check_springs, check_total};
use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// Which families of springs a cloth gets.
///
/// A plain grid, structural springs only, each as long as a cell's side:
///
/// ```
/// use sprung::build::{self, ClothSprings};
///
/// let grid = ClothSprings { shear: false, bending: false, ..ClothSprings::default() };
/// let cloth = build::cloth(5, 5, 1.0, 1.0, grid).unwrap();
/// assert_eq!(cloth.springs.len(), 2 * 4 * 5);
/// assert!(cloth.springs.iter().all(|s| cloth.rest_length(s) == 0.25));
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClothSprings {
    /// Springs to the 4 grid neighbours.
    pub structural: bool,
    /// Springs on both diagonals of each cell; without them the grid has no
    /// resistance to shear and collapses.
    pub shear: bool,
    /// Springs two cells apart along x and y, resisting folding.
    pub bending: bool,
}

impl Default for ClothSprings {
    fn default() -> Self {
        ClothSprings {
            structural: true,
            shear: true,
            bending: true,
        }
    }
}

/// A cloth of `nx × ny` particles (each at least 2) spanning `width × height`
/// (m) in the xy-plane with its corner at the origin. Particle `(x, y)` has
/// index `y * nx + x`. Each cell gives two triangles, counter-clockwise
/// seen from +z.
///
/// # Examples
///
/// Structural springs join each particle to its 4 grid neighbours, shear
/// springs cross each cell twice, bending springs skip one particle:
///
/// ```
/// use sprung::build::{self, ClothSprings};
/// use sprung::Vec3;
///
/// let (nx, ny) = (4, 3);
/// let cloth = build::cloth(nx, ny, 3.0, 1.0, ClothSprings::default()).unwrap();
/// assert_eq!(cloth.position[2 * nx + 1], Vec3::new(1.0, 1.0, 0.0)); // (x, y) = (1, 2)
/// assert_eq!(cloth.faces.len(), 2 * (nx - 1) * (ny - 1));
/// let structural = (nx - 1) * ny + nx * (ny - 1);
/// let shear = 2 * (nx - 1) * (ny - 1);
/// let bending = (nx - 2) * ny + nx * (ny - 2);
/// assert_eq!(cloth.springs.len(), structural + shear + bending);
/// let error = build::cloth(1, 3, 1.0, 1.0, ClothSprings::default()).unwrap_err();
/// assert_eq!(error.to_string(), "`cloth.nx` = 1: a cloth needs at least 2 particles along x");
/// ```
pub fn cloth(
    nx: usize,
    ny: usize,
    width: Real,
    height: Real,
    springs: ClothSprings,
) -> Result<BodyData, BuildError> {
    check_count(
        "cloth.nx",
        nx,
        2,
        "a cloth needs at least 2 particles along x",
    )?;
    check_count(
        "cloth.ny",
        ny,
        2,
        "a cloth needs at least 2 particles along y",
    )?;
    check_total("cloth.nx", &[nx, ny])?;
    check_length("cloth.width", width)?;
    check_length("cloth.height", height)?;
    check_springs("cloth.nx", spring_count(nx, ny, springs))?;
    let (dx, dy) = (width / (nx - 1) as Real, height / (ny - 1) as Real);
    let id = |x: usize, y: usize| y * nx + x;
    let position = (0..ny)
        .flat_map(|y| (0..nx).map(move |x| Vec3::new(x as Real * dx, y as Real * dy, 0.0)))
        .collect();
    let mut body = BodyData::from_positions(position);
    let mut add = |a: usize, b: usize| body.springs.push(SpringData::between(a, b));
    for y in 0..ny {
        for x in 0..nx {
            if springs.structural && x + 1 < nx {
                add(id(x, y), id(x + 1, y));
            }
            if springs.structural && y + 1 < ny {
                add(id(x, y), id(x, y + 1));
            }
            if springs.shear && x + 1 < nx && y + 1 < ny {
                add(id(x, y), id(x + 1, y + 1));
                add(id(x + 1, y), id(x, y + 1));
            }
            if springs.bending && x + 2 < nx {
                add(id(x, y), id(x + 2, y));
            }
            if springs.bending && y + 2 < ny {
                add(id(x, y), id(x, y + 2));
            }
        }
    }
    body.faces = (0..ny - 1)
        .flat_map(|y| (0..nx - 1).map(move |x| (x, y)))
        .flat_map(|(x, y)| {
            [
                [id(x, y), id(x + 1, y), id(x + 1, y + 1)],
                [id(x, y), id(x + 1, y + 1), id(x, y + 1)],
            ]
        })
        .collect();
    Ok(body)
}

/// How many springs [`cloth`] makes for `nx × ny` particles (each at least
/// 2, at most [`super::MAX_PARTICLES`] in all).
fn spring_count(nx: usize, ny: usize, springs: ClothSprings) -> usize {
    let structural = (nx - 1) * ny + nx * (ny - 1);
    let shear = 2 * (nx - 1) * (ny - 1);
    let bending = (nx - 2) * ny + nx * (ny - 2);
    [
        (springs.structural, structural),
        (springs.shear, shear),
        (springs.bending, bending),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .map(|(_, count)| count)
    .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_spring_count_is_that_of_the_cloth_built() {
        for (nx, ny) in [(2, 2), (3, 2), (7, 5)] {
            for bits in 0..8 {
                let springs = ClothSprings {
                    structural: bits & 1 != 0,
                    shear: bits & 2 != 0,
                    bending: bits & 4 != 0,
                };
                let body = cloth(nx, ny, 1.0, 1.0, springs).expect("a small cloth");
                assert_eq!(spring_count(nx, ny, springs), body.springs.len());
            }
        }
    }
}
