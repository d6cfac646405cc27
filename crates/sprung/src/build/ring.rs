//! A ring: the 2D soft ball of the textbook (docs/physics.md §2), `N` particles
//! on a circle joined into a closed loop.

use super::{check_count, check_length, check_total};
use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// A ring of `particles` particles (at least 3) on a circle of `radius` (m)
/// centred on the origin in the xy-plane, counter-clockwise from +x; a
/// spring joins each particle to the next, closing the loop, and the loop's
/// segments bound the area a gas fills.
///
/// # Examples
///
/// The `N` sides of a ring of radius `r` are `2 r sin(π/N)` long, and the
/// closed loop can hold a gas:
///
/// ```
/// use sprung::{build, BodyData, Gas};
///
/// let ring = build::ring(12, 0.5).unwrap();
/// assert_eq!((ring.segments.len(), ring.springs.len()), (12, 12));
/// assert!(ring.is_closed());
/// let side = 2.0 * 0.5 * (std::f64::consts::PI / 12.0).sin();
/// // The positions come from cos and sin: rounded, a few ulps off.
/// assert!(ring.springs.iter().all(|s| (ring.rest_length(s) - side).abs() < 1e-15));
/// let balloon = BodyData { gas: Some(Gas::new(10.0, 0.5)), ..ring };
/// assert_eq!(balloon.validate(), Ok(()));
/// ```
pub fn ring(particles: usize, radius: Real) -> Result<BodyData, BuildError> {
    check_count(
        "ring.particles",
        particles,
        3,
        "a ring needs at least 3 particles",
    )?;
    check_length("ring.radius", radius)?;
    check_total("ring.particles", &[particles])?;
    let position = (0..particles)
        .map(|k| {
            let angle = std::f64::consts::TAU * k as Real / particles as Real;
            Vec3::new(radius * angle.cos(), radius * angle.sin(), 0.0)
        })
        .collect();
    let mut body = BodyData::from_positions(position);
    body.segments = (0..particles).map(|k| [k, (k + 1) % particles]).collect();
    body.springs = body
        .segments
        .iter()
        .map(|&[a, b]| SpringData::between(a, b))
        .collect();
    Ok(body)
}
