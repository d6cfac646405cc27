//! A rope: a chain of particles hanging from the origin along -y, springs
//! between neighbours, the top particle pinned.

use super::{check_count, check_length, check_total};
use crate::body::{BodyData, SpringData};
use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// A rope of `particles` particles (at least 2), evenly spaced over
/// `length` (m) from the origin down along -y, with a spring between each
/// pair of neighbours (parent above child, so one-sided springs pull the
/// lower particle) and particle 0 pinned.
///
/// ```
/// use sprung::{build, Vec3};
///
/// let rope = build::rope(5, 2.0).unwrap();
/// assert_eq!(rope.particle_count(), 5);
/// assert_eq!(rope.position[4], Vec3::new(0.0, -2.0, 0.0));
/// assert_eq!(rope.pinned, [0]);
/// assert_eq!(rope.springs.len(), 4);
/// assert!(rope.springs.iter().all(|s| rope.rest_length(s) == 0.5));
/// assert!(build::rope(1, 2.0).is_err()); // a rope needs two ends
/// ```
pub fn rope(particles: usize, length: Real) -> Result<BodyData, BuildError> {
    check_count(
        "rope.particles",
        particles,
        2,
        "a rope needs at least 2 particles",
    )?;
    check_length("rope.length", length)?;
    check_total("rope.particles", &[particles])?;
    let spacing = length / (particles - 1) as Real;
    let position = (0..particles)
        .map(|i| Vec3::new(0.0, -spacing * i as Real, 0.0))
        .collect();
    let mut body = BodyData::from_positions(position).with_pinned(vec![0]);
    body.springs = (1..particles)
        .map(|i| SpringData::between(i - 1, i))
        .collect();
    Ok(body)
}
