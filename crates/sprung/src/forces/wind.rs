//! Wind on surfaces (docs/physics.md §3): a surface with unit normal `n` moving
//! with velocity `v` in a wind `w` feels a force along `n`, largest when the
//! wind blows straight onto it and zero when it blows along it. Two models:
//!
//! - **simple** (the textbook's, per particle): `f_i = c ((w - v_i) · n_i) n_i`
//!   with `n_i` the normalised average of the unit normals of the faces
//!   around particle `i`, and `c` (N·s/m) a coefficient, 1 by default;
//! - **area** (per face, scaled by its size): `f = ρ_air A ((w - v) · n) n`
//!   with `A` the face's area, `v` the mean velocity of its vertices and `w`
//!   the wind at its centroid, shared equally among its three vertices. This
//!   is docs/physics.md's form, linear in the relative wind: `ρ_air` (kg/m³)
//!   multiplies an implied reference speed of 1 m/s. An optional `lift`
//!   adds `lift` times the part of that force perpendicular to the relative
//!   wind.
//!
//! Wind acts on every body with faces (cloth, gas bodies' surfaces, meshes)
//! and on 2D loops (a segment of length `l` counts as an area `l` per metre
//! of depth). The sign of a normal does not matter: `n` appears twice.

use super::faces::Surfaces;
use super::wind_field::WindField;
use super::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use crate::error::BuildError;
use crate::parallel;
use crate::units::{Real, Vec3};

/// Air density at sea level and 20 °C (kg/m³), the default of the area model.
pub const AIR_DENSITY: Real = 1.2;

/// How wind turns into force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WindModel {
    /// Per particle, `c ((w - v) · n) n`.
    Simple {
        /// Coefficient `c` (N·s/m), 1 in the textbook model.
        coefficient: Real,
    },
    /// Per face, `ρ_air A ((w - v) · n) n`, plus lift.
    Area {
        /// Air density `ρ_air` (kg/m³).
        air_density: Real,
        /// Lift coefficient: the extra share of the force perpendicular to
        /// the relative wind (0 for none).
        lift: Real,
    },
}

impl WindModel {
    /// Check the coefficients: finite and not negative.
    pub fn validate(&self) -> Result<(), BuildError> {
        let checks: &[(&'static str, Real)] = match self {
            WindModel::Simple { coefficient } => &[("coefficient", *coefficient)],
            WindModel::Area { air_density, lift } => {
                &[("air_density", *air_density), ("lift", *lift)]
            }
        };
        for &(field, value) in checks {
            if !(value.is_finite() && value >= 0.0) {
                return Err(BuildError::OutOfRange {
                    field,
                    value,
                    reason: "must be finite and not negative",
                });
            }
        }
        Ok(())
    }
}

/// Wind blowing on every surface of the world.
///
/// A flag in the xy-plane, at rest in a wind `w`: the simple model pushes
/// each particle with `c (w · n) n`, `n = ±z` its normal, so only the wind
/// across the flag counts:
///
/// ```
/// use sprung::build::{self, ClothSprings};
/// use sprung::forces::{Wind, WindField, WindModel};
/// use sprung::{IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::Verlet);
/// world.set_gravity(Vec3::ZERO);
/// let flag = build::cloth(4, 3, 1.5, 1.0, ClothSprings::default()).unwrap();
/// world.add_body("flag", flag.with_stiffness(100.0)).unwrap();
/// let breeze = WindField::uniform(Vec3::new(1.0, 0.0, 2.0));
/// let model = WindModel::Simple { coefficient: 0.5 };
/// world.forces.push(Box::new(Wind::new(breeze, model).unwrap()));
/// world.evaluate_forces(); // the springs, at rest, pull nothing
/// assert!(world.particles.force.iter().all(|&f| f == Vec3::new(0.0, 0.0, 1.0)));
/// // Blowing along the flag, it pushes nothing.
/// world.forces.get_mut::<Wind>().unwrap().field.velocity = Vec3::X;
/// world.evaluate_forces();
/// assert!(world.particles.force.iter().all(|&f| f == Vec3::ZERO));
/// ```
#[derive(Debug, Clone)]
pub struct Wind {
    /// The wind velocity field.
    pub field: WindField,
    /// How it turns into force.
    pub model: WindModel,
    /// Factor of the wind each body feels, by body index (1 where absent).
    pub body_scale: Vec<Real>,
    /// Scratch: the summed face normals around each particle (simple model).
    normals: Vec<Vec3>,
    /// The bodies' surfaces of more than a chunk of elements, in blocks for
    /// the threads (smaller ones are taken in order).
    surfaces: Surfaces,
}

impl Wind {
    /// Wind from `field` acting through `model`, both checked.
    pub fn new(field: WindField, model: WindModel) -> Result<Self, BuildError> {
        field.validate()?;
        model.validate()?;
        Ok(Wind {
            field,
            model,
            body_scale: Vec::new(),
            normals: Vec::new(),
            surfaces: Surfaces::default(),
        })
    }

    /// Make body `body` feel `scale` times the wind velocity (a sheet in a
    /// sheltered spot, say); `scale` must be finite and not negative.
    pub fn set_body_scale(&mut self, body: usize, scale: Real) -> Result<(), BuildError> {
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(BuildError::OutOfRange {
                field: "wind_scale",
                value: scale,
                reason: "must be finite and not negative",
            });
        }
        if self.body_scale.len() <= body {
            self.body_scale.resize(body + 1, 1.0);
        }
        self.body_scale[body] = scale;
        Ok(())
    }

    /// The wind velocity felt by body `body` at `x` and time `t` (m/s).
    fn wind_at(&self, body: usize, x: Vec3, t: Real) -> Vec3 {
        self.body_scale.get(body).copied().unwrap_or(1.0) * self.field.velocity_at(x, t)
    }

    fn simple(&mut self, coefficient: Real, context: &ForceContext, force: &mut [Vec3]) {
        let x = context.position;
        self.normals.clear();
        self.normals.resize(x.len(), Vec3::ZERO);
        for (index, body) in context.bodies.iter().enumerate() {
            let faces = self.surfaces.faces(index, body, x.len());
            faces.scatter(&mut self.normals, |_, w| {
                let [a, b, c] = [w.particle(0), w.particle(1), w.particle(2)];
                let n = (x[b] - x[a]).cross(x[c] - x[a]).normalize_or_zero();
                (0..3).for_each(|k| w.add(k, n));
            });
            let segments = self.surfaces.segments(index, body, x.len());
            segments.scatter(&mut self.normals, |_, w| {
                let n = segment_normal(x[w.particle(0)], x[w.particle(1)]).normalize_or_zero();
                (0..2).for_each(|k| w.add(k, n));
            });
        }
        for (index, body) in context.bodies.iter().enumerate() {
            let range = body.particles.clone();
            let normals = &self.normals[range.clone()];
            let wind = &*self;
            parallel::for_each_span(&mut force[range.clone()], |start, force| {
                for (k, f) in force.iter_mut().enumerate() {
                    let i = range.start + start + k;
                    let n = normals[start + k].normalize_or_zero();
                    if n != Vec3::ZERO {
                        let relative =
                            wind.wind_at(index, x[i], context.time) - context.velocity[i];
                        *f += coefficient * relative.dot(n) * n;
                    }
                }
            });
        }
    }

    fn area(&mut self, air_density: Real, lift: Real, context: &ForceContext, force: &mut [Vec3]) {
        let (x, v) = (context.position, context.velocity);
        let (field, body_scale) = (&self.field, &self.body_scale);
        // The force on a surface element of `vertices` with area normal
        // `area_normal`, for each of its vertices.
        let share = |body: usize, vertices: &[usize], area_normal: Vec3| -> Vec3 {
            let area = area_normal.length();
            if area == 0.0 {
                return Vec3::ZERO;
            }
            let count = vertices.len() as Real;
            let n = area_normal / area;
            let centroid = vertices.iter().map(|&i| x[i]).sum::<Vec3>() / count;
            let mean_velocity = vertices.iter().map(|&i| v[i]).sum::<Vec3>() / count;
            let scale = body_scale.get(body).copied().unwrap_or(1.0);
            let relative = scale * field.velocity_at(centroid, context.time) - mean_velocity;
            let mut f = air_density * area * relative.dot(n) * n;
            if lift != 0.0 {
                let along = relative.normalize_or_zero();
                f += lift * (f - f.dot(along) * along);
            }
            f / count
        };
        for (index, body) in context.bodies.iter().enumerate() {
            let faces = self.surfaces.faces(index, body, x.len());
            faces.scatter(force, |_, w| {
                let [a, b, c] = [w.particle(0), w.particle(1), w.particle(2)];
                let f = share(index, &[a, b, c], 0.5 * (x[b] - x[a]).cross(x[c] - x[a]));
                (0..3).for_each(|k| w.add(k, f));
            });
            let segments = self.surfaces.segments(index, body, x.len());
            segments.scatter(force, |_, w| {
                let [a, b] = [w.particle(0), w.particle(1)];
                let f = share(index, &[a, b], segment_normal(x[a], x[b]));
                (0..2).for_each(|k| w.add(k, f));
            });
        }
    }
}

/// The normal of the segment `a → b` in the xy-plane, of length `|b - a|`
/// (outward for a counter-clockwise loop).
fn segment_normal(a: Vec3, b: Vec3) -> Vec3 {
    let d = b - a;
    Vec3::new(d.y, -d.x, 0.0)
}

impl Force for Wind {
    fn name(&self) -> &'static str {
        "wind"
    }

    /// The simple model's `c (w - v)·n n` damps a particle's velocity along
    /// its unit normal at `c / m` (counted on every particle, faces or not);
    /// the area model's force grows with the square of the relative speed
    /// and has no fixed rate (not counted).
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        if let WindModel::Simple { coefficient } = self.model {
            for (rate, w) in bounds.damping.iter_mut().zip(context.inverse_mass) {
                *rate += coefficient * w;
            }
        }
    }

    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        match self.model {
            WindModel::Simple { coefficient } => self.simple(coefficient, context, force),
            WindModel::Area { air_density, lift } => self.area(air_density, lift, context, force),
        }
    }

    /// Wind does work on the system: no potential energy.
    fn energy_name(&self) -> Option<&'static str> {
        None
    }

    fn add_potential_energy(&self, _: &ForceContext, _: &mut Real) {}

    fn linearize(&mut self, _context: &ForceContext) -> Linearization {
        Linearization::Explicit
    }

    /// Explicit in the implicit solvers (see the module documentation).
    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }

    /// Explicit in the implicit solvers (see the module documentation).
    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}
