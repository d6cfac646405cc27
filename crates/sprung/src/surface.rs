//! Closed surfaces: the triangles (3D) or segments (2D) that bound a body,
//! their edges, and the volume (area in 2D) they enclose (docs/physics.md §4).
//!
//! The volume comes from the divergence theorem with the field
//! `F = (x, 0, 0)`, whose divergence is 1:
//!
//! ```text
//! V = ∮ x n_x dS = Σ_faces x̄_f n_{x,f} A_f        (3D)
//! A = ∮ x n_x dl = Σ_edges x̄_e n_{x,e} l_e        (2D)
//! ```
//!
//! With `A_f n_f = ½ (b - a) × (c - a)` and `l_e n_e = (Δy, -Δx)` for a
//! counter-clockwise loop, both sums are exact for flat faces: the 3D one
//! equals the signed-tetrahedron sum `(1/6) Σ a · (b × c)`, the 2D one the
//! shoelace formula. Each is a single pass over the faces.
//!
//! The textbook's 2D code sums `½ |x1 - x2| |n_x| d` per segment instead:
//! that is `½ |Δx| |Δy|`, which is not a signed area term. It is kept here
//! as [`textbook_segment_area`] only so a test can show that it is wrong.

use std::collections::{HashMap, HashSet};

use crate::parallel;
use crate::units::{Real, Vec3};

/// Area-weighted normals at the vertices of the triangles `faces` over
/// `position` (m): each vertex gets the sum of `(b − a) × (c − a)` of the
/// faces around it (twice their areas, outward for counter-clockwise
/// faces), unnormalised; zero at a vertex on no face. Faces with an index
/// out of range or a non-finite normal are skipped. For smooth shading
/// (the pictures, OBJ and glTF frames).
pub fn vertex_normals(faces: &[[u32; 3]], position: &[Vec3]) -> Vec<Vec3> {
    let mut normals = vec![Vec3::ZERO; position.len()];
    for face in faces {
        let [Some(&a), Some(&b), Some(&c)] = face.map(|i| position.get(i as usize)) else {
            continue;
        };
        let n = (b - a).cross(c - a);
        if n.is_finite() {
            for &i in face {
                normals[i as usize] += n;
            }
        }
    }
    normals
}

/// [`vertex_normals`] of unit length, for the exported frames: +z where
/// there is none (a vertex on no face, or whose faces have no area), the
/// same in every format.
pub fn unit_vertex_normals(faces: &[[u32; 3]], position: &[Vec3]) -> Vec<Vec3> {
    let mut normals = vertex_normals(faces, position);
    for n in &mut normals {
        *n = n.try_normalize().unwrap_or(Vec3::Z);
    }
    normals
}

/// Volume enclosed by triangles `faces` (counter-clockwise seen from
/// outside) at `position`, by the divergence theorem (m³). Positive for an
/// outward-oriented closed surface.
pub fn enclosed_volume(position: &[Vec3], faces: &[[u32; 3]]) -> Real {
    parallel::sum(faces.len(), |range| {
        faces[range]
            .iter()
            .map(|&[a, b, c]| {
                let (a, b, c) = (
                    position[a as usize],
                    position[b as usize],
                    position[c as usize],
                );
                let area_normal = 0.5 * (b - a).cross(c - a);
                (a.x + b.x + c.x) / 3.0 * area_normal.x
            })
            .sum()
    })
}

/// Area enclosed by the closed loop of `segments` (each `[from, to]`,
/// counter-clockwise) in the xy-plane at `position`, by the divergence
/// theorem (m²). Positive for a counter-clockwise loop.
pub fn enclosed_area(position: &[Vec3], segments: &[[u32; 2]]) -> Real {
    parallel::sum(segments.len(), |range| {
        segments[range]
            .iter()
            .map(|&[a, b]| {
                let (a, b) = (position[a as usize], position[b as usize]);
                0.5 * (a.x + b.x) * (b.y - a.y)
            })
            .sum()
    })
}

/// The textbook's 2D "volume" (docs/physics.md §4): `Σ ½ |x1 - x2| |n_x| d`
/// over the segments. Wrong: it is `Σ ½ |Δx| |Δy|`, about `2πR²/N` for a
/// regular N-gon and 0 for an axis-aligned square. Not used by the engine.
pub fn textbook_segment_area(position: &[Vec3], segments: &[[u32; 2]]) -> Real {
    segments
        .iter()
        .map(|&[a, b]| {
            let delta = position[a as usize] - position[b as usize];
            let length = delta.truncate().length();
            let normal_x = if length > 0.0 { delta.y / length } else { 0.0 };
            0.5 * delta.x.abs() * normal_x.abs() * length
        })
        .sum()
}

/// Every undirected edge of `triangles` once, as `[lower, higher]`, in the
/// order of first appearance.
pub fn unique_edges(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    let mut seen = HashSet::with_capacity(triangles.len() * 2);
    let mut edges = Vec::with_capacity(triangles.len() * 3 / 2);
    for &[a, b, c] in triangles {
        for (u, v) in [(a, b), (b, c), (c, a)] {
            let key = [u.min(v), u.max(v)];
            if u != v && seen.insert(key) {
                edges.push(key);
            }
        }
    }
    edges
}

/// For every edge shared by exactly two triangles, the pair of vertices
/// opposite it `[lower, higher]`: a bending spring across the two triangles
/// resists folding the surface along the edge. Deduplicated, in order of
/// first appearance; pairs that are already edges are left out, and edges of
/// more than two triangles give none.
pub fn bending_pairs(triangles: &[[usize; 3]]) -> Vec<[usize; 2]> {
    let edges: HashSet<[usize; 2]> = unique_edges(triangles).into_iter().collect();
    // For each edge in order of first appearance: the vertices opposite it.
    let mut order = Vec::new();
    let mut opposite: HashMap<[usize; 2], Vec<usize>> = HashMap::new();
    for &[a, b, c] in triangles {
        for (u, v, w) in [(a, b, c), (b, c, a), (c, a, b)] {
            let key = [u.min(v), u.max(v)];
            let entry = opposite.entry(key).or_default();
            if entry.is_empty() {
                order.push(key);
            }
            entry.push(w);
        }
    }
    let mut seen = HashSet::new();
    order
        .into_iter()
        .filter_map(|key| match opposite[&key].as_slice() {
            &[p, q] if p != q => Some([p.min(q), p.max(q)]),
            _ => None,
        })
        .filter(|pair| !edges.contains(pair) && seen.insert(*pair))
        .collect()
}

/// Why a set of faces or segments cannot hold a gas.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum SurfaceProblem {
    /// An edge used by one face only (the surface has a hole there).
    Boundary([usize; 2]),
    /// An edge traversed twice in the same direction: the faces disagree
    /// about which side is out, or more than two faces share the edge.
    Misoriented([usize; 2]),
    /// A 2D loop where a particle does not have exactly one segment in and
    /// one out.
    BrokenLoop(usize),
}

impl std::fmt::Display for SurfaceProblem {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SurfaceProblem::Boundary([a, b]) => write!(f, "edge {a}-{b} belongs to one face only (the surface is open)"),
            SurfaceProblem::Misoriented([a, b]) => write!(f, "edge {a}-{b} is traversed twice in the same direction (the faces are not consistently oriented, or more than two share it)"),
            SurfaceProblem::BrokenLoop(p) => write!(f, "particle {p} does not have exactly one segment in and one out (the loop is not closed)"),
        }
    }
}

/// Check that `faces` form a closed, edge-manifold, consistently oriented
/// surface: every edge used by exactly two faces, in opposite directions.
pub fn check_closed_faces(faces: &[[usize; 3]]) -> Result<(), SurfaceProblem> {
    let mut directed: HashMap<[usize; 2], u32> = HashMap::with_capacity(faces.len() * 3);
    for &[a, b, c] in faces {
        for (u, v) in [(a, b), (b, c), (c, a)] {
            let count = directed.entry([u, v]).or_default();
            *count += 1;
            if *count > 1 {
                return Err(SurfaceProblem::Misoriented([u.min(v), u.max(v)]));
            }
        }
    }
    for &[a, b, c] in faces {
        for (u, v) in [(a, b), (b, c), (c, a)] {
            if !directed.contains_key(&[v, u]) {
                return Err(SurfaceProblem::Boundary([u.min(v), u.max(v)]));
            }
        }
    }
    Ok(())
}

/// Check that `segments` form closed loops: every particle they touch has
/// exactly one segment leaving it and one arriving.
pub fn check_closed_loop(segments: &[[usize; 2]]) -> Result<(), SurfaceProblem> {
    let mut degree: HashMap<usize, (u32, u32)> = HashMap::with_capacity(segments.len());
    for &[a, b] in segments {
        degree.entry(a).or_default().0 += 1;
        degree.entry(b).or_default().1 += 1;
    }
    let mut bad: Vec<usize> = degree
        .into_iter()
        .filter(|(_, (out, into))| (*out, *into) != (1, 1))
        .map(|(p, _)| p)
        .collect();
    bad.sort_unstable();
    match bad.first() {
        Some(&p) => Err(SurfaceProblem::BrokenLoop(p)),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_normals_are_the_faces_and_plus_z_where_there_is_none() {
        // A triangle in the xy-plane, counter-clockwise from +z, whose
        // normal at each corner is +z; a triangle folded on x = 1 (no
        // area: the normal of its corner 3 alone is none); a vertex on no
        // face. Claim: unit normals, +z where there is none, so every
        // exporter writes the same.
        let position = [
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 2.0, 0.0),
            Vec3::new(4.0, 0.0, 0.0),
            Vec3::new(5.0, 5.0, 5.0),
        ];
        let faces = [[0, 1, 2], [1, 3, 1]];
        let normals = unit_vertex_normals(&faces, &position);
        assert_eq!(normals, vec![Vec3::Z; 5]);
        // Turned over: -z where a face is, +z still where none is.
        let flipped = unit_vertex_normals(&[[0, 2, 1]], &position);
        assert_eq!(flipped[..3], [-Vec3::Z; 3]);
        assert_eq!(flipped[3..], [Vec3::Z; 2]);
    }
}
