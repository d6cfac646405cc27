//! Kinematic motion of a collider: a displacement given at keyframes and
//! interpolated linearly in between (a piecewise-linear path, so the
//! velocity is piecewise constant).

use crate::error::BuildError;
use crate::units::{Real, Vec3};

/// A prescribed displacement of a collider over time: keyframes
/// `(time (s), displacement (m))` with strictly increasing times, joined by
/// straight segments travelled at constant velocity. Before the first
/// keyframe the displacement is the first one's, after the last keyframe the
/// last one's: the collider is at rest there.
///
/// ```
/// use sprung::{Path, Vec3};
///
/// let lift = Path::new(vec![(0.0, Vec3::ZERO), (2.0, Vec3::new(0.0, 1.0, 0.0))]).unwrap();
/// assert_eq!(lift.offset_at(0.5), Vec3::new(0.0, 0.25, 0.0));
/// assert_eq!(lift.velocity_at(0.5), Vec3::new(0.0, 0.5, 0.0));
/// assert_eq!(lift.offset_at(3.0), Vec3::new(0.0, 1.0, 0.0)); // held after the last
/// assert_eq!(lift.velocity_at(3.0), Vec3::ZERO);
/// assert!(Path::new(vec![(1.0, Vec3::ZERO), (1.0, Vec3::X)]).is_err()); // times must increase
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    keyframes: Vec<(Real, Vec3)>,
}

impl Path {
    /// A path through `keyframes` `(time (s), displacement (m))`. Refused:
    /// no keyframe, a non-finite time or displacement, or times that do not
    /// increase strictly (field `path`, with the keyframe's index where it
    /// names one).
    pub fn new(keyframes: Vec<(Real, Vec3)>) -> Result<Self, BuildError> {
        if keyframes.is_empty() {
            return Err(BuildError::OutOfRange {
                field: "path",
                value: 0.0,
                reason: "a path needs at least one keyframe (time, displacement)",
            });
        }
        for (index, &(time, displacement)) in keyframes.iter().enumerate() {
            let values = std::iter::once(time).chain(displacement.to_array());
            if let Some(value) = values.into_iter().find(|c| !c.is_finite()) {
                return Err(BuildError::NotFinite {
                    field: "path",
                    index,
                    value,
                });
            }
        }
        if let Some(pair) = keyframes.windows(2).find(|pair| pair[1].0 <= pair[0].0) {
            return Err(BuildError::OutOfRange {
                field: "path",
                value: pair[1].0,
                reason: "keyframe times must increase strictly (s)",
            });
        }
        Ok(Path { keyframes })
    }

    /// The keyframes `(time (s), displacement (m))`, times increasing.
    pub fn keyframes(&self) -> &[(Real, Vec3)] {
        &self.keyframes
    }

    /// The segment `[k, k + 1]` whose time span `[t_k, t_{k+1})` holds
    /// `time`, or `None` before the first and from the last keyframe on (and
    /// for a NaN time).
    fn segment(&self, time: Real) -> Option<usize> {
        let first = self.keyframes[0].0;
        let last = self.keyframes[self.keyframes.len() - 1].0;
        if !(time >= first && time < last) {
            return None;
        }
        // The first keyframe later than `time`: at least 1, at most len - 1.
        let next = self.keyframes.partition_point(|&(t, _)| t <= time);
        Some(next - 1)
    }

    /// The keyframes' displacements (m), in order.
    pub fn offsets(&self) -> impl Iterator<Item = Vec3> + '_ {
        self.keyframes.iter().map(|&(_, offset)| offset)
    }

    /// The displacement (m) at time `time` (s): linear between keyframes,
    /// held before the first and after the last.
    pub fn offset_at(&self, time: Real) -> Vec3 {
        match self.segment(time) {
            Some(k) => {
                let ((t0, x0), (t1, x1)) = (self.keyframes[k], self.keyframes[k + 1]);
                x0 + (x1 - x0) * ((time - t0) / (t1 - t0))
            }
            None if time >= self.keyframes[0].0 => self.keyframes[self.keyframes.len() - 1].1,
            None => self.keyframes[0].1,
        }
    }

    /// Velocity at `time` (m/s): the slope of the segment holding `time`
    /// (a segment `[t_k, t_{k+1})` includes its start), zero before the first
    /// and from the last keyframe on.
    pub fn velocity_at(&self, time: Real) -> Vec3 {
        match self.segment(time) {
            Some(k) => {
                let ((t0, x0), (t1, x1)) = (self.keyframes[k], self.keyframes[k + 1]);
                (x1 - x0) / (t1 - t0)
            }
            None => Vec3::ZERO,
        }
    }
}
