//! Adding bodies to a world: checks against the world's limits, the
//! springs stored in the order the spring force reads fastest, the
//! rods, muscles and rigid bodies.

use crate::body::{Body, BodyData};
use crate::constrain::{Muscle, RigidBody};
use crate::error::BuildError;
use crate::order;
use crate::springs::{self};
use crate::surface;
use crate::units::{Real, Vec3};

use super::World;

impl World {
    /// Check `data` and add it as a body called `name`; returns the body's
    /// index. Nothing is added when the body is refused.
    ///
    /// A name can be used once:
    ///
    /// ```
    /// use sprung::{build, BuildError, IntegratorKind, World};
    ///
    /// let mut world = World::new(IntegratorKind::Verlet);
    /// let rope = build::rope(5, 1.0).unwrap().with_stiffness(100.0);
    /// assert_eq!(world.add_body("left", rope.clone()), Ok(0));
    /// assert_eq!(world.add_body("right", rope.clone()), Ok(1));
    /// assert_eq!(world.bodies[1].particles, 5..10);
    /// let again = world.add_body("left", rope);
    /// assert_eq!(again, Err(BuildError::DuplicateName("left".into())));
    /// assert_eq!(world.particles.len(), 10); // nothing added
    /// ```
    pub fn add_body(&mut self, name: &str, data: BodyData) -> Result<usize, BuildError> {
        data.validate()?;
        self.check_limits(&data)?;
        if name.is_empty() || name.contains([',', '"', '\n', '\r']) {
            return Err(BuildError::BadName(name.to_string()));
        }
        if self.names.contains_key(name) {
            return Err(BuildError::DuplicateName(name.to_string()));
        }
        let offset = self.particles.len();
        let mut pinned = vec![false; data.particle_count()];
        data.pinned.iter().for_each(|&i| pinned[i] = true);
        for (i, (&position, &mass)) in data.position.iter().zip(&data.mass).enumerate() {
            let velocity = data.velocity.get(i).copied().unwrap_or(Vec3::ZERO);
            self.particles.push(position, velocity, mass, pinned[i]);
        }
        let first_spring = self.springs.len();
        let index = |i: usize| (offset + i) as u32;
        // Runs of springs stepping along the particles first, then the rest
        // by lowest particle (in the numbering the spring force works in,
        // where the body's own has no locality): the orders the force reads
        // fastest (`springs::storage_order`).
        let ends: Vec<[u32; 2]> = data
            .springs
            .iter()
            .map(|s| [s.first as u32, s.second as u32])
            .collect();
        let mut order = springs::storage_order(&ends, None);
        let number = order::locality_numbering(&ends, &order, data.position.len());
        if number.is_some() {
            order = springs::storage_order(&ends, number.as_deref());
        }
        // Where each spring of the data went (for the muscles).
        let mut stored = vec![0; order.len()];
        for (place, &k) in order.iter().enumerate() {
            stored[k] = first_spring + place;
        }
        for s in order.iter().map(|&k| &data.springs[k]) {
            self.springs.push(
                index(s.first),
                index(s.second),
                data.rest_length(s),
                s.stiffness,
                s.damping,
                s.one_sided,
            );
        }
        self.limits
            .set(&self.springs, first_spring..self.springs.len(), data.limits);
        let mut body = Body {
            name: name.to_string(),
            particles: offset..self.particles.len(),
            springs: first_spring..self.springs.len(),
            faces: data.faces.iter().map(|f| f.map(index)).collect(),
            segments: data.segments.iter().map(|s| s.map(index)).collect(),
            closed: data.is_closed(),
            gas: data.gas.clone(),
            edges: surface::unique_edges(&data.faces)
                .into_iter()
                .map(|e| e.map(index))
                .collect(),
            contact: data.contact,
            rods: self.rods.len()..self.rods.len() + data.rods.len(),
            rigid: data.rigid,
            gravitating: data.gravitating,
            spring_numbering: number,
            scene_springs: stored.iter().map(|&k| (k - first_spring) as u32).collect(),
        };
        for rod in &data.rods {
            self.rods
                .push(index(rod.first), index(rod.second), data.rod_length(rod));
        }
        for muscle in &data.muscles {
            let spring = stored[muscle.spring];
            let rest_length = self.springs.rest_length[spring];
            let factor = muscle.drive.factor(self.time);
            if factor.is_finite() && factor > 0.0 {
                self.springs.rest_length[spring] = rest_length * factor;
            }
            self.muscles.list.push(Muscle {
                spring,
                rest_length,
                drive: muscle.drive.clone(),
            });
        }
        if data.rigid {
            self.rigid.list.push(RigidBody::new(
                body.particles.clone(),
                &self.particles.position,
                &self.particles.mass,
            ));
        }
        orient_outward(&mut body, &self.particles.position);
        self.names.insert(body.name.clone(), self.bodies.len());
        self.bodies.push(body);
        Ok(self.bodies.len() - 1)
    }

    /// Refuse a body that starts beyond the blow-up limits, or whose masses
    /// or stiffnesses would give energies that overflow within them.
    pub(super) fn check_limits(&self, data: &BodyData) -> Result<(), BuildError> {
        let limits = &self.settings;
        let g = self.gravity().length();
        let within = |field, vectors: &[Vec3], limit: Real| {
            vectors.iter().enumerate().try_for_each(|(index, &x)| {
                let value = magnitude(x);
                if value > limit {
                    Err(BuildError::BeyondLimit {
                        field,
                        index,
                        value,
                        limit,
                    })
                } else {
                    Ok(())
                }
            })
        };
        within("particles", &data.position, limits.max_distance)?;
        within("velocities", &data.velocity, limits.max_speed)?;
        // A rod longer than the world is wide cannot hold within it: its
        // ends would run past the limit at the first step.
        for (index, rod) in data.rods.iter().enumerate() {
            let value = data.rod_length(rod);
            if value > 2.0 * limits.max_distance {
                return Err(BuildError::BeyondLimit {
                    field: "rod_lengths",
                    index,
                    value,
                    limit: 2.0 * limits.max_distance,
                });
            }
        }
        let overflow = |field, index, value: Real, energy: Real| {
            (energy.is_nan() || energy >= crate::error::ENERGY_LIMIT).then_some(
                BuildError::EnergyOverflow {
                    field,
                    index,
                    value,
                    energy,
                },
            )
        };
        for (index, &m) in data.mass.iter().enumerate() {
            let energy = m * (g * limits.max_distance + 0.5 * limits.max_speed.powi(2));
            if let Some(error) = overflow("masses", index, m, energy) {
                return Err(error);
            }
        }
        for (index, s) in data.springs.iter().enumerate() {
            let reach = 2.0 * limits.max_distance;
            // Its ends within the world, a spring longer at rest than the
            // world is wide would hold more than the bound below allows.
            if let Some(value) = s.rest_length.filter(|&l| l > reach) {
                return Err(BuildError::BeyondLimit {
                    field: "rest_lengths",
                    index,
                    value,
                    limit: reach,
                });
            }
            let energy = 0.5 * s.stiffness * reach * reach;
            if let Some(error) = overflow("stiffness", index, s.stiffness, energy) {
                return Err(error);
            }
        }
        Ok(())
    }
}

/// `|x|` for a finite `x`, finite even where `|x|²` overflows (the
/// largest component when `|x|` itself would).
pub(super) fn magnitude(x: Vec3) -> Real {
    let largest = x.abs().max_element();
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    let length = largest * (x / largest).length();
    if length.is_finite() {
        length
    } else {
        largest
    }
}

/// Turn a closed body's faces (or segments) around if they enclose a
/// negative volume, so that their normals point out.
pub(super) fn orient_outward(body: &mut Body, position: &[Vec3]) {
    if body.enclosed_volume(position).is_some_and(|v| v < 0.0) {
        body.faces.iter_mut().for_each(|f| f.swap(1, 2));
        body.segments.iter_mut().for_each(|s| s.swap(0, 1));
    }
}
