//! Topology of triangle meshes: edges, closedness, orientation, volume.
//!
//! A gas body (docs/physics.md section 4) needs a closed surface: every edge
//! shared by exactly two triangles, which traverse it in opposite
//! directions (a consistent orientation), with the normals pointing out.
//! Its volume comes from the divergence theorem, which for flat triangles is
//! exactly the sum of signed tetrahedra `(1/6) Σ a·(b×c)`; it is positive
//! when the triangles wind counter-clockwise seen from outside.
//!
//! Edges are reported in the order they first appear in the triangle list
//! (triangle 0's edges `ab`, `bc`, `ca`, then triangle 1's...), each as
//! `[lower, higher]` vertex index, so "the first offending edge" is well
//! defined and stable.

use std::collections::{HashMap, VecDeque};
use std::path::Path;

use super::error::{MeshError, MeshErrorKind};
use super::TriangleMesh;

/// Signed volume enclosed by the triangles, by the divergence theorem:
/// `(1/6) Σ a·(b×c)` over the triangles `(a, b, c)`, in one pass.
///
/// In the positions' units cubed. Exact (up to rounding) for a closed
/// surface, positive when it is oriented outward (counter-clockwise seen
/// from outside); for an open surface the value depends on the origin.
/// Returns NaN if a triangle refers to a vertex that does not exist.
pub fn signed_volume(positions: &[[f64; 3]], triangles: &[[usize; 3]]) -> f64 {
    let mut six_volume = 0.0;
    for &[i, j, k] in triangles {
        let (Some(a), Some(b), Some(c)) = (positions.get(i), positions.get(j), positions.get(k))
        else {
            return f64::NAN;
        };
        six_volume += triple_product(*a, *b, *c);
    }
    six_volume / 6.0
}

/// `a · (b × c)`: six times the signed volume of the tetrahedron
/// (origin, a, b, c).
fn triple_product([ax, ay, az]: [f64; 3], [bx, by, bz]: [f64; 3], [cx, cy, cz]: [f64; 3]) -> f64 {
    ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
}

/// Undirected edges of a triangle list and how the triangles use them.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct EdgeReport {
    /// Every undirected edge `[lower, higher]` with the number of triangles
    /// that use it, in order of first appearance.
    pub edges: Vec<([usize; 2], usize)>,
    /// Edges used by one triangle only: the rim of a hole or of an open sheet.
    pub boundary: Vec<[usize; 2]>,
    /// Edges used by more than two triangles.
    pub non_manifold: Vec<[usize; 2]>,
    /// Edges used by exactly two triangles that traverse them in the same
    /// direction: the two triangles are oriented inconsistently.
    pub misoriented: Vec<[usize; 2]>,
    /// Triangles that repeat a vertex (their edges are not counted).
    pub degenerate: Vec<usize>,
}

impl EdgeReport {
    /// Whether the triangles form a closed, edge-manifold surface: every
    /// edge shared by exactly two triangles, and no degenerate triangle.
    pub fn is_closed(&self) -> bool {
        !self.edges.is_empty()
            && self.boundary.is_empty()
            && self.non_manifold.is_empty()
            && self.degenerate.is_empty()
    }
}

/// One undirected edge and the triangles using it: (triangle, whether the
/// triangle traverses it from the lower to the higher vertex).
struct EdgeUses {
    key: [usize; 2],
    uses: Vec<(usize, bool)>,
}

/// Whether a triangle names a vertex twice (a line or a point, no area).
pub(super) fn is_degenerate(&[a, b, c]: &[usize; 3]) -> bool {
    a == b || b == c || c == a
}

/// Edges of every non-degenerate triangle, in order of first appearance.
fn edge_uses(triangles: &[[usize; 3]]) -> Vec<EdgeUses> {
    let mut index_of: HashMap<[usize; 2], usize> = HashMap::with_capacity(triangles.len() * 2);
    let mut edges: Vec<EdgeUses> = Vec::with_capacity(triangles.len() * 3 / 2);
    for (t, tri) in triangles.iter().enumerate() {
        if is_degenerate(tri) {
            continue;
        }
        let [a, b, c] = *tri;
        for (u, v) in [(a, b), (b, c), (c, a)] {
            let key = [u.min(v), u.max(v)];
            let slot = *index_of.entry(key).or_insert_with(|| {
                edges.push(EdgeUses {
                    key,
                    uses: Vec::with_capacity(2),
                });
                edges.len() - 1
            });
            if let Some(edge) = edges.get_mut(slot) {
                edge.uses.push((t, u < v));
            }
        }
    }
    edges
}

/// Counts the triangles on every undirected edge and lists the boundary,
/// non-manifold and misoriented edges and the degenerate triangles.
pub fn edge_report(triangles: &[[usize; 3]]) -> EdgeReport {
    let mut report = EdgeReport {
        degenerate: (0..triangles.len())
            .filter(|&t| triangles.get(t).is_some_and(is_degenerate))
            .collect(),
        ..EdgeReport::default()
    };
    for edge in edge_uses(triangles) {
        let count = edge.uses.len();
        report.edges.push((edge.key, count));
        match edge.uses.as_slice() {
            [_] => report.boundary.push(edge.key),
            [(_, first), (_, second)] => {
                if first == second {
                    report.misoriented.push(edge.key);
                }
            }
            _ => report.non_manifold.push(edge.key),
        }
    }
    report
}

/// One spring per edge and the bending pairs of a mesh body come from the
/// engine, which builds surface bodies; re-exported for mesh users.
pub use sprung::surface::{bending_pairs, unique_edges};

/// Checks that `mesh` is a closed, edge-manifold, orientable surface and
/// returns it oriented outward.
///
/// Triangles are reoriented so that each edge-connected component is
/// consistent (a breadth-first walk over the faces flips the triangles that
/// disagree with their neighbours), then every component whose signed volume
/// is negative is flipped as a whole. Each component is thus made to enclose
/// positive volume, so a cavity modelled as an inner, inward-facing shell is
/// turned outward too. Positions and vertex numbering are unchanged
/// (vertices used by no triangle are kept).
///
/// Errors, naming `file` and the object: indices out of range, non-finite
/// positions, no triangles, a degenerate triangle, boundary edges,
/// non-manifold edges (each with the count and the first edge), a
/// non-orientable surface, and a flat component (signed volume below
/// `1e-12` times its bounding-box diagonal cubed: rounding, not a volume).
/// Non-manifold vertices (two fans touching at a vertex) are accepted.
pub fn closed_surface(mesh: &TriangleMesh, file: &Path) -> Result<TriangleMesh, MeshError> {
    let fail = |kind: MeshErrorKind| MeshError::new(file, kind).in_object(&mesh.name);
    let vertex_count = mesh.positions.len();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        if let Some(&bad) = tri.iter().find(|&&v| v >= vertex_count) {
            return Err(fail(MeshErrorKind::IndexOutOfRange {
                face: t,
                index: i64::try_from(bad).unwrap_or(i64::MAX),
                vertices: vertex_count,
            }));
        }
    }
    if let Some(bad) = mesh.positions.iter().flatten().find(|c| !c.is_finite()) {
        return Err(fail(MeshErrorKind::NonFinite {
            value: bad.to_string(),
        }));
    }
    if mesh.triangles.is_empty() {
        return Err(fail(MeshErrorKind::NoMesh));
    }
    if let Some((t, &[a, b, c])) = mesh
        .triangles
        .iter()
        .enumerate()
        .find(|(_, tri)| is_degenerate(tri))
    {
        let vertex = if a == b || a == c { a } else { b };
        return Err(fail(MeshErrorKind::Degenerate {
            triangle: t,
            vertex,
        }));
    }

    let edges = edge_uses(&mesh.triangles);
    let boundary: Vec<[usize; 2]> = edges
        .iter()
        .filter(|e| e.uses.len() == 1)
        .map(|e| e.key)
        .collect();
    if let Some(&first) = boundary.first() {
        return Err(fail(MeshErrorKind::NotClosed {
            count: boundary.len(),
            first,
        }));
    }
    let non_manifold: Vec<&EdgeUses> = edges.iter().filter(|e| e.uses.len() > 2).collect();
    if let Some(first) = non_manifold.first() {
        return Err(fail(MeshErrorKind::NonManifold {
            count: non_manifold.len(),
            first: first.key,
            triangles: first.uses.len(),
        }));
    }

    let flips = consistent_flips(mesh.triangles.len(), &edges).map_err(fail)?;
    let mut triangles: Vec<[usize; 3]> = mesh
        .triangles
        .iter()
        .zip(&flips.flip)
        .map(|(&[a, b, c], &flip)| if flip { [a, c, b] } else { [a, b, c] })
        .collect();

    // Per component: signed volume and bounding box, in one pass.
    let mut stats: Vec<Option<ComponentStats>> = vec![None; flips.component_count];
    for (t, (tri, &component)) in triangles.iter().zip(&flips.component).enumerate() {
        let corners = tri.map(|v| mesh.positions.get(v).copied().unwrap_or_default());
        if let Some(slot) = stats.get_mut(component) {
            slot.get_or_insert_with(|| ComponentStats::new(t))
                .add(corners);
        }
    }
    for s in stats.iter().flatten() {
        // Rounding in the triple products is about 1e-16 of diagonal³ per
        // triangle; 1e-12 leaves room for 10⁴ triangles and more.
        if s.volume.abs() <= 1e-12 * s.diagonal().powi(3) {
            return Err(fail(MeshErrorKind::FlatComponent {
                triangle: s.first_triangle,
                volume: s.volume,
            }));
        }
    }
    for (tri, &component) in triangles.iter_mut().zip(&flips.component) {
        if stats
            .get(component)
            .and_then(Option::as_ref)
            .is_some_and(|s| s.volume < 0.0)
        {
            tri.swap(1, 2);
        }
    }
    Ok(TriangleMesh {
        name: mesh.name.clone(),
        positions: mesh.positions.clone(),
        triangles,
    })
}

/// Signed volume and bounding box of one edge-connected component.
#[derive(Clone)]
struct ComponentStats {
    first_triangle: usize,
    volume: f64,
    lower: [f64; 3],
    upper: [f64; 3],
}

impl ComponentStats {
    fn new(first_triangle: usize) -> Self {
        ComponentStats {
            first_triangle,
            volume: 0.0,
            lower: [f64::INFINITY; 3],
            upper: [f64::NEG_INFINITY; 3],
        }
    }

    fn add(&mut self, [a, b, c]: [[f64; 3]; 3]) {
        self.volume += triple_product(a, b, c) / 6.0;
        for p in [a, b, c] {
            for ((lo, hi), x) in self.lower.iter_mut().zip(self.upper.iter_mut()).zip(p) {
                *lo = lo.min(x);
                *hi = hi.max(x);
            }
        }
    }

    fn diagonal(&self) -> f64 {
        self.lower
            .iter()
            .zip(self.upper)
            .map(|(lo, hi)| (hi - lo) * (hi - lo))
            .sum::<f64>()
            .sqrt()
    }
}

/// The outcome of the orientation walk.
struct Flips {
    /// Whether each triangle must be flipped to agree with its component.
    flip: Vec<bool>,
    /// The edge-connected component of each triangle.
    component: Vec<usize>,
    component_count: usize,
}

/// Breadth-first walk over the faces of a closed edge-manifold mesh (every
/// edge used by exactly two triangles): two neighbours agree when they
/// traverse their shared edge in opposite directions.
fn consistent_flips(triangle_count: usize, edges: &[EdgeUses]) -> Result<Flips, MeshErrorKind> {
    // neighbours[t]: (other triangle, same direction on the shared edge, edge)
    let mut neighbours: Vec<Vec<(usize, bool, [usize; 2])>> =
        vec![Vec::with_capacity(3); triangle_count];
    for edge in edges {
        if let [(t1, d1), (t2, d2)] = *edge.uses.as_slice() {
            if let Some(n) = neighbours.get_mut(t1) {
                n.push((t2, d1 == d2, edge.key));
            }
            if let Some(n) = neighbours.get_mut(t2) {
                n.push((t1, d1 == d2, edge.key));
            }
        }
    }
    let mut flip = vec![false; triangle_count];
    let mut component = vec![usize::MAX; triangle_count];
    let mut component_count = 0;
    let mut queue = VecDeque::new();
    for seed in 0..triangle_count {
        if component.get(seed) != Some(&usize::MAX) {
            continue;
        }
        if let Some(c) = component.get_mut(seed) {
            *c = component_count;
        }
        queue.push_back(seed);
        while let Some(t) = queue.pop_front() {
            let t_flip = flip.get(t).copied().unwrap_or(false);
            for &(other, same_direction, key) in neighbours.get(t).map_or(&[][..], Vec::as_slice) {
                // Traversing the edge the same way, the two need opposite flips.
                let wanted = t_flip ^ same_direction;
                match component.get(other) {
                    Some(&usize::MAX) => {
                        if let (Some(c), Some(f)) = (component.get_mut(other), flip.get_mut(other))
                        {
                            *c = component_count;
                            *f = wanted;
                        }
                        queue.push_back(other);
                    }
                    Some(_) if flip.get(other) != Some(&wanted) => {
                        return Err(MeshErrorKind::NotOrientable { edge: key });
                    }
                    Some(_) | None => {}
                }
            }
        }
        component_count += 1;
    }
    Ok(Flips {
        flip,
        component,
        component_count,
    })
}
