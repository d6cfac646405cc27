//! Whether a point is inside a closed surface, and how deep: a check of
//! contact after the fact (for tests and diagnostics), not part of the
//! step. Brute force over every particle and face.

use super::geometry::{closest_on_segment, closest_on_triangle};
use crate::body::Body;
use crate::units::{Real, Vec3};

/// The winding number of the closed, outward-oriented triangles `faces`
/// (indices into `position`) around `p`: 1 inside, 0 outside. It is the sum
/// of the triangles' signed solid angles over 4π (Van Oosterom and
/// Strackee, "The solid angle of a plane triangle", IEEE Trans. Biomed.
/// Eng. 30, 1983).
pub fn winding_number(p: Vec3, position: &[Vec3], faces: &[[u32; 3]]) -> Real {
    let mut total = 0.0;
    for f in faces {
        let [a, b, c] = f.map(|i| position[i as usize] - p);
        let (la, lb, lc) = (a.length(), b.length(), c.length());
        let numerator = a.dot(b.cross(c));
        let denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
        total += 2.0 * numerator.atan2(denominator);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// The winding number of the closed 2D loop `segments` around `p` (in the
/// xy-plane): 1 inside a counter-clockwise loop, 0 outside.
pub fn winding_number_2d(p: Vec3, position: &[Vec3], segments: &[[u32; 2]]) -> Real {
    let mut total = 0.0;
    for s in segments {
        let [a, b] = s.map(|i| position[i as usize] - p);
        total += (a.x * b.y - a.y * b.x).atan2(a.x * b.x + a.y * b.y);
    }
    total / (2.0 * std::f64::consts::PI)
}

/// How far (m) `p` is inside the closed `body` at `position`: its distance
/// to the surface when inside, 0 outside (and for a body that is not
/// closed).
pub fn depth_inside(p: Vec3, body: &Body, position: &[Vec3]) -> Real {
    if !body.closed {
        return 0.0;
    }
    if body.is_planar() {
        if winding_number_2d(p, position, &body.segments).abs() < 0.5 {
            return 0.0;
        }
        body.segments
            .iter()
            .map(|s| {
                let [a, b] = s.map(|i| position[i as usize]);
                p.distance(a + closest_on_segment(p, a, b) * (b - a))
            })
            .fold(Real::INFINITY, Real::min)
    } else {
        if winding_number(p, position, &body.faces).abs() < 0.5 {
            return 0.0;
        }
        body.faces
            .iter()
            .map(|f| {
                let [a, b, c] = f.map(|i| position[i as usize]);
                let w = closest_on_triangle(p, a, b, c);
                p.distance(w[0] * a + w[1] * b + w[2] * c)
            })
            .fold(Real::INFINITY, Real::min)
    }
}

/// The deepest (m) any particle of any body lies inside another closed
/// body (0 when none does).
pub fn deepest_interpenetration(bodies: &[Body], position: &[Vec3]) -> Real {
    let mut deepest: Real = 0.0;
    for (a, body) in bodies.iter().enumerate() {
        for (b, other) in bodies.iter().enumerate() {
            if a != b && other.closed {
                for i in body.particles.clone() {
                    deepest = deepest.max(depth_inside(position[i], other, position));
                }
            }
        }
    }
    deepest
}
