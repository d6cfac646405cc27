//! Helpers of the wind tests (`wind_forces.rs`, `wind_motion.rs`,
//! `wind_fields.rs`): a world with nothing but a body and the wind, the
//! flat patches blown on, the area model, and how far apart two states are.

use sprung::build::{self, ClothSprings};
use sprung::forces::{Wind, WindField, WindModel};
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

/// A world without gravity holding `body`, stepped by `kind`, with `wind`
/// (from `field`, through `model`) as its one extra force.
pub fn windy_world(
    kind: IntegratorKind,
    body: BodyData,
    field: WindField,
    model: WindModel,
) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("patch", body).expect("valid body");
    let wind = Wind::new(field, model).expect("valid wind model");
    world.forces.push(Box::new(wind));
    world
}

/// A tilted triangle's frame: the unit normal `n = (1, 2, 2)/3` and two
/// unit vectors `e1 = (2, 1, -2)/3`, `e2 = (2, -2, 1)/3` in its plane (the
/// three are orthonormal: every dot product is 0 and every length 1).
pub fn frame() -> (Vec3, Vec3, Vec3) {
    (
        Vec3::new(1.0, 2.0, 2.0) / 3.0,
        Vec3::new(2.0, 1.0, -2.0) / 3.0,
        Vec3::new(2.0, -2.0, 1.0) / 3.0,
    )
}

/// Area of [`triangle`] (m²): in-plane corners (0, 0), (1.5, 0), (0.5, 1.2),
/// so base 1.5 m and height 1.2 m.
pub const TRIANGLE_AREA: Real = 0.9;

/// One springless triangle of particles of mass `mass` (kg) in the plane of
/// [`frame`], its corners at in-plane coordinates (0, 0), (1.5, 0),
/// (0.5, 1.2) from the point (0.4, -0.7, 1.3).
pub fn triangle(mass: Real) -> BodyData {
    let (_, e1, e2) = frame();
    let origin = Vec3::new(0.4, -0.7, 1.3);
    let corners = [(0.0, 0.0), (1.5, 0.0), (0.5, 1.2)];
    let mut body =
        BodyData::from_positions(corners.map(|(a, b)| origin + a * e1 + b * e2).to_vec())
            .with_mass(mass);
    body.faces = vec![[0, 1, 2]];
    body
}

/// A springless `nx × ny` cloth of `width × height` (m) in the plane z = 0,
/// every particle of mass `mass` (kg). Its faces are counter-clockwise seen
/// from +z: every normal is exactly (0, 0, 1).
pub fn flat_cloth(nx: usize, ny: usize, width: Real, height: Real, mass: Real) -> BodyData {
    let none = ClothSprings {
        structural: false,
        shear: false,
        bending: false,
    };
    build::cloth(nx, ny, width, height, none)
        .expect("valid cloth")
        .with_mass(mass)
}

pub const RHO: Real = 1.2; // kg/m³
pub const AREA: WindModel = WindModel::Area {
    air_density: RHO,
    lift: 0.0,
};

/// Largest distance between corresponding particles (m).
pub fn largest_distance(a: &[Vec3], b: &[Vec3]) -> Real {
    a.iter()
        .zip(b)
        .map(|(p, q)| p.distance(*q))
        .fold(0.0, Real::max)
}
