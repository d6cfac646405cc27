//! A body whose particles are numbered with no locality (a mesh whose
//! vertices come in no order along it) is the same body: the world reads
//! its springs in a numbering of its own (reverse Cuthill–McKee) for speed,
//! and that changes nothing but the order in which each particle's spring
//! forces are added up.

mod common;

use common::Rng;
use sprung::build::{self, ClothSprings};
use sprung::error::BuildError;
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

/// Particles along a side of the cloth: 10 000 particles, more than the
/// two chunks of 4096 below which a world is read in any order.
const SIDE: usize = 100;

/// A 1 m square cloth hanging from two corners, numbered along its rows.
fn cloth() -> BodyData {
    build::cloth(SIDE, SIDE, 1.0, 1.0, ClothSprings::default())
        .expect("valid cloth")
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.01)
        .with_pinned(vec![(SIDE - 1) * SIDE, SIDE * SIDE - 1])
}

/// Particles of the rope added before the cloth, so that the cloth's
/// particles do not start at 0.
const BEFORE: usize = 5;

/// The positions (m) of `body` after `steps` steps of symplectic Euler at
/// 1e-4 s (below the stable estimate of 1.4e-4 s for these springs and
/// masses) on `threads` threads: a small rope added before it, and a lone
/// particle (no springs) after it.
fn positions_after(body: BodyData, steps: usize, threads: usize) -> Vec<Vec3> {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world
        .add_body("rope", common::rope(BEFORE - 1, 0.01, 100.0, 0.1))
        .expect("valid rope");
    world.add_body("cloth", body).expect("valid body");
    world
        .add_body(
            "lone",
            BodyData::from_positions(vec![Vec3::new(2.0, 0.0, 0.0)]),
        )
        .expect("valid particle");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool");
    pool.install(|| {
        for _ in 0..steps {
            world.step(1e-4).expect("stable step");
        }
    });
    world.particles.position[BEFORE..BEFORE + SIDE * SIDE].to_vec()
}

#[test]
fn a_cloth_numbered_at_random_moves_as_the_same_cloth_numbered_in_rows() {
    // 100 steps (10 ms) of falling and swinging: each particle of the
    // shuffled cloth where its counterpart in rows is. The forces on a
    // particle are the same terms added in another order, equal to a few
    // roundings; each step moves a particle by a velocity times 1e-4 s, so
    // those roundings reach the positions (about 1 m, rounded to 2.2e-16 m)
    // only now and then: 4e-16 m apart at worst in this run, and within
    // 1e-14 m (a few tens of roundings of a position) by this test. A
    // spring read at the wrong particles would move them by centimetres.
    let steps = 100;
    let number = Rng::new(7).numbering(SIDE * SIDE);
    let rows = positions_after(cloth(), steps, 1);
    let shuffled = positions_after(cloth().renumbered(&number).expect("a numbering"), steps, 1);
    let worst = (0..rows.len())
        .map(|p| rows[p].distance(shuffled[number[p]]))
        .fold(0.0, Real::max);
    assert!(worst <= 1e-14, "positions differ by {worst} m");
    // And the cloth did move: by gravity alone, 5 mm in 10 ms.
    let start = cloth().position;
    let moved = rows
        .iter()
        .zip(&start)
        .map(|(x, x0)| x.distance(*x0))
        .fold(0.0, Real::max);
    assert!(moved > 1e-4, "moved {moved} m");
}

#[test]
fn a_cloth_numbered_at_random_steps_to_the_same_bits_on_one_and_two_threads() {
    let number = Rng::new(11).numbering(SIDE * SIDE);
    let body = cloth().renumbered(&number).expect("a numbering");
    let one = positions_after(body.clone(), 20, 1);
    let two = positions_after(body, 20, 2);
    assert!(one
        .iter()
        .zip(&two)
        .all(|(a, b)| a.to_array().map(Real::to_bits) == b.to_array().map(Real::to_bits)));
}

#[test]
fn a_numbering_must_number_each_particle_once() {
    let body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X, Vec3::Y]);
    assert_eq!(
        body.renumbered(&[0, 2, 2]),
        Err(BuildError::NotARenumbering {
            particles: 3,
            index: 2,
            value: 2
        })
    );
    assert_eq!(
        body.renumbered(&[0, 3, 1]),
        Err(BuildError::NotARenumbering {
            particles: 3,
            index: 1,
            value: 3
        })
    );
    assert!(matches!(
        body.renumbered(&[1, 0]),
        Err(BuildError::LengthMismatch {
            found: 2,
            expected: 3,
            ..
        })
    ));
    let renumbered = body.renumbered(&[2, 0, 1]).expect("a numbering");
    assert_eq!(renumbered.position, vec![Vec3::X, Vec3::Y, Vec3::ZERO]);
}
