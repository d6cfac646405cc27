//! The contact scenes: gas balls packed in a box, and a large cloth lying
//! in folds that collides with itself; each built with contact on or off,
//! so the cost of contact (detecting pairs, their forces and friction) can
//! be set against the rest of the step (springs, gas, integration).

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::{Collider, ContactResponse, Gas, IntegratorKind, Real, Shape, Vec3, World};

use crate::error::CliError;

/// Time step of the contact scenes (s).
pub const DT: Real = 2e-4;

fn input(e: impl std::fmt::Display) -> CliError {
    CliError::Input(format!("bench: {e}"))
}

/// `count` gas balls (icospheres of 162 particles, radius 0.2 m) packed in
/// a grid with 5 mm gaps in a box, on the floor, touching their
/// neighbours within the contact thickness once the gas pushes them out.
pub fn balls_in_a_box(count: usize, contacts: bool) -> Result<World, CliError> {
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

/// A `size × size` cloth (2 m square) folded like an accordion into eight
/// layers 15 mm apart, with self-collision: every layer lies just beyond
/// the contact thickness (1 cm) from the next and within the search's
/// reach, so that the candidate pairs cover the whole cloth as it falls
/// and springs open: the densest self-contact a cloth has.
pub fn folded_cloth(size: usize, contacts: bool) -> Result<World, CliError> {
    let (side, layers, gap) = (2.0, 8.0, 0.015);
    let mut cloth = build::cloth(size, size, side, side, ClothSprings::default())
        .map_err(input)?
        .with_total_mass(1.0)
        .with_stiffness(1000.0)
        .with_damping(0.02);
    let strip = side / layers;
    for x in &mut cloth.position {
        // The builder lays the cloth in the xy-plane from the origin: x
        // runs across the folds, y along them.
        let (across, along) = (x.x, x.y);
        let layer = (across / strip).floor().min(layers - 1.0);
        let within = across - layer * strip;
        let back_and_forth = if layer % 2.0 == 0.0 {
            within
        } else {
            strip - within
        };
        *x = Vec3::new(back_and_forth, 0.3 + layer * gap, along);
    }
    cloth.contact.self_collision = true;
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.contacts.settings.enabled = contacts;
    world.add_body("cloth", cloth).map_err(input)?;
    Ok(world)
}
