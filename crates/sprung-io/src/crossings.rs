//! Surfaces passing through each other, counted from a run's frames alone
//! (`sprung check --intersections RUN_DIR`): a check of any run that does
//! not trust the engine's own collision handling, written apart from it.
//!
//! Two counts per frame, each between bodies and within one body:
//!
//! - **Points through**: a particle on the other side of a triangle than
//!   in the frame before, having passed through it. The motion between
//!   frames is taken as straight lines, cut into [`PIECES`] equal pieces;
//!   on a piece where the signed volume of the triangle and the point
//!   changes sign, bisection finds where the point meets the triangle's
//!   plane, and the point passed through where it is over the triangle
//!   there. With a frame each step this follows the engine's own motion.
//! - **Edges through**: an edge of a surface through a triangle it does
//!   not share a particle with, in the frame itself.
//!
//! Within a body counts folds of one surface through itself, which only a
//! body with `self_collision` is kept from.

use std::collections::BTreeSet;

use sprung::{Real, Vec3};

use crate::export::VtkFrame;

/// Pieces the motion between two frames is cut into.
pub const PIECES: usize = 8;

/// Bisections locating where a point meets a triangle's plane.
const BISECTIONS: usize = 60;

/// The surfaces of a frame: points, each point's body, triangles.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Surfaces {
    /// Point positions (m).
    pub points: Vec<Vec3>,
    /// Per point, its body (0 where the frame does not say).
    pub body: Vec<u32>,
    /// Triangles (point indices).
    pub triangles: Vec<[u32; 3]>,
    /// The triangles' edges, each once.
    pub edges: Vec<[u32; 2]>,
}

impl Surfaces {
    /// The surfaces of `world` as they are now, as a frame of it would
    /// hold them.
    pub fn of_world(world: &sprung::World) -> Self {
        let mut body = vec![0; world.particles.len()];
        let mut faces = Vec::new();
        for (b, each) in world.bodies.iter().enumerate() {
            body[each.particles.clone()].fill(b as u32);
            faces.extend(each.faces.iter().map(|f| f.to_vec()));
        }
        let frame = VtkFrame {
            points: world.particles.position.clone(),
            polygons: faces,
            ..VtkFrame::default()
        };
        Surfaces {
            body,
            ..Surfaces::of_frame(&frame)
        }
    }

    /// The triangles of a VTK frame, with the `body` point array.
    pub fn of_frame(frame: &VtkFrame) -> Self {
        let n = frame.points.len();
        let body = frame
            .point_scalars("body")
            .map(|b| b.iter().map(|&b| b as u32).collect())
            .unwrap_or_else(|| vec![0; n]);
        let triangles: Vec<[u32; 3]> = frame
            .polygons
            .iter()
            .filter(|p| p.len() == 3 && p.iter().all(|&i| (i as usize) < n))
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        let edges: BTreeSet<[u32; 2]> = triangles
            .iter()
            .flat_map(|&[a, b, c]| [[a, b], [b, c], [c, a]])
            .map(|[a, b]| [a.min(b), a.max(b)])
            .collect();
        Surfaces {
            points: frame.points.clone(),
            body,
            triangles,
            edges: edges.into_iter().collect(),
        }
    }
}

/// What passed through what in one frame.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Crossings {
    /// Points through a triangle of another body since the last frame.
    pub points_between: usize,
    /// Edges through a triangle of another body.
    pub edges_between: usize,
    /// Points through a triangle of their own body since the last frame.
    pub points_within: usize,
    /// Edges through a triangle of their own body.
    pub edges_within: usize,
}

impl std::ops::AddAssign for Crossings {
    /// Add another frame's counts, kind by kind.
    fn add_assign(&mut self, other: Crossings) {
        self.points_between += other.points_between;
        self.edges_between += other.edges_between;
        self.points_within += other.points_within;
        self.edges_within += other.edges_within;
    }
}

impl Crossings {
    /// Crossings between bodies.
    pub fn between(&self) -> usize {
        self.points_between + self.edges_between
    }

    /// Crossings within bodies.
    pub fn within(&self) -> usize {
        self.points_within + self.edges_within
    }
}

/// The crossings of frame `now` since frame `before` (the same points and
/// triangles; `None` for the first frame, whose points cannot have moved
/// through anything).
pub fn count(before: Option<&Surfaces>, now: &Surfaces) -> Crossings {
    let mut crossings = Crossings::default();
    let tri_box = |s: &Surfaces, t: &[u32; 3]| bounds(t.iter().map(|&i| s.points[i as usize]));
    // Edges through triangles, in this frame.
    let edge_boxes: Vec<_> = now
        .edges
        .iter()
        .map(|e| bounds(e.iter().map(|&i| now.points[i as usize])))
        .collect();
    let triangle_boxes: Vec<_> = now.triangles.iter().map(|t| tri_box(now, t)).collect();
    overlapping(&edge_boxes, &triangle_boxes, |e, t| {
        let (edge, triangle) = (now.edges[e], now.triangles[t]);
        if triangle.contains(&edge[0]) || triangle.contains(&edge[1]) {
            return;
        }
        let p = |i: u32| now.points[i as usize];
        let [a, b, c] = triangle.map(p);
        if segment_through(p(edge[0]), p(edge[1]), a, b, c) {
            if now.body[edge[0] as usize] == now.body[triangle[0] as usize] {
                crossings.edges_within += 1;
            } else {
                crossings.edges_between += 1;
            }
        }
    });
    let Some(before) = before.filter(|b| b.points.len() == now.points.len()) else {
        return crossings;
    };
    // Points through triangles, on the way from the last frame.
    let on_surface: BTreeSet<u32> = now.triangles.iter().flatten().copied().collect();
    let points: Vec<u32> = on_surface.into_iter().collect();
    let path_boxes: Vec<_> = points
        .iter()
        .map(|&i| bounds([before.points[i as usize], now.points[i as usize]].into_iter()))
        .collect();
    let swept: Vec<_> = now
        .triangles
        .iter()
        .map(|t| {
            let (lo0, hi0) = tri_box(before, t);
            let (lo1, hi1) = tri_box(now, t);
            (lo0.min(lo1), hi0.max(hi1))
        })
        .collect();
    overlapping(&path_boxes, &swept, |k, t| {
        let (i, triangle) = (points[k], now.triangles[t]);
        if triangle.contains(&i) {
            return;
        }
        let at = |s: Real, j: u32| {
            let (x0, x1) = (before.points[j as usize], now.points[j as usize]);
            x0 + s * (x1 - x0)
        };
        let volume = |s: Real| {
            let [a, b, c] = triangle.map(|j| at(s, j));
            (b - a).cross(c - a).dot(at(s, i) - a)
        };
        let through = (0..PIECES).any(|piece| {
            let (mut s0, mut s1) = (
                piece as Real / PIECES as Real,
                (piece + 1) as Real / PIECES as Real,
            );
            let (v0, v1) = (volume(s0), volume(s1));
            if v0 == 0.0 || (v0 > 0.0) == (v1 > 0.0) {
                return false;
            }
            // Where the point meets the triangle's plane, by bisection,
            // and whether it is over the triangle there.
            for _ in 0..BISECTIONS {
                let middle = 0.5 * (s0 + s1);
                if (volume(middle) > 0.0) == (v0 > 0.0) {
                    s0 = middle;
                } else {
                    s1 = middle;
                }
            }
            let meet = 0.5 * (s0 + s1);
            let [a, b, c] = triangle.map(|j| at(meet, j));
            over_triangle(at(meet, i), a, b, c)
        });
        if through {
            if now.body[i as usize] == now.body[triangle[0] as usize] {
                crossings.points_within += 1;
            } else {
                crossings.points_between += 1;
            }
        }
    });
    crossings
}

/// The box (low and high corners) of `points`.
fn bounds(points: impl Iterator<Item = Vec3>) -> (Vec3, Vec3) {
    points.fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), p| {
        (lo.min(p), hi.max(p))
    })
}

/// Call `meet(a, b)` for every box of `first` that overlaps one of
/// `second`: both sorted along x and swept.
fn overlapping(
    first: &[(Vec3, Vec3)],
    second: &[(Vec3, Vec3)],
    mut meet: impl FnMut(usize, usize),
) {
    let mut order: Vec<(Real, bool, usize)> = first
        .iter()
        .enumerate()
        .map(|(i, b)| (b.0.x, false, i))
        .chain(second.iter().enumerate().map(|(i, b)| (b.0.x, true, i)))
        .collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
    let overlap = |a: &(Vec3, Vec3), b: &(Vec3, Vec3)| a.0.cmple(b.1).all() && b.0.cmple(a.1).all();
    for (k, &(_, is_second, i)) in order.iter().enumerate() {
        let own = if is_second { second[i] } else { first[i] };
        for &(low, other_second, j) in &order[k + 1..] {
            if low > own.1.x {
                break;
            }
            if other_second == is_second {
                continue;
            }
            let other = if other_second { second[j] } else { first[j] };
            if overlap(&own, &other) {
                if is_second {
                    meet(j, i);
                } else {
                    meet(i, j);
                }
            }
        }
    }
}

/// Whether the segment `p → q` passes through the triangle `(a, b, c)`:
/// its ends strictly on either side of the triangle's plane, and the point
/// where it meets the plane inside the triangle or on its edges. A segment
/// in the plane, or ending on it, touches but does not pass through.
fn segment_through(p: Vec3, q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let normal = (b - a).cross(c - a);
    let (dp, dq) = (normal.dot(p - a), normal.dot(q - a));
    if dp == 0.0 || dq == 0.0 || (dp > 0.0) == (dq > 0.0) {
        return false;
    }
    over_triangle(p + dp / (dp - dq) * (q - p), a, b, c)
}

/// Whether `x` lies over the triangle `(a, b, c)` (its edges included),
/// seen along the triangle's normal.
fn over_triangle(x: Vec3, a: Vec3, b: Vec3, c: Vec3) -> bool {
    let normal = (b - a).cross(c - a);
    let sides = [(a, b), (b, c), (c, a)].map(|(u, v)| normal.dot((v - u).cross(x - u)));
    sides.iter().all(|&s| s >= 0.0) || sides.iter().all(|&s| s <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sheet(z: Real, body: u32, offset: u32) -> (Vec<Vec3>, Vec<u32>, Vec<[u32; 3]>) {
        let points = vec![
            Vec3::new(-1.0, -1.0, z),
            Vec3::new(1.0, -1.0, z),
            Vec3::new(0.0, 1.0, z),
        ];
        (
            points,
            vec![body; 3],
            vec![[offset, offset + 1, offset + 2]],
        )
    }

    fn surfaces(points: Vec<Vec3>, body: Vec<u32>, triangles: Vec<[u32; 3]>) -> Surfaces {
        let frame = VtkFrame {
            points,
            polygons: triangles.iter().map(|t| t.to_vec()).collect(),
            point_data: [(
                "body".to_string(),
                crate::export::DataArray {
                    components: 1,
                    values: body.iter().map(|&b| Real::from(b)).collect(),
                },
            )]
            .into(),
            ..VtkFrame::default()
        };
        Surfaces::of_frame(&frame)
    }

    #[test]
    fn a_triangle_moving_through_another_is_counted_once_per_point() {
        // A triangle at z = 0 and a second one (body 1) moving from z = 1
        // to z = -1 through it: its three points passed through between
        // the frames, and in neither frame does an edge cross.
        let (mut points, mut body, mut triangles) = sheet(0.0, 0, 0);
        let (p, b, t) = sheet(1.0, 1, 3);
        let shrink = |v: Vec3| Vec3::new(0.3 * v.x, 0.3 * v.y, v.z);
        points.extend(p.into_iter().map(shrink));
        body.extend(b);
        triangles.extend(t);
        let before = surfaces(points.clone(), body.clone(), triangles.clone());
        for p in &mut points[3..] {
            p.z = -1.0;
        }
        let now = surfaces(points.clone(), body.clone(), triangles.clone());
        let counted = count(Some(&before), &now);
        assert_eq!((counted.points_between, counted.edges_between), (3, 0));
        assert_eq!(counted.within(), 0);
        // Halfway, tilted through the plane: edges through, no point yet.
        points[3].z = 0.5;
        points[4].z = -0.5;
        points[5].z = 0.5;
        let halfway = surfaces(points, body, triangles);
        let counted = count(None, &halfway);
        assert!(counted.edges_between >= 1, "{counted:?}");
        assert_eq!(counted.points_between, 0);
    }
}
