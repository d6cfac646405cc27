//! Where a step's time goes: a ball dropped on a trampoline, profiled.
//!
//! Shows: contact between two bodies (a gas ball and a cloth pinned at its
//! corners), `world.set_profiling(true)` and the table of `world.profile()`,
//! stage by stage (finding contact pairs, forces, the integrator, ...).
//!
//!     cargo run --release -p sprung --example profile

use sprung::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // A 2 m × 2 m cloth of 20 × 20 particles laid flat at y = 0, held by
    // its four corners.
    let n = 20;
    let trampoline = build::cloth(n, n, 2.0, 2.0, ClothSprings::default())?
        .with_total_mass(0.5)
        .with_stiffness(500.0)
        .with_damping(0.05)
        .with_pinned(vec![0, n - 1, n * (n - 1), n * n - 1])
        .placed(1.0, Vec3::new(90.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, -1.0));
    let mut ball = build::icosphere(0.3, 2, SurfaceSprings::default())?
        .with_total_mass(0.5)
        .with_stiffness(1000.0)
        .with_damping(0.2)
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 0.8, 0.0));
    ball.gas = Some(Gas::new(200.0, 0.0));

    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.add_body("trampoline", trampoline)?;
    let ball = world.add_body("ball", ball)?;
    let dt = 2e-4;
    world.set_profiling(true);
    let mut touching = 0;
    for _ in 0..5000 {
        world.step(dt)?;
        touching = touching.max(world.active_contacts());
    }
    let profile = world.profile();
    println!(
        "{} particles, {} steps of {dt:.0e} s",
        world.particles.len(),
        profile.steps()
    );
    println!("at most {touching} pair(s) of bodies touching at once");
    println!(
        "ball's centre now at y = {:.3} m\n",
        world.centroid(ball).expect("the ball").y
    );
    println!("{profile}");

    let shares: f64 = Stage::ALL.iter().map(|&s| profile.share(s)).sum();
    assert!(touching > 0, "the ball never reached the trampoline");
    assert!(shares <= 1.0 + 1e-9);
    Ok(())
}
