//! Time integrators (PHYSICS.md §6).
//!
//! An integrator advances positions and velocities by one time step, asking a
//! [`Derivative`] for accelerations at whatever trial states it needs. It
//! owns its scratch buffers, sized on first use, so a step allocates nothing.
//! Pinned particles need no special case: their acceleration is zero and
//! their velocity stays zero.
//!
//! To add an integrator: a file here with a type implementing
//! [`Integrator`], a variant of [`IntegratorKind`] with its scene name, and a
//! line in [`IntegratorKind::create`].

mod euler;
mod midpoint;
mod rk4;
mod symplectic_euler;
mod verlet;

pub use euler::ExplicitEuler;
pub use midpoint::Midpoint;
pub use rk4::RungeKutta4;
pub use symplectic_euler::SymplecticEuler;
pub use verlet::Verlet;

use crate::{Real, Vec3};

/// The derivative function of the system: accelerations at a trial state.
pub trait Derivative {
    /// Write `a = f(x, v, t) / m` (m/s²) into `acceleration`, one entry per
    /// particle (zero for pinned particles).
    fn acceleration(
        &mut self,
        time: Real,
        position: &[Vec3],
        velocity: &[Vec3],
        acceleration: &mut [Vec3],
    );
}

/// A time-stepping method.
pub trait Integrator: Send + std::fmt::Debug {
    /// Which method this is.
    fn kind(&self) -> IntegratorKind;
    /// Advance `position` (m) and `velocity` (m/s) from `time` by `dt` (s).
    fn step(
        &mut self,
        time: Real,
        dt: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        system: &mut dyn Derivative,
    );
}

/// The integrators a scene can name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    /// Explicit (forward) Euler, order 1: gains energy.
    Euler,
    /// Semi-implicit (symplectic) Euler, order 1: bounded energy error.
    SymplecticEuler,
    /// Explicit midpoint (RK2), order 2.
    Midpoint,
    /// Classic Runge-Kutta, order 4.
    Rk4,
    /// Position (Störmer) Verlet, order 2.
    Verlet,
}

impl IntegratorKind {
    /// Every integrator, in the order of the documentation.
    pub const ALL: [IntegratorKind; 5] = [
        IntegratorKind::Euler,
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Midpoint,
        IntegratorKind::Rk4,
        IntegratorKind::Verlet,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Euler => "euler",
            IntegratorKind::SymplecticEuler => "symplectic_euler",
            IntegratorKind::Midpoint => "midpoint",
            IntegratorKind::Rk4 => "rk4",
            IntegratorKind::Verlet => "verlet",
        }
    }

    /// The integrator named `name` (as in scene files), if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The order of accuracy: global error ∝ dtᵖ.
    pub fn order(self) -> u32 {
        match self {
            IntegratorKind::Euler | IntegratorKind::SymplecticEuler => 1,
            IntegratorKind::Midpoint | IntegratorKind::Verlet => 2,
            IntegratorKind::Rk4 => 4,
        }
    }

    /// Derivative evaluations per step (the cost of a step, in force passes).
    pub fn evaluations_per_step(self) -> u32 {
        match self {
            IntegratorKind::Midpoint => 2,
            IntegratorKind::Rk4 => 4,
            _ => 1,
        }
    }

    /// A fresh integrator of this kind.
    pub fn create(self) -> Box<dyn Integrator> {
        match self {
            IntegratorKind::Euler => Box::new(ExplicitEuler::default()),
            IntegratorKind::SymplecticEuler => Box::new(SymplecticEuler::default()),
            IntegratorKind::Midpoint => Box::new(Midpoint::default()),
            IntegratorKind::Rk4 => Box::new(RungeKutta4::default()),
            IntegratorKind::Verlet => Box::new(Verlet::default()),
        }
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = String;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Self::from_name(name).ok_or_else(|| {
            let known: Vec<_> = Self::ALL.iter().map(|k| k.name()).collect();
            format!(
                "unknown integrator \"{name}\" (known: {})",
                known.join(", ")
            )
        })
    }
}

/// Resize a scratch buffer to `len` (allocates only when the size changes).
fn fit(buffer: &mut Vec<Vec3>, len: usize) {
    buffer.resize(len, Vec3::ZERO);
}
