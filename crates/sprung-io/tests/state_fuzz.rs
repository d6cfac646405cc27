//! The state reader never panics and never takes a damaged file: a real
//! state file, damaged in thousands of deterministic random ways (bytes
//! flipped, inserted, deleted, the file cut short), is refused; with the
//! checksum made to match again, so that the parser itself meets the
//! damage, it still gives `Ok` or `Err` without a panic, and a state it
//! accepts either fits the world or is refused by `restore_state`.

mod common;

use common::mutate::XorShift;
use sprung::{build, IntegratorKind, World};
use sprung_io::state::{read_state, write_state};

fn world() -> World {
    let mut world = World::new(IntegratorKind::Verlet);
    let rope = build::rope(6, 1.0)
        .expect("valid rope")
        .with_pinned(vec![0]);
    world.add_body("rope", rope).expect("valid body");
    for _ in 0..3 {
        world.step(1e-3).expect("stable");
    }
    world
}

/// One random change to `bytes`.
fn damage(bytes: &mut Vec<u8>, rng: &mut XorShift) {
    let at = rng.below(bytes.len());
    match rng.below(4) {
        0 => bytes[at] ^= 1 << rng.below(8),
        1 => bytes.insert(at, rng.next() as u8),
        2 => {
            bytes.remove(at);
        }
        _ => bytes.truncate(at),
    }
}

#[test]
fn damaged_state_files_are_refused_without_a_panic() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("state.bin");
    let mut world = world();
    write_state(&path, &world, &world.save_state()).expect("written");
    let original = std::fs::read(&path).unwrap();
    assert!(
        read_state(&path, &world).is_ok(),
        "the undamaged file reads"
    );
    let mut rng = XorShift(0x5eed_57a7e);
    let mut parsed = 0;
    for case in 0..3000 {
        let mut bytes = original.clone();
        for _ in 0..=rng.below(3) {
            if bytes.is_empty() {
                break;
            }
            damage(&mut bytes, &mut rng);
        }
        if bytes == original {
            continue;
        }
        // Every other case gets a matching checksum again.
        let rechecked = case % 2 == 1 && bytes.len() >= 4;
        if rechecked {
            let body = bytes.len() - 4;
            let sum = crc32fast::hash(&bytes[..body]);
            bytes[body..].copy_from_slice(&sum.to_le_bytes());
        }
        std::fs::write(&path, &bytes).unwrap();
        let outcome = common::without_panic(|| {
            read_state(&path, &world).map(|state| world.restore_state(&state).is_ok())
        });
        match outcome {
            Err(message) => panic!("case {case}: the reader panicked: {message}"),
            Ok(Ok(_)) => {
                assert!(rechecked, "case {case}: a damaged file passed its checksum");
                parsed += 1;
            }
            Ok(Err(_)) => {}
        }
    }
    // Flips inside the numbers keep the layout: some damaged files parse
    // (their numbers changed), so the parser's own checks were reached.
    assert!(parsed > 0);
}
