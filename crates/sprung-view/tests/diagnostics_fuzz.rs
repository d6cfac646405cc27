//! The `diagnostics.csv` reader of `sprung plot` never panics: a real
//! table, written by a run of a demo, damaged in thousands of
//! deterministic random ways (the mutations of the io crate's fuzz tests:
//! lines deleted, duplicated or moved, bytes flipped, numbers replaced by
//! `nan` or huge values, the file cut short), gives a table or an error.

#[path = "../../sprung-io/tests/common/mutate.rs"]
#[allow(dead_code)] // the helpers of the io tests, shared
mod mutate;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;

use mutate::{mutate, XorShift};
use sprung_io::export::Diagnostics;
use sprung_view::plot::DiagnosticsTable;

/// The diagnostics of 200 steps of the stack demo (three gas balls, so
/// every kind of column is there), with two probes.
fn real_table(dir: &Path) -> String {
    let demo = sprung_io::demos::find("stack").expect("the stack demo");
    let mut scene = demo.load().expect("it loads");
    let path = dir.join("diagnostics.csv");
    let mut diagnostics = Diagnostics::create(&path, &scene.world, &[0, 5]).expect("writable");
    diagnostics.record(&scene.world).expect("written");
    for step in 1..=200 {
        scene.world.step(scene.dt).expect("stable");
        if step % 20 == 0 {
            diagnostics.record(&scene.world).expect("written");
        }
    }
    diagnostics.finish().expect("committed");
    std::fs::read_to_string(&path).expect("readable")
}

#[test]
fn damaged_diagnostics_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let text = real_table(dir.path());
    let path = Path::new("diagnostics.csv");
    assert!(
        DiagnosticsTable::parse(&text, path).is_ok(),
        "the real table reads"
    );
    let mut rng = XorShift(0x0dd_ba11_cafe);
    let (mut accepted, mut refused) = (0, 0);
    for case in 0..3000 {
        let mut bytes = text.as_bytes().to_vec();
        let steps: Vec<String> = (0..1 + rng.below(3))
            .map(|_| mutate(&mut bytes, &mut rng))
            .collect();
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let text = String::from_utf8_lossy(&bytes);
            DiagnosticsTable::parse(&text, path).is_ok()
        }));
        match outcome {
            Ok(true) => accepted += 1,
            Ok(false) => refused += 1,
            Err(_) => panic!("case {case} panicked after {steps:?}"),
        }
    }
    // Both outcomes occur, or the mutations are not reaching the reader.
    assert!(
        accepted > 0 && refused > 0,
        "{accepted} accepted, {refused} refused"
    );
}
