//! What the GPU step runs, and the refusal of a world that asks for more.
//!
//! The GPU step is the explicit step of a world of particles, springs,
//! gas (the exact volume), wind, gravity, air drag and static colliders (plane and sphere, projection
//! or penalty), under symplectic Euler, Verlet or RK4, with a fixed
//! number of substeps. Everything else is refused before the run with the
//! feature named ([`GpuError::Unsupported`]), so a scene never runs on
//! the GPU with a force or stage quietly left out.

use sprung::forces::{AirDrag, Gravity, Wind};
use sprung::{IntegratorKind, Substeps, VolumeModel, World};

use crate::gas::MAX_GAS_BODIES;
use crate::GpuError;

/// The integrators the GPU step has.
pub const INTEGRATORS: [IntegratorKind; 3] = [
    IntegratorKind::SymplecticEuler,
    IntegratorKind::Verlet,
    IntegratorKind::Rk4,
];

/// The most colliders a world on the GPU may have (they are held in the
/// kernels' uniform block).
pub const MAX_COLLIDERS: usize = 64;

/// `Ok` if the GPU step can run `world` as the engine would, else the
/// first feature it lacks.
pub fn check(world: &World) -> Result<(), GpuError> {
    let lacks = |feature: &str| Err(GpuError::Unsupported(feature.to_string()));
    let kind = world.integrator();
    if !INTEGRATORS.contains(&kind) {
        return lacks(&format!(
            "the {kind} integrator (the GPU step has symplectic_euler, verlet and rk4)"
        ));
    }
    if world.settings.substeps == Substeps::Auto {
        return lacks("substeps = \"auto\" (give a fixed number)");
    }
    if world.particles.len() >= u32::MAX as usize / 4 {
        return lacks("more than a billion particles");
    }
    for force in world.forces.iter() {
        let any = force as &dyn std::any::Any;
        let name = force.name();
        let idle = match name {
            "springs" => true,
            "gravity" => any.is::<Gravity>(),
            "air drag" => any.is::<AirDrag>(),
            "collider contacts" => true,
            "gas pressure" => true,
            "wind" => {
                any.is::<Wind>() && world.forces.iter().filter(|f| f.name() == "wind").count() == 1
            }
            "body contacts" => !world.bodies_may_touch(),
            _ => false,
        };
        if !idle {
            return lacks(name);
        }
    }
    let gases = world.bodies.iter().filter_map(|b| b.gas.as_ref());
    if gases.clone().any(|g| g.volume_model != VolumeModel::Exact) {
        return lacks("the bounding-box and bounding-ellipsoid volume models (the GPU step has the exact volume)");
    }
    if gases.count() > MAX_GAS_BODIES {
        return lacks(&format!("more than {MAX_GAS_BODIES} bodies with gas"));
    }
    if !world.rods.is_empty() {
        return lacks("rods");
    }
    if !world.rigid.list.is_empty() {
        return lacks("rigid bodies");
    }
    if !world.muscles.list.is_empty() {
        return lacks("muscles");
    }
    if !world.joins.is_empty() {
        return lacks("joins");
    }
    if world.limits.enabled() {
        return lacks("breaking and plasticity (spring limits)");
    }
    if world.colliders.len() > MAX_COLLIDERS {
        return lacks(&format!("more than {MAX_COLLIDERS} colliders"));
    }
    if world.colliders.iter().any(|c| c.path.is_some()) {
        return lacks("moving colliders");
    }
    if world.is_guarded() {
        return lacks(
            "the no-pass-through CCD of sphere colliders and contacts (set ccd = false in [contact])",
        );
    }
    Ok(())
}
