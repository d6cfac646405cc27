//! Internal structure for a closed surface body: a lattice of particles
//! filling the inside, with springs to its 26 neighbours, tied to the
//! surface (docs/physics.md §2: "a lattice filling the inside tied to the
//! surface"). It holds a mesh's shape without gas, like jelly.

use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// Most tests of a lattice point against a face or a surface vertex a fill
/// may take (a few seconds).
const MAX_FILL_WORK: Real = 1e9;

/// Interior lattice points of the closed surface (`position`, `faces`) at
/// `spacing` (m), and the springs to add: between neighbouring lattice
/// points (26-neighbourhood) and from every surface vertex to its nearest
/// lattice point within a cell diagonal (`√3 spacing`). Indices of new points start at `position.len()`; the
/// springs are pairs of indices into the surface points followed by the new
/// points.
pub(crate) fn lattice_fill(
    position: &[Vec3],
    faces: &[[usize; 3]],
    spacing: Real,
) -> Result<(Vec<Vec3>, Vec<[usize; 2]>), BuildError> {
    let low = position.iter().copied().fold(Vec3::INFINITY, Vec3::min);
    let high = position.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
    // As many points along each axis as fit `spacing` apart strictly inside
    // the bounding box, centred in it: none lands on a flat bounding face.
    let counts = ((high - low) / spacing).floor().max(Vec3::ONE);
    let cells = counts.x * counts.y * counts.z;
    if cells.is_nan() || cells > super::MAX_PARTICLES as Real {
        return Err(BuildError::OutOfRange {
            field: "lattice_spacing",
            value: spacing,
            reason: "the internal lattice would have more than 10 000 000 particles",
        });
    }
    // Each cell is tested against every face, and each vertex measured to
    // every lattice particle: refused before that takes more than some
    // seconds, or makes more springs than a scene may hold (13 per cell).
    let work = cells * (faces.len() + position.len()) as Real;
    if work > MAX_FILL_WORK {
        return Err(BuildError::OutOfRange {
            field: "lattice_spacing",
            value: spacing,
            reason: "filling the inside would take more than 1e9 tests of a lattice point against a face or vertex (cells × (faces + vertices)): take a larger spacing or a coarser mesh",
        });
    }
    if 13.0 * cells > super::MAX_SPRINGS as Real {
        return Err(BuildError::OutOfRange {
            field: "lattice_spacing",
            value: spacing,
            reason:
                "the internal lattice's box would hold more than 20 000 000 springs (13 per cell)",
        });
    }
    let [nx, ny, nz] = [counts.x as usize, counts.y as usize, counts.z as usize];
    let origin = 0.5 * (low + high) - 0.5 * spacing * (counts - Vec3::ONE);
    let mut index = vec![usize::MAX; nx * ny * nz];
    let mut points = Vec::new();
    let offset = position.len();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let p = origin + spacing * Vec3::new(x as Real, y as Real, z as Real);
                if inside(p, position, faces) {
                    index[(z * ny + y) * nx + x] = offset + points.len();
                    points.push(p);
                }
            }
        }
    }
    let mut springs = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let here = index[(z * ny + y) * nx + x];
                if here == usize::MAX {
                    continue;
                }
                for (dx, dy, dz) in forward_neighbours() {
                    let (u, v, w) = (x as isize + dx, y as isize + dy, z as isize + dz);
                    if u < 0
                        || v < 0
                        || w < 0
                        || u >= nx as isize
                        || v >= ny as isize
                        || w >= nz as isize
                    {
                        continue;
                    }
                    let there = index[(w as usize * ny + v as usize) * nx + u as usize];
                    if there != usize::MAX {
                        springs.push([here, there]);
                    }
                }
            }
        }
    }
    // Tie each surface vertex to its nearest lattice particle, if that is
    // within a cell diagonal: thin parts far from the lattice (a horse's
    // legs) stay free rather than all pulling on one interior particle.
    let reach = 3.0_f64.sqrt() * spacing;
    for (vertex, &p) in position.iter().enumerate() {
        let nearest = (0..points.len()).min_by(|&a, &b| {
            points[a]
                .distance_squared(p)
                .total_cmp(&points[b].distance_squared(p))
        });
        if let Some(nearest) = nearest.filter(|&n| points[n].distance(p) <= reach) {
            springs.push([vertex, offset + nearest]);
        }
    }
    Ok((points, springs))
}

/// The 13 lattice offsets that are lexicographically positive: each pair
/// of the 26-neighbourhood once.
fn forward_neighbours() -> impl Iterator<Item = (isize, isize, isize)> {
    (-1..=1)
        .flat_map(|dz| (-1..=1).flat_map(move |dy| (-1..=1).map(move |dx| (dx, dy, dz))))
        .filter(|&(dx, dy, dz)| (dz, dy, dx) > (0, 0, 0))
}

/// Whether `p` is inside the closed surface: a ray from `p` in a fixed
/// direction, chosen off every axis so that it almost surely misses edges
/// and vertices, crosses the surface an odd number of times
/// (Möller-Trumbore intersection).
fn inside(p: Vec3, position: &[Vec3], faces: &[[usize; 3]]) -> bool {
    let direction = Vec3::new(1.0, 0.001_414_213_56, 0.001_732_050_81).normalize();
    let crossings = faces
        .iter()
        .filter(|&&[a, b, c]| {
            let (a, b, c) = (position[a], position[b], position[c]);
            let (e1, e2) = (b - a, c - a);
            let h = direction.cross(e2);
            let det = e1.dot(h);
            if det.abs() < 1e-300 {
                return false;
            }
            let s = p - a;
            let u = s.dot(h) / det;
            let q = s.cross(e1);
            let v = direction.dot(q) / det;
            let t = e2.dot(q) / det;
            (0.0..=1.0).contains(&u) && v >= 0.0 && u + v <= 1.0 && t > 0.0
        })
        .count();
    crossings % 2 == 1
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::build::{icosphere, SurfaceSprings};

    #[test]
    fn a_fill_that_would_take_too_long_is_refused_before_it_starts() {
        // A unit icosphere of 5120 faces and 2562 vertices: every cell of
        // its 2 m box is tested against all 7682. Spacing 0.1 m: 20³ cells,
        // 6e7 tests, filled; 0.034 m: 58³ ≈ 2e5 cells (well within the
        // particle limit), 1.5e9 tests, refused at once.
        let sphere = icosphere(1.0, 4, SurfaceSprings::default()).expect("icosphere");
        let (position, faces) = (&sphere.position, &sphere.faces);
        let (points, _) = lattice_fill(position, faces, 0.1).expect("a coarse fill");
        assert!(!points.is_empty());
        let error = lattice_fill(position, faces, 0.034).expect_err("too much work");
        assert!(
            matches!(
                error,
                BuildError::OutOfRange {
                    field: "lattice_spacing",
                    ..
                }
            ),
            "{error}"
        );
    }
}
