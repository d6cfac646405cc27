//! # sprung: a mass-spring-damper engine for elastic materials
//!
//! Bodies are point masses ([`Particles`]) joined by damped springs
//! ([`Springs`]). A [`World`] holds them together with the forces acting on
//! them, the colliders they hit and the time integrator that moves them.
//! The physics follows `docs/physics.md` (the classic mass-spring-damper model of
//! elastic materials); every quantity is in SI units (m, kg, s, N).
//!
//! The engine is pure: it reads no files and draws nothing. Scene files,
//! meshes and exports live in `sprung-io`, the command line in `sprung-cli`.
//!
//! ```
//! use sprung::{build, Vec3, World, IntegratorKind};
//!
//! let mut world = World::new(IntegratorKind::SymplecticEuler);
//! world.set_gravity(Vec3::new(0.0, -9.81, 0.0));
//! let rope = build::rope(10, 2.0).expect("valid rope").with_stiffness(500.0);
//! world.add_body("rope", rope).expect("valid body");
//! for _ in 0..100 {
//!     world.step(1e-3).expect("stable");
//! }
//! assert!(world.particles.position[9].y < -2.0); // stretched under gravity
//! ```

/// Compile the function it wraps once for each vector unit (AVX-512, AVX2
/// with FMA, NEON) besides the baseline, and run the widest one the
/// processor has, chosen at run time (`multiversion`). A plain release
/// build thus uses the wide units without `-C target-cpu=native`.
macro_rules! vectorised {
    ($function:item) => {
        #[multiversion::multiversion(targets(
            "x86_64+avx512f+avx512vl+avx512dq+avx2+fma",
            "x86_64+avx2+fma",
            "aarch64+neon"
        ))]
        $function
    };
}

pub mod body;
pub mod build;
mod cache;
pub mod colliders;
pub mod constrain;
pub mod contact;
pub mod error;
pub mod forces;
pub mod gas;
pub mod integrate;
pub mod interrupt;
pub mod measure;
pub mod model;
mod order;
pub mod parallel;
pub mod particles;
pub mod prelude;
pub mod springs;
pub mod stage;
pub mod state;
pub mod surface;
pub mod tearing;
pub mod units;
mod unknown;
pub mod world;

pub use body::{Body, BodyContact, BodyData, MuscleData, MuscleDrive, RodData, SpringData};
pub use colliders::{Collider, ContactResponse, Path, Shape};
pub use constrain::{ConstraintSettings, Rods};
pub use contact::{ContactSettings, Contacts};
pub use error::{BuildError, StepError};
pub use gas::{Gas, VolumeModel};
pub use integrate::IntegratorKind;
pub use measure::Energies;
pub use model::Model;
pub use particles::Particles;
pub use springs::Springs;
pub use stage::{Profile, Stage};
pub use state::{StateError, WorldState};
pub use tearing::{JoinData, JoinEnd, StrainLimits};
pub use units::{Real, Vec3};
pub use unknown::UnknownName;
pub use world::{Settings, Substeps, World};
