//! Contact between bodies: gas balls packed in a box, and a large cloth
//! colliding with itself, each timed with contacts on and off, so the cost
//! of contact (detecting pairs and their forces and friction) can be set
//! against the rest of the step (springs, gas, integration).

use std::time::Instant;

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::{Collider, ContactResponse, Gas, IntegratorKind, Real, Shape, Vec3, World};

use crate::run::CliError;

/// Time step of the contact scenes (s).
const DT: Real = 2e-4;

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::Input(format!("bench: {e}"))
}

/// `count` gas balls (icospheres of 162 particles, radius 0.2 m) packed in
/// a grid with 5 mm gaps in a box, on the floor, touching their
/// neighbours within the contact thickness once the gas pushes them out.
fn balls_in_a_box(count: usize, contacts: bool) -> Result<World, CliError> {
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.contacts.settings.enabled = contacts;
    world.contacts.settings.friction = 0.3;
    let side = (count as Real).cbrt().ceil() as usize;
    let (radius, gap) = (0.2, 0.005);
    let pitch = 2.0 * radius + gap;
    for index in 0..count {
        let (i, j, k) = (index % side, (index / side) % side, index / (side * side));
        let centre = Vec3::new(
            i as Real * pitch,
            radius + gap + k as Real * pitch,
            j as Real * pitch,
        );
        let mut ball = build::icosphere(radius, 2, SurfaceSprings::default())
            .map_err(input)?
            .with_total_mass(0.2)
            .with_stiffness(500.0)
            .with_damping(0.2)
            .placed(1.0, Vec3::ZERO, centre);
        ball.gas = Some(Gas::new(40.0, 0.0));
        world
            .add_body(&format!("ball{index}"), ball)
            .map_err(input)?;
    }
    let extent = side as Real * pitch;
    let walls = [
        (Vec3::ZERO, Vec3::Y),
        (Vec3::new(-radius - gap, 0.0, 0.0), Vec3::X),
        (Vec3::new(extent - radius, 0.0, 0.0), -Vec3::X),
        (Vec3::new(0.0, 0.0, -radius - gap), Vec3::Z),
        (Vec3::new(0.0, 0.0, extent - radius), -Vec3::Z),
    ];
    for (point, normal) in walls {
        let shape = Shape::plane(point, normal).map_err(input)?;
        let response = ContactResponse::Projection {
            restitution: 0.0,
            friction: 0.3,
        };
        world
            .colliders
            .push(Collider::new(shape, response).map_err(input)?);
    }
    Ok(world)
}

/// A `size × size` cloth (2 m square) lying in folds: a sine wave of
/// amplitude 0.1 m, so that its layers come within reach of each other,
/// with self-collision.
fn folded_cloth(size: usize, contacts: bool) -> Result<World, CliError> {
    let mut cloth = build::cloth(size, size, 2.0, 2.0, ClothSprings::default())
        .map_err(input)?
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.02)
        .placed(1.0, Vec3::new(90.0, 0.0, 0.0), Vec3::new(0.0, 0.3, 0.0));
    for x in &mut cloth.position {
        x.y += 0.1 * (x.x * 12.0).sin();
    }
    cloth.contact.self_collision = true;
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.contacts.settings.enabled = contacts;
    world.add_body("cloth", cloth).map_err(input)?;
    Ok(world)
}

/// A scene of the contact bench: its name, how to build it with contacts
/// on or off, and how many steps to time.
type Case = (String, Box<dyn Fn(bool) -> Result<World, CliError>>, u32);

/// Seconds per step of `world` over `steps` steps after `warm_up`.
fn per_step(world: &mut World, warm_up: u32, steps: u32) -> Result<Real, CliError> {
    for _ in 0..warm_up {
        world.step(DT).map_err(input)?;
    }
    let start = Instant::now();
    for _ in 0..steps {
        world.step(DT).map_err(input)?;
    }
    Ok(start.elapsed().as_secs_f64() / Real::from(steps))
}

/// Time the contact scenes and print a table.
pub fn run() -> Result<(), CliError> {
    println!("contact between bodies (symplectic Euler, dt = {DT} s), 1 thread");
    println!(
        "{:<34} {:>9} {:>13} {:>13} {:>13} {:>12}",
        "scene", "particles", "ms/step", "no contact", "contact part", "pairs/step"
    );
    let mut cases: Vec<Case> = Vec::new();
    for count in [10, 100, 1000] {
        cases.push((
            format!("{count} gas balls in a box"),
            Box::new(move |on| balls_in_a_box(count, on)),
            if count > 100 { 10 } else { 50 },
        ));
    }
    cases.push((
        "128×128 cloth, self-collision".into(),
        Box::new(|on| folded_cloth(128, on)),
        20,
    ));
    for (name, make, steps) in cases {
        let mut with = make(true)?;
        let time_with = per_step(&mut with, 5, steps)?;
        let pairs = with.contacts.pairs.len();
        let mut without = make(false)?;
        let time_without = per_step(&mut without, 5, steps)?;
        println!(
            "{:<34} {:>9} {:>13.3} {:>13.3} {:>12.0} % {:>12}",
            name,
            with.particles.len(),
            time_with * 1e3,
            time_without * 1e3,
            100.0 * (time_with - time_without) / time_with,
            pairs
        );
    }
    Ok(())
}
