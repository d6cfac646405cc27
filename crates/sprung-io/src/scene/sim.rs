//! The `[sim]` table: the integrator, the time step and the length of the
//! run, the world's settings and limits, and the implicit solvers' keys.

use sprung::integrate::{Preconditioner, SolverSettings};
use sprung::world::MAX_SUBSTEPS;
use sprung::{IntegratorKind, Real, Substeps, World};

use super::tables::{SimTable, SubstepsValue};
use super::{body, positive, vector, KeyError, DEFAULT_DURATION, MAX_STEPS};

/// Where a scene's steps run (`device` in `[sim]`, `--device`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Device {
    /// The engine, on the processor's threads.
    #[default]
    Cpu,
    /// The GPU step (`sprung-gpu`) in f32, for the scenes it has what they
    /// ask for (docs/gpu.md).
    Gpu,
    /// The GPU step in f64, on adapters that have it.
    GpuF64,
}

impl Device {
    /// Its name in scenes and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Device::Cpu => "cpu",
            Device::Gpu => "gpu",
            Device::GpuF64 => "gpu_f64",
        }
    }

    /// Whether the steps run on the GPU (in either precision).
    pub fn is_gpu(self) -> bool {
        self != Device::Cpu
    }
}

impl std::str::FromStr for Device {
    type Err = sprung::UnknownName;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        match name {
            "cpu" => Ok(Device::Cpu),
            "gpu" => Ok(Device::Gpu),
            "gpu_f64" => Ok(Device::GpuF64),
            _ => Err(sprung::UnknownName::new(
                "device",
                name,
                ["cpu", "gpu", "gpu_f64"],
            )),
        }
    }
}

impl std::fmt::Display for Device {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// `device` in `[sim]`: the CPU unless it names the GPU.
pub(super) fn device(sim: &SimTable) -> Result<Device, KeyError> {
    match &sim.device {
        None => Ok(Device::Cpu),
        Some(name) => name
            .parse()
            .map_err(|e: sprung::UnknownName| ("device", e.to_string())),
    }
}

/// The latest time a run may reach (s): the same bound as its energies'
/// ([`sprung::error::ENERGY_LIMIT`]).
const TIME_LIMIT: Real = sprung::error::ENERGY_LIMIT;

pub(super) fn timing(sim: &SimTable) -> Result<(IntegratorKind, Real, u64), KeyError> {
    let integrator = match &sim.integrator {
        None => IntegratorKind::SymplecticEuler,
        Some(name) => name
            .parse()
            .map_err(|e: sprung::UnknownName| ("integrator", e.to_string()))?,
    };
    let dt = positive(
        "dt",
        sim.dt,
        "the time step must be positive and finite (s)",
    )?;
    let steps = match (sim.duration, sim.steps) {
        (Some(_), Some(_)) => {
            return Err(("steps", "give `duration` or `steps`, not both".into()));
        }
        (None, Some(0)) => return Err(("steps", "`steps` must be at least 1".into())),
        (None, Some(steps)) if steps > MAX_STEPS => {
            return Err((
                "steps",
                format!("`steps` = {steps}: at most {MAX_STEPS:.0e}"),
            ));
        }
        (None, Some(steps)) => steps,
        (duration, None) => {
            let duration = positive(
                "duration",
                duration.unwrap_or(DEFAULT_DURATION),
                "the duration must be positive and finite (s)",
            )?;
            let steps = (duration / dt).round().max(1.0);
            if steps > MAX_STEPS as f64 {
                return Err((
                    "duration",
                    format!("`duration` / `dt` = {steps:.3e} steps: at most {MAX_STEPS:.0e}"),
                ));
            }
            steps as u64
        }
    };
    // Finite in, finite out: the run's clock must end finite, within the
    // bound the energies keep to.
    let end = dt * steps as Real;
    if end > TIME_LIMIT {
        return Err((
            "dt",
            format!("`dt` × steps = {end:.3e} s: the run would end past {TIME_LIMIT:.0e} s, beyond the numbers a run may write"),
        ));
    }
    if sim.every == Some(0) {
        return Err((
            "every",
            "`every` must be at least 1 (record every K steps)".into(),
        ));
    }
    Ok((integrator, dt, steps))
}

pub(super) fn apply_settings(world: &mut World, sim: &SimTable) -> Result<(), KeyError> {
    if let Some(g) = &sim.gravity {
        world.set_gravity(vector("gravity", g)?);
    }
    if let Some(c) = sim.air_drag {
        if !(c.is_finite() && c >= 0.0) {
            return Err((
                "air_drag",
                format!("`air_drag` = {c}: must be finite and not negative (N·s/m)"),
            ));
        }
        world.set_air_drag(c);
    }
    let settings = &mut world.settings;
    if let Some(substeps) = &sim.substeps {
        settings.substeps = match substeps {
            SubstepsValue::Name(name) if name == "auto" => Substeps::Auto,
            SubstepsValue::Count(n) if *n >= 1 && *n <= i64::from(MAX_SUBSTEPS) => {
                Substeps::Fixed(*n as u32)
            }
            SubstepsValue::Name(name) => {
                return Err((
                    "substeps",
                    format!(
                    "`substeps` = \"{name}\": give a number of substeps (at least 1) or \"auto\""
                ),
                ))
            }
            SubstepsValue::Count(n) => {
                return Err((
                    "substeps",
                    format!(
                        "`substeps` = {n}: give a number from 1 to {MAX_SUBSTEPS}, or \"auto\""
                    ),
                ))
            }
            SubstepsValue::Other(value) => {
                return Err((
                    "substeps",
                    format!(
                        "`substeps` = {value}: give a whole number of substeps from 1 to {MAX_SUBSTEPS} (no fraction or exponent), or \"auto\""
                    ),
                ))
            }
        };
    }
    // Limits beyond 1e100 would let the energies within them overflow the
    // diagnostics' sums; refused here rather than blamed on a body's
    // masses or springs when it is added.
    let limit = |key: &'static str, value: Real, unit: &str| {
        positive(key, value, &format!("must be positive ({unit})"))
            .and_then(|v| {
                (v <= MAX_LIMIT)
                    .then_some(v)
                    .ok_or((key, format!("`{key}` = {v:e}: must be at most 1e100 ({unit}), so that the energies within it can be summed")))
            })
    };
    if let Some(d) = sim.max_distance {
        settings.max_distance = limit("max_distance", d, "m")?;
    }
    if let Some(v) = sim.max_speed {
        settings.max_speed = limit("max_speed", v, "m/s")?;
    }
    if let Some(tolerance) = sim.constraint_tolerance {
        settings.constraints.tolerance = tolerance;
    }
    if let Some(iterations) = sim.constraint_iterations {
        settings.constraints.iterations = iterations;
    }
    settings
        .constraints
        .validate()
        .map_err(|e| (body::key_of(&e), e.to_string()))?;
    Ok(())
}

/// The implicit solvers' keys of `[sim]`: each belongs to the integrators
/// that read it, and is refused with any other.
pub(super) fn solver_settings(
    sim: &SimTable,
    integrator: IntegratorKind,
) -> Result<SolverSettings, KeyError> {
    use IntegratorKind::{ImplicitEuler, Projective, Rk45};
    let keys: [(&'static str, bool, &[IntegratorKind]); 6] = [
        (
            "solver_tolerance",
            sim.solver_tolerance.is_some(),
            &[ImplicitEuler, Projective],
        ),
        (
            "max_iterations",
            sim.max_iterations.is_some(),
            &[ImplicitEuler, Projective],
        ),
        (
            "newton_iterations",
            sim.newton_iterations.is_some(),
            &[ImplicitEuler],
        ),
        ("iterations", sim.iterations.is_some(), &[Projective]),
        (
            "preconditioner",
            sim.preconditioner.is_some(),
            &[ImplicitEuler],
        ),
        ("error_tolerance", sim.error_tolerance.is_some(), &[Rk45]),
    ];
    for (key, given, readers) in keys {
        if given && !readers.contains(&integrator) {
            let names: Vec<_> = readers.iter().map(|k| k.name()).collect();
            return Err((
                key,
                format!(
                    "`{key}` is a setting of the {} integrator, but the scene's integrator is {integrator}",
                    names.join(" and ")
                ),
            ));
        }
    }
    let defaults = SolverSettings::default();
    let settings = SolverSettings {
        tolerance: sim.solver_tolerance.unwrap_or(defaults.tolerance),
        max_iterations: sim.max_iterations.unwrap_or(defaults.max_iterations),
        newton_iterations: sim.newton_iterations.unwrap_or(defaults.newton_iterations),
        iterations: sim.iterations.unwrap_or(defaults.iterations),
        error_tolerance: sim.error_tolerance.unwrap_or(defaults.error_tolerance),
        preconditioner: match &sim.preconditioner {
            None => defaults.preconditioner,
            Some(name) => Preconditioner::from_name(name).ok_or_else(|| {
                (
                    "preconditioner",
                    format!("unknown preconditioner \"{name}\" (known: auto, jacobi, laplacian, stiffness)"),
                )
            })?,
        },
    };
    settings
        .validate()
        .map_err(|e| (body::key_of(&e), e.to_string()))?;
    Ok(settings)
}

/// The largest `max_distance` (m) or `max_speed` (m/s) a scene may set.
const MAX_LIMIT: Real = 1e100;
