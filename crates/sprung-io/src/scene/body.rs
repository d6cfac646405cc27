//! `[[body]]` tables into [`BodyData`].
//!
//! A body comes from exactly one builder: `particles` (explicit, with
//! `springs`, `rest_lengths`, `faces`, `segments`), `rope`, `cloth`,
//! `lattice`, `ring`, `sphere` or `mesh` (a file relative to the scene, with
//! `object` to pick one object). Sphere and mesh bodies get a spring per
//! edge, `bending` springs across adjacent triangles (default on) and
//! `internal = "centre"` springs to a centre particle, or `internal =
//! "lattice"` with `lattice_spacing` (m), a 26-neighbour lattice filling the
//! inside tied to the surface (default `"none"`).
//! `refine = N` splits each triangle of a mesh in four, N times. A closed
//! body may carry `gas = { nrt, ramp_time, schedule, leak_rate,
//! leak_start, volume }`. Keys
//! every body accepts: `mass` (kg, each particle), `masses` (one per
//! particle) or `total_mass` (kg, shared), `stiffness` (N/m) and `damping`
//! (N·s/m) for all springs or one per spring, `one_sided`, `pinned`,
//! `velocity` (m/s, all particles) or `velocities`, and the placement
//! `scale`, `rotate` (degrees about x, y, z) and `translate` (m), applied
//! in that order; `rods = [[i, j], ...]` (rigid rods, with optional
//! `rod_lengths`, m, else the distance at creation), `muscles = [{ spring,
//! amplitude, period, phase }, ...]` (springs whose rest length is
//! `L0 (1 + a sin(2π t / T + φ))`), `rigid` and `gravitating`. Particle and
//! spring indices are the body's own. Defaults: 1 kg per particle,
//! [`DEFAULT_STIFFNESS`], no damping, not rigid, gravitating; a rope pins
//! its top particle unless `pinned` says otherwise.

use std::path::Path;

use sprung::build::{self, ClothSprings, Internal, SurfaceSprings};
use sprung::{
    BodyContact, BodyData, BuildError, Gas, MuscleData, MuscleDrive, RodData, SpringData,
    StrainLimits, Vec3, VolumeModel,
};

use super::tables::{BodyTable, GasTable, PerSpring};
use super::FileSource;
use super::{positive, vector, KeyError};
use crate::mesh;

/// Spring stiffness when a body gives none (N/m).
pub const DEFAULT_STIFFNESS: f64 = 100.0;

/// Most triangles a mesh body may have after `refine` (a million: about
/// half a million particles and three million springs, some 300 MB).
pub const MAX_REFINED_TRIANGLES: usize = 1_000_000;

/// Most levels of `refine` on a mesh body.
pub const MAX_REFINE: usize = 5;

/// Time over which a gas is pumped up when `ramp_time` is not given (s).
pub const DEFAULT_RAMP_TIME: f64 = 1.0;

/// Build the body a table describes (not yet checked: `World::add_body`
/// does); mesh paths are relative to `scene_dir`.
pub(crate) fn body_data(
    table: &BodyTable,
    scene_dir: &Path,
    files: &dyn FileSource,
) -> Result<BodyData, KeyError> {
    let mut data = builder(table, scene_dir, files)?;
    if let Some(gas) = &table.gas {
        data.gas = Some(gas_of(gas)?);
    }
    apply_masses(table, &mut data)?;
    apply_springs(table, &mut data)?;
    apply_constraints(table, &mut data)?;
    if let Some(pinned) = &table.pinned {
        data.pinned = pinned.clone();
    }
    data.contact = BodyContact {
        collide: table.collide.unwrap_or(true),
        self_collision: table.self_collision.unwrap_or(false),
    };
    match (&table.velocity, &table.velocities) {
        (Some(_), Some(_)) => {
            return Err((
                "velocity",
                "give `velocity` or `velocities`, not both".into(),
            ))
        }
        (Some(v), None) => data = data.with_velocity(vector("velocity", v)?),
        (None, Some(list)) => {
            same_dimension("velocities", list)?;
            data.velocity = list
                .iter()
                .map(|v| vector("velocities", v))
                .collect::<Result<_, _>>()?;
        }
        (None, None) => {}
    }
    let scale = positive(
        "scale",
        table.scale.unwrap_or(1.0),
        "the scale must be positive and finite",
    )?;
    if table.rotate.as_ref().is_some_and(|r| r.len() == 2) {
        return Err((
            "rotate",
            "`rotate` takes three angles (degrees about x, y and z); a 2D body turns in its plane about z: [0.0, 0.0, angle]".into(),
        ));
    }
    let rotate = table
        .rotate
        .as_deref()
        .map(|r| vector("rotate", r))
        .transpose()?
        .unwrap_or(Vec3::ZERO);

    let translate = table
        .translate
        .as_deref()
        .map(|t| vector("translate", t))
        .transpose()?
        .unwrap_or(Vec3::ZERO);
    // Springs whose ends the placement rounds onto one place (a
    // translation of 1e308 m swallows a spacing of 1 m): refused here, on
    // the placement's line, not as zero-length springs of the scene.
    let apart = |data: &BodyData, s: &SpringData| {
        data.position[s.first].distance(data.position[s.second]) > 0.0
    };
    let apart_before: Vec<bool> = data
        .springs
        .iter()
        .map(|s| s.first < data.position.len() && s.second < data.position.len() && apart(&data, s))
        .collect();
    let data = data.placed(scale, rotate, translate);
    if let Some(k) =
        (0..data.springs.len()).find(|&k| apart_before[k] && !apart(&data, &data.springs[k]))
    {
        let key = if table.translate.is_some() {
            "translate"
        } else {
            "scale"
        };
        return Err((
            key,
            format!(
                "`scale` = {scale}, `translate` = {:?} put the two ends of spring {k} at one place (the coordinates are too large, or the scale too small, for the spacing of the particles to survive rounding)",
                translate.to_array()
            ),
        ));
    }
    // A 2D body (bounded by segments) lies in a plane of constant z, where
    // its contacts take their sides: a turn that tilts that plane is
    // refused here (a 2D gas body is refused on its `gas` line by the
    // body's own check, which also holds it to z = 0). The turn alone
    // decides: the z axis must stay the z axis (to rounding, as a half
    // turn about x leaves it).
    let axis = BodyData::from_positions(vec![Vec3::Z])
        .placed(1.0, rotate, Vec3::ZERO)
        .position[0];
    let tilted = axis.x.abs() > 1e-9 || axis.y.abs() > 1e-9;
    if !data.segments.is_empty() && data.gas.is_none() && tilted {
        return Err((
            "rotate",
            format!(
                "`rotate` = {:?} tilts this 2D body (it has segments) out of its plane: turn it about z, [0.0, 0.0, angle] (or half a turn about x or y, which flips it over)",
                rotate.to_array()
            ),
        ));
    }
    // A spin about the placed body's centre of mass, on top of its
    // velocity.
    match table.spin.as_deref() {
        Some(spin) => Ok(data.with_spin(vector("spin", spin)?)),
        None => Ok(data),
    }
}

fn builder(
    table: &BodyTable,
    scene_dir: &Path,
    files: &dyn FileSource,
) -> Result<BodyData, KeyError> {
    let chosen: Vec<&str> = [
        ("particles", table.particles.is_some()),
        ("rope", table.rope.is_some()),
        ("cloth", table.cloth.is_some()),
        ("lattice", table.lattice.is_some()),
        ("ring", table.ring.is_some()),
        ("sphere", table.sphere.is_some()),
        ("mesh", table.mesh.is_some()),
    ]
    .into_iter()
    .filter_map(|(key, given)| given.then_some(key))
    .collect();
    match chosen.as_slice() {
        [] => return Err(("name", "the body has no particles: give `particles = [...]` or a builder (`rope`, `cloth`, `lattice`, `ring`, `sphere`, `mesh`)".into())),
        [_] => {}
        several => {
            return Err((several[1], format!("the body is given by {}: choose one", several.join(" and "))))
        }
    }
    if table.particles.is_none() {
        let explicit_only = [
            ("springs", table.springs.is_some()),
            ("rest_lengths", table.rest_lengths.is_some()),
            ("faces", table.faces.is_some()),
            ("segments", table.segments.is_some()),
        ];
        if let Some((key, _)) = explicit_only.iter().find(|(_, given)| *given) {
            return Err((
                key,
                format!(
                    "`{key}` belongs to explicit bodies (`particles = ...`), not to a `{}` body",
                    chosen[0]
                ),
            ));
        }
    }
    let surface_only = [
        ("bending", table.bending.is_some()),
        ("internal", table.internal.is_some()),
    ];
    if table.sphere.is_none() && table.mesh.is_none() {
        if let Some((key, _)) = surface_only.iter().find(|(_, given)| *given) {
            return Err((
                key,
                format!("`{key}` belongs to `sphere` and `mesh` bodies"),
            ));
        }
    }
    if table.mesh.is_none() {
        if table.object.is_some() {
            return Err(("object", "`object` picks an object of a `mesh` file".into()));
        }
        if table.refine.is_some() {
            return Err((
                "refine",
                "`refine` subdivides the triangles of a `mesh` body".into(),
            ));
        }
    }
    if let Some(ring) = &table.ring {
        return build::ring(ring.particles, ring.radius).map_err(|e| (key_of(&e), e.to_string()));
    }
    if let Some(sphere) = &table.sphere {
        let springs = surface_springs(table)?;
        return build::icosphere(sphere.radius, sphere.subdivisions, springs)
            .map_err(|e| (key_of(&e), e.to_string()));
    }
    if let Some(file) = &table.mesh {
        return mesh_body(table, &scene_dir.join(file), files);
    }
    let built = match (&table.rope, &table.cloth, &table.lattice) {
        (Some(rope), _, _) => build::rope(rope.particles, rope.length),
        (_, Some(cloth), _) => {
            let families = ClothSprings {
                structural: cloth.structural,
                shear: cloth.shear,
                bending: cloth.bending,
            };
            build::cloth(cloth.nx, cloth.ny, cloth.width, cloth.height, families)
        }
        (_, _, Some(lattice)) => {
            build::lattice(lattice.nx, lattice.ny, lattice.nz, lattice.spacing)
        }
        (None, None, None) => return explicit(table),
    };
    built.map_err(|e| (key_of(&e), e.to_string()))
}

/// The springs a sphere or mesh body asks for.
fn surface_springs(table: &BodyTable) -> Result<SurfaceSprings, KeyError> {
    let internal = match table.internal.as_deref() {
        None | Some("none") => Internal::None,
        Some("centre") | Some("center") => Internal::Centre,
        // The spacing is in the scene's metres; the body is built in the
        // mesh's own units and scaled afterwards.
        Some("lattice") => Internal::Lattice {
            spacing: table.lattice_spacing.ok_or((
                "internal",
                "`internal = \"lattice\"` needs `lattice_spacing` (m)".to_string(),
            ))? / table.scale.unwrap_or(1.0),
        },
        Some(other) => {
            return Err((
                "internal",
                format!("`internal` = \"{other}\": known internal structures are \"none\", \"centre\" and \"lattice\""),
            ))
        }
    };
    if table.lattice_spacing.is_some() && !matches!(internal, Internal::Lattice { .. }) {
        return Err((
            "lattice_spacing",
            "`lattice_spacing` goes with `internal = \"lattice\"`".into(),
        ));
    }
    Ok(SurfaceSprings {
        bending: table.bending.unwrap_or(true),
        internal,
    })
}

/// The object of the mesh file at `path` that `table` names (checked
/// closed and oriented outward for a gas body), or the mesh file's own
/// error.
fn mesh_object(
    table: &BodyTable,
    path: &Path,
    files: &dyn FileSource,
) -> Result<mesh::TriangleMesh, mesh::MeshError> {
    let format = mesh::MeshFormat::from_path(path)?;
    let bytes = files
        .read(path)
        .map_err(|e| mesh::MeshError::new(path, mesh::MeshErrorKind::Io(e.to_string())))?;
    let objects = mesh::parse_mesh(&bytes, format, path)?;
    let object = mesh::select_object(objects, table.object.as_deref(), path)?;
    if table.gas.is_some() {
        return mesh::closed_surface(&object, path);
    }
    Ok(object)
}

/// The mesh file's own error where the body `table` fails on its mesh
/// (read again: only for the error's sake), else `None`.
pub(super) fn mesh_error(
    table: &BodyTable,
    scene_dir: &Path,
    files: &dyn FileSource,
) -> Option<mesh::MeshError> {
    let file = table.mesh.as_ref()?;
    mesh_object(table, &scene_dir.join(file), files).err()
}

/// A body from one object of a mesh file. A gas body needs a closed,
/// edge-manifold, orientable surface, oriented outward here; anything else
/// is refused with the file, the object and the first offending edge. Open
/// meshes are fine as cloth.
fn mesh_body(table: &BodyTable, path: &Path, files: &dyn FileSource) -> Result<BodyData, KeyError> {
    let object = mesh_object(table, path, files).map_err(|e| ("mesh", e.to_string()))?;
    let mut position: Vec<Vec3> = object
        .positions
        .iter()
        .map(|&p| Vec3::from_array(p))
        .collect();
    let mut faces = object.triangles;
    let levels = table.refine.unwrap_or(0);
    if levels > MAX_REFINE {
        return Err(("refine", format!("`refine` = {levels}: at most {MAX_REFINE} (each level makes four times the triangles)")));
    }
    let triangles = faces.len() as f64 * 4f64.powi(levels as i32);
    if triangles > MAX_REFINED_TRIANGLES as f64 {
        return Err((
            "refine",
            format!(
                "`refine` = {levels} would make {triangles:.2e} triangles (about {:.2e} particles) of this mesh's {}: at most {MAX_REFINED_TRIANGLES:.0e} (refine less)",
                triangles / 2.0,
                faces.len()
            ),
        ));
    }
    for _ in 0..levels {
        faces = build::refine(&mut position, &faces);
    }
    build::surface(position, faces, surface_springs(table)?)
        .map_err(|e| (key_of(&e), e.to_string()))
}

/// The gas of a `gas = { ... }` table.
fn gas_of(table: &GasTable) -> Result<Gas, KeyError> {
    let mut gas = Gas::new(table.nrt, table.ramp_time.unwrap_or(DEFAULT_RAMP_TIME));
    gas.keyframes = table
        .schedule
        .iter()
        .flatten()
        .map(|&[time, nrt]| (time, nrt))
        .collect();
    gas.leak_rate = table.leak_rate.unwrap_or(0.0);
    gas.leak_start = table.leak_start.unwrap_or(0.0);
    if let Some(name) = &table.volume {
        gas.volume_model = VolumeModel::from_name(name).ok_or_else(|| {
            (
                "gas",
                format!("`gas.volume` = \"{name}\": known volume models are \"exact\", \"bounding_box\" and \"bounding_ellipsoid\""),
            )
        })?;
    }
    gas.validate().map_err(|e| ("gas", e.to_string()))?;
    Ok(gas)
}

/// Refuse a list of vectors (`key`) that mixes 2-number (x, y) and
/// 3-number (x, y, z) ones: a body is given in 2D or in 3D, and a point
/// missing its z among 3D ones is more likely a slip than a z of zero.
fn same_dimension(key: &'static str, vectors: &[Vec<f64>]) -> Result<(), KeyError> {
    let Some(first) = vectors.first() else {
        return Ok(());
    };
    match vectors.iter().position(|v| v.len() != first.len()) {
        Some(k) if matches!((first.len(), vectors[k].len()), (2, 3) | (3, 2)) => Err((
            key,
            format!(
                "`{key}` mixes 2D and 3D vectors: entry 0 has {} numbers, entry {k} has {}; \
                 give every entry as (x, y) or every one as (x, y, z)",
                first.len(),
                vectors[k].len()
            ),
        )),
        _ => Ok(()),
    }
}

fn explicit(table: &BodyTable) -> Result<BodyData, KeyError> {
    let points = table.particles.as_deref().unwrap_or_default();
    same_dimension("particles", points)?;
    let positions = points
        .iter()
        .map(|p| vector("particles", p))
        .collect::<Result<Vec<_>, _>>()?;
    let mut data = BodyData::from_positions(positions);
    let pairs = table.springs.as_deref().unwrap_or_default();
    data.springs = pairs
        .iter()
        .map(|&[a, b]| SpringData::between(a, b))
        .collect();
    if let Some(lengths) = &table.rest_lengths {
        if lengths.len() != pairs.len() {
            return Err((
                "rest_lengths",
                format!(
                    "`rest_lengths` has {} entries but the body has {} springs",
                    lengths.len(),
                    pairs.len()
                ),
            ));
        }
        for (spring, &length) in data.springs.iter_mut().zip(lengths) {
            spring.rest_length = Some(length);
        }
    }
    data.faces = table.faces.clone().unwrap_or_default();
    data.segments = table.segments.clone().unwrap_or_default();
    Ok(data)
}

fn apply_masses(table: &BodyTable, data: &mut BodyData) -> Result<(), KeyError> {
    let given = [
        table.mass.is_some(),
        table.masses.is_some(),
        table.total_mass.is_some(),
    ];
    if given.iter().filter(|&&g| g).count() > 1 {
        return Err((
            "mass",
            "give one of `mass`, `masses` and `total_mass`".into(),
        ));
    }
    if let Some(m) = table.mass {
        let m = positive("mass", m, "mass must be positive and finite (kg)")?;
        *data = std::mem::take(data).with_mass(m);
    } else if let Some(masses) = &table.masses {
        data.mass = masses.clone();
    } else if let Some(total) = table.total_mass {
        let total = positive("total_mass", total, "mass must be positive and finite (kg)")?;
        *data = std::mem::take(data).with_total_mass(total);
    }
    Ok(())
}

fn apply_springs(table: &BodyTable, data: &mut BodyData) -> Result<(), KeyError> {
    let count = data.springs.len();
    let each = |key: &'static str,
                value: &Option<PerSpring>,
                default: f64|
     -> Result<Vec<f64>, KeyError> {
        match value {
            None => Ok(vec![default; count]),
            Some(PerSpring::All(v)) => Ok(vec![*v; count]),
            Some(PerSpring::Each(list)) if list.len() == count => Ok(list.clone()),
            Some(PerSpring::Each(list)) => Err((
                key,
                format!(
                    "`{key}` has {} entries but the body has {count} springs",
                    list.len()
                ),
            )),
        }
    };
    let stiffness = each("stiffness", &table.stiffness, DEFAULT_STIFFNESS)?;
    let damping = each("damping", &table.damping, 0.0)?;
    let one_sided = table.one_sided.unwrap_or(false);
    for ((spring, k), c) in data.springs.iter_mut().zip(stiffness).zip(damping) {
        spring.stiffness = k;
        spring.damping = c;
        spring.one_sided = one_sided;
    }
    Ok(())
}

/// Rods, muscles, `rigid`, `gravitating` and the strain limits (checked
/// by `World::add_body`).
fn apply_constraints(table: &BodyTable, data: &mut BodyData) -> Result<(), KeyError> {
    let pairs = table.rods.as_deref().unwrap_or_default();
    data.rods = pairs
        .iter()
        .map(|&[first, second]| RodData {
            first,
            second,
            length: None,
        })
        .collect();
    if let Some(lengths) = &table.rod_lengths {
        if lengths.len() != pairs.len() {
            return Err((
                "rod_lengths",
                format!(
                    "`rod_lengths` has {} entries but the body has {} rods",
                    lengths.len(),
                    pairs.len()
                ),
            ));
        }
        for (rod, &length) in data.rods.iter_mut().zip(lengths) {
            rod.length = Some(length);
        }
    }
    data.muscles = table
        .muscles
        .iter()
        .flatten()
        .map(|m| MuscleData {
            spring: m.spring,
            drive: MuscleDrive::Sine {
                amplitude: m.amplitude,
                period: m.period,
                phase: m.phase.unwrap_or(0.0),
            },
        })
        .collect();
    data.rigid = table.rigid.unwrap_or(false);
    data.gravitating = table.gravitating.unwrap_or(true);
    data.limits = StrainLimits {
        break_strain: table.break_strain,
        yield_strain: table.yield_strain,
        hardening: table.hardening.unwrap_or(0.0),
    };
    Ok(())
}

/// The keys a user may have written for `key` (mass may come from three).
pub(crate) fn aliases(key: &str) -> Vec<&str> {
    match key {
        "masses" | "mass" | "total_mass" => vec![key, "masses", "mass", "total_mass"],
        "velocities" => vec![key, "velocity"],
        "rest_lengths" => vec![key, "springs"],
        "rod_lengths" => vec![key, "rods"],
        _ => vec![key],
    }
}

/// What a body's `pinned` list asks that will not happen as written, each
/// with the key to point at: particles listed more than once (pinned
/// once), and pinned particles given a velocity (they stay where they are:
/// the engine sets their velocity to zero).
pub(crate) fn pinning_warnings(table: &BodyTable, data: &BodyData) -> Vec<(&'static str, String)> {
    let mut warnings = Vec::new();
    let mut pinned = data.pinned.clone();
    pinned.sort_unstable();
    let twice: Vec<usize> = pinned
        .windows(2)
        .filter(|w| w[0] == w[1])
        .map(|w| w[0])
        .collect();
    pinned.dedup();
    if !twice.is_empty() {
        warnings.push((
            "pinned",
            format!(
                "`pinned` lists {} more than once (each is pinned once)",
                listed("particle", &twice)
            ),
        ));
    }
    let moving: Vec<usize> = pinned
        .into_iter()
        .filter(|&i| data.velocity.get(i).is_some_and(|v| *v != Vec3::ZERO))
        .collect();
    if !moving.is_empty() {
        let key = if table.velocities.is_some() {
            "velocities"
        } else {
            "velocity"
        };
        warnings.push((
            key,
            format!(
                "{} given a velocity {} pinned: a pinned particle stays where it is, so its velocity is set to zero",
                listed("particle", &moving),
                if moving.len() == 1 { "is" } else { "are" }
            ),
        ));
    }
    warnings
}

/// `particle 3`, `particles 3, 7 and 9`, or the first few and a count.
fn listed(what: &str, indices: &[usize]) -> String {
    const SHOWN: usize = 5;
    let shown: Vec<String> = indices.iter().take(SHOWN).map(usize::to_string).collect();
    match indices.len() {
        1 => format!("{what} {}", shown[0]),
        n if n <= SHOWN => format!("{what}s {} and {}", shown[..n - 1].join(", "), shown[n - 1]),
        n => format!("{what}s {} and {} more", shown.join(", "), n - SHOWN),
    }
}

/// The scene key a [`BuildError`] is about, to find its line.
pub(crate) fn key_of(error: &BuildError) -> &'static str {
    match error {
        BuildError::NoParticles | BuildError::NotARenumbering { .. } => "particles",
        BuildError::LengthMismatch { field, .. }
        | BuildError::BadMass { field, .. }
        | BuildError::NotFinite { field, .. }
        | BuildError::OutOfRange { field, .. }
        | BuildError::TooMany { field, .. } => field,
        BuildError::SpringIndexOutOfRange { .. }
        | BuildError::SelfSpring { .. }
        | BuildError::DuplicateSpring { .. }
        | BuildError::ZeroLengthSpring { .. } => "springs",
        BuildError::NegativeSpringCoefficient { field, .. } => field,
        BuildError::PinnedOutOfRange { .. } => "pinned",
        BuildError::BadFace { .. } => "faces",
        BuildError::BadSegment { .. } => "segments",
        BuildError::GasWithoutSurface
        | BuildError::OpenSurface { .. }
        | BuildError::GasOffPlane { .. } => "gas",
        BuildError::SelfCollisionWithoutSurface | BuildError::SelfCollisionWithoutCollide => {
            "self_collision"
        }
        BuildError::DuplicateName(_) | BuildError::BadName(_) => "name",
        BuildError::RodIndexOutOfRange { .. }
        | BuildError::BadRodLength { .. }
        | BuildError::ConflictingRods { .. }
        | BuildError::RodLoop { .. }
        | BuildError::PinnedRod { .. } => "rods",
        BuildError::MuscleSpringOutOfRange { .. } | BuildError::BadMuscle { .. } => "muscles",
        BuildError::RigidTooSmall | BuildError::RigidPinned | BuildError::RigidMuscles => "rigid",
        BuildError::BeyondLimit { field, .. } | BuildError::EnergyOverflow { field, .. } => field,
        BuildError::JoinUnknownBody { end, .. }
        | BuildError::JoinParticleOutOfRange { end, .. } => end,
        BuildError::BadJoin(_) => "a",
        BuildError::YieldAboveBreak { .. } => "yield_strain",
    }
}

/// The scene key a [`BuildError`] of the body `table` is about: as
/// [`key_of`], but a rod whose length the scene gave (`rod_lengths`) is
/// found on that key's line.
pub(crate) fn key_in(error: &BuildError, table: &BodyTable) -> &'static str {
    match error {
        BuildError::BadRodLength { rod, .. } => {
            let joins_two = table
                .rods
                .as_deref()
                .and_then(|rods| rods.get(*rod))
                .is_some_and(|[first, second]| first != second);
            if table.rod_lengths.is_some() && joins_two {
                "rod_lengths"
            } else {
                "rods"
            }
        }
        BuildError::ConflictingRods { .. } | BuildError::RodLoop { .. }
            if table.rod_lengths.is_some() =>
        {
            "rod_lengths"
        }
        // Placed beyond the world's limit: the placement moved it there.
        BuildError::BeyondLimit {
            field: "particles", ..
        } if table.translate.is_some() || table.scale.is_some() => {
            if table.translate.is_some() {
                "translate"
            } else {
                "scale"
            }
        }
        _ => key_of(error),
    }
}
