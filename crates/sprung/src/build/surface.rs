//! A body from a triangulated surface (a sphere, a mesh from a modelling
//! tool): a spring on every edge, plus the longer springs a soft body
//! needs, which a mesh file lacks (docs/physics.md §2).

use std::collections::HashMap;

use super::fill::lattice_fill;
use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::surface::{bending_pairs, unique_edges};
use crate::units::{Real, Vec3};

/// Which springs a surface body gets besides one per edge.
///
/// A centre particle joined to every vertex, and no bending springs:
///
/// ```
/// use sprung::build::{self, Internal, SurfaceSprings};
///
/// let shell = SurfaceSprings { bending: false, internal: Internal::None };
/// let spoked = SurfaceSprings { bending: false, internal: Internal::Centre };
/// let shell = build::icosphere(1.0, 1, shell).unwrap();
/// let spoked = build::icosphere(1.0, 1, spoked).unwrap();
/// assert_eq!(shell.springs.len(), 120); // one per edge
/// assert_eq!(spoked.particle_count(), 42 + 1);
/// assert_eq!(spoked.springs.len(), 120 + 42);
/// assert!(spoked.position[42].length() < 1e-15); // the centre, to rounding
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceSprings {
    /// A spring across each pair of adjacent triangles, between the two
    /// vertices opposite their shared edge: resists folding along the edge.
    pub bending: bool,
    /// Structure inside the surface that holds the shape without gas.
    pub internal: Internal,
}

impl Default for SurfaceSprings {
    fn default() -> Self {
        SurfaceSprings {
            bending: true,
            internal: Internal::None,
        }
    }
}

/// Internal structure of a surface body.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Internal {
    /// The surface alone.
    None,
    /// An extra particle at the centroid, joined by a spring to every vertex.
    Centre,
    /// A lattice of particles `spacing` (m) apart filling the inside, with
    /// 26-neighbour springs, each surface vertex tied to its nearest lattice
    /// particle. Meaningful for closed surfaces only.
    Lattice {
        /// Distance between lattice particles (m), positive.
        spacing: Real,
    },
}

/// A body with particles at `position` (m), the triangles `faces` and the
/// springs `springs` asks for. Internal particles (a centre, a lattice) come
/// after the surface's and belong to no face. A pair of distinct vertices at the same place (real
/// meshes have them: `UUSALKU.ASC`'s "Object" does) gets no spring, since a
/// spring of zero rest length has no direction.
///
/// # Examples
///
/// A tetrahedron from its corners and outward triangles: a spring on each
/// of its 6 edges (the vertices across an edge are joined by an edge
/// already, so no bending spring), and the exact volume `1/6`:
///
/// ```
/// use sprung::build::{self, SurfaceSprings};
/// use sprung::{IntegratorKind, Vec3, World};
///
/// let corners = vec![Vec3::ZERO, Vec3::X, Vec3::Y, Vec3::Z];
/// let faces = vec![[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
/// let tetrahedron = build::surface(corners, faces, SurfaceSprings::default()).unwrap();
/// assert_eq!(tetrahedron.springs.len(), 6);
/// assert!(tetrahedron.is_closed());
/// let mut world = World::new(IntegratorKind::Verlet);
/// let index = world.add_body("tetrahedron", tetrahedron).unwrap();
/// assert_eq!(world.volume(index), Some(1.0 / 6.0));
/// ```
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
    match springs.internal {
        Internal::None => {}
        Internal::Centre => {
            let centre = position.iter().sum::<Vec3>() / count as Real;
            position.push(centre);
            pairs.extend((0..count).map(|i| [i, count]));
        }
        Internal::Lattice { spacing } => {
            if !(spacing.is_finite() && spacing > 0.0) {
                return Err(BuildError::OutOfRange {
                    field: "lattice_spacing",
                    value: spacing,
                    reason: "the internal lattice spacing must be positive (m)",
                });
            }
            let (points, ties) = lattice_fill(&position, &faces, spacing)?;
            position.extend(points);
            pairs.extend(ties);
        }
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
