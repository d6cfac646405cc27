//! The checks of a [`BodyData`] before it joins a world: everything a user
//! could get wrong, each refusal naming the scene key and index.

use std::collections::HashMap;

use super::{BodyData, MuscleDrive};
use crate::error::BuildError;
use crate::surface;
use crate::units::{Real, Vec3};

/// Rods agree to a billionth of their length (the tolerance the constrain
/// stage converges to by default).
const ROD_SLACK: Real = 1e-9;

/// Steps the search for paths of rods shorter than a rod may take (a
/// particle reached, or a rod looked at), over all of a body's rods: past
/// it, the remaining rods are not checked.
pub const ROD_SEARCH_LIMIT: usize = 10_000_000;

impl BodyData {
    /// Check everything a user could get wrong; the first problem found is
    /// returned, naming the scene key and index.
    ///
    /// ```
    /// use sprung::{BodyData, BuildError, Vec3};
    ///
    /// let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
    /// body.mass[1] = -2.0;
    /// let error = body.validate().unwrap_err();
    /// assert_eq!(error, BuildError::BadMass { field: "masses", index: 1, value: -2.0 });
    /// assert_eq!(error.to_string(), "`masses`[1] = -2: mass must be positive and finite (kg)");
    /// ```
    pub fn validate(&self) -> Result<(), BuildError> {
        let count = self.position.len();
        if count == 0 {
            return Err(BuildError::NoParticles);
        }
        self.validate_particles(count)?;
        self.validate_springs(count)?;
        self.validate_faces(count)?;
        self.validate_segments(count)?;
        self.validate_gas()?;
        self.validate_rods(count)?;
        self.validate_muscles()?;
        self.limits.validate()?;
        if let (Some(value), false) = (self.limits.yield_strain, self.muscles.is_empty()) {
            return Err(BuildError::OutOfRange {
                field: "yield_strain",
                value,
                reason: "cannot be combined with `muscles`: a muscle's drive sets its spring's rest length every step, which would undo each yield",
            });
        }
        if self.rigid && count < 2 {
            return Err(BuildError::RigidTooSmall);
        }
        if self.rigid && !self.pinned.is_empty() {
            return Err(BuildError::RigidPinned);
        }
        if self.rigid && !self.muscles.is_empty() {
            return Err(BuildError::RigidMuscles);
        }
        if self.contact.self_collision && self.faces.is_empty() && self.segments.is_empty() {
            return Err(BuildError::SelfCollisionWithoutSurface);
        }
        if self.contact.self_collision && !self.contact.collide {
            return Err(BuildError::SelfCollisionWithoutCollide);
        }
        Ok(())
    }

    fn validate_segments(&self, count: usize) -> Result<(), BuildError> {
        for (segment, &[a, b]) in self.segments.iter().enumerate() {
            if a >= count || b >= count || a == b {
                return Err(BuildError::BadSegment {
                    segment,
                    indices: [a, b],
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_gas(&self) -> Result<(), BuildError> {
        let Some(gas) = &self.gas else {
            return Ok(());
        };
        gas.validate()?;
        let closed = if !self.faces.is_empty() {
            surface::check_closed_faces(&self.faces)
        } else if !self.segments.is_empty() {
            surface::check_closed_loop(&self.segments)
        } else {
            return Err(BuildError::GasWithoutSurface);
        };
        closed.map_err(|problem| BuildError::OpenSurface { problem })?;
        if self.faces.is_empty() {
            // A 2D gas takes the area its loop encloses in the xy-plane. A
            // z of a billionth of the body's size (or speed) is rounding: a
            // ring turned half a turn about x has z of some 1e-17.
            let off = |vectors: &[Vec3], what| {
                let size = vectors
                    .iter()
                    .fold(0.0, |m: Real, v| m.max(v.x.abs()).max(v.y.abs()));
                vectors
                    .iter()
                    .position(|v| v.z.abs() > 1e-9 * size)
                    .map(|particle| BuildError::GasOffPlane {
                        particle,
                        what,
                        value: vectors[particle].z,
                    })
            };
            if let Some(error) =
                off(&self.position, "z").or_else(|| off(&self.velocity, "velocity z"))
            {
                return Err(error);
            }
        }
        Ok(())
    }

    fn validate_particles(&self, count: usize) -> Result<(), BuildError> {
        check_len("masses", self.mass.len(), count, "particles")?;
        if !self.velocity.is_empty() {
            check_len("velocities", self.velocity.len(), count, "particles")?;
        }
        for (index, p) in self.position.iter().enumerate() {
            check_finite_vec("particles", index, *p)?;
        }
        for (index, v) in self.velocity.iter().enumerate() {
            check_finite_vec("velocities", index, *v)?;
        }
        for (index, &m) in self.mass.iter().enumerate() {
            if !(m.is_finite() && m > 0.0) {
                return Err(BuildError::BadMass {
                    field: "masses",
                    index,
                    value: m,
                });
            }
        }
        for (entry, &index) in self.pinned.iter().enumerate() {
            if index >= count {
                return Err(BuildError::PinnedOutOfRange {
                    entry,
                    index,
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_springs(&self, count: usize) -> Result<(), BuildError> {
        let mut seen: HashMap<(usize, usize), usize> = HashMap::with_capacity(self.springs.len());
        for (index, s) in self.springs.iter().enumerate() {
            let (first, second) = (s.first, s.second);
            if let Some(bad) = [first, second].into_iter().find(|&i| i >= count) {
                return Err(BuildError::SpringIndexOutOfRange {
                    spring: index,
                    first,
                    second,
                    bad,
                    particles: count,
                });
            }
            if first == second {
                return Err(BuildError::SelfSpring {
                    spring: index,
                    particle: first,
                });
            }
            let key = (first.min(second), first.max(second));
            if let Some(&earlier) = seen.get(&key) {
                return Err(BuildError::DuplicateSpring {
                    spring: index,
                    earlier,
                    first,
                    second,
                });
            }
            seen.insert(key, index);
            for (field, value) in [("stiffness", s.stiffness), ("damping", s.damping)] {
                if !value.is_finite() {
                    return Err(BuildError::NotFinite {
                        field,
                        index,
                        value,
                    });
                }
                if value < 0.0 {
                    return Err(BuildError::NegativeSpringCoefficient {
                        field,
                        spring: index,
                        value,
                    });
                }
            }
            let length = self.rest_length(s);
            if !length.is_finite() {
                return Err(BuildError::NotFinite {
                    field: "rest_lengths",
                    index,
                    value: length,
                });
            }
            if length <= 0.0 {
                return Err(BuildError::ZeroLengthSpring {
                    spring: index,
                    first,
                    second,
                    length,
                });
            }
        }
        Ok(())
    }

    fn validate_faces(&self, count: usize) -> Result<(), BuildError> {
        for (face, &indices) in self.faces.iter().enumerate() {
            let reason = if indices.iter().any(|&i| i >= count) {
                Some("particle index out of range")
            } else if indices[0] == indices[1]
                || indices[1] == indices[2]
                || indices[0] == indices[2]
            {
                Some("a face needs three different particles")
            } else {
                None
            };
            if let Some(reason) = reason {
                return Err(BuildError::BadFace {
                    face,
                    indices,
                    reason,
                    particles: count,
                });
            }
        }
        Ok(())
    }

    fn validate_rods(&self, count: usize) -> Result<(), BuildError> {
        for (rod, r) in self.rods.iter().enumerate() {
            if let Some(bad) = [r.first, r.second].into_iter().find(|&i| i >= count) {
                return Err(BuildError::RodIndexOutOfRange {
                    rod,
                    bad,
                    particles: count,
                });
            }
            let length = self.rod_length(r);
            if r.first == r.second || !(length.is_finite() && length > 0.0) {
                return Err(BuildError::BadRodLength { rod, length });
            }
            let pinned = |i| self.pinned.contains(&i);
            if pinned(r.first) && pinned(r.second) {
                return Err(BuildError::PinnedRod { rod });
            }
        }
        self.validate_rod_lengths()
    }

    /// Refuse rods whose lengths cannot all hold at once: two on the same
    /// two particles at different lengths, or a rod longer than a path of
    /// other rods joining its two ends (they would have to stretch; the
    /// constrain stage would pull forever and pump energy in). Three rods
    /// on a triangle, one longer than the other two together, are the
    /// commonest case. Each rod's ends are joined by the shortest path of
    /// the others shorter than it (Dijkstra's search, given up at the
    /// rod's length, so a rod among longer ones costs no more than its
    /// neighbours; it starts from the end with fewer rods); past
    /// [`ROD_SEARCH_LIMIT`] steps in all, the remaining rods are not
    /// checked. Lengths all taken from the positions always hold.
    fn validate_rod_lengths(&self) -> Result<(), BuildError> {
        // Lengths taken from the positions hold at once (they are the
        // distances of one placement), to rounding far below the slack.
        if self.rods.iter().all(|r| r.length.is_none()) {
            return Ok(());
        }
        let mut rod_of: HashMap<(usize, usize), usize> = HashMap::with_capacity(self.rods.len());
        let mut ends: HashMap<usize, Vec<(usize, usize)>> = HashMap::new();
        for (rod, r) in self.rods.iter().enumerate() {
            let key = (r.first.min(r.second), r.first.max(r.second));
            if let Some(&other) = rod_of.get(&key) {
                let (length, other_length) =
                    (self.rod_length(r), self.rod_length(&self.rods[other]));
                if (length - other_length).abs() > ROD_SLACK * length.max(other_length) {
                    return Err(BuildError::ConflictingRods {
                        rod,
                        length,
                        other,
                        other_length,
                    });
                }
                continue;
            }
            rod_of.insert(key, rod);
            ends.entry(key.0).or_default().push((key.1, rod));
            ends.entry(key.1).or_default().push((key.0, rod));
        }
        let mut budget = ROD_SEARCH_LIMIT;
        for (rod, r) in self.rods.iter().enumerate() {
            let key = (r.first.min(r.second), r.first.max(r.second));
            if rod_of.get(&key) != Some(&rod) {
                continue;
            }
            let length = self.rod_length(r);
            // From the end with fewer rods: a hub of many rods is reached
            // last, if at all.
            let degree = |p: usize| ends.get(&p).map_or(0, Vec::len);
            let (from, to) = if degree(r.first) <= degree(r.second) {
                (r.first, r.second)
            } else {
                (r.second, r.first)
            };
            let Some((mut path, together)) =
                self.shorter_path(&ends, rod, from, to, length, &mut budget)
            else {
                if budget == 0 {
                    break;
                }
                continue;
            };
            if from != r.first {
                path.reverse();
            }
            return Err(BuildError::RodLoop {
                rod,
                length,
                path,
                together,
            });
        }
        Ok(())
    }

    /// The rods (in order from `from` to `to`) of the shortest path between
    /// them through rods other than `rod`, and its length (m), if it is
    /// shorter than `length` (m) by more than [`ROD_SLACK`]. Each particle
    /// reached takes one from `budget`, and one for each of its rods;
    /// `None` as well when it runs out.
    fn shorter_path(
        &self,
        ends: &HashMap<usize, Vec<(usize, usize)>>,
        rod: usize,
        from: usize,
        to: usize,
        length: Real,
        budget: &mut usize,
    ) -> Option<(Vec<usize>, Real)> {
        use std::cmp::Reverse;
        use std::collections::BinaryHeap;
        /// A distance (m) ordered for the heap: lengths are finite and
        /// positive (checked before).
        struct Distance(Real);
        impl PartialEq for Distance {
            fn eq(&self, other: &Self) -> bool {
                self.cmp(other).is_eq()
            }
        }
        impl Eq for Distance {}
        impl PartialOrd for Distance {
            fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
                Some(self.cmp(other))
            }
        }
        impl Ord for Distance {
            fn cmp(&self, other: &Self) -> std::cmp::Ordering {
                self.0.total_cmp(&other.0)
            }
        }
        // Paths at least this long can hold with the rod.
        let bound = length / (1.0 + ROD_SLACK);
        // Per particle reached: its distance and the rod it was reached by.
        let mut reached: HashMap<usize, (Real, usize)> = HashMap::new();
        let mut heap = BinaryHeap::new();
        reached.insert(from, (0.0, rod));
        heap.push(Reverse((Distance(0.0), from)));
        while let Some(Reverse((Distance(distance), particle))) = heap.pop() {
            if distance >= bound || *budget == 0 {
                return None;
            }
            if reached.get(&particle).is_some_and(|&(d, _)| d < distance) {
                continue;
            }
            // A particle reached, and each of its rods looked at.
            let rods = ends.get(&particle).map_or(0, Vec::len);
            *budget = budget.saturating_sub(1 + rods);
            if particle == to {
                let mut path = Vec::new();
                let mut at = to;
                while at != from {
                    let via = reached[&at].1;
                    path.push(via);
                    let r = &self.rods[via];
                    at = if r.first == at { r.second } else { r.first };
                }
                path.reverse();
                return Some((path, distance));
            }
            for &(next, via) in ends.get(&particle).into_iter().flatten() {
                if via == rod {
                    continue;
                }
                let through = distance + self.rod_length(&self.rods[via]);
                if through < bound && reached.get(&next).is_none_or(|&(d, _)| through < d) {
                    reached.insert(next, (through, via));
                    heap.push(Reverse((Distance(through), next)));
                }
            }
        }
        None
    }

    fn validate_muscles(&self) -> Result<(), BuildError> {
        for (muscle, m) in self.muscles.iter().enumerate() {
            if self.muscles[..muscle].iter().any(|e| e.spring == m.spring) {
                return Err(BuildError::BadMuscle {
                    muscle,
                    field: "spring",
                    value: m.spring as Real,
                    reason: "another muscle drives this spring already: one muscle per spring",
                });
            }
            if m.spring >= self.springs.len() {
                return Err(BuildError::MuscleSpringOutOfRange {
                    muscle,
                    spring: m.spring,
                    springs: self.springs.len(),
                });
            }
            if let MuscleDrive::Sine {
                amplitude,
                period,
                phase,
            } = m.drive
            {
                let bad = |field, value, reason| {
                    Err(BuildError::BadMuscle {
                        muscle,
                        field,
                        value,
                        reason,
                    })
                };
                if !(amplitude.is_finite() && amplitude.abs() < 1.0) {
                    return bad(
                        "amplitude",
                        amplitude,
                        "|amplitude| must be below 1 (the rest length would reach zero)",
                    );
                }
                if !(period.is_finite() && period > 0.0) {
                    return bad("period", period, "must be a positive time (s)");
                }
                if !phase.is_finite() {
                    return bad("phase", phase, "must be a finite angle (rad)");
                }
            }
        }
        Ok(())
    }
}

fn check_len(
    field: &'static str,
    found: usize,
    expected: usize,
    what: &'static str,
) -> Result<(), BuildError> {
    if found == expected {
        Ok(())
    } else {
        Err(BuildError::LengthMismatch {
            field,
            expected,
            found,
            what,
        })
    }
}

fn check_finite_vec(field: &'static str, index: usize, v: Vec3) -> Result<(), BuildError> {
    match v.to_array().into_iter().find(|c| !c.is_finite()) {
        Some(value) => Err(BuildError::NotFinite {
            field,
            index,
            value,
        }),
        None => Ok(()),
    }
}
