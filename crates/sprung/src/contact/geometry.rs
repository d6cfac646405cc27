//! Closest points between the elements that touch: a point and a triangle
//! (3D), a point and a segment (2D loops, and a triangle's edges), and two
//! segments (the edges of cloth). Each returns the weights of the closest
//! points, so a contact force can be shared among the element's vertices
//! in the same proportions (which keeps forces and torques balanced).
//!
//! The point–triangle test walks the triangle's Voronoi regions (vertices,
//! then edges, then the face), and the segment–segment test clamps the
//! unconstrained solution to the unit square, as set out in Ericson,
//! *Real-Time Collision Detection*, §5.1.5 and §5.1.9.

use crate::units::{Real, Vec3};

/// Barycentric weights `[u, v, w]` (`u + v + w = 1`, each in `[0, 1]`) of
/// the point of triangle `(a, b, c)` closest to `p`: `u a + v b + w c`.
/// A degenerate triangle (zero area) gives the closest point on its edges.
#[inline(always)]
pub fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> [Real; 3] {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 && d1 - d3 > 0.0 {
        let v = d1 / (d1 - d3);
        return [1.0 - v, v, 0.0];
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 && d2 - d6 > 0.0 {
        let w = d2 / (d2 - d6);
        return [1.0 - w, 0.0, w];
    }
    let va = d3 * d6 - d5 * d4;
    let (e, f) = (d4 - d3, d5 - d6);
    if va <= 0.0 && e >= 0.0 && f >= 0.0 && e + f > 0.0 {
        let w = e / (e + f);
        return [0.0, 1.0 - w, w];
    }
    let total = va + vb + vc;
    if total > 0.0 {
        let (v, w) = (vb / total, vc / total);
        return [1.0 - v - w, v, w];
    }
    // Degenerate: the best of the three edges.
    let edges = [
        (closest_on_segment(p, a, b), [0, 1]),
        (closest_on_segment(p, b, c), [1, 2]),
        (closest_on_segment(p, c, a), [2, 0]),
    ];
    let corner = [a, b, c];
    let mut best = [1.0, 0.0, 0.0];
    let mut best_distance = Real::INFINITY;
    for (t, [i, j]) in edges {
        let q = corner[i] + t * (corner[j] - corner[i]);
        let distance = p.distance_squared(q);
        if distance < best_distance {
            best_distance = distance;
            best = [0.0; 3];
            best[i] = 1.0 - t;
            best[j] = t;
        }
    }
    best
}

/// Parameter `t` in `[0, 1]` of the point of segment `a → b` closest to `p`
/// (`a + t (b - a)`); 0 for a segment of zero length.
#[inline(always)]
pub fn closest_on_segment(p: Vec3, a: Vec3, b: Vec3) -> Real {
    let ab = b - a;
    let length = ab.length_squared();
    if length > 0.0 {
        ((p - a).dot(ab) / length).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// Parameters `(s, t)` in `[0, 1]²` of the closest points `p1 + s (q1 -
/// p1)` and `p2 + t (q2 - p2)` of two segments. Parallel segments give one
/// of the closest pairs.
#[inline(always)]
pub fn closest_between_segments(p1: Vec3, q1: Vec3, p2: Vec3, q2: Vec3) -> (Real, Real) {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.length_squared(), d2.length_squared(), d2.dot(r));
    if a <= 0.0 && e <= 0.0 {
        return (0.0, 0.0);
    }
    if a <= 0.0 {
        return (0.0, (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(r);
    if e <= 0.0 {
        return ((-c / a).clamp(0.0, 1.0), 0.0);
    }
    let b = d1.dot(d2);
    let denominator = a * e - b * b;
    let mut s = if denominator > 0.0 {
        ((b * f - c * e) / denominator).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (s, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closest point found, and a brute-force minimum over a fine
    /// barycentric grid: the found one is never farther.
    fn check_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) {
        let [u, v, w] = closest_on_triangle(p, a, b, c);
        assert!((u + v + w - 1.0).abs() < 1e-12 && u >= 0.0 && v >= 0.0 && w >= 0.0);
        let found = p.distance(u * a + v * b + w * c);
        let n = 200;
        for i in 0..=n {
            for j in 0..=(n - i) {
                let (s, t) = (i as Real / n as Real, j as Real / n as Real);
                let q = a + s * (b - a) + t * (c - a);
                assert!(
                    found <= p.distance(q) + 1e-12,
                    "{p}: found {found}, grid {}",
                    p.distance(q)
                );
            }
        }
    }

    #[test]
    fn the_closest_point_of_a_triangle_in_every_region() {
        let (a, b, c) = (
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.5, 1.5, 0.0),
        );
        for p in [
            Vec3::new(0.6, 0.4, 0.7),   // above the face
            Vec3::new(-1.0, -1.0, 0.2), // beyond a
            Vec3::new(3.0, -0.5, -0.1), // beyond b
            Vec3::new(0.4, 2.5, 0.0),   // beyond c
            Vec3::new(1.0, -1.0, 0.3),  // beyond edge ab
            Vec3::new(1.8, 1.2, 0.0),   // beyond edge bc
            Vec3::new(-0.8, 1.0, -0.4), // beyond edge ca
        ] {
            check_triangle(p, a, b, c);
        }
        // Inside the face, the weights are the barycentric coordinates.
        let [u, v, w] = closest_on_triangle(Vec3::new(0.9, 0.3, 5.0), a, b, c);
        let q = u * a + v * b + w * c;
        assert!((q - Vec3::new(0.9, 0.3, 0.0)).length() < 1e-14);
    }

    #[test]
    fn a_degenerate_triangle_falls_back_to_its_edges() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::new(2.0, 0.0, 0.0));
        let [u, v, w] = closest_on_triangle(Vec3::new(1.5, 1.0, 0.0), a, b, c);
        let q = u * a + v * b + w * c;
        assert!((q - Vec3::new(1.5, 0.0, 0.0)).length() < 1e-14, "{q}");
    }

    #[test]
    fn the_closest_points_of_two_segments() {
        // Crossing at right angles 1 apart.
        let (s, t) = closest_between_segments(
            Vec3::new(-1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, -1.0, 1.0),
            Vec3::new(0.0, 1.0, 1.0),
        );
        assert!((s - 0.5).abs() < 1e-15 && (t - 0.5).abs() < 1e-15);
        // Clamped at an end.
        let (s, t) = closest_between_segments(
            Vec3::ZERO,
            Vec3::X,
            Vec3::new(3.0, 1.0, 0.0),
            Vec3::new(3.0, 2.0, 0.0),
        );
        assert_eq!((s, t), (1.0, 0.0));
        // Against a brute-force minimum.
        let (p1, q1, p2, q2) = (
            Vec3::new(0.1, 0.2, 0.3),
            Vec3::new(1.3, -0.4, 0.9),
            Vec3::new(-0.5, 1.1, 0.2),
            Vec3::new(0.7, 0.1, -0.6),
        );
        let (s, t) = closest_between_segments(p1, q1, p2, q2);
        let found = (p1 + s * (q1 - p1)).distance(p2 + t * (q2 - p2));
        for i in 0..=100 {
            for j in 0..=100 {
                let (s, t) = (i as Real / 100.0, j as Real / 100.0);
                let d = (p1 + s * (q1 - p1)).distance(p2 + t * (q2 - p2));
                assert!(found <= d + 1e-12);
            }
        }
    }
}
