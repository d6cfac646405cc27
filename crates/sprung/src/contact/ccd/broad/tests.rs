//! The broad phase's tests: every pair that meets is handed on, with
//! the pairs kept or searched at each check.

use super::super::test;
use super::*;
use crate::build::{self, ClothSprings};
use crate::contact::random::Random;
use crate::{integrate::IntegratorKind, world::World};

/// Two cloths 10 cm square, one colliding with itself, 6 mm apart, and
/// a rope of loose particles between them, 3 mm from each.
fn three_bodies() -> World {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let mut lower = build::cloth(6, 6, 0.1, 0.1, ClothSprings::default()).unwrap();
    lower.contact.self_collision = true;
    let upper = build::cloth(6, 6, 0.1, 0.1, ClothSprings::default())
        .unwrap()
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.0, 0.006));
    let rope = build::rope(8, 0.1)
        .unwrap()
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.05, 0.003));
    world.add_body("lower", lower).unwrap();
    world.add_body("upper", upper).unwrap();
    world.add_body("rope", rope).unwrap();
    world
}

/// The elements of `world`'s bodies, which can meet.
fn elements_of(world: &World) -> Elements {
    let mut elements = Elements::default();
    assert!(elements.gather(&world.bodies));
    elements
}

#[test]
fn every_pair_that_meets_is_handed_on_however_the_bodies_move() {
    every_pair_that_meets_is_handed_on(None);
}

#[test]
fn every_pair_that_meets_is_handed_on_when_no_pairs_are_kept() {
    // No allowance: every pair of bodies is searched at each check.
    every_pair_that_meets_is_handed_on(Some(0));
}

#[test]
fn the_allowance_is_per_element_at_least_two_million_at_most_every_pair() {
    assert_eq!(kept_pairs_most(0), 0);
    // 40 elements make 780 pairs; 6,125 (the bullet demo's) 18.8
    // million, of which 2 million are kept; 10,000 keep 256 each.
    assert_eq!(kept_pairs_most(40), 780);
    assert_eq!(kept_pairs_most(6125), MIN_KEPT_PAIRS);
    assert_eq!(kept_pairs_most(10_000), 2_560_000);
    // Each pair 16 bytes, up to three times over at a search's peak,
    // and its stamp, 4.
    assert_eq!(Sweep::most_bytes(40), 3 * 780 * 16 + 780 * 4);
}

#[test]
fn pairs_searched_at_each_check_are_those_kept() {
    // The same random motion through a sweep that keeps its pairs and
    // one that keeps none: every check hands on the same pairs (in
    // another order), and so anchors the same bodies.
    let world = three_bodies();
    let elements = elements_of(&world);
    let mut kept = Sweep::default();
    let mut searched = Sweep {
        allowance: Some(0),
        ..Sweep::default()
    };
    let mut noise = Random(0xC0DE);
    let mut start = world.particles.position.clone();
    let mut handed = 0;
    for step in 0..120 {
        let mut end = start.clone();
        let jitter = [1e-4, 1e-3, 6e-3][step % 3];
        for body in world.bodies.iter() {
            let shift = noise.vector(if step % 7 == 0 { 0.03 } else { 0.002 });
            for x in &mut end[body.particles.clone()] {
                *x += shift + noise.vector(jitter);
            }
        }
        let mut on = [Vec::new(), Vec::new()];
        for (sweep, on) in [&mut kept, &mut searched].into_iter().zip(&mut on) {
            sweep
                .prepare(&elements, &start, &end, 0.01, 1e-3, 1e-3)
                .expect("a motion within bounds");
            sweep.overlaps(&elements, |a, b, _| on.push((a, b)));
            on.sort_unstable();
        }
        assert_eq!(on[0], on[1], "step {step}");
        assert_eq!(kept.clock, searched.clock, "step {step}");
        handed += on[0].len();
        start = end;
    }
    assert!(kept.found.values().all(|f| f.pairs.is_some()));
    assert!(handed > 100, "{handed} pairs handed on");
}

#[test]
fn every_pair_that_meets_is_handed_on_when_few_pairs_are_kept() {
    // An allowance some searches fit in and others do not.
    every_pair_that_meets_is_handed_on(Some(1000));
}

fn every_pair_that_meets_is_handed_on(allowance: Option<usize>) {
    // The three bodies moved at random: each body by a common shift
    // of up to 3 cm a step and each particle by up to 0.1–6 mm, so
    // they crumple, drift apart and through each other, and the anchors are left often. At every
    // step every pair of elements the narrow test finds meeting (by
    // testing them all) must be among those the broad phase hands on:
    // exact, as the broad phase only ever leaves out pairs it has
    // bounded apart.
    let world = three_bodies();
    let bodies = &world.bodies;
    let elements = elements_of(&world);
    let (thickness, gap, radius) = (0.01, 1e-3, 1e-3);
    let mut sweep = Sweep {
        allowance,
        ..Sweep::default()
    };
    let mut noise = Random(0x5EED);
    let mut start = world.particles.position.clone();
    let (mut met, mut searched, mut kept_some) = (0, 0, 0);
    for step in 0..120 {
        let mut end = start.clone();
        let jitter = [1e-4, 1e-3, 6e-3][step % 3];
        for body in bodies.iter() {
            let shift = noise.vector(if step % 7 == 0 { 0.03 } else { 0.002 });
            for x in &mut end[body.particles.clone()] {
                *x += shift + noise.vector(jitter);
            }
        }
        sweep
            .prepare(&elements, &start, &end, thickness, gap, radius)
            .expect("a motion within bounds");
        let kept: usize = sweep
            .found
            .values()
            .filter_map(|f| f.pairs.as_ref())
            .map(Vec::len)
            .sum();
        assert!(
            kept <= allowance.unwrap_or(usize::MAX),
            "step {step}: {kept} pairs kept"
        );
        searched += sweep.found.values().filter(|f| f.pairs.is_none()).count();
        kept_some += sweep
            .found
            .values()
            .filter(|f| f.pairs.as_ref().is_some_and(|p| !p.is_empty()))
            .count();
        let mut on = Vec::new();
        sweep.overlaps(&elements, |a, b, _| on.push((a, b)));
        on.sort_unstable();
        for a in 0..elements.list.len() {
            for b in a + 1..elements.list.len() {
                let Some((p, q)) = elements.pair(a, b) else {
                    continue;
                };
                let (ep, eq) = (&elements.list[p], &elements.list[q]);
                if test(ep, eq, &start, &end, gap, radius).is_some() {
                    met += 1;
                    assert!(
                        on.binary_search(&(p, q)).is_ok(),
                        "step {step}: elements {p} and {q} meet but were not handed on"
                    );
                }
            }
        }
        start = end;
    }
    // The motion does make them meet.
    assert!(met > 100, "{met} pairs met");
    // Pairs of bodies over the allowance were searched at each check.
    assert_eq!(searched > 0, allowance.is_some(), "{searched} searched");
    // And, but with no allowance, others kept theirs.
    assert_eq!(kept_some > 0, allowance != Some(0), "{kept_some} kept");
}

#[test]
fn bodies_moving_together_keep_their_pairs_and_hand_on_none() {
    // The three bodies fall together by 1 cm a step, each particle
    // jittered by at most 1 µm: the bodies are anchored once (one
    // search per body), and no pair is handed on, as none comes
    // within 3 mm less the jitter of another.
    let world = three_bodies();
    let elements = elements_of(&world);
    let mut sweep = Sweep::default();
    let mut noise = Random(7);
    let mut start = world.particles.position.clone();
    for _ in 0..200 {
        let end: Vec<Vec3> = start
            .iter()
            .map(|x| *x - 0.01 * Vec3::Z + noise.vector(1e-6))
            .collect();
        sweep
            .prepare(&elements, &start, &end, 0.01, 1e-5, 1e-3)
            .expect("a motion within bounds");
        sweep.overlaps(&elements, |a, b, _| {
            panic!(
                "{a} and {b} handed on: {:?} {:?}",
                elements.list[a], elements.list[b]
            )
        });
        start = end;
    }
    assert_eq!(sweep.clock, 3);
    // The cloths' pairs 6 mm apart are within their margins (2.5 mm
    // each) and the gap of each other through the rope: found.
    assert!(sweep
        .found
        .values()
        .any(|f| f.pairs.as_ref().is_some_and(|p| !p.is_empty())));
}
