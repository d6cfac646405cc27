//! Scene files: TOML read with serde into a ready-to-step [`World`].
//!
//! A scene has `[sim]` (time step `dt`, `integrator`, `gravity`,
//! `duration` or `steps`, `air_drag`, `every`, the solvers' and the
//! constraints' tolerances), any number of `[[body]]` tables (see the
//! README for the keys), `[[collider]]` tables, and optional `[wind]`,
//! `[contact]`, `[gravitation]` and `[camera]` tables. Every
//! unknown key is an error naming it; every error names the file and the
//! line. Nothing is half-built: a scene either loads whole or not at all.
//!
//! Here the scene is built, table by table. Reading the text (a
//! `[[body]]` section at a time, as `sections` finds them; errors placed
//! at their line) is in `read`, the `[sim]` table in `sim`, the bodies in
//! `body` (their long arrays in `bulk`), the colliders, contact and
//! gravitation in `interactions`, and the wind in `wind`. Overrides of
//! the scene's keys (`--set KEY=VALUE`) are read and applied in `overrides`.

mod body;
mod bulk;
mod error;
mod interactions;
mod overrides;
mod read;
mod sections;
mod sim;
mod tables;
mod wind;

pub use error::SceneError;
pub use overrides::{
    apply_overrides, check_text_depth, check_value_depth, load_scene_overridden, overridden_table,
    parse_scene_overridden, scene_toml, Override, OverrideError, MAX_KEY_BYTES, MAX_KEY_PARTS,
    MAX_VALUE_DEPTH,
};
pub use sim::Device;

use std::path::{Path, PathBuf};

use sprung::build;
use sprung::forces::{gravitating_pairs, gravitating_particles, MAX_GRAVITATING};
use sprung::{BuildError, JoinData, JoinEnd, Real, Vec3, World};

use error::{line_of, line_of_entry, line_of_key};
use interactions::{collider, contact, gravitation};
use read::{body_section, parse_toml};
use sections::{Lines, Sections};
use sim::{apply_settings, solver_settings, timing};
use sprung::error::Readable;
use tables::{BodyTable, SceneFile};
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
    /// Where the steps run (`device` in `[sim]`).
    pub device: Device,
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

/// Diagnostics rows per simulated second when neither the scene's
/// `every` nor the caller says how often to record.
pub const DEFAULT_RECORD_RATE: Real = 50.0;

impl Scene {
    /// The steps of `dt` in `time` (s), rounded, at least 1; `None` when
    /// `time` is not a positive finite time or takes more than
    /// [`MAX_STEPS`].
    ///
    /// ```
    /// # let text = "[[body]]\nname = \"a\"\nparticles = [[0, 0, 0]]\n[sim]\ndt = 1e-3\n";
    /// # let scene = sprung_io::parse_scene(text, "a.toml".as_ref()).unwrap();
    /// assert_eq!(scene.steps_in(0.25), Some(250));
    /// assert_eq!(scene.steps_in(-1.0), None);
    /// ```
    pub fn steps_in(&self, time: Real) -> Option<u64> {
        let steps = (time / self.dt).round();
        (time.is_finite() && time > 0.0 && steps <= MAX_STEPS as Real)
            .then(|| (steps as u64).max(1))
    }

    /// Steps between diagnostics rows: `every` when given, else the
    /// scene's `every`, else [`DEFAULT_RECORD_RATE`] rows per simulated
    /// second (at least every step).
    pub fn record_every(&self, every: Option<u64>) -> u64 {
        every
            .or(self.every)
            .unwrap_or_else(|| ((1.0 / DEFAULT_RECORD_RATE / self.dt).round() as u64).max(1))
    }
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
///
/// ```
/// let path = std::env::temp_dir().join(format!("sprung-doc-scene-{}.toml", std::process::id()));
/// let text = r#"
/// [sim]
/// dt = 2e-3
/// steps = 50
///
/// [[body]]
/// name = "rope"
/// rope = { particles = 8, length = 1.0 }
/// stiffness = 100.0
/// "#;
/// std::fs::write(&path, text).unwrap();
/// let mut scene = sprung_io::load_scene(&path).unwrap();
/// assert_eq!((scene.dt, scene.steps, scene.world.particles.len()), (2e-3, 50, 8));
/// for _ in 0..scene.steps {
///     scene.world.step(scene.dt).unwrap();
/// }
/// assert!(scene.world.particles.position[7].y < -1.0); // stretched under gravity
///
/// // A missing file is an error naming it.
/// std::fs::remove_file(&path).unwrap();
/// let error = sprung_io::load_scene(&path).unwrap_err();
/// assert!(error.to_string().contains("cannot read the scene file"), "{error}");
/// ```
pub fn load_scene(path: &Path) -> Result<Scene, SceneError> {
    let text = crate::input::read_scene_file(path)?;
    parse_scene(&text, path)
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
///
/// A cloth hanging from two corners, from a string:
///
/// ```
/// use std::path::Path;
///
/// let text = r#"
/// [sim]
/// dt = 1e-3
/// duration = 0.5
/// integrator = "verlet"
///
/// [[body]]
/// name = "cloth"
/// cloth = { nx = 5, ny = 4, width = 1.0, height = 0.75 }
/// total_mass = 0.2
/// stiffness = 300.0
/// pinned = [15, 19]
/// "#;
/// let mut scene = sprung_io::parse_scene(text, Path::new("cloth.toml")).unwrap();
/// assert_eq!(scene.dt, 1e-3);
/// assert_eq!(scene.steps, 500);
/// assert_eq!(scene.world.particles.len(), 20);
/// assert_eq!(scene.world.body("cloth").unwrap().particles, 0..20);
/// assert_eq!(scene.world.integrator(), sprung::IntegratorKind::Verlet);
/// for _ in 0..scene.steps {
///     scene.world.step(scene.dt).unwrap();
/// }
/// // The pinned corners held; the free ones fell.
/// assert_eq!(scene.world.particles.position[15].y, 0.75);
/// assert!(scene.world.particles.position[0].y < 0.0);
/// ```
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene, SceneError> {
    parse_scene_with(text, path, &Disk)
}

/// Refuse scene `text` (named `path` in errors) that is longer than a
/// scene file may be ([`crate::input::check_scene_text`]), or whose arrays
/// and tables nest deeper than [`MAX_VALUE_DEPTH`] (at its line): before
/// any TOML reader, which recurses, sees it. Every reading of scene text
/// passes here, with overrides or without.
pub(crate) fn check_text(text: &str, path: &Path) -> Result<(), SceneError> {
    crate::input::check_scene_text(text, path)?;
    match overrides::too_deep_at(text) {
        None => Ok(()),
        Some(at) => {
            let message = format!(
                "arrays or tables nest more than {MAX_VALUE_DEPTH} deep here, the most a value may"
            );
            Err(SceneError::new(path, Some(line_of(text, at)), message))
        }
    }
}

/// [`parse_scene`] with the files it refers to read from `files`.
pub fn parse_scene_with(
    text: &str,
    path: &Path,
    files: &dyn FileSource,
) -> Result<Scene, SceneError> {
    check_text(text, path)?;
    // Parsed one body at a time (see `sections`): the rest first, then
    // each `[[body]]` section, built into the world and dropped.
    let sections = Sections::find(text);
    let file: SceneFile = parse_toml(&sections.without_bodies(text), 0, text, path)?;
    let sim_span = file.sim.span();
    // The lines before a table are counted once, on from the last table
    // placed: the bodies' warnings come in the file's order, and counting
    // from the top for each was quadratic in the bodies.
    let lines = Lines::new(text);
    let at = |span: std::ops::Range<usize>, key: &str, message: String| {
        let keys = body::aliases(key);
        let (base, before) = lines.line_start(span.start);
        let (part, start) = (&text[base..], span.start.min(text.len()) - base);
        let line = before
            + line_of_entry(part, start, &keys, &message)
                .or_else(|| line_of_key(part, start, &keys))
                .unwrap_or_else(|| line_of(part, start));
        SceneError::new(path, Some(line), message).with_key(key)
    };
    let sim = file.sim.get_ref();
    let (integrator, dt, steps) = timing(sim).map_err(|(key, m)| at(sim_span.clone(), key, m))?;
    let device = sim::device(sim).map_err(|(key, m)| at(sim_span.clone(), key, m))?;
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
        let data = body::body_data(body, scene_dir, files).map_err(|(key, m)| {
            let error = at(span.clone(), key, format!("body \"{}\": {m}", body.name));
            match key {
                "mesh" => error.with_mesh(body::mesh_error(body, scene_dir, files)),
                _ => error,
            }
        })?;
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
        collider
            .validate_within(world.settings.max_distance)
            .map_err(|e| {
                let key = match &e {
                    BuildError::EnergyOverflow { .. } => "penalty_stiffness",
                    BuildError::BeyondLimit { index, .. } if *index > 0 => "path",
                    _ if table.get_ref().plane.is_some() => "plane",
                    _ => "sphere",
                };
                at(span.clone(), key, format!("collider: {e}"))
            })?;
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
    for (index, table) in file.join.iter().enumerate() {
        let span = table.span();
        let join = table.get_ref();
        let data = JoinData {
            a: JoinEnd::new(&join.a.0, join.a.1),
            b: JoinEnd::new(&join.b.0, join.b.1),
            stiffness: join.stiffness.unwrap_or(0.0),
            damping: join.damping.unwrap_or(0.0),
            rest_length: join.rest_length,
            rod: join.rod.unwrap_or(false),
            break_strain: join.break_strain,
        };
        if !data.rod && join.stiffness.is_none() {
            let message =
                format!("join {index}: a spring join needs `stiffness` (N/m), or `rod = true`");
            return Err(at(span, "a", message));
        }
        world.add_join(data).map_err(|e| {
            let key = match &e {
                BuildError::OutOfRange { field, .. }
                | BuildError::EnergyOverflow { field, .. }
                | BuildError::BeyondLimit { field, .. } => field,
                BuildError::BadJoin(m) if m.starts_with("`break_strain`") => "break_strain",
                BuildError::BadJoin(m) if m.starts_with("its ends") => "rest_length",
                _ => body::key_of(&e),
            };
            at(span.clone(), key, format!("join {index}: {e}"))
        })?;
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
        device,
        steps,
        every: sim.every,
        path: path.to_path_buf(),
        warnings,
    })
}

/// A problem with one key: the key and the message.
pub(crate) type KeyError = (&'static str, String);

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
