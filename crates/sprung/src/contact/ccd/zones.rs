//! Impact zones (Provot 1997; Bridson, Fedkiw and Anderson 2002, §7.4;
//! Harmon et al. 2008): particles whose collisions the impulses did not
//! clear are merged into zones, and each zone moves as one rigid body over
//! the step, with the linear and angular momentum its particles had.
//!
//! Why that ends every collision within a zone: a zone's particles move by
//! `u_i = p + ω × (x_i − c)`, so at time `t` of the step they sit at
//! `A(t) x_i + b(t)` with `A(t) = I + t [ω]×`, an affine map whose
//! determinant `1 + t² |ω|²` is never zero. The signed volume of any four
//! of its points (the coplanarity of a point and a triangle, or of two
//! edges) is scaled by that positive determinant, so it never changes sign
//! within the zone, and distances only grow (`|A r|² = |r|² + t² |ω × r|²`).
//! Merging zones as long as collisions remain between them ends, at the
//! latest, with every colliding particle in one zone.

use crate::units::{Real, Vec3};
use glam::DMat3;

/// Particles grouped into zones by union–find.
#[derive(Debug, Clone, Default)]
pub(super) struct Zones {
    parent: Vec<u32>,
    /// Scratch: the members of the zone being moved.
    members: Vec<u32>,
}

impl Zones {
    /// Every particle of `count` alone.
    pub fn reset(&mut self, count: usize) {
        self.parent.clear();
        self.parent.extend(0..count as u32);
    }

    /// The zone (its root particle) of `particle`.
    pub fn find(&mut self, mut particle: u32) -> u32 {
        while self.parent[particle as usize] != particle {
            let grand = self.parent[self.parent[particle as usize] as usize];
            self.parent[particle as usize] = grand;
            particle = grand;
        }
        particle
    }

    /// Merge the zones of `a` and `b` (the smaller root stays the root, so
    /// the zones do not depend on the order of merging); whether they were
    /// apart.
    pub fn union(&mut self, a: u32, b: u32) -> bool {
        let (a, b) = (self.find(a), self.find(b));
        if a == b {
            return false;
        }
        let (root, child) = (a.min(b), a.max(b));
        self.parent[child as usize] = root;
        true
    }

    /// Move the zone of `root`, its particles among `candidates`, as one
    /// rigid body: from `start` (m), each particle's end `position` (m)
    /// set to `start + p + ω × (start − c)`, which keeps the zone's
    /// momentum (`inverse_mass` in 1/kg; pinned particles hold the zone,
    /// which then moves as they do where they all move alike, or stays).
    pub fn rigidify(
        &mut self,
        root: u32,
        candidates: &[u32],
        start: &[Vec3],
        position: &mut [Vec3],
        inverse_mass: &[Real],
    ) {
        let mut members = std::mem::take(&mut self.members);
        members.clear();
        for &i in candidates {
            if self.find(i) == root {
                members.push(i);
            }
        }
        move_rigidly(&members, start, position, inverse_mass);
        self.members = members;
    }
}

/// Give `members` one rigid motion over the step (see [`Zones::rigidify`]).
pub(super) fn move_rigidly(
    members: &[u32],
    start: &[Vec3],
    position: &mut [Vec3],
    inverse_mass: &[Real],
) {
    let motion = |i: u32| position[i as usize] - start[i as usize];
    let mut pinned = members.iter().filter(|&&i| inverse_mass[i as usize] == 0.0);
    if let Some(&first) = pinned.next() {
        let held = motion(first);
        let alike = pinned.all(|&i| motion(i) == held);
        let shift = if alike { held } else { Vec3::ZERO };
        for &i in members {
            if inverse_mass[i as usize] > 0.0 {
                position[i as usize] = start[i as usize] + shift;
            }
        }
        return;
    }
    let (mut total, mut centre, mut mean) = (0.0, Vec3::ZERO, Vec3::ZERO);
    for &i in members {
        let m = 1.0 / inverse_mass[i as usize];
        total += m;
        centre += m * start[i as usize];
        mean += m * motion(i);
    }
    if total <= 0.0 || !total.is_finite() {
        return;
    }
    let (centre, mean) = (centre / total, mean / total);
    let (mut momentum, mut inertia) = (Vec3::ZERO, DMat3::ZERO);
    for &i in members {
        let m = 1.0 / inverse_mass[i as usize];
        let r = start[i as usize] - centre;
        momentum += m * r.cross(motion(i) - mean);
        inertia += m
            * (DMat3::from_diagonal(Vec3::splat(r.length_squared()))
                - DMat3::from_cols(r * r.x, r * r.y, r * r.z));
    }
    // A zone on a line (two particles) has no inertia about it, nor any
    // angular momentum along it: a small regularisation gives the
    // least-squares spin.
    let trace = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    let regular = inertia + DMat3::from_diagonal(Vec3::splat(1e-12 * trace + Real::MIN_POSITIVE));
    let spin = if regular.determinant() != 0.0 {
        regular.inverse() * momentum
    } else {
        Vec3::ZERO
    };
    let spin = if spin.is_finite() { spin } else { Vec3::ZERO };
    for &i in members {
        let r = start[i as usize] - centre;
        position[i as usize] = start[i as usize] + mean + spin.cross(r);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_zone_keeps_its_momentum_and_its_shape_to_first_order() {
        // Four particles of 1, 2, 3, 4 kg moving apart and about: after
        // the rigid fit the mass-weighted motion (momentum times the step)
        // is the same to rounding, and every distance is no shorter than
        // at the start (|A r| ≥ |r|).
        let start = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let mut position = [
            Vec3::new(0.1, 0.0, -0.2),
            Vec3::new(1.0, 0.3, 0.0),
            Vec3::new(-0.2, 1.0, 0.1),
            Vec3::new(0.0, 0.0, 0.4),
        ];
        let inverse_mass = [1.0, 0.5, 1.0 / 3.0, 0.25];
        let momentum =
            |x: &[Vec3]| -> Vec3 { (0..4).map(|i| (x[i] - start[i]) / inverse_mass[i]).sum() };
        let before = momentum(&position);
        move_rigidly(&[0, 1, 2, 3], &start, &mut position, &inverse_mass);
        assert!((momentum(&position) - before).length() < 1e-14);
        for i in 0..4 {
            for j in 0..i {
                let (d0, d1) = (start[i] - start[j], position[i] - position[j]);
                assert!(d1.length() >= d0.length() * (1.0 - 1e-15));
            }
        }
        // A pinned particle holds the zone where it is.
        let mut position = [start[0], Vec3::ONE, Vec3::ONE, Vec3::ONE];
        move_rigidly(&[0, 1, 2, 3], &start, &mut position, &[0.0, 1.0, 1.0, 1.0]);
        assert_eq!(&position[1..], &start[1..]);
    }
}
