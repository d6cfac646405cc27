//! The demo scenes with sphere colliders, loaded from `scenes/` and run:
//! no particle is ever found inside a sphere. Both spheres use the
//! projection form, which puts a penetrating particle back on the surface
//! every step, so the depth after any step is round-off: 1e-12 m is a
//! thousand times the rounding of coordinates of order 1 m.

use std::path::Path;

use sprung::Shape;
use sprung_io::load_scene;

/// Deepest penetration into any sphere collider after each of `steps` steps.
fn deepest_inside_spheres(scene: &str, steps: usize) -> f64 {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(scene);
    let mut scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
    let mut deepest: f64 = 0.0;
    for _ in 0..steps {
        scene.world.step(scene.dt).unwrap_or_else(|e| panic!("{e}"));
        let time = scene.world.time();
        for collider in &scene.world.colliders {
            let shape = collider.shape_at(time);
            if let Shape::Sphere { .. } = shape {
                for &x in &scene.world.particles.position {
                    deepest = deepest.max(-shape.distance_and_normal(x).0);
                }
            }
        }
    }
    deepest
}

#[test]
fn the_draped_cloth_never_enters_the_ball() {
    // 2 s at 2e-4 s: the cloth lands at about 0.4 s and is draped by 1.5 s.
    let deepest = deepest_inside_spheres("drape.toml", 10_000);
    assert!(deepest <= 1e-12, "{deepest} m inside");
}

#[test]
fn the_poking_ball_never_enters_the_horse_nor_the_horse_the_ball() {
    // 1.7 s at 4e-4 s: the ball reaches the flank at about 1.3 s and is 0.8 m
    // along its path at 1.6 s.
    let deepest = deepest_inside_spheres("poke.toml", 4_250);
    assert!(deepest <= 1e-12, "{deepest} m inside");
}
