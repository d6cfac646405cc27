//! The stiff cloth of the implicit solvers (docs/physics.md §6): particles of
//! 2 g joined by springs of 2·10⁴ N/m, hanging from two corners of its top
//! edge and swinging down from flat, stepped at the frame rate dt = 1/60 s
//! by `implicit_euler` and `projective`, against symplectic Euler (the
//! explicit integrator that costs least per simulated second) at its
//! stable step.

use sprung::build::{self, ClothSprings};
use sprung::integrate::Preconditioner;
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

use crate::error::CliError;

/// The frame step the implicit solvers take (s).
pub const FRAME: Real = 1.0 / 60.0;

/// The stiff cloth of `size × size` particles (1 m square) for `kind`:
/// particles of 2 g, damping 0.01 N·s/m.
pub fn stiff_cloth(size: usize, kind: IntegratorKind) -> Result<World, CliError> {
    hung(size, kind, Preconditioner::Auto, |cloth| {
        cloth.with_mass(0.002).with_damping(0.01)
    })
}

/// Issue 35's light stiff cloth of `size × size` particles (1 m square,
/// 0.2 kg in all, damped 0.5 N·s/m): the cloth its goals, and MuJoCo's
/// figures, are measured on. `preconditioner` is `implicit_euler`'s.
pub fn light_cloth(
    size: usize,
    kind: IntegratorKind,
    preconditioner: Preconditioner,
) -> Result<World, CliError> {
    hung(size, kind, preconditioner, |cloth| {
        cloth.with_total_mass(0.2).with_damping(0.5)
    })
}

/// Issue 51's light cloth hung in its plane (not laid flat first) from the
/// two corners of its top edge: it stretches under its weight and settles
/// within a second. `kind` at its defaults.
pub fn hung_in_plane(size: usize, kind: IntegratorKind) -> Result<World, CliError> {
    let cloth = build::cloth(size, size, 1.0, 1.0, ClothSprings::default())
        .map_err(|e| CliError::Input(format!("hung cloth {size}: {e}")))?
        .with_stiffness(2e4)
        .with_total_mass(0.2)
        .with_damping(0.5)
        .with_pinned(vec![size * (size - 1), size * size - 1]);
    let mut world = World::new(kind);
    world
        .add_body("cloth", cloth)
        .map_err(|e| CliError::Input(e.to_string()))?;
    Ok(world)
}

/// A cloth of `size × size` particles (1 m square, springs of 2·10⁴ N/m,
/// its masses and damping set by `set`) hung from the two corners of its
/// top edge, swinging down from flat, alone in a world of `kind`.
fn hung(
    size: usize,
    kind: IntegratorKind,
    preconditioner: Preconditioner,
    set: impl FnOnce(BodyData) -> BodyData,
) -> Result<World, CliError> {
    let cloth = build::cloth(size, size, 1.0, 1.0, ClothSprings::default())
        .map_err(|e| CliError::Input(format!("hung cloth {size}: {e}")))?
        .with_stiffness(2e4)
        .with_pinned(vec![size * (size - 1), size * size - 1])
        .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
    let mut world = World::new(kind);
    world.settings.solver.preconditioner = preconditioner;
    world
        .add_body("cloth", set(cloth))
        .map_err(|e| CliError::Input(e.to_string()))?;
    Ok(world)
}
