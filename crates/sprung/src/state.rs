//! A world's state between steps, to stop a run and go on with it later
//! (checkpoints) with the same bits as a run that never stopped.
//!
//! Everything the scene builds again the same way (masses, springs,
//! bodies, forces, colliders and their paths, the gas schedule, the wind's
//! random modes drawn from its seed) is not part of the state. What is:
//! the time and step count, positions and velocities, the muscles' current
//! rest lengths, the rigid bodies' last rotations, the solver and rod
//! statistics, and the integrator's history (Verlet's previous positions,
//! the step `rk45` proposes next). [`World::save_state`] gathers it and
//! [`World::restore_state`] puts it back into a world built from the same
//! scene; `sprung-io` writes it to a file.
//!
//! [`World::save_state`]: crate::World::save_state
//! [`World::restore_state`]: crate::World::restore_state

use thiserror::Error;

use crate::units::{Real, Vec3};

/// Named arrays of numbers: the state of a world, or one part of it (an
/// integrator's history). Names are unique; the order is the order saved.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WorldState {
    /// The name of the integrator whose history is in the entries
    /// ([`crate::IntegratorKind::name`]).
    pub integrator: String,
    /// `(name, values)` pairs, in SI units as the fields they come from.
    pub entries: Vec<(String, Vec<Real>)>,
}

/// Why a saved state cannot be put back into a world.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum StateError {
    /// An entry the world needs is not in the state.
    #[error("the state has no `{0}`")]
    Missing(String),
    /// An entry has a different length than this world needs: the state
    /// belongs to another scene.
    #[error("the state's `{name}` has {found} numbers where this world needs {expected} (a state from another scene?)")]
    Length {
        /// The entry.
        name: String,
        /// Numbers this world needs.
        expected: usize,
        /// Numbers in the state.
        found: usize,
    },
    /// An entry holds a number that cannot be a state (NaN, inf, a
    /// negative count).
    #[error("the state's `{name}` has an impossible value {value} at {index}")]
    BadValue {
        /// The entry.
        name: String,
        /// Index of the number in the entry.
        index: usize,
        /// The number.
        value: Real,
    },
}

impl WorldState {
    /// Add `values` under `name` (replacing an entry of that name).
    pub fn put(&mut self, name: &str, values: Vec<Real>) {
        match self.entries.iter_mut().find(|(n, _)| n == name) {
            Some(entry) => entry.1 = values,
            None => self.entries.push((name.to_string(), values)),
        }
    }

    /// Add vectors under `name`, three numbers each.
    pub fn put_vectors(&mut self, name: &str, vectors: &[Vec3]) {
        self.put(name, vectors.iter().flat_map(|v| v.to_array()).collect());
    }

    /// The numbers under `name`, as they are.
    fn entry(&self, name: &str) -> Result<&[Real], StateError> {
        self.entries
            .iter()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v.as_slice())
            .ok_or_else(|| StateError::Missing(name.to_string()))
    }

    /// The entry `name`, which must hold `expected` finite numbers.
    pub fn get(&self, name: &str, expected: usize) -> Result<&[Real], StateError> {
        let values = self.entry(name)?;
        if values.len() != expected {
            return Err(StateError::Length {
                name: name.to_string(),
                expected,
                found: values.len(),
            });
        }
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(StateError::BadValue {
                name: name.to_string(),
                index,
                value,
            });
        }
        Ok(values)
    }

    /// The entry `name`, of any length, all finite numbers.
    pub fn get_any(&self, name: &str) -> Result<&[Real], StateError> {
        self.get(name, self.entry(name)?.len())
    }

    /// The entry `name` as `count` vectors.
    pub fn get_vectors(&self, name: &str, count: usize) -> Result<Vec<Vec3>, StateError> {
        Ok(self
            .get(name, 3 * count)?
            .chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect())
    }

    /// The entry `name` as one whole number below 2⁵³ (a step count).
    pub fn get_count(&self, name: &str) -> Result<u64, StateError> {
        let value = self.get(name, 1)?[0];
        if value < 0.0 || value.fract() != 0.0 || value > (1u64 << 53) as Real {
            return Err(StateError::BadValue {
                name: name.to_string(),
                index: 0,
                value,
            });
        }
        Ok(value as u64)
    }
}
