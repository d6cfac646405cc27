//! `sprung check SCENE`: load and validate a scene and its meshes without
//! running it; print what it holds, the memory it would take, and its time
//! step against the stable step of the explicit integrators.

use std::path::Path;

use sprung::error::Readable;
use sprung::forces::{
    gravitating_pairs, gravitating_particles, Gravitation, Wind, MAX_GRAVITATING,
};
use sprung::world::MAX_SUBSTEPS;
use sprung::{IntegratorKind, Real, Shape, Substeps, World};
use sprung_io::{load_scene_overridden, Device, Override};

use crate::bench::memory;
use crate::error::CliError;

/// Check the scene at `path` with `overrides` applied: exit status 0 when
/// it loads, 1 (with the error) when it does not, or when `device` (else
/// the scene's own `device`) is the GPU step and the GPU step cannot run
/// it.
pub fn run(path: &Path, overrides: &[Override], device: Option<Device>) -> Result<(), CliError> {
    let loading = memory::mark();
    let before = memory::in_use();
    let mut scene = load_scene_overridden(path, overrides)?;
    let load_peak = loading.peak();
    let world = &scene.world;
    let faces: usize = world.bodies.iter().map(|b| b.faces.len()).sum();
    let segments: usize = world.bodies.iter().map(|b| b.segments.len()).sum();
    println!("{}: loads", path.display());
    println!(
        "  {} bodies, {} particles, {} springs, {} faces, {} segments, {} rods, {} muscles, {} rigid",
        world.bodies.len(),
        world.particles.len(),
        world.springs.len(),
        faces,
        segments,
        world.rods.len(),
        world.muscles.list.len(),
        world.rigid.list.len(),
    );
    let pairs = world
        .contact_pairs_now(scene.dt)
        .map_err(|e| CliError::Input(e.to_string()))?;
    if pairs > 0 {
        println!(
            "  {pairs} candidate contact pairs at the start (more where bodies press together)"
        );
    }
    let file_bytes = std::fs::metadata(path).map_or(0, |m| m.len());
    println!(
        "  memory while loading: {:.1} MB at most (the file: {:.1} MB)",
        load_peak as f64 / 1e6,
        file_bytes as f64 / 1e6
    );
    println!(
        "  {} steps of dt = {} s with {} ({} s)",
        scene.steps,
        Readable(scene.dt),
        world.integrator(),
        Readable(scene.steps as f64 * scene.dt)
    );
    if world.forces.get::<Gravitation>().is_some() {
        let members = gravitating_particles(&world.bodies) as f64;
        println!(
            "  gravitation: {members} particles, {} pairs summed every step (at most {MAX_GRAVITATING} particles)",
            Readable(gravitating_pairs(members as usize))
        );
    }
    // With the contacts the bodies start in.
    let stable = world.stable_time_step_now();
    if stable.is_finite() {
        println!("  stable step of the explicit integrators: about {stable:.3e} s");
        let substeps = world.settings.substeps;
        let kind = world.integrator();
        // The implicit solvers and rk45 (which picks its own steps, and
        // is never split) are not limited by the estimate.
        let explicit = !kind.is_implicit() && kind != IntegratorKind::Rk45;
        if explicit && substeps == Substeps::Auto && scene.dt > stable {
            // The step splits itself, as `World::step` does (0.9 of the
            // estimate): say how, rather than warn.
            println!(
                "  substeps = \"auto\": about {} substeps a step at the start",
                (scene.dt / (0.9 * stable))
                    .ceil()
                    .min(Real::from(MAX_SUBSTEPS))
            );
        } else if let (true, Substeps::Fixed(n)) = (explicit, substeps) {
            let substep = scene.dt / Real::from(n);
            if substep > stable {
                let what = if n > 1 {
                    format!("a substep of dt / {n} = {} s", Readable(substep))
                } else {
                    format!("dt = {} s", Readable(scene.dt))
                };
                // The estimate is a bound (Gershgorin's), below the real
                // limit: say by how much the step passes it.
                eprintln!(
                    "warning: {what} is {:.2} times the stable estimate {stable:.3e} s, a conservative bound (`sprung study` measures the real limit): {} may blow up (lower dt, use substeps = \"auto\", or an implicit integrator)",
                    substep / stable,
                    world.integrator()
                );
            }
        }
    } else {
        println!("  stable step of the explicit integrators: unlimited (nothing stiff)");
    }
    let gpu = sprung_gpu::support::check(world);
    match &gpu {
        Ok(()) => println!("  the GPU step (--device gpu) can run it"),
        Err(sprung_gpu::GpuError::Unsupported(feature)) => {
            println!("  the GPU step (--device gpu) lacks {feature}");
        }
        Err(other) => println!("  the GPU step (--device gpu): {other}"),
    }
    // A scene `run` would refuse for its device is refused here too, in
    // the same words.
    let device = device.unwrap_or(scene.device);
    if let (true, Err(error)) = (device.is_gpu(), &gpu) {
        return Err(crate::on_gpu::failed(error));
    }
    for warning in scene.warnings.iter().chain(&start_warnings(world)) {
        eprintln!("warning: {warning}");
    }
    // Measured, not estimated: the heap of the world as loaded, then the
    // peak over its first steps (the schedules, the integrator's and the
    // contacts' buffers are made there), and the loading's own peak, which
    // a run's process keeps (freed memory is not handed back).
    let resident = memory::in_use().saturating_sub(before);
    let stepping = memory::mark();
    for _ in 0..STEPS_MEASURED {
        if scene.world.step(scene.dt).is_err() {
            break;
        }
    }
    let running = resident + stepping.peak();
    println!(
        "  memory while running: about {:.1} MB (the world {:.1} MB, its first steps {:.1} MB more; at least the loading's {:.1} MB; frames add their own buffers)",
        running.max(load_peak) as f64 / 1e6,
        resident as f64 / 1e6,
        stepping.peak() as f64 / 1e6,
        load_peak as f64 / 1e6,
    );
    let ccd = scene.world.ccd_memory_most();
    if ccd > 0 {
        println!(
            "  the CCD's pairs may add up to {:.1} MB where bodies press together at speed (it keeps {} per element that collides, {} at least, no more than the pairs there are; not counted: the collisions of a step and the penalty contacts' pairs)",
            ccd as f64 / 1e6,
            sprung::contact::ccd::KEPT_PAIRS_PER_ELEMENT,
            sprung::contact::ccd::MIN_KEPT_PAIRS,
        );
    }
    Ok(())
}

/// Steps `check` takes to measure a run's memory: the first builds the
/// schedules and buffers, the second uses them.
const STEPS_MEASURED: usize = 2;

/// What a user should know before running `world` that is not an error:
/// bodies that start inside a collider, bodies the wind cannot touch,
/// `substeps = "auto"` with an integrator it does not split.
pub fn start_warnings(world: &World) -> Vec<String> {
    let mut warnings = inside_colliders(world);
    warnings.extend(overlapping(world));
    warnings.extend(windless(world));
    let kind = world.integrator();
    if world.settings.substeps == Substeps::Auto
        && (kind.is_implicit() || kind == IntegratorKind::Rk45)
    {
        warnings.push(format!(
            "substeps = \"auto\" does nothing with {kind}: it splits the steps of the explicit fixed-step integrators ({}), where the stable step asks",
            if kind == IntegratorKind::Rk45 {
                "rk45 picks its own steps"
            } else {
                "the implicit solvers are stable at any step"
            }
        ));
    }
    warnings
}

/// One warning for each pair of bodies that start pressed into each other
/// ([`World::overlapping_bodies`]), at most [`MOST_OVERLAP_WARNINGS`],
/// and one counting the particles of the others.
fn overlapping(world: &World) -> Vec<String> {
    let (pairs, others) = world.overlapping_bodies(MOST_OVERLAP_WARNINGS);
    let thickness = world.contacts.settings.thickness;
    let named = |b: usize| format!("\"{}\"", world.bodies[b].name);
    let mut warnings: Vec<String> = pairs
        .iter()
        .map(|&(a, b, touches)| {
            let which = match a == b {
                true => format!("body {} starts pressed into itself", named(a)),
                false => format!(
                    "bodies {} and {} start pressed into each other",
                    named(a),
                    named(b)
                ),
            };
            format!(
                "{which} ({touches} particles nearer than half the contact thickness {} m to a surface, or inside it): their contact pushes them apart at once, and the CCD that keeps every particle from passing through a surface sees them collide at every step until they part, at many times its usual cost (start them apart by the thickness)",
                Readable(thickness)
            )
        })
        .collect();
    if others > 0 {
        warnings.push(format!(
            "{others} more particles start pressed into other bodies than those of the pairs above"
        ));
    }
    warnings
}

/// The most pairs of overlapping bodies warned about one by one.
const MOST_OVERLAP_WARNINGS: usize = 8;

/// One warning naming the bodies that `[wind]` blows on (a `wind_scale`
/// above zero) but cannot push: wind acts on faces and 2D loops, and a
/// rope, a lattice or a cloud of particles has neither.
fn windless(world: &World) -> Option<String> {
    let wind = world.forces.get::<Wind>()?;
    let names: Vec<String> = world
        .bodies
        .iter()
        .enumerate()
        .filter(|(b, body)| {
            let scale = wind.body_scale.get(*b).copied().unwrap_or(1.0);
            scale > 0.0 && body.faces.is_empty() && body.segments.is_empty()
        })
        .map(|(_, body)| format!("\"{}\"", body.name))
        .collect();
    (!names.is_empty()).then(|| {
        format!(
            "[wind] does not act on {}: wind pushes on faces (3D surfaces) and segments (2D loops), and {} none (give a body faces to catch the wind, or `air_drag` for still air)",
            names.join(", "),
            if names.len() == 1 { "it has" } else { "they have" }
        )
    })
}

/// One warning for each body and collider where free particles of the
/// body are inside the collider now (at the world's time): the first steps
/// push them out onto its surface, and what joins them to the particles
/// outside is stretched by as much (a cloth laid through a sphere gains
/// tens of joules). Pinned particles are not moved and not counted.
fn inside_colliders(world: &World) -> Vec<String> {
    let particles = &world.particles;
    let mut warnings = Vec::new();
    for (k, collider) in world.colliders.iter().enumerate() {
        let shape = collider.shape_at(world.time());
        let what = match shape {
            Shape::Plane { .. } => "below the plane",
            Shape::Sphere { .. } => "inside the sphere",
        };
        for body in &world.bodies {
            let (mut inside, mut deepest) = (0, 0.0 as Real);
            for i in body.particles.clone() {
                let depth = -shape.distance_and_normal(particles.position[i]).0;
                if particles.inverse_mass[i] > 0.0 && depth > 0.0 {
                    inside += 1;
                    deepest = deepest.max(depth);
                }
            }
            if inside > 0 {
                warnings.push(format!(
                    "{inside} particles of body \"{}\" start {what} of collider {} (the scene's [[collider]] tables counted from 1), up to {deepest:.3e} m deep: the first steps push them out onto its surface, stretching the springs that join them to the rest (start the body clear of the collider)",
                    body.name,
                    k + 1,
                ));
            }
        }
    }
    warnings
}
