//! Springs as a structure of arrays: endpoints, rest length, stiffness and
//! damping in parallel `Vec`s.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::Real;

/// The next number [`Springs::topology`] hands out.
static NEXT_TOPOLOGY: AtomicU64 = AtomicU64::new(1);

/// The damped springs of a world (docs/physics.md §1), stored as parallel arrays.
///
/// Spring `s` joins particles `first()[s]` and `second()[s]`. A *one-sided*
/// spring pushes and pulls only its `second` (child) particle: rope builders
/// use it to keep segment lengths equal under load, at the price of momentum
/// conservation.
///
/// The endpoints change only through [`Springs::push`] and
/// [`Springs::set_endpoints`], which give the springs a new
/// [`Springs::topology`]: what is built from the endpoints (the force's
/// thread schedule, the projective solver's factor, the contact exclusions)
/// knows by that number when to build again. Rest lengths, stiffnesses and
/// damping may be changed in place.
#[derive(Debug, Clone, Default)]
pub struct Springs {
    /// Index of the first (parent) particle of each spring.
    first: Vec<u32>,
    /// Index of the second (child) particle of each spring.
    second: Vec<u32>,
    /// Rest length of each spring (m), positive.
    pub rest_length: Vec<Real>,
    /// Stiffness of each spring (N/m), non-negative.
    pub stiffness: Vec<Real>,
    /// Damping along each spring (N·s/m), non-negative.
    pub damping: Vec<Real>,
    /// Whether each spring acts on its second particle only.
    pub one_sided: Vec<bool>,
    /// Which endpoints these are (see [`Springs::topology`]).
    topology: u64,
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
        self.topology = NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed);
        self.rest_length.push(rest_length);
        self.stiffness.push(stiffness);
        self.damping.push(damping);
        self.one_sided.push(one_sided);
    }

    /// Index of the first (parent) particle of each spring.
    pub fn first(&self) -> &[u32] {
        &self.first
    }

    /// Index of the second (child) particle of each spring.
    pub fn second(&self) -> &[u32] {
        &self.second
    }

    /// The particles spring `s` joins, `[first, second]`.
    pub fn endpoints(&self, s: usize) -> [u32; 2] {
        [self.first[s], self.second[s]]
    }

    /// Join spring `s` to particles `first` and `second` instead.
    pub fn set_endpoints(&mut self, s: usize, first: u32, second: u32) {
        self.first[s] = first;
        self.second[s] = second;
        self.topology = NEXT_TOPOLOGY.fetch_add(1, Ordering::Relaxed);
    }

    /// A number that changes whenever the endpoints do, and that no other
    /// set of endpoints has had in this process (a clone keeps it: its
    /// endpoints are the same); 0 for none ever pushed.
    pub fn topology(&self) -> u64 {
        self.topology
    }
}
