//! A body from a triangulated surface (a sphere, a mesh from a modelling
//! tool): a spring on every edge, plus the longer springs a soft body
//! needs, which a mesh file lacks (PHYSICS.md §2).

use std::collections::HashMap;

use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::surface::{bending_pairs, unique_edges};
use crate::Vec3;

/// Which springs a surface body gets besides one per edge.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SurfaceSprings {
    /// A spring across each pair of adjacent triangles, between the two
    /// vertices opposite their shared edge: resists folding along the edge.
    pub bending: bool,
    /// An extra particle at the centroid, joined by a spring to every
    /// vertex: an internal skeleton that holds the shape without gas.
    pub centre: bool,
}

impl Default for SurfaceSprings {
    fn default() -> Self {
        SurfaceSprings {
            bending: true,
            centre: false,
        }
    }
}

/// A body with particles at `position` (m), the triangles `faces` and the
/// springs `springs` asks for. The centre particle, if any, comes last and
/// belongs to no face. A pair of distinct vertices at the same place (real
/// meshes have them: `UUSALKU.ASC`'s "Object" does) gets no spring, since a
/// spring of zero rest length has no direction.
pub fn surface(
    position: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
    springs: SurfaceSprings,
) -> Result<BodyData, BuildError> {
    let count = position.len();
    if count == 0 {
        return Err(BuildError::NoParticles);
    }
    let mut pairs = unique_edges(&faces);
    if springs.bending {
        pairs.extend(bending_pairs(&faces));
    }
    let mut position = position;
    if springs.centre {
        let centre = position.iter().sum::<Vec3>() / count as f64;
        position.push(centre);
        pairs.extend((0..count).map(|i| [i, count]));
    }
    pairs.retain(|&[a, b]| position[a] != position[b]);
    let mut body = BodyData::from_positions(position);
    body.springs = pairs
        .into_iter()
        .map(|[a, b]| SpringData::between(a, b))
        .collect();
    body.faces = faces;
    Ok(body)
}

/// Split every triangle in four through its edge midpoints (shared between
/// neighbours, appended to `points`), keeping the orientation. Refining a
/// coarse mesh (the 8-vertex textbook cube) gives the gas a surface it can
/// round out.
pub fn refine(points: &mut Vec<Vec3>, faces: &[[usize; 3]]) -> Vec<[usize; 3]> {
    let mut midpoints: HashMap<(usize, usize), usize> = HashMap::new();
    let mut midpoint = |a: usize, b: usize, points: &mut Vec<Vec3>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            points.push(0.5 * (points[a] + points[b]));
            points.len() - 1
        })
    };
    let mut refined = Vec::with_capacity(faces.len() * 4);
    for &[a, b, c] in faces {
        let ab = midpoint(a, b, points);
        let bc = midpoint(b, c, points);
        let ca = midpoint(c, a, points);
        refined.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    refined
}
