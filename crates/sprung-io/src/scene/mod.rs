//! Scene files: TOML read with serde into a ready-to-step [`World`].
//!
//! A scene has `[sim]` (time step `dt`, `integrator`, `gravity`,
//! `duration` or `steps`, `air_drag`, `every`, the solvers' and the
//! constraints' tolerances), any number of `[[body]]` tables (see the
//! README for the keys), `[[collider]]` tables, and optional `[wind]`,
//! `[contact]`, `[gravitation]` and `[camera]` tables. Every
//! unknown key is an error naming it; every error names the file and the
//! line. Nothing is half-built: a scene either loads whole or not at all.

mod body;
mod bulk;
mod error;
mod sections;
mod tables;
mod wind;

pub use error::SceneError;

use std::path::{Path, PathBuf};

use sprung::build;
use sprung::forces::{
    gravitating_pairs, gravitating_particles, Gravitation, GRAVITATIONAL_CONSTANT, MAX_GRAVITATING,
};
use sprung::integrate::{Preconditioner, SolverSettings};
use sprung::world::MAX_SUBSTEPS;
use sprung::{
    collide, Collider, ContactResponse, ContactSettings, IntegratorKind, Real, Shape, Substeps,
    Vec3, World,
};

use bulk::BulkArrays;
use error::{key_before, line_of, line_of_entry, line_of_key};
use sections::Sections;
use sprung::error::Readable;
use tables::{BodySection, BodyTable, ColliderTable, SceneFile, SimTable, SubstepsValue};
use toml::Spanned;

/// Most steps a scene may ask for (a run of 10¹² steps would take days).
pub const MAX_STEPS: u64 = 1_000_000_000_000;

/// Simulated time when `[sim]` gives neither `duration` nor `steps` (s).
pub const DEFAULT_DURATION: Real = 5.0;

/// A loaded scene: the world and how to run it.
#[derive(Debug)]
pub struct Scene {
    /// The world, built and checked.
    pub world: World,
    /// Time step (s).
    pub dt: Real,
    /// Number of steps to run.
    pub steps: u64,
    /// Record every K steps, if the scene says.
    pub every: Option<u64>,
    /// The file it came from (relative paths inside it are relative to its folder).
    pub path: PathBuf,
    /// Where pictures are taken from, if the scene says (`[camera]`).
    pub camera: SceneCamera,
    /// What the scene asks that is not an error but will not do what it
    /// seems to, each as `file:line: message` (a velocity given to pinned
    /// particles, a particle pinned twice).
    pub warnings: Vec<String>,
}

/// The `[camera]` table: each part `None` where the scene leaves it to the
/// picture maker (framing the bodies automatically).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SceneCamera {
    /// Where the camera stands (m).
    pub eye: Option<Vec3>,
    /// The point looked at (m).
    pub target: Option<Vec3>,
    /// Vertical field of view (degrees, in (0, 180)).
    pub fov: Option<Real>,
}

/// Read and build the scene file at `path`.
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let bytes = crate::input::read_input(path, crate::input::DEFAULT_MAX_SCENE_BYTES)
        .map_err(|e| SceneError::new(path, None, format!("cannot read the scene file: {e}")))?;
    let text = scene_text(&bytes, path)?;
    parse_scene(text, path)
}

/// The scene file's bytes as text; not UTF-8 is refused with the line
/// and the byte (in that line) of the first bad byte.
pub fn scene_text<'a>(bytes: &'a [u8], path: &Path) -> Result<&'a str, SceneError> {
    std::str::from_utf8(bytes).map_err(|e| {
        let good = &bytes[..e.valid_up_to()];
        let line = good.iter().filter(|&&b| b == b'\n').count() + 1;
        let column = good.len() - good.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1) + 1;
        SceneError::new(
            path,
            None,
            format!(
                "line {line}, byte {column}: the scene file is not UTF-8 text (byte 0x{:02x})",
                bytes[e.valid_up_to()]
            ),
        )
    })
}

/// Where the files a scene refers to (meshes) are read from: the disk, or,
/// where there is none (a web page), files bundled into the program.
pub trait FileSource {
    /// The contents of the file at `path`.
    fn read(&self, path: &Path) -> std::io::Result<Vec<u8>>;
}

/// Files read from the disk.
#[derive(Debug, Clone, Copy, Default)]
pub struct Disk;

impl FileSource for Disk {
    fn read(&self, path: &Path) -> std::io::Result<Vec<u8>> {
        crate::input::read_input(path, crate::input::DEFAULT_MAX_INPUT_BYTES)
    }
}

/// Build a scene from its TOML `text`; `path` names it in errors and anchors
/// relative paths; mesh files come from the disk.
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene, SceneError> {
    parse_scene_with(text, path, &Disk)
}

/// [`parse_scene`] with the files it refers to read from `files`.
pub fn parse_scene_with(
    text: &str,
    path: &Path,
    files: &dyn FileSource,
) -> Result<Scene, SceneError> {
    // Parsed one body at a time (see `sections`): the rest first, then
    // each `[[body]]` section, built into the world and dropped.
    let sections = Sections::find(text);
    let file: SceneFile = parse_toml(&sections.without_bodies(text), 0, text, path)?;
    let sim_span = file.sim.span();
    let at = |span: std::ops::Range<usize>, key: &str, message: String| {
        let keys = body::aliases(key);
        let line = line_of_entry(text, span.start, &keys, &message)
            .or_else(|| line_of_key(text, span.start, &keys))
            .unwrap_or_else(|| line_of(text, span.start));
        SceneError::new(path, Some(line), message)
    };
    let sim = file.sim.get_ref();
    let (integrator, dt, steps) = timing(sim).map_err(|(key, m)| at(sim_span.clone(), key, m))?;
    let mut world = World::new(integrator);
    apply_settings(&mut world, sim).map_err(|(key, m)| at(sim_span.clone(), key, m))?;
    world.settings.solver =
        solver_settings(sim, integrator).map_err(|(key, m)| at(sim_span.clone(), key, m))?;
    let scene_dir = path.parent().unwrap_or(Path::new("."));
    if let (Some(_), Some(section)) = (&file.body, sections.bodies.first()) {
        let message = "`body` is given both as a value and as `[[body]]` tables".to_string();
        return Err(at(section.clone(), "body", message));
    }
    // What the later tables need of each body: (span, name, wind_scale,
    // gravitating).
    let mut bodies = Vec::new();
    let mut warnings = Vec::new();
    let mut add = |world: &mut World, table: Spanned<BodyTable>| -> Result<(), SceneError> {
        let span = table.span();
        let body = table.get_ref();
        let data = body::body_data(body, scene_dir, files)
            .map_err(|(key, m)| at(span.clone(), key, format!("body \"{}\": {m}", body.name)))?;
        for (key, message) in body::pinning_warnings(body, &data) {
            let message = format!("body \"{}\": {message}", body.name);
            warnings.push(at(span.clone(), key, message).to_string());
        }
        // Each builder keeps within the limits; the bodies together must
        // too, checked before the world takes a copy of this one.
        let particles = world.particles.len() + data.position.len();
        let springs = world.springs.len() + data.springs.len();
        if let Some((what, count, limit)) = build::over_limit(particles, springs) {
            let message = format!(
                "body \"{}\": the bodies up to this one hold {count} {what}, more than the {limit} a scene may hold",
                body.name
            );
            return Err(at(span.clone(), "name", message));
        }
        world.add_body(&body.name, data).map_err(|e| {
            let key = body::key_in(&e, body);
            let placed = if matches!(key, "translate" | "scale") {
                " (where `scale`, `rotate` and `translate` put it)"
            } else {
                ""
            };
            at(
                span.clone(),
                key,
                format!("body \"{}\": {e}{placed}", body.name),
            )
        })?;
        let body = table.into_inner();
        bodies.push((span, body.name, body.wind_scale, body.gravitating));
        Ok(())
    };
    for table in file.body.unwrap_or_default() {
        add(&mut world, table)?;
    }
    for section in &sections.bodies {
        for table in body_section(text, section.clone(), path)? {
            add(&mut world, table)?;
        }
    }
    for table in &file.collider {
        let span = table.span();
        let collider = collider(table.get_ref())
            .map_err(|(key, m)| at(span.clone(), key, format!("collider: {m}")))?;
        world.colliders.push(collider);
    }
    if let Some(table) = &file.wind {
        let span = table.span();
        let mut wind = wind::wind(table.get_ref())
            .map_err(|(key, m)| at(span.clone(), key, format!("wind: {m}")))?;
        for (index, (span, name, scale, _)) in bodies.iter().enumerate() {
            if let Some(scale) = *scale {
                wind.set_body_scale(index, scale)
                    .map_err(|e| at(span.clone(), "wind_scale", format!("body \"{name}\": {e}")))?;
            }
        }
        world.forces.set(wind);
    } else if let Some((span, name, ..)) = bodies.iter().find(|b| b.2.is_some()) {
        let message = format!("body \"{name}\": `wind_scale` needs a `[wind]` table");
        return Err(at(span.clone(), "wind_scale", message));
    }
    if let Some(table) = &file.gravitation {
        let gravitation = gravitation(table.get_ref())
            .map_err(|(key, m)| at(table.span(), key, format!("gravitation: {m}")))?;
        let members = gravitating_particles(&world.bodies);
        if members > MAX_GRAVITATING {
            let message = format!(
                "gravitation between {members} particles is a direct sum over {:.1e} pairs every step, beyond the {MAX_GRAVITATING} particles sprung takes (2e8 pairs, about a second a step): leave bodies out with `gravitating = false`",
                gravitating_pairs(members)
            );
            return Err(at(table.span(), "gravitation", message));
        }
        world.forces.set(gravitation);
    } else if let Some((span, name, ..)) = bodies.iter().find(|b| b.3.is_some()) {
        let message = format!("body \"{name}\": `gravitating` needs a `[gravitation]` table");
        return Err(at(span.clone(), "gravitating", message));
    }
    if let Some(table) = &file.contact {
        world.contacts.settings = contact(table.get_ref(), &world.settings)
            .map_err(|(key, m)| at(table.span(), key, format!("contact: {m}")))?;
    }
    let camera = match &file.camera {
        None => SceneCamera::default(),
        Some(table) => camera(table.get_ref())
            .map_err(|(key, m)| at(table.span(), key, format!("camera: {m}")))?,
    };
    Ok(Scene {
        camera,
        world,
        dt,
        steps,
        every: sim.every,
        path: path.to_path_buf(),
        warnings,
    })
}

/// The body table of the `[[body]]` section `section` of `text`, its long
/// arrays read in bulk, its span in the whole text.
fn body_section(
    text: &str,
    section: std::ops::Range<usize>,
    path: &Path,
) -> Result<Vec<Spanned<BodyTable>>, SceneError> {
    let part = &text[section.clone()];
    let (bulk, blanked) = BulkArrays::read(part);
    let chunk: BodySection = parse_toml(
        blanked.as_deref().unwrap_or(part),
        section.start,
        text,
        path,
    )?;
    // One `[[body]]` header per section: one table.
    let mut bulk = Some(bulk);
    Ok(chunk
        .body
        .into_iter()
        .map(|table| {
            let span = table.span();
            let mut body = table.into_inner();
            if let Some(bulk) = bulk.take() {
                bulk.fill(&mut body);
            }
            Spanned::new(section.start + span.start..section.start + span.end, body)
        })
        .collect())
}

/// Parse `part` of a scene's `text` (which starts at byte `offset` of it)
/// into `T`, its error placed at its line of the whole text.
fn parse_toml<T: serde::de::DeserializeOwned>(
    part: &str,
    offset: usize,
    text: &str,
    path: &Path,
) -> Result<T, SceneError> {
    toml::from_str(part).map_err(|e| {
        let start = e.span().map(|s| offset + s.start);
        let line = start.map(|s| line_of(text, s));
        let message = e.message().trim();
        // A table header: `[[contact]]` for the one `[contact]` table, or
        // a table given twice.
        let header = start
            .and_then(|s| text.get(..s.min(text.len())))
            .map(|before| {
                let from = before.rfind('\n').map_or(0, |i| i + 1);
                let end = text[from..].find('\n').map_or(text.len(), |i| from + i);
                text[from..end].trim()
            })
            .filter(|line| line.starts_with('['));
        let name = header.map(|h| {
            h.trim_start_matches('[')
                .split(']')
                .next()
                .unwrap_or("")
                .trim()
        });
        let message = match (header, name) {
            (Some(h), Some(name)) if h.starts_with("[[") && message.starts_with("invalid type") => {
                format!(
                    "`[[{name}]]`: `{name}` is one table, written `[{name}]`, not a list of them"
                )
            }
            (Some(_), Some(name)) if message.starts_with("duplicate key") => {
                format!("`[{name}]` is given twice: write its keys in one table")
            }
            _ if message.starts_with("duplicate key") => {
                let key = start.and_then(|s| key_at(text, s));
                key.map_or(message.to_string(), |key| {
                    format!("`{key}` is given twice in its table")
                })
            }
            _ => match start.and_then(|s| key_before(text, s)) {
                Some(key) if !message.contains(&format!("`{key}`")) => {
                    format!("`{key}`: {message}")
                }
                _ => message.to_string(),
            },
        };
        SceneError::new(path, line, message)
    })
}

/// The key assigned on the line of byte `offset` of `text` (`dt` in
/// `dt = 1e-3`), if the line is an assignment.
fn key_at(text: &str, offset: usize) -> Option<&str> {
    let from = text
        .get(..offset.min(text.len()))?
        .rfind('\n')
        .map_or(0, |i| i + 1);
    let line = &text[from..];
    let key = line[..line.find('=')?].trim();
    (!key.is_empty() && !key.contains('\n')).then_some(key)
}

/// A problem with one key: the key and the message.
pub(crate) type KeyError = (&'static str, String);

fn timing(sim: &SimTable) -> Result<(IntegratorKind, Real, u64), KeyError> {
    let integrator = match &sim.integrator {
        None => IntegratorKind::SymplecticEuler,
        Some(name) => name.parse().map_err(|m| ("integrator", m))?,
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
    if sim.every == Some(0) {
        return Err((
            "every",
            "`every` must be at least 1 (record every K steps)".into(),
        ));
    }
    Ok((integrator, dt, steps))
}

fn apply_settings(world: &mut World, sim: &SimTable) -> Result<(), KeyError> {
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
fn solver_settings(sim: &SimTable, integrator: IntegratorKind) -> Result<SolverSettings, KeyError> {
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
                    format!("unknown preconditioner \"{name}\" (known: jacobi, laplacian)"),
                )
            })?,
        },
    };
    settings
        .validate()
        .map_err(|e| (body::key_of(&e), e.to_string()))?;
    Ok(settings)
}

fn collider(table: &ColliderTable) -> Result<Collider, KeyError> {
    let shape = match (&table.plane, &table.sphere) {
        (Some(_), Some(_)) => {
            return Err(("sphere", "a collider is a `plane` or a `sphere`, not both".into()));
        }
        (Some(plane), None) => {
            let point = vector("plane", &plane.point)?;
            let normal = vector("plane", &plane.normal)?;
            Shape::plane(point, normal).map_err(|e| ("plane", e.to_string()))?
        }
        (None, Some(sphere)) => {
            let centre = vector("sphere", &sphere.centre)?;
            Shape::sphere(centre, sphere.radius).map_err(|e| ("sphere", e.to_string()))?
        }
        (None, None) => {
            return Err((
                "plane",
                "a collider needs a shape: `plane = { point, normal }` or `sphere = { centre, radius }`".into(),
            ))
        }
    };
    let friction = table.friction.unwrap_or(0.0);
    let response = match table.penalty_stiffness {
        Some(stiffness) => {
            if table.restitution.is_some() {
                return Err((
                    "restitution",
                    "`restitution` belongs to the projection form; the penalty form (`penalty_stiffness`) bounces through its spring".into(),
                ));
            }
            ContactResponse::Penalty {
                stiffness,
                damping: table.penalty_damping.unwrap_or(0.0),
                friction,
            }
        }
        None => {
            if table.penalty_damping.is_some() {
                return Err((
                    "penalty_damping",
                    "`penalty_damping` needs `penalty_stiffness`".into(),
                ));
            }
            ContactResponse::Projection {
                restitution: table.restitution.unwrap_or(0.0),
                friction,
            }
        }
    };
    let mut collider =
        Collider::new(shape, response).map_err(|e| (body::key_of(&e), e.to_string()))?;
    if let Some(keyframes) = &table.path {
        let keyframes = keyframes
            .iter()
            .map(|k| match k.as_slice() {
                [t, rest @ ..] => Ok((*t, vector("path", rest)?)),
                [] => Err((
                    "path",
                    "a `path` keyframe is [time, x, y] or [time, x, y, z]".to_string(),
                )),
            })
            .collect::<Result<Vec<_>, _>>()?;
        let path = collide::Path::new(keyframes).map_err(|e| ("path", e.to_string()))?;
        collider = collider.with_path(path);
    }
    Ok(collider)
}

fn contact(
    table: &tables::ContactTable,
    limits: &sprung::world::Settings,
) -> Result<ContactSettings, KeyError> {
    let defaults = ContactSettings::default();
    let settings = ContactSettings {
        enabled: table.enabled.unwrap_or(defaults.enabled),
        thickness: table.thickness.unwrap_or(defaults.thickness),
        friction: table.friction.unwrap_or(defaults.friction),
        stiffness: table.stiffness,
        damping: table.damping,
    };
    settings
        .validate_within(limits.max_distance, limits.max_speed)
        .map_err(|e| {
            let key = match body::key_of(&e) {
                k if k.starts_with("contact.") => &k["contact.".len()..],
                k => k,
            };
            (key, e.to_string())
        })?;
    Ok(settings)
}

/// The `[gravitation]` force: `constant` (N·m²/kg², default
/// [`GRAVITATIONAL_CONSTANT`]) and `softening` (m, default 0).
fn gravitation(table: &tables::GravitationTable) -> Result<Gravitation, KeyError> {
    Gravitation::new(
        table.constant.unwrap_or(GRAVITATIONAL_CONSTANT),
        table.softening.unwrap_or(0.0),
    )
    .map_err(|e| {
        let key = match body::key_of(&e) {
            k if k.starts_with("gravitation.") => &k["gravitation.".len()..],
            k => k,
        };
        (key, e.to_string())
    })
}

fn camera(table: &tables::CameraTable) -> Result<SceneCamera, KeyError> {
    let eye = table.eye.as_deref().map(|v| vector("eye", v)).transpose()?;
    let target = table
        .target
        .as_deref()
        .map(|v| vector("target", v))
        .transpose()?;
    if eye.is_some() && eye == target {
        return Err((
            "target",
            "`eye` and `target` are the same point: the camera needs a direction".into(),
        ));
    }
    if let Some(fov) = table.fov {
        if !(fov.is_finite() && fov > 0.0 && fov < 180.0) {
            return Err((
                "fov",
                format!("`fov` = {fov}: must be between 0 and 180 degrees"),
            ));
        }
    }
    Ok(SceneCamera {
        eye,
        target,
        fov: table.fov,
    })
}

/// The largest `max_distance` (m) or `max_speed` (m/s) a scene may set.
const MAX_LIMIT: Real = 1e100;

/// `value` if it is positive and finite, else an error for `key`.
pub(crate) fn positive(key: &'static str, value: Real, reason: &str) -> Result<Real, KeyError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err((key, format!("`{key}` = {}: {reason}", Readable(value))))
    }
}

/// A vector from a list of 2 (z = 0) or 3 finite numbers.
pub(crate) fn vector(key: &'static str, values: &[f64]) -> Result<Vec3, KeyError> {
    let v = match values {
        [x, y] => Vec3::new(*x, *y, 0.0),
        [x, y, z] => Vec3::new(*x, *y, *z),
        _ => {
            return Err((
                key,
                format!(
                    "`{key}` has {} numbers: a vector needs 2 (x, y) or 3 (x, y, z)",
                    values.len()
                ),
            ))
        }
    };
    if !v.is_finite() {
        return Err((
            key,
            format!("`{key}` = {values:?}: every number must be finite"),
        ));
    }
    Ok(v)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The file read whole by the TOML parser, bodies and all.
    fn whole(text: &str) -> Option<String> {
        toml::from_str::<SceneFile>(text)
            .ok()
            .map(|f| format!("{f:?}"))
    }

    /// The file read as `parse_scene` reads it: the rest, then each body
    /// section with its long arrays in bulk.
    fn sectioned(text: &str) -> Option<String> {
        let sections = Sections::find(text);
        let mut file: SceneFile = toml::from_str(&sections.without_bodies(text)).ok()?;
        let path = Path::new("t.toml");
        for section in &sections.bodies {
            file.body
                .get_or_insert_with(Vec::new)
                .extend(body_section(text, section.clone(), path).ok()?);
        }
        Some(format!("{file:?}"))
    }

    /// A tiny deterministic generator for the damage.
    fn next(state: &mut u64) -> usize {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 16) as usize
    }

    /// Reading a scene a body at a time means what reading it whole means:
    /// the same tables with the same spans, or an error in both, for every
    /// demo scene, tricky forms of headers and arrays, and thousands of
    /// damaged variants of them.
    #[test]
    fn sections_read_what_the_whole_file_says() {
        let tricky = [
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0, 0, 0], [1.5, 0, 0], # é\n [0, 1e0, -0.0]]\nsprings = [[0, 1], [1, 2],]\nfaces = [[0, 1, 2]]\nmasses = [1, 2.5, 3]\npinned = [0]\n[body.gas]\nnrt = 1.0\n[[body]]\nname = \"b\"\nrope = { particles = 3, length = 1.0 }\n",
            "[[ body ]]\nname = \"a\"\nparticles = [[0, 0, 0]]\n[sim]\ndt = 1e-3\n[body.gas]\nnrt = 1.0\n",
            "[[\"body\"]]\nname = \"a\"\nparticles = [[0, 0, 0]]\nparticles = [[1, 0, 0]]\n[sim]\ndt = 1e-3\n",
            "[sim]\ndt = 1e-3\nbody = [{ name = \"a\", particles = [[0, 0, 0]] }]\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0x10, 1_0, 0]]\nsprings = [[0, +1]]\nrods = [[0, 1, 2]]\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [\n  [0, 0, 0],\n  [1, 0, 0]\n] # end\nvelocities = [[1, 2, 3], [4, 5, 6]] mass = 1\n",
            "[body]\nname = \"a\"\n[[body]]\nname = \"b\"\n[sim]\ndt = 1\n",
            "[sim]\ndt = 1e-3\nbody = []\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nparticles = [[0, 0, 0],\r[1, 0, 0]]\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nmasses = [1, # \u{7f}\n 2]\nparticles = [[0, 0, 0], [1, 0, 0]]\n",
            "[sim]\ndt = 1e-3\n[[\"bod\\u0079\"]]\nname = \"a\"\n[[body]]\nname = \"b\"\n",
            "[sim]\ndt = 1e-3\n[[body]]\nname = \"a\"\nnote = '''\n[[body]]\nname = \"fake\"\n'''\n",
        ];
        let mut texts: Vec<String> = tricky.iter().map(|t| t.to_string()).collect();
        texts.extend(crate::demos::DEMOS.iter().map(|d| d.text.to_string()));
        let mut agreed_ok = 0;
        for text in &texts {
            assert_eq!(whole(text), sectioned(text), "{text}");
            agreed_ok += usize::from(whole(text).is_some());
            let mut state = 0x9e37_79b9_7f4a_7c15_u64 ^ text.len() as u64;
            for _ in 0..500 {
                let mut damaged = text.clone().into_bytes();
                for _ in 0..=next(&mut state) % 3 {
                    let at = next(&mut state) % damaged.len().max(1);
                    let pieces: &[&[u8]] = &[
                        b"[",
                        b"]",
                        b"[[body]]\n",
                        b"[body.gas]\n",
                        b",",
                        b"\n",
                        b"#",
                        b"\"",
                        b"=",
                        b"0",
                        b"-",
                        b".",
                        b"e",
                        b"{",
                        b"}",
                        b" ",
                    ];
                    match next(&mut state) % 3 {
                        0 if at < damaged.len() => {
                            damaged.remove(at);
                        }
                        _ => {
                            let piece = pieces[next(&mut state) % pieces.len()];
                            damaged.splice(at..at, piece.iter().copied());
                        }
                    }
                }
                let Ok(damaged) = String::from_utf8(damaged) else {
                    continue;
                };
                assert_eq!(whole(&damaged), sectioned(&damaged), "{damaged}");
                agreed_ok += usize::from(whole(&damaged).is_some());
            }
        }
        // Many damaged files still parse: the comparison saw real tables.
        assert!(agreed_ok > texts.len(), "{agreed_ok}");
    }
}
