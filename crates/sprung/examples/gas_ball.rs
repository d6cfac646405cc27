//! A gas-filled ball built in code and dropped on a floor.
//!
//! Shows: a body from a builder (`build::icosphere`), its gas (`Gas`: the
//! pressure is nRT / V on the enclosed volume), a floor collider, and
//! reading the volume, pressure and height back while the ball falls,
//! squashes and bounces.
//!
//!     cargo run --release -p sprung --example gas_ball

use sprung::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // 162 particles, a spring on every edge and across every pair of
    // neighbouring triangles; 1 kg in all; centred 2 m above the floor.
    let mut ball = build::icosphere(0.5, 2, SurfaceSprings::default())?
        .with_total_mass(1.0)
        .with_stiffness(2000.0)
        .with_damping(0.5)
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0));
    // nRT = 500 J, switched on over the first 0.3 s.
    let gas = Gas::new(500.0, 0.3);
    ball.gas = Some(gas.clone());

    let mut world = World::new(IntegratorKind::SymplecticEuler);
    let index = world.add_body("ball", ball)?;
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y)?;
    let response = ContactResponse::Projection {
        restitution: 0.3,
        friction: 0.3,
    };
    world.colliders.push(Collider::new(floor, response)?);

    let dt = 2e-4;
    println!(
        "{} particles, stable step {:.2e} s, step {dt:.0e} s",
        world.particles.len(),
        world.stable_time_step()
    );
    println!(
        "{:>5} {:>9} {:>9} {:>9} {:>9}",
        "t (s)", "V (m³)", "P (Pa)", "nRT/V", "y (m)"
    );
    let mut lowest = Real::INFINITY;
    for row in 0..=12 {
        if row > 0 {
            for _ in 0..1000 {
                world.step(dt)?;
                let bottom = world.particles.position.iter().map(|x| x.y);
                lowest = lowest.min(bottom.fold(Real::INFINITY, Real::min));
            }
        }
        let volume = world.volume(index).expect("a closed surface");
        let pressure = world.pressure(index).unwrap_or(0.0);
        let height = world.centroid(index).expect("the ball").y;
        println!(
            "{:>5.1} {volume:>9.4} {pressure:>9.1} {:>9.1} {height:>9.3}",
            world.time(),
            gas.nrt_at(world.time()) / volume,
        );
    }
    println!("lowest particle: {lowest:.4} m (the floor is at 0)");

    // The ball has landed, kept its gas in and stayed above the floor.
    let height = world.centroid(index).expect("the ball").y;
    assert!(height > 0.3 && height < 1.0, "centre at {height} m");
    assert!(lowest > -1e-9, "a particle went {lowest} m into the floor");
    Ok(())
}
