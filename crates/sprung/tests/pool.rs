//! Where a step runs: `World::step` called from a thread outside the
//! engine's pool of threads hands the whole step of a world large enough
//! to share its loops (more than `parallel::CHUNK` particles) to a thread
//! of the pool, one hand-over a step instead of one for each of its
//! parallel loops; a smaller world steps on the calling thread, where a
//! hand-over would cost more than its step; called from a thread of a
//! pool, a step runs right there.

mod common;

use std::sync::{Arc, Mutex};

use common::{rope, Watcher};
use sprung::parallel::{Pool, CHUNK};
use sprung::{IntegratorKind, World};

/// A rope of `free` free particles under RK4 (four force evaluations a
/// step) with the recorder.
fn world(free: usize, seen: &Arc<Mutex<Vec<Option<usize>>>>) -> World {
    let mut world = World::new(IntegratorKind::Rk4);
    world
        .add_body("rope", rope(free, 0.1, 100.0, 0.1))
        .unwrap_or_else(|e| panic!("{e}"));
    // Records the pool thread (its index in its pool, `None` outside any
    // pool) each force evaluation runs on.
    let record = Arc::clone(seen);
    world.forces.push(Box::new(Watcher(Box::new(move || {
        if let Ok(mut seen) = record.lock() {
            seen.push(rayon::current_thread_index());
        }
    }))));
    world
}

fn seen(record: &Arc<Mutex<Vec<Option<usize>>>>) -> Vec<Option<usize>> {
    record.lock().map(|s| s.clone()).unwrap_or_default()
}

#[test]
fn a_large_step_from_outside_the_pool_runs_on_a_thread_of_the_pool() {
    let record = Arc::new(Mutex::new(Vec::new()));
    let mut world = world(CHUNK, &record);
    assert!(world.particles.len() > CHUNK);
    // The test's own thread belongs to no pool.
    assert_eq!(rayon::current_thread_index(), None);
    for _ in 0..3 {
        world.step(1e-3).unwrap_or_else(|e| panic!("{e}"));
    }
    let seen = seen(&record);
    assert_eq!(seen.len(), 12, "RK4: four evaluations a step");
    assert!(
        seen.iter().all(Option::is_some),
        "every evaluation on a pool thread: {seen:?}"
    );
}

#[test]
fn a_small_step_from_outside_the_pool_runs_on_the_calling_thread() {
    let record = Arc::new(Mutex::new(Vec::new()));
    let mut world = world(5, &record);
    world.step(1e-3).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(seen(&record), vec![None; 4]);
}

#[test]
fn a_step_on_a_thread_of_a_pool_runs_there() {
    let record = Arc::new(Mutex::new(Vec::new()));
    let mut world = world(CHUNK, &record);
    let pool = Pool::new(2).unwrap_or_else(|e| panic!("{e}"));
    let caller = pool.install(|| {
        world.step(1e-3).unwrap_or_else(|e| panic!("{e}"));
        rayon::current_thread_index()
    });
    assert!(caller.is_some());
    assert_eq!(seen(&record), vec![caller; 4], "on the caller's own thread");
}
