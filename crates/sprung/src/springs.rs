//! Springs as a structure of arrays: endpoints, rest length, stiffness and
//! damping in parallel `Vec`s.

use crate::Real;

/// The damped springs of a world (PHYSICS.md §1), stored as parallel arrays.
///
/// Spring `s` joins particles `first[s]` and `second[s]`. A *one-sided*
/// spring pushes and pulls only its `second` (child) particle: rope builders
/// use it to keep segment lengths equal under load, at the price of momentum
/// conservation.
#[derive(Debug, Clone, Default)]
pub struct Springs {
    /// Index of the first (parent) particle of each spring.
    pub first: Vec<u32>,
    /// Index of the second (child) particle of each spring.
    pub second: Vec<u32>,
    /// Rest length of each spring (m), positive.
    pub rest_length: Vec<Real>,
    /// Stiffness of each spring (N/m), non-negative.
    pub stiffness: Vec<Real>,
    /// Damping along each spring (N·s/m), non-negative.
    pub damping: Vec<Real>,
    /// Whether each spring acts on its second particle only.
    pub one_sided: Vec<bool>,
}

impl Springs {
    /// Number of springs.
    pub fn len(&self) -> usize {
        self.first.len()
    }

    /// True when there are no springs.
    pub fn is_empty(&self) -> bool {
        self.first.is_empty()
    }

    /// Append one spring between particles `first` and `second` with rest
    /// length (m), stiffness (N/m) and damping (N·s/m).
    pub fn push(
        &mut self,
        first: u32,
        second: u32,
        rest_length: Real,
        stiffness: Real,
        damping: Real,
        one_sided: bool,
    ) {
        self.first.push(first);
        self.second.push(second);
        self.rest_length.push(rest_length);
        self.stiffness.push(stiffness);
        self.damping.push(damping);
        self.one_sided.push(one_sided);
    }
}
