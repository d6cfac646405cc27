//! Bodies: the description a builder or a scene gives ([`BodyData`], local
//! indices, checked before use by [`BodyData::validate`]) and the body as
//! the world stores it ([`Body`], ranges into the world's particle and
//! spring arrays).

use std::ops::Range;

use crate::gas::{Gas, VolumeModel};
use crate::surface;
use crate::units::{Real, Vec3};

mod data;
mod validate;

pub use data::{BodyContact, BodyData, MuscleData, MuscleDrive, RodData, SpringData};
pub use validate::ROD_SEARCH_LIMIT;

/// The particles of the bodies that `keep` says (and that have any), as
/// runs of consecutive bodies' particles: each run a range of particles
/// that a loop can take in one piece.
pub(crate) fn runs_of<'a>(
    bodies: &'a [Body],
    keep: impl Fn(&Body) -> bool + 'a,
) -> impl Iterator<Item = Range<usize>> + 'a {
    let mut index = 0;
    let kept = move |b: &Body| keep(b) && !b.particles.is_empty();
    std::iter::from_fn(move || {
        let first = index + bodies[index..].iter().position(&kept)?;
        let mut run = bodies[first].particles.clone();
        index = first + 1;
        while index < bodies.len()
            && kept(&bodies[index])
            && bodies[index].particles.start == run.end
        {
            run.end = bodies[index].particles.end;
            index += 1;
        }
        Some(run)
    })
}

/// A body as the world stores it: a name and ranges into the world's
/// particle and spring arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    /// Unique name, used for diagnostics columns (`NAME.cx`, ...).
    pub name: String,
    /// Indices of the body's particles in the world.
    pub particles: Range<usize>,
    /// Indices of the body's springs in the world.
    pub springs: Range<usize>,
    /// Triangles with world particle indices, counter-clockwise seen from
    /// outside when the body is closed.
    pub faces: Vec<[u32; 3]>,
    /// Segments of a closed 2D loop with world particle indices,
    /// counter-clockwise.
    pub segments: Vec<[u32; 2]>,
    /// Whether `faces` (or `segments`) enclose a volume (area).
    pub closed: bool,
    /// The gas inside, if any.
    pub gas: Option<Gas>,
    /// The edges of `faces`, each once (for edge–edge contacts).
    pub edges: Vec<[u32; 2]>,
    /// How the body takes part in contacts between bodies.
    pub contact: BodyContact,
    /// Indices of the body's rods in the world's [`crate::Rods`].
    pub rods: Range<usize>,
    /// The body is rigid (see [`BodyData::rigid`]).
    pub rigid: bool,
    /// The body takes part in mutual gravitation.
    pub gravitating: bool,
    /// Where the body's own numbering of its particles has no locality:
    /// per particle of the body, its number within the body in the order
    /// its springs are stored in and the spring force reads them in
    /// (reverse Cuthill–McKee, `order::locality_numbering`); `None` where
    /// the force reads them in the body's own numbering.
    pub(crate) spring_numbering: Option<Vec<u32>>,
    /// Per spring of the body in the scene's order (its
    /// [`BodyData::springs`]), its place in `springs` counted from the
    /// range's start: the world stores a body's springs in an order of its
    /// own (runs first, for the spring force).
    pub(crate) scene_springs: Vec<u32>,
}

impl Body {
    /// The volume of this body at `position` by the gas's volume `model`
    /// (m³, or m² for a 2D body); 0 for a body that is not closed.
    pub fn gas_volume(&self, model: VolumeModel, position: &[Vec3]) -> Real {
        let body = self;
        let Some(exact) = body.enclosed_volume(position) else {
            return 0.0;
        };
        if model == VolumeModel::Exact {
            return exact;
        }
        let points = &position[body.particles.clone()];
        let low = points.iter().copied().fold(Vec3::INFINITY, Vec3::min);
        let high = points.iter().copied().fold(Vec3::NEG_INFINITY, Vec3::max);
        let size = (high - low).max(Vec3::ZERO);
        let (boxed, fraction) = if body.is_planar() {
            (size.x * size.y, std::f64::consts::FRAC_PI_4)
        } else {
            (size.x * size.y * size.z, std::f64::consts::PI / 6.0)
        };
        match model {
            VolumeModel::BoundingEllipsoid => fraction * boxed,
            _ => boxed,
        }
    }

    /// The body's springs (indices in the world's [`crate::Springs`]) in
    /// the order the scene gave them ([`BodyData::springs`]), the order its
    /// spring indices (muscles, outputs) count in; `springs` ranges over
    /// them in the order the world stores them.
    pub fn springs_in_scene_order(&self) -> impl Iterator<Item = usize> + '_ {
        self.scene_springs
            .iter()
            .map(|&k| self.springs.start + k as usize)
    }

    /// True for a 2D body (bounded by segments in the xy-plane).
    pub fn is_planar(&self) -> bool {
        self.faces.is_empty() && !self.segments.is_empty()
    }

    /// The exact enclosed volume (m³), or area in 2D (m²), at `position`;
    /// `None` for a body that is not closed.
    pub fn enclosed_volume(&self, position: &[Vec3]) -> Option<Real> {
        if !self.closed {
            None
        } else if self.is_planar() {
            Some(surface::enclosed_area(position, &self.segments))
        } else {
            Some(surface::enclosed_volume(position, &self.faces))
        }
    }
}
