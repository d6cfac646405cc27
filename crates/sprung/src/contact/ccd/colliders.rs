//! The colliders' share of the CCD: a particle whose straight path
//! over the step passes through a sphere, in and out again (too fast for the
//! projection, which sees only where it ends, or for the penalty spring,
//! which needs it inside) is stopped where it entered, on the sphere as
//! the sphere has moved, its velocity into the surface (relative to the
//! surface) taken away. A plane bounds a half-space, which no path can
//! leave on the far side; a particle that ends inside a projection
//! collider is moved out by the collide stage.

use crate::body::{self, Body};
use crate::colliders::{Collider, Shape};
use crate::units::{Real, Vec3};

/// Stop every particle of `bodies` but the rigid ones whose path over the step from `start` to
/// `position` (m), the step ending at `time` (s) after `dt` (s), passes
/// through a sphere collider; returns how many were stopped.
#[allow(clippy::too_many_arguments)]
pub(crate) fn sweep_colliders(
    colliders: &[Collider],
    time: Real,
    dt: Real,
    bodies: &[Body],
    start: &[Vec3],
    position: &mut [Vec3],
    velocity: &mut [Vec3],
    inverse_mass: &[Real],
) -> u64 {
    let mut stopped = 0;
    for collider in colliders {
        let (Shape::Sphere { centre: c0, radius }, Shape::Sphere { centre: c1, .. }) =
            (collider.shape_at(time - dt), collider.shape_at(time))
        else {
            continue;
        };
        let surface = collider.velocity_at(time);
        for i in body::runs_of(bodies, |b| !b.rigid).flatten() {
            if inverse_mass[i] == 0.0 {
                continue;
            }
            let from = start[i] - c0;
            let to = position[i] - c1;
            let Some(t) = entry(from, to, radius) else {
                continue;
            };
            let normal = (from + t * (to - from)).normalize_or(Vec3::Y);
            position[i] = c1 + radius * normal;
            let inward = (velocity[i] - surface).dot(normal);
            if inward < 0.0 {
                velocity[i] -= inward * normal;
            }
            stopped += 1;
        }
    }
    stopped
}

/// Where (in `[0, 1]`) a path from `from` to `to` (m, relative to the
/// sphere's centre) that starts and ends outside a sphere of `radius` (m)
/// enters it, if it passes through it: deeper than half the radius (a
/// path that only grazes the sphere, as a particle sliding over it from
/// one step's projection to the next, is left to the projection).
fn entry(from: Vec3, to: Vec3, radius: Real) -> Option<Real> {
    let r2 = radius * radius;
    let c = from.length_squared() - r2;
    if c < 0.0 || to.length_squared() < r2 {
        return None;
    }
    let d = to - from;
    let a = d.length_squared();
    let b = 2.0 * from.dot(d);
    if a == 0.0 || b >= 0.0 {
        return None;
    }
    // The path's closest approach to the centre.
    let closest = (from + (-b / (2.0 * a)).min(1.0) * d).length_squared();
    if closest >= 0.25 * r2 {
        return None;
    }
    let disc = b * b - 4.0 * a * c;
    if disc <= 0.0 {
        return None;
    }
    let t = 2.0 * c / (-b + disc.sqrt());
    (t <= 1.0).then_some(t)
}

#[cfg(test)]
mod tests {
    use super::entry;
    use crate::units::Vec3;

    #[test]
    fn a_path_through_a_sphere_enters_where_it_meets_it() {
        // From x = -3 to x = +3 through a unit sphere: in at t = 1/3.
        let t = entry(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(3.0, 0.0, 0.0), 1.0);
        assert!((t.unwrap() - 1.0 / 3.0).abs() < 1e-15);
        // Passing beside it, stopping short of it, or ending inside: none.
        assert_eq!(
            entry(Vec3::new(-3.0, 1.5, 0.0), Vec3::new(3.0, 1.5, 0.0), 1.0),
            None
        );
        assert_eq!(
            entry(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(-2.0, 0.0, 0.0), 1.0),
            None
        );
        assert_eq!(
            entry(Vec3::new(-3.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0), 1.0),
            None
        );
    }
}
