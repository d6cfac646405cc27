//! Tests of the candidate pairs: passing over the pairs beyond the
//! allowance, the buckets of clearance, and the members of a step.

use super::*;
use crate::contact::buckets::CLEARANCE_BUCKETS;
use crate::contact::geometry::closest_between_segments;
use crate::contact::random::Random;

/// The touches of `pairs` at `position` with `allowance`.
fn touches(pairs: &mut ContactPairs, position: &[Vec3], allowance: Real) -> Vec<Touch> {
    pairs.allowance = allowance;
    let mut found = Vec::new();
    pairs.for_each_touch(position, THICKNESS, |t| found.push(t));
    found
}

const THICKNESS: Real = 0.01;

#[test]
fn a_pair_whose_clearance_exceeds_the_allowance_cannot_touch() {
    // Claim: after every particle has moved by at most `moved` from
    // where a pair was found, a pair whose clearance exceeds twice
    // that (the allowance of a step with no closing) touches nowhere,
    // so passing it over changes nothing. Random elements of 2 cm
    // around a particle within the search's reach (three thicknesses),
    // moved in random directions by up to the allowance's half, the
    // four kinds of pairs; each perturbed state measured with every
    // pair (infinite allowance) and with the allowance gives the same
    // touches. Some states are chosen near the edge cases: a particle
    // near the triangle's plane beyond an edge (which may end up
    // behind it), and nearly parallel edges.
    let mut random = Random(0x5eed);
    let reach = 3.0 * THICKNESS;
    let (mut skipped, mut measured) = (0, 0);
    for trial in 0..20_000 {
        let mut position: Vec<Vec3> = (0..4).map(|_| random.vector(0.02)).collect();
        if trial % 4 == 1 {
            // The particle just off the triangle's plane, beyond one of
            // its edges.
            let [a, b, c] = [position[1], position[2], position[3]];
            let normal = (b - a).cross(c - a).normalize();
            let out = a + 1.3 * (b - a) + 0.2 * (c - a);
            position[0] = out + 0.002 * random.symmetric() * normal;
        }
        if trial % 4 == 2 {
            // Nearly parallel edges 0–1 and 2–3.
            let along = random.vector(0.02);
            position[1] = position[0] + along;
            position[3] = position[2] + along + random.vector(0.001);
        }
        let side = if random.symmetric() > 0.0 { 1.0 } else { -1.0 };
        // The 3D pairs, and the 2D pair in the xy-plane.
        let (mut pairs, mut flat_pairs) = (ContactPairs::default(), ContactPairs::default());
        let triangle = PointTriangle {
            particle: 0,
            element: [1, 2, 3],
            body: 1,
            side,
            clearance: 0.0,
        };
        if triangle.touch(&position, reach).is_some() {
            pairs.point_triangle.push(PointTriangle {
                clearance: triangle.clearance_at(&position, THICKNESS, reach),
                ..triangle
            });
        }
        let segment = PointSegment {
            particle: 0,
            element: [1, 2],
            body: 1,
            side,
            clearance: 0.0,
        };
        let flat: Vec<Vec3> = position.iter().map(|x| Vec3::new(x.x, x.y, 0.0)).collect();
        if segment.touch(&flat, reach).is_some() {
            flat_pairs.point_segment.push(PointSegment {
                clearance: segment.clearance_at(&flat, THICKNESS, reach),
                ..segment
            });
        }
        let mut edges = EdgeEdge {
            first: [0, 1],
            second: [2, 3],
            direction: Vec3::ZERO,
            clearance: 0.0,
        };
        let distance = edges.distance_at(&position);
        let (s, t) = closest_between_segments(position[0], position[1], position[2], position[3]);
        let gap = (position[0] + s * (position[1] - position[0]))
            - (position[2] + t * (position[3] - position[2]));
        if distance < reach && distance > 0.0 {
            edges.direction = gap / distance;
            edges.clearance = beyond(distance, THICKNESS);
            pairs.edge_edge.push(edges);
        }
        let gap = position[0] - position[3];
        if gap.length() < reach {
            pairs.point_point.push(PointPoint {
                first: 0,
                second: 3,
                direction: gap.normalize(),
                clearance: beyond(gap.length(), THICKNESS),
            });
        }
        let moved = 0.5 * THICKNESS * (random.symmetric() + 1.0);
        let allowance = 2.0 * moved;
        let shift = |random: &mut Random, x: Vec3, flat: bool| {
            let mut step = random.vector(1.0);
            if flat {
                step.z = 0.0;
            }
            let length = step.length();
            if length > 1.0 || length == 0.0 {
                x
            } else {
                x + moved * step / length * random.symmetric().abs()
            }
        };
        for state in 0..8 {
            let flat_state = state % 2 == 1;
            let (from, pairs) = if flat_state {
                (&flat, &mut flat_pairs)
            } else {
                (&position, &mut pairs)
            };
            let at: Vec<Vec3> = if state < 2 {
                from.clone()
            } else {
                from.iter()
                    .map(|&x| shift(&mut random, x, flat_state))
                    .collect()
            };
            let all = touches(pairs, &at, Real::INFINITY);
            let some = touches(pairs, &at, allowance);
            assert_eq!(
                all, some,
                "trial {trial}, state {state}: {pairs:?} at {at:?}"
            );
        }
        let far = |c: Real| c > allowance;
        skipped += pairs
            .point_triangle
            .iter()
            .filter(|p| far(p.clearance))
            .count()
            + flat_pairs
                .point_segment
                .iter()
                .filter(|p| far(p.clearance))
                .count()
            + pairs.edge_edge.iter().filter(|p| far(p.clearance)).count()
            + pairs
                .point_point
                .iter()
                .filter(|p| far(p.clearance))
                .count();
        measured += pairs.len() + flat_pairs.len();
    }
    // The claim is not empty: many pairs are passed over.
    assert!(
        skipped > measured / 10,
        "{skipped} of {measured} passed over"
    );
}

#[test]
fn buckets_of_clearance_hold_every_pair_an_allowance_reaches() {
    // Claim: after the pairs are put in buckets of clearance, the pairs
    // a measure reads for an allowance (a prefix of each list) hold
    // every pair whose clearance is within it; no pair is lost; the
    // pairs keep their order within a bucket; and a particle's run of
    // point–triangle pairs stays whole, in the bucket of its nearest.
    let mut random = Random(0xb0c5);
    let width = 0.02 / CLEARANCE_BUCKETS as Real;
    let mut clearance = move |i: u32| {
        if i.is_multiple_of(7) {
            0.0
        } else {
            0.01 * (random.symmetric() + 1.0)
        }
    };
    let mut pairs = ContactPairs::default();
    for i in 0..5000u32 {
        pairs.edge_edge.push(EdgeEdge {
            first: [i, i + 1],
            second: [i + 2, i + 3],
            direction: Vec3::X,
            clearance: clearance(i),
        });
        // Runs of one to four pairs a particle.
        pairs.point_triangle.push(PointTriangle {
            particle: i / 4 * 4 + (i % 4).min(i / 4 % 3),
            element: [i, i + 1, i + 2],
            body: 1,
            side: 1.0,
            clearance: clearance(i),
        });
    }
    let before = pairs.clone();
    pairs.bucket(width, &mut Spare::default());
    let buckets = &pairs.buckets;
    // Edges: nothing lost, buckets in order, order kept within one.
    let mut sorted = pairs.edge_edge.clone();
    sorted.sort_by_key(|p| p.first[0]);
    assert_eq!(sorted, before.edge_edge);
    let bucket = buckets[Kind::EdgeEdge as usize].clone();
    for w in pairs.edge_edge.windows(2) {
        let (a, b) = (bucket.of(w[0].clearance), bucket.of(w[1].clearance));
        assert!(a < b || (a == b && w[0].first[0] < w[1].first[0]));
    }
    // Triangles: each particle's run whole and in its original order.
    let mut sorted = pairs.point_triangle.clone();
    sorted.sort_by_key(|p| p.element[0]);
    assert_eq!(sorted, before.point_triangle);
    for w in pairs.point_triangle.windows(2) {
        if w[0].particle == w[1].particle {
            assert_eq!(w[0].element[0] + 1, w[1].element[0]);
        }
    }
    let runs = before
        .point_triangle
        .chunk_by(|a, b| a.particle == b.particle)
        .count();
    let kept = pairs
        .point_triangle
        .chunk_by(|a, b| a.particle == b.particle)
        .count();
    assert_eq!(runs, kept);
    for allowance in [0.0, 1e-4, 0.0025, 0.003, 0.01, 0.0199, 0.02, 1.0] {
        pairs.allowance = allowance;
        for (kind, list) in [
            (
                Kind::EdgeEdge,
                pairs
                    .edge_edge
                    .iter()
                    .map(|p| p.clearance)
                    .collect::<Vec<_>>(),
            ),
            (
                Kind::PointTriangle,
                pairs.point_triangle.iter().map(|p| p.clearance).collect(),
            ),
        ] {
            let reached = pairs.len_of(kind);
            assert!(list[reached..].iter().all(|&c| c > allowance), "{kind:?}");
        }
    }
    // Pairs added after the buckets were made are all read.
    pairs.edge_edge.push(before.edge_edge[1]);
    pairs.allowance = 0.0;
    assert_eq!(pairs.len_of(Kind::EdgeEdge), pairs.edge_edge.len());
}

#[test]
fn members_count_a_particle_once_per_body_and_only_pairs_that_can_touch() {
    // Particle 0 with three triangles of body 1 (two within the
    // allowance of 1 mm, one beyond) and one of body 2; particle 9 with
    // one triangle of body 1, beyond. Claim: the stable step's members
    // are particle 0 once for body 1 and once for body 2, and the
    // vertices of the three triangles within the allowance; nothing of
    // the pairs beyond it.
    let pair = |particle, triangle, body, clearance| PointTriangle {
        particle,
        element: triangle,
        body,
        side: 1.0,
        clearance,
    };
    let pairs = ContactPairs {
        point_triangle: vec![
            pair(0, [1, 2, 3], 1, 0.0),
            pair(0, [2, 3, 4], 1, 0.002),
            pair(0, [3, 4, 5], 1, 0.0005),
            pair(0, [6, 7, 8], 2, 0.001),
            pair(9, [1, 2, 3], 1, 0.005),
        ],
        allowance: 0.001,
        ..ContactPairs::default()
    };
    let mut members = Vec::new();
    pairs.for_each_member(|particles| members.push(particles.collect::<Vec<_>>()));
    assert_eq!(
        members,
        vec![vec![0, 1, 2, 3], vec![3, 4, 5], vec![0, 6, 7, 8]]
    );
}
