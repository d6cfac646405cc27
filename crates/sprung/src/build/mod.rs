//! Builders: functions that lay out the particles, springs and faces of a
//! common body (docs/physics.md §2) as a [`BodyData`](crate::BodyData), ready for
//! [`crate::World::add_body`]. Every particle has mass 1 kg and every spring
//! zero stiffness and damping until the caller sets them with the
//! `BodyData::with_*` methods.
//!
//! To add a builder: a file here with a function returning
//! `Result<BodyData, BuildError>` that checks its own parameters.

mod cloth;
mod fill;
mod lattice;
mod ring;
mod rope;
mod sphere;
mod surface;

pub use cloth::{cloth, ClothSprings};
pub use lattice::lattice;
pub use ring::ring;
pub use rope::rope;
pub use sphere::{icosphere, MAX_SUBDIVISIONS};
pub use surface::{refine, surface, Internal, SurfaceSprings};

use crate::error::BuildError;
use crate::units::Real;

/// Most particles a builder makes (ten million: about 1 GB of state).
pub const MAX_PARTICLES: usize = 10_000_000;

/// Most springs a builder makes, and a scene holds in all (twenty million:
/// with as many particles as allowed, about 3 GB while the scene is built).
pub const MAX_SPRINGS: usize = 20_000_000;

/// Refuse `count` springs, set by the parameter `field`, above
/// [`MAX_SPRINGS`].
fn check_springs(field: &'static str, count: usize) -> Result<(), BuildError> {
    if count > MAX_SPRINGS {
        return Err(BuildError::TooMany {
            field,
            what: "springs",
            count,
            limit: MAX_SPRINGS,
        });
    }
    Ok(())
}

/// The first of the limits that `particles` and `springs` (a scene's
/// bodies together) exceed, as `(what, count, limit)`; `None` within both.
pub fn over_limit(particles: usize, springs: usize) -> Option<(&'static str, usize, usize)> {
    [
        ("particles", particles, MAX_PARTICLES),
        ("springs", springs, MAX_SPRINGS),
    ]
    .into_iter()
    .find(|&(_, count, limit)| count > limit)
}

/// The product of `counts` (particles along each axis), refused above
/// [`MAX_PARTICLES`] or if it overflows.
fn check_total(field: &'static str, counts: &[usize]) -> Result<usize, BuildError> {
    let total = counts
        .iter()
        .try_fold(1usize, |product, &n| product.checked_mul(n));
    match total {
        Some(total) if total <= MAX_PARTICLES => Ok(total),
        _ => Err(BuildError::OutOfRange {
            field,
            value: counts.iter().map(|&n| n as Real).product(),
            reason: "too many particles (at most 10 000 000)",
        }),
    }
}

/// Refuse a count below `min`.
fn check_count(
    field: &'static str,
    value: usize,
    min: usize,
    reason: &'static str,
) -> Result<(), BuildError> {
    if value < min {
        return Err(BuildError::OutOfRange {
            field,
            value: value as Real,
            reason,
        });
    }
    Ok(())
}

/// Refuse a length that is not positive and finite.
fn check_length(field: &'static str, value: Real) -> Result<(), BuildError> {
    if !(value.is_finite() && value > 0.0) {
        return Err(BuildError::OutOfRange {
            field,
            value,
            reason: "must be a positive, finite length (m)",
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_over_either_limit_is_named_by_the_first_it_exceeds() {
        assert_eq!(over_limit(MAX_PARTICLES, MAX_SPRINGS), None);
        assert_eq!(
            over_limit(MAX_PARTICLES + 1, MAX_SPRINGS),
            Some(("particles", MAX_PARTICLES + 1, MAX_PARTICLES))
        );
        assert_eq!(
            over_limit(10, MAX_SPRINGS + 1),
            Some(("springs", MAX_SPRINGS + 1, MAX_SPRINGS))
        );
    }
}
