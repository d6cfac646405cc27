//! The scene loader never panics: every demo scene of the repository,
//! damaged in hundreds of deterministic random ways (the same mutations as
//! the mesh readers' fuzz test), gives a scene or an error; a scene that
//! loads takes a few steps without a panic (a blow-up is an error, fine).

mod common;

use common::mutate::{mutate, XorShift};
use sprung_io::demos::{Bundled, DEMOS};
use sprung_io::scene::parse_scene_with;

/// Parse `bytes` as the demo's scene and, if it loads and is small, step
/// it twice; `Err` carries the panic message if anything panicked.
fn exercise(bytes: &[u8], demo: &sprung_io::demos::Demo) -> Result<bool, String> {
    common::without_panic(|| {
        let Ok(text) = std::str::from_utf8(bytes) else {
            return false;
        };
        let Ok(mut scene) = parse_scene_with(text, &demo.path(), &Bundled) else {
            return false;
        };
        // Stepping a damaged horse is slow and tells nothing new.
        if scene.world.particles.len() <= 2000 {
            for _ in 0..2 {
                if scene.world.step(scene.dt).is_err() {
                    break;
                }
            }
        }
        true
    })
}

#[test]
fn damaged_demo_scenes_never_panic() {
    // 60 damaged copies of each of the demos (1 to 3 mutations each): a
    // couple of seconds in all, every run the same.
    let mut rng = XorShift(0x2545_F491_4F6C_DD1D);
    let (mut accepted, mut refused) = (0, 0);
    for demo in DEMOS {
        assert_eq!(
            exercise(demo.text.as_bytes(), demo),
            Ok(true),
            "{}",
            demo.name
        );
        for case in 0..60 {
            let mut bytes = demo.text.as_bytes().to_vec();
            let steps: Vec<String> = (0..1 + rng.below(3))
                .map(|_| mutate(&mut bytes, &mut rng))
                .collect();
            match exercise(&bytes, demo) {
                Ok(true) => accepted += 1,
                Ok(false) => refused += 1,
                Err(message) => {
                    panic!(
                        "{}: case {case} panicked ({message}) after: {steps:?}",
                        demo.name
                    )
                }
            }
        }
    }
    // Both outcomes occur, or the mutations are not reaching the loader.
    assert!(
        accepted > 0 && refused > 0,
        "{accepted} accepted, {refused} refused"
    );
}
