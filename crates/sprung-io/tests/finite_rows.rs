//! Finite in, finite out, where the rows are written and where the clock
//! runs: a row that would hold a non-finite number is not written (the
//! writer says which quantity), and a step that would carry the clock past
//! the largest finite time fails before it moves anything.

use sprung::{BodyData, IntegratorKind, SpringData, StepError, Vec3, World};
use sprung_io::export::{Diagnostics, NotFiniteValue};

#[test]
fn a_row_with_an_infinite_energy_is_not_written() {
    let dir = tempfile::tempdir().expect("tempdir");
    let path = dir.path().join("diagnostics.csv");
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(0.0, -3.0, 0.0)]);
    body.springs.push(SpringData {
        rest_length: Some(1.0),
        ..SpringData::between(0, 1)
    });
    world.add_body("pair", body).unwrap();
    let mut diagnostics = Diagnostics::create(&path, &world, &[]).expect("created");
    diagnostics.record(&world).expect("a finite row");
    // Set by hand past what a scene may give: ½ k (L - L0)² = ½ 1e308 · 2²
    // overflows.
    world.springs.stiffness[0] = 1e308;
    let error = diagnostics.record(&world).expect_err("not written");
    let bad = error
        .get_ref()
        .and_then(|e| e.downcast_ref::<NotFiniteValue>())
        .expect("the quantity named");
    assert_eq!(bad.quantity, "spring");
    assert!(bad.value.is_infinite());
    assert_eq!(diagnostics.rows(), 1);
    diagnostics.finish().expect("finished");
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().count(), 2, "the header and the finite row");
    assert!(!text.contains("inf"));
}

#[test]
fn a_step_past_the_largest_finite_time_fails_before_it_moves() {
    // One particle at rest, no forces: the first step of 1e308 s reaches
    // t = 1e308; the second would reach 2e308 = ∞.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world
        .add_body("dot", BodyData::from_positions(vec![Vec3::ZERO]))
        .unwrap();
    world.step(1e308).expect("t = 1e308 is finite");
    match world.step(1e308) {
        Err(StepError::NotFinite { quantity, step, .. }) => {
            assert_eq!((quantity.as_str(), step), ("time", 1));
        }
        other => panic!("expected NotFinite, got {other:?}"),
    }
    assert_eq!((world.time(), world.steps()), (1e308, 1));
}
