//! The exact tests of continuous collision detection: over a step each
//! particle moves on a straight line, `x(t) = x₀ + t u` for `t` in
//! `[0, 1]` (`u` its displacement, m), and two elements collide where they
//! come within the gap `δ` (m) of each other at some `t`.
//!
//! A point and a triangle, or two edges, can only pass through each other
//! where their four points are coplanar: where the cubic
//! `f(t) = (b − a) × (c − a) · (d − a)` vanishes (Provot 1997; Bridson,
//! Fedkiw and Anderson 2002, §4). Each root in `[0, 1]` is found on an
//! interval where `f` is monotonic (split at the roots of `f′`) by
//! bisection, and the elements collide there when they are within the gap.
//! In 2D a point crosses a segment where the quadratic `(b − a) × (p − a)`
//! vanishes. Two particles of bodies without surfaces are balls of radius
//! `r`: they collide where the quadratic `|Δx(t)|² − (2r)²` has a root.
//! A pair whose elements end the step within the gap collides too (they
//! are pushed apart to it), so rounding cannot carry a point across a
//! plane it lies on.

use crate::contact::geometry::{closest_between_segments, closest_on_segment, closest_on_triangle};
use crate::units::{Real, Vec3};

/// A collision found: the weights of its closest points (`+` on the first
/// element, `−` on the second, summing to zero) and the unit normal the
/// first element is to be pushed along (its side at the start of the
/// step), with the separation (m) along it the response makes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Hit {
    /// Up to four particles; unused ones have weight zero.
    pub particles: [u32; 4],
    /// Their weights.
    pub weights: [Real; 4],
    /// From the second element towards the first.
    pub normal: Vec3,
    /// The separation (m) the response leaves along the normal.
    pub separation: Real,
}

/// How close (in fractions of the step) two successive estimates of a
/// root must come for the search to stop: `2⁻⁴⁸`, far below any motion
/// that matters.
const ROOT_TOLERANCE: Real = 1.0 / (1u64 << 48) as Real;

/// The most iterations on one root's interval: each at least halves the
/// bracket where Newton's step would leave it, so this is past the
/// tolerance from any start.
const MOST_ITERATIONS: usize = 64;

/// The roots in `[0, 1]` of `f(t) = c₀ + c₁ t + c₂ t² + c₃ t³`, in
/// increasing order (at most three), on the intervals where `f` is
/// monotonic, each by Newton's method kept inside the interval's bracket
/// (a step that would leave it is a bisection instead), from the secant
/// through the interval's ends; a root exactly at an end counts. Newton
/// takes about five iterations where bisection took 48, and this search
/// was a fifth of the CCD's time on sheets pressed together.
fn cubic_roots(c: [Real; 4]) -> ([Real; 3], usize) {
    // The cubic's Bernstein coefficients on [0, 1]: it lies within their
    // hull, so where all four have one strict sign it has no root there
    // (most pairs of layers that only near each other).
    let bernstein = [
        c[0],
        c[0] + c[1] / 3.0,
        c[0] + (2.0 * c[1] + c[2]) / 3.0,
        c[0] + c[1] + c[2] + c[3],
    ];
    if bernstein.iter().all(|&b| b > 0.0) || bernstein.iter().all(|&b| b < 0.0) {
        return ([0.0; 3], 0);
    }
    let f = |t: Real| ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
    let slope = |t: Real| (3.0 * c[3] * t + 2.0 * c[2]) * t + c[1];
    // Below this, a value of f is its evaluation's rounding: the root is
    // found as well as it can be.
    let noise = 8.0 * Real::EPSILON * c.iter().map(|x| x.abs()).sum::<Real>();
    // The turning points: roots of f′ = c₁ + 2 c₂ t + 3 c₃ t², unless f′'s
    // own Bernstein coefficients share a sign (f monotonic on [0, 1]).
    let mut ends = [0.0; 4];
    let mut count = 1;
    let (qa, qb, qc) = (3.0 * c[3], 2.0 * c[2], c[1]);
    let derivative = [qc, qc + 0.5 * qb, qa + qb + qc];
    let monotonic = derivative.iter().all(|&d| d > 0.0) || derivative.iter().all(|&d| d < 0.0);
    let mut turning = [Real::NAN; 2];
    if !monotonic {
        if qa != 0.0 {
            let disc = qb * qb - 4.0 * qa * qc;
            if disc >= 0.0 {
                let root = disc.sqrt();
                let q = -0.5 * (qb + qb.signum() * root);
                turning = [q / qa, if q != 0.0 { qc / q } else { -qb / (2.0 * qa) }];
            }
        } else if qb != 0.0 {
            turning[0] = -qc / qb;
        }
    }
    if turning[0] > turning[1] {
        turning.swap(0, 1);
    }
    for t in turning {
        if t > 0.0 && t < 1.0 {
            ends[count] = t;
            count += 1;
        }
    }
    ends[count] = 1.0;
    let mut roots = [0.0; 3];
    let mut found = 0;
    for k in 0..count {
        let (mut lo, mut hi) = (ends[k], ends[k + 1]);
        let (flo, fhi) = (f(lo), f(hi));
        if flo == 0.0 {
            if found == 0 || roots[found - 1] != lo {
                roots[found] = lo;
                found += 1;
            }
            continue;
        }
        if fhi != 0.0 && (flo > 0.0) == (fhi > 0.0) {
            continue;
        }
        if fhi == 0.0 {
            if k + 1 == count && found < 3 {
                roots[found] = hi;
                found += 1;
            }
            continue;
        }
        let rising = fhi > flo;
        // The secant's root lies strictly inside: flo and fhi differ in
        // sign.
        let mut t = (lo + flo / (flo - fhi) * (hi - lo)).clamp(lo, hi);
        for _ in 0..MOST_ITERATIONS {
            let value = f(t);
            if value.abs() <= noise {
                break;
            }
            if (value > 0.0) == rising {
                hi = t;
            } else {
                lo = t;
            }
            // A zero or vanishing slope (a turning point at the bracket's
            // end) gives no step inside: bisect.
            let newton = t - value / slope(t);
            let next = if newton > lo && newton < hi {
                newton
            } else {
                0.5 * (lo + hi)
            };
            let step = (next - t).abs();
            t = next;
            if step <= ROOT_TOLERANCE || hi - lo <= ROOT_TOLERANCE {
                break;
            }
        }
        if found < 3 {
            roots[found] = t;
            found += 1;
        }
    }
    (roots, found)
}

/// The times a test looks at: the roots in `(0, 1]` of its coplanarity
/// (the first `count` of `roots`), then the end of the step. A root at the
/// very start is no crossing: the elements start the step on one plane
/// (as layers that started within the gap of each other), and which side
/// they are on is where they end; looking there would find the same
/// collision at every round however far the impulses part them, and
/// every such layer would go to the impact zones.
fn crossing_times(roots: [Real; 3], count: usize) -> impl Iterator<Item = Real> {
    roots
        .into_iter()
        .take(count)
        .filter(|&t| t > 0.0)
        .chain(std::iter::once(1.0))
}

/// Positions and displacements (m) of the points of a test.
#[derive(Debug, Clone, Copy)]
pub(super) struct Moving<const N: usize> {
    /// Where each point starts.
    pub start: [Vec3; N],
    /// How far each moves over the step.
    pub motion: [Vec3; N],
}

impl<const N: usize> Moving<N> {
    /// The points at `t` in `[0, 1]`.
    fn at(&self, t: Real) -> [Vec3; N] {
        std::array::from_fn(|i| self.start[i] + t * self.motion[i])
    }
}

/// How far (m) any point of an element moving by `first` can come
/// towards any point of one moving by `second` over the step (their
/// vertices' displacements, m): the most either moves relative to the
/// second's first vertex, added.
fn relative_motion(first: &[Vec3], second: &[Vec3]) -> Real {
    let frame = second[0];
    let most = |moves: &[Vec3]| {
        moves
            .iter()
            .map(|u| (*u - frame).length_squared())
            .fold(0.0, Real::max)
            .sqrt()
    };
    most(first) + most(second)
}

/// The coefficients of `f(t) = (p₁ − p₀) × (p₂ − p₀) · (p₃ − p₀)` for
/// points moving on straight lines.
fn coplanarity(m: &Moving<4>) -> [Real; 4] {
    let [x0, x1, x2, x3] = m.start;
    let [u0, u1, u2, u3] = m.motion;
    let (e1, e2, d) = (x1 - x0, x2 - x0, x3 - x0);
    let (f1, f2, g) = (u1 - u0, u2 - u0, u3 - u0);
    let c0 = e1.cross(e2);
    let c1 = e1.cross(f2) + f1.cross(e2);
    let c2 = f1.cross(f2);
    [
        c0.dot(d),
        c1.dot(d) + c0.dot(g),
        c2.dot(d) + c1.dot(g),
        c2.dot(g),
    ]
}

/// The unit normal of triangle `(a, b, c)`, if it has area.
fn triangle_normal(a: Vec3, b: Vec3, c: Vec3) -> Option<Vec3> {
    (b - a).cross(c - a).try_normalize()
}

/// Whether a particle moving from `start[0]` by `motion[0]` comes within
/// `gap` (m) of the triangle `start[1..]` moving by `motion[1..]`, and if
/// so the hit, the particle pushed to the side of the triangle it started
/// on. `particles`: the particle, then the triangle's.
pub(super) fn point_triangle(m: &Moving<4>, particles: [u32; 4], gap: Real) -> Option<Hit> {
    // The distance between a point and a triangle changes by no more than
    // their vertices move relative to one another: pairs farther apart at
    // the start than that and the gap cannot meet (most pairs, cheaply).
    let [p, a, b, c] = m.start;
    let [u, v, w] = closest_on_triangle(p, a, b, c);
    let distance = (p - (u * a + v * b + w * c)).length();
    if distance - relative_motion(&m.motion[..1], &m.motion[1..]) > gap {
        return None;
    }
    // The particle is point 3 of the coplanarity cubic.
    let ordered = Moving {
        start: [m.start[1], m.start[2], m.start[3], m.start[0]],
        motion: [m.motion[1], m.motion[2], m.motion[3], m.motion[0]],
    };
    let coefficients = coplanarity(&ordered);
    let side0 = coefficients[0];
    let (roots, count) = cubic_roots(coefficients);
    let times = crossing_times(roots, count);
    for t in times {
        let [p, a, b, c] = m.at(t);
        let [u, v, w] = closest_on_triangle(p, a, b, c);
        let closest = u * a + v * b + w * c;
        if (p - closest).length_squared() >= gap * gap {
            continue;
        }
        let normal = triangle_normal(a, b, c)?;
        // The side it started on; exactly on the plane, where it ends up
        // after the step (the normal's own side if that too is zero).
        let side = if side0 != 0.0 {
            side0
        } else {
            normal.dot(m.start[0] + m.motion[0] - closest)
        };
        let normal = if side < 0.0 { -normal } else { normal };
        return Some(Hit {
            particles,
            weights: [1.0, -u, -v, -w],
            normal,
            separation: 2.0 * gap,
        });
    }
    None
}

/// Whether the edges `start[0..2]` and `start[2..4]`, moving by `motion`,
/// come within `gap` (m) of each other, and if so the hit, the first edge
/// pushed to the side of the second it started on.
pub(super) fn edge_edge(m: &Moving<4>, particles: [u32; 4], gap: Real) -> Option<Hit> {
    let [p1, q1, p2, q2] = m.start;
    let (s, r) = closest_between_segments(p1, q1, p2, q2);
    let distance = ((p1 + s * (q1 - p1)) - (p2 + r * (q2 - p2))).length();
    if distance - relative_motion(&m.motion[..2], &m.motion[2..]) > gap {
        return None;
    }
    let coefficients = coplanarity(m);
    let (roots, count) = cubic_roots(coefficients);
    let times = crossing_times(roots, count);
    for t in times {
        let [p1, q1, p2, q2] = m.at(t);
        let (s, r) = closest_between_segments(p1, q1, p2, q2);
        let (c1, c2) = (p1 + s * (q1 - p1), p2 + r * (q2 - p2));
        if (c1 - c2).length_squared() >= gap * gap {
            continue;
        }
        // Along the edges' common normal where they are not parallel,
        // else along the line between their closest points at the start.
        // The side is the one the first edge started on; where the edges
        // started crossing each other (layers that start within the gap),
        // where it ends the step, as for a point on a triangle's plane.
        let [s1, e1, s2, e2] = m.start;
        let (a0, b0) = (s1 + s * (e1 - s1), s2 + r * (e2 - s2));
        let [f1, g1, f2, g2] = m.at(1.0);
        let (a1, b1) = (f1 + s * (g1 - f1), f2 + r * (g2 - f2));
        let normal = (q1 - p1)
            .cross(q2 - p2)
            .try_normalize()
            .map(|n| {
                let side = match n.dot(a0 - b0) {
                    0.0 => n.dot(a1 - b1),
                    side => side,
                };
                if side < 0.0 {
                    -n
                } else {
                    n
                }
            })
            .or_else(|| (a0 - b0).try_normalize())
            .or_else(|| (c1 - c2).try_normalize())?;
        return Some(Hit {
            particles,
            weights: [1.0 - s, s, r - 1.0, -r],
            normal,
            separation: 2.0 * gap,
        });
    }
    None
}

/// Whether a particle (`start[0]`) comes within `gap` (m) of the segment
/// `start[1..3]` of a 2D loop in the xy-plane, and if so the hit, pushed to
/// the side it started on.
pub(super) fn point_segment(m: &Moving<3>, particles: [u32; 3], gap: Real) -> Option<Hit> {
    let [p, a, b] = m.start;
    let [up, ua, ub] = m.motion;
    // (b − a) × (p − a), z component, as a quadratic in t.
    let (e, d) = (b - a, p - a);
    let (f, g) = (ub - ua, up - ua);
    let cross = |x: Vec3, y: Vec3| x.x * y.y - x.y * y.x;
    let c = [cross(e, d), cross(e, g) + cross(f, d), cross(f, g), 0.0];
    let (roots, count) = cubic_roots(c);
    let times = crossing_times(roots, count);
    for t in times {
        let [p, a, b] = m.at(t);
        let s = closest_on_segment(p, a, b);
        let closest = a + s * (b - a);
        if (p - closest).length_squared() >= gap * gap {
            continue;
        }
        let e = b - a;
        let normal = Vec3::new(e.y, -e.x, 0.0).try_normalize()?;
        let side = if c[0] != 0.0 {
            -c[0]
        } else {
            normal.dot(m.start[0] + m.motion[0] - closest)
        };
        // (Δy, −Δx) points to the right of a → b, where the cross product
        // (b − a) × (p − a) is negative.
        let normal = if side < 0.0 { -normal } else { normal };
        return Some(Hit {
            particles: [particles[0], particles[1], particles[2], particles[2]],
            weights: [1.0, s - 1.0, -s, 0.0],
            normal,
            separation: 2.0 * gap,
        });
    }
    None
}

/// Whether two particles, balls of radius `radius` (m), come closer than
/// `2 radius` over the step while closing, and if so the hit: pushed apart
/// to that distance along the line between them at the start, or no
/// closer than they started where they began closer.
pub(super) fn point_point(m: &Moving<2>, particles: [u32; 2], radius: Real) -> Option<Hit> {
    let reach = 2.0 * radius;
    let d0 = m.start[0] - m.start[1];
    let du = m.motion[0] - m.motion[1];
    let closing = du.dot(d0);
    if closing >= 0.0 {
        return None;
    }
    // The closest approach on [0, 1].
    let t = (-closing / du.length_squared()).min(1.0);
    let closest = (d0 + t * du).length_squared();
    if closest >= reach * reach {
        return None;
    }
    let distance = d0.length();
    let normal = (d0 / distance)
        .try_normalize()
        .or_else(|| (-du).try_normalize())?;
    Some(Hit {
        particles: [particles[0], particles[1], particles[1], particles[1]],
        weights: [1.0, -1.0, 0.0, 0.0],
        normal,
        separation: reach.min(distance),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still<const N: usize>(start: [Vec3; N]) -> Moving<N> {
        Moving {
            start,
            motion: [Vec3::ZERO; N],
        }
    }

    #[test]
    fn the_cubic_roots_are_found_in_order() {
        // (t − 0.2)(t − 0.5)(t − 0.9) = t³ − 1.6 t² + 0.73 t − 0.09.
        let (roots, count) = cubic_roots([-0.09, 0.73, -1.6, 1.0]);
        assert_eq!(count, 3);
        // Newton's steps to 2⁻⁴⁸ (its error then a square of that), the
        // coefficients rounded: within 1e-12 of the exact roots.
        for (r, e) in roots.iter().zip([0.2, 0.5, 0.9]) {
            assert!((r - e).abs() < 1e-12, "{roots:?}");
        }
        // A root at the end of the step counts; none outside [0, 1].
        assert_eq!(cubic_roots([-1.0, 1.0, 0.0, 0.0]), ([1.0, 0.0, 0.0], 1));
        assert_eq!(cubic_roots([-2.0, 1.0, 0.0, 0.0]).1, 0);
    }

    /// The roots of the cubic `c` in `[0, 1]`, one per interval between
    /// the turning points `ends` where it changes sign, by 200
    /// bisections: the reference Newton's method is held to.
    fn bisected(c: [Real; 4], ends: &[Real]) -> Vec<Real> {
        let f = |t: Real| ((c[3] * t + c[2]) * t + c[1]) * t + c[0];
        let mut roots = Vec::new();
        for w in ends.windows(2) {
            let (mut lo, mut hi) = (w[0], w[1]);
            if (f(lo) > 0.0) == (f(hi) > 0.0) {
                continue;
            }
            let rising = f(hi) > f(lo);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if (f(mid) > 0.0) == rising {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        roots
    }

    #[test]
    fn newton_finds_the_roots_bisection_finds() {
        // Claim: on cubics with three simple roots in (0, 1), spread and
        // clustered (down to 5e-5 apart), scaled from 1e-12 to 1e3 (the
        // coplanarity of nearly flat cloth is tiny), the roots are the
        // exact ones, and those of bisection to the last bit of the
        // interval, to the cubic's rounding over its slope (the roots are
        // simple, so Newton's error after a step of 2⁻⁴⁸ is about its
        // square). And the cubic lifted above zero on [0, 1] gives none.
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as Real / (1u64 << 53) as Real
        };
        for case in 0..2000 {
            let first = 0.05 + 0.3 * uniform();
            let spacing = if case % 2 == 0 { 0.3 } else { 1e-4 };
            let expected = [first, first + spacing * (0.5 + uniform()), 0.95];
            let [r0, r1, r2] = expected;
            let scale = Real::powf(10.0, -12.0 + 15.0 * uniform());
            // scale (t − r0)(t − r1)(t − r2)
            let c = [
                -scale * r0 * r1 * r2,
                scale * (r0 * r1 + r0 * r2 + r1 * r2),
                -scale * (r0 + r1 + r2),
                scale,
            ];
            let (roots, count) = cubic_roots(c);
            assert_eq!(count, 3, "{c:?}");
            // Where |f| falls below its rounding (8 ε Σ|cᵢ|, as in
            // `cubic_roots`) the search stops: a root is then off by
            // that over the slope, twice for the exact root (the
            // coefficients are rounded too).
            let rounding = 8.0 * Real::EPSILON * c.iter().map(|x| x.abs()).sum::<Real>() / scale;
            let within = |e: Real| {
                let slope = (e - r0) * (e - r1) + (e - r0) * (e - r2) + (e - r1) * (e - r2);
                1e-15 + 2.0 * rounding / slope.abs()
            };
            for (r, e) in roots.iter().zip(expected) {
                assert!((r - e).abs() < within(e), "{c:?}: {roots:?}");
            }
            // The same intervals as cubic_roots: split at the roots of f′
            // (both inside (0, 1), between the three roots).
            let (qa, qb, qc) = (3.0 * c[3], 2.0 * c[2], c[1]);
            let disc = (qb * qb - 4.0 * qa * qc).sqrt();
            let mut ends = vec![
                0.0,
                (-qb - disc) / (2.0 * qa),
                (-qb + disc) / (2.0 * qa),
                1.0,
            ];
            ends.sort_by(Real::total_cmp);
            let reference = bisected(c, &ends);
            for (r, e) in roots.iter().zip(&reference) {
                let near = (r - e).abs() < within(*e);
                assert!(near, "{c:?}: {roots:?} against {reference:?}");
            }
            // Shifted up past its highest point on [0, 1]: no root.
            let above = [c[0] + 2.0 * scale, c[1], c[2], c[3]];
            assert_eq!(cubic_roots(above).1, 0, "{above:?}");
        }
    }

    #[test]
    fn a_point_through_a_triangle_at_any_speed_is_caught_on_its_side() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        for speed in [1e-3, 1.0, 1e3, 1e6] {
            let mut m = still([Vec3::new(0.2, 0.2, 0.5), a, b, c]);
            m.motion[0] = Vec3::new(0.0, 0.0, -speed);
            let hit = point_triangle(&m, [0, 1, 2, 3], 1e-6);
            if speed < 0.5 {
                assert!(hit.is_none(), "stops short at {speed}");
                continue;
            }
            let hit = hit.expect("crosses");
            assert_eq!(hit.normal, Vec3::Z);
            // The closest point is (0.2, 0.2, 0): weights 0.6, 0.2, 0.2.
            let w = hit.weights;
            assert!((w[1] + 0.6).abs() < 1e-12 && (w[2] + 0.2).abs() < 1e-12);
            assert!(w.iter().sum::<Real>().abs() < 1e-15);
        }
        // Beside the triangle it passes by.
        let mut m = still([Vec3::new(0.8, 0.8, 0.5), a, b, c]);
        m.motion[0] = Vec3::new(0.0, 0.0, -1.0);
        assert!(point_triangle(&m, [0, 1, 2, 3], 1e-6).is_none());
    }

    #[test]
    fn crossing_edges_are_caught_and_parallel_ones_passed() {
        let mut m = still([
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.5, -1.0, 0.0),
            Vec3::new(0.5, 1.0, 0.0),
        ]);
        m.motion[0] = Vec3::new(0.0, 0.0, -2.0);
        m.motion[1] = Vec3::new(0.0, 0.0, -2.0);
        let hit = edge_edge(&m, [0, 1, 2, 3], 1e-6).expect("cross at t = 1/2");
        assert_eq!(hit.normal, Vec3::Z);
        assert!((hit.weights[0] - 0.5).abs() < 1e-12 && (hit.weights[2] + 0.5).abs() < 1e-12);
        m.start[0].y = 2.0;
        m.start[1].y = 2.0;
        assert!(edge_edge(&m, [0, 1, 2, 3], 1e-6).is_none());
    }

    #[test]
    fn a_point_through_a_segment_and_balls_through_each_other_are_caught() {
        let mut m = still([Vec3::new(0.5, 1.0, 0.0), Vec3::ZERO, Vec3::X]);
        m.motion[0] = Vec3::new(0.0, -100.0, 0.0);
        let hit = point_segment(&m, [0, 1, 2], 1e-6).expect("crosses");
        assert_eq!(hit.normal, Vec3::Y);
        let mut m = still([Vec3::new(-1.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)]);
        m.motion = [Vec3::new(100.0, 0.0, 0.0), Vec3::new(-100.0, 0.0, 0.0)];
        let hit = point_point(&m, [0, 1], 0.01).expect("pass through each other");
        assert_eq!((hit.normal, hit.separation), (-Vec3::X, 0.02));
        m.start[1].y = 0.5;
        assert!(point_point(&m, [0, 1], 0.01).is_none());
    }
}
