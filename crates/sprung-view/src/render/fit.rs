//! The automatic 3D view: from a fixed elevated direction, aimed at the
//! middle of everything the run shows and just far enough back that every
//! particle of every frame (and every sphere collider) is in the picture.

use sprung::{Real, Shape, Vec3};

use super::camera::{basis, Bounds, AZIMUTH_DEGREES, ELEVATION_DEGREES};
use super::snapshot::Snapshot;

/// At most this many points are used to fit the automatic 3D view.
const FIT_POINTS: usize = 200_000;

/// Every finite point of `snapshots`, thinned evenly to at most
/// [`FIT_POINTS`] (frames are skipped, never particles of a frame, so each
/// frame used counts whole).
pub(super) fn sample_points(snapshots: &[Snapshot]) -> Vec<Vec3> {
    let total: usize = snapshots.iter().map(|s| s.position.len()).sum();
    let stride = total.div_ceil(FIT_POINTS).max(1);
    let last = snapshots.len().saturating_sub(1);
    snapshots
        .iter()
        .enumerate()
        .filter(|(k, _)| k % stride == 0 || *k == last)
        .flat_map(|(_, s)| {
            s.position
                .iter()
                .copied()
                .chain(obstacle_points(&s.colliders))
        })
        .filter(|p| p.is_finite())
        .collect()
}

/// Points on the sphere colliders (the ends of three axes and eight
/// diagonals), so framing shows them whole.
pub(super) fn obstacle_points(colliders: &[Shape]) -> impl Iterator<Item = Vec3> + '_ {
    colliders.iter().flat_map(|shape| {
        let (centre, radius) = match *shape {
            Shape::Sphere { centre, radius } if centre.is_finite() && radius.is_finite() => {
                (centre, radius)
            }
            _ => (Vec3::ZERO, Real::NAN),
        };
        let d = 1.0 / Real::sqrt(3.0);
        let directions = [
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
            Vec3::new(d, d, d),
            Vec3::new(-d, d, d),
            Vec3::new(d, -d, d),
            Vec3::new(-d, -d, d),
            Vec3::new(d, d, -d),
            Vec3::new(-d, d, -d),
            Vec3::new(d, -d, -d),
            Vec3::new(-d, -d, -d),
        ];
        directions
            .into_iter()
            .map(move |u| centre + radius * u)
            .filter(|p| p.is_finite())
    })
}

/// The half-angle tangents the points must fit in.
pub(super) struct Fit {
    pub(super) tan_x: Real,
    pub(super) tan_y: Real,
}

impl Fit {
    /// Eye and target for the elevated automatic direction: the target
    /// (given, or moved so the points sit centred in the picture) and the
    /// eye just far enough back that every point fits.
    pub(super) fn eye(
        &self,
        points: &[Vec3],
        bounds: &Bounds,
        target: Option<Vec3>,
    ) -> (Vec3, Vec3) {
        let (az, el) = (AZIMUTH_DEGREES.to_radians(), ELEVATION_DEGREES.to_radians());
        let back = Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
        let mut centre = target.unwrap_or_else(|| bounds.centre());
        let (right, up, forward) = basis(centre + back, centre);
        let floor = 0.5 * bounds.diagonal().max(1e-3);
        let mut distance = self.distance(points, centre, right, up, forward).max(floor);
        if target.is_none() {
            // Twice: aim at the middle of the points' picture, then refit.
            for _ in 0..2 {
                let eye = centre + back * distance;
                let (mut lo, mut hi) =
                    (Vec3::splat(Real::INFINITY), Vec3::splat(Real::NEG_INFINITY));
                for p in points {
                    let q = *p - eye;
                    let depth = q.dot(forward).max(1e-9);
                    let v = Vec3::new(q.dot(right) / depth, q.dot(up) / depth, 0.0);
                    lo = lo.min(v);
                    hi = hi.max(v);
                }
                if !(lo.is_finite() && hi.is_finite()) {
                    break;
                }
                let mid = 0.5 * (lo + hi);
                centre += distance * (mid.x * right + mid.y * up);
                distance = self.distance(points, centre, right, up, forward).max(floor);
            }
        }
        (centre + back * distance, centre)
    }

    /// The least distance back from `centre` along `-forward` at which every
    /// point is inside the picture.
    fn distance(
        &self,
        points: &[Vec3],
        centre: Vec3,
        right: Vec3,
        up: Vec3,
        forward: Vec3,
    ) -> Real {
        let mut distance: Real = 0.0;
        for p in points {
            let q = *p - centre;
            let along = q.dot(forward);
            distance = distance
                .max(q.dot(right).abs() / self.tan_x - along)
                .max(q.dot(up).abs() / self.tan_y - along);
        }
        distance
    }
}
