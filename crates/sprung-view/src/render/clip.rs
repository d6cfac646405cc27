//! Clipping against the camera's near plane (Sutherland–Hodgman for
//! polygons), so geometry behind a perspective camera is never projected.

use sprung::Real;

use super::camera::ViewPoint;

fn lerp(a: ViewPoint, b: ViewPoint, t: Real) -> ViewPoint {
    ViewPoint {
        x: a.x + t * (b.x - a.x),
        y: a.y + t * (b.y - a.y),
        depth: a.depth + t * (b.depth - a.depth),
    }
}

/// The part of the segment `a`–`b` at depth ≥ `near` (m), if any.
pub fn segment(a: ViewPoint, b: ViewPoint, near: Real) -> Option<(ViewPoint, ViewPoint)> {
    match (a.depth >= near, b.depth >= near) {
        (true, true) => Some((a, b)),
        (false, false) => None,
        (true, false) => Some((a, lerp(a, b, (near - a.depth) / (b.depth - a.depth)))),
        (false, true) => Some((lerp(a, b, (near - a.depth) / (b.depth - a.depth)), b)),
    }
}

/// The part of the polygon `points` at depth ≥ `near` (m); empty when it
/// lies wholly in front of the near plane.
pub fn polygon(points: &[ViewPoint], near: Real) -> Vec<ViewPoint> {
    if points.iter().all(|p| p.depth >= near) {
        return points.to_vec();
    }
    let mut out = Vec::with_capacity(points.len() + 2);
    for (k, &a) in points.iter().enumerate() {
        let b = points[(k + 1) % points.len()];
        let (inside_a, inside_b) = (a.depth >= near, b.depth >= near);
        if inside_a {
            out.push(a);
        }
        if inside_a != inside_b {
            out.push(lerp(a, b, (near - a.depth) / (b.depth - a.depth)));
        }
    }
    out
}
