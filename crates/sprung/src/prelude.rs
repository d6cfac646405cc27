//! The names most programs need, in one import:
//!
//! ```
//! use sprung::prelude::*;
//!
//! let mut world = World::new(IntegratorKind::Verlet);
//! let cloth = build::cloth(8, 8, 1.0, 1.0, ClothSprings::default())
//!     .unwrap()
//!     .with_total_mass(0.1)
//!     .with_stiffness(200.0)
//!     .with_pinned(vec![56, 63]);
//! world.add_body("cloth", cloth).unwrap();
//! let floor = Shape::plane(Vec3::new(0.0, -2.0, 0.0), Vec3::Y).unwrap();
//! world.colliders.push(Collider::new(floor, ContactResponse::Projection { restitution: 0.5, friction: 0.3 }).unwrap());
//! world.step(1e-3).unwrap();
//! assert_eq!(world.steps(), 1);
//! ```

pub use crate::build::{self, ClothSprings, SurfaceSprings};
pub use crate::forces::{
    AirDrag, Force, ForceContext, JacobianScale, Linearization, MouseSpring, StiffnessBounds, Wind,
};
pub use crate::{
    body::{BodyData, SpringData},
    colliders::{Collider, ContactResponse, Path, Shape},
    contact::ContactSettings,
    error::{BuildError, StepError},
    gas::Gas,
    integrate::IntegratorKind,
    measure::Energies,
    stage::{Profile, Stage},
    units::{Real, Vec3},
    world::{Settings, Substeps, World},
};
