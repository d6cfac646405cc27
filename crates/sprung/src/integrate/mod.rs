//! Time integrators (docs/physics.md §6).
//!
//! An integrator advances positions and velocities by one time step, asking a
//! [`Derivative`] for forces and accelerations at whatever trial states it
//! needs, and, for the implicit ones, for the products of the forces'
//! Jacobians with vectors. It owns its scratch buffers, sized on first use,
//! so a step allocates nothing. Pinned particles (inverse mass 0) need no
//! special case in the explicit methods: their acceleration is zero and
//! their velocity stays zero; the implicit ones treat them as constraints of
//! their linear solves.
//!
//! To add an integrator: a file here with a type implementing
//! [`Integrator`], a variant of [`IntegratorKind`] with its scene name, and a
//! line in [`IntegratorKind::create`].

mod dynamics;
mod euler;
mod implicit;
mod midpoint;
mod rk4;
mod rk45;
mod symplectic_euler;
mod verlet;

pub use dynamics::Dynamics;
pub use euler::ExplicitEuler;
pub use implicit::{
    measure_substitution, ImplicitEuler, Preconditioner, Projective, SolverSettings,
    SubstitutionFigures,
};
pub use midpoint::Midpoint;
pub use rk4::RungeKutta4;
pub use rk45::RungeKutta45;
pub use symplectic_euler::SymplecticEuler;
pub use verlet::Verlet;

use crate::colliders::ContactConstraint;
use crate::error::SolverError;
use crate::forces::{JacobianScale, Jacobians, Linearization};
use crate::parallel;
use crate::springs::Springs;
use crate::state::{StateError, WorldState};
use crate::units::{Real, Vec3};

pub use crate::model::State;

/// The system an integrator advances: its masses, and its forces and their
/// Jacobians at trial states.
pub trait Derivative {
    /// Particle masses (kg).
    fn mass(&self) -> &[Real];
    /// Inverse masses (1/kg); 0 marks a pinned particle, which stays where
    /// it is with zero velocity.
    fn inverse_mass(&self) -> &[Real];
    /// The springs of the forces that are sums of springs
    /// ([`crate::forces::Force::springs`]; none: no springs), which the
    /// projective solver and the Laplacian preconditioner build their
    /// matrix `M + dt² L` from.
    fn springs(&self) -> &Springs;
    /// The acceleration every particle's forces give it alike (m/s²):
    /// gravity's ([`crate::forces::ForceList::uniform_acceleration`]). The
    /// implicit solvers measure their residuals against the impulse it
    /// gives in a step.
    fn uniform_acceleration(&self) -> Vec3;
    /// Write the total force `f(x, v, t)` (N) into `force`, one entry per
    /// particle.
    fn force(&mut self, time: Real, position: &[Vec3], velocity: &[Vec3], force: &mut [Vec3]);
    /// Write `a = f(x, v, t) / m` (m/s²) into `acceleration`, one entry per
    /// particle (zero for pinned particles).
    fn acceleration(
        &mut self,
        time: Real,
        position: &[Vec3],
        velocity: &[Vec3],
        acceleration: &mut [Vec3],
    ) {
        self.force(time, position, velocity, acceleration);
        let inverse_mass = self.inverse_mass();
        parallel::for_each_span(acceleration, |start, a| {
            for (a, &w) in a.iter_mut().zip(&inverse_mass[start..]) {
                *a *= w;
            }
        });
    }
    /// Set `out` to the contacts with projection colliders over a step of
    /// `dt` (s) from `state` (see [`ContactConstraint`]); the implicit
    /// integrators hold them in their solves.
    fn contact_constraints(&self, state: State, dt: Real, out: &mut Vec<ContactConstraint>);
    /// Linearise the forces `which` asks for at `state`; the least exact
    /// [`Linearization`] among those with Jacobian products, or
    /// [`Linearization::Zero`] when their products are all zero.
    fn linearize(&mut self, state: State, which: Jacobians) -> Linearization;
    /// Set `out` to `scale.position ∂f/∂x·p + scale.velocity ∂f/∂v·p` (N
    /// per unit of `p`) for the forces `which` asks for, the Jacobians taken
    /// at `state`, which must be the state of the last
    /// [`Derivative::linearize`].
    fn jacobian_products(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    );
    /// Set `diagonal` to the diagonal of `scale.position ∂f/∂x +
    /// scale.velocity ∂f/∂v` at `state` (as for the products).
    fn jacobian_diagonal(
        &self,
        state: State,
        which: Jacobians,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    );
}

/// What one step of an integrator reports.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepReport {
    /// Iterations of the solver (conjugate-gradient iterations summed over
    /// the Newton iterations for implicit Euler, local/global iterations for
    /// the projective solver); `None` for the explicit methods.
    pub iterations: Option<u32>,
    /// The final relative residual of the linear solve (implicit Euler);
    /// `None` where there is none.
    pub residual: Option<Real>,
    /// True when the solver stopped at its iteration limit above its
    /// tolerance: the step was taken, but less accurately than asked.
    pub unconverged: bool,
    /// Internal steps taken (adaptive `rk45`, or `substeps` of the world);
    /// `None` for one plain step.
    pub substeps: Option<u32>,
    /// The length of the last internal step (s), where there were any.
    pub step_size: Option<Real>,
    /// The preconditioner of implicit Euler's last linear solve (never
    /// [`Preconditioner::Auto`]: the one it chose); `None` for the other
    /// methods.
    pub preconditioner: Option<Preconditioner>,
    /// How many times implicit Euler factored its stiffness preconditioner
    /// in the step (auto keeps a factor across steps and makes it again
    /// only when it stops paying); `None` for the other methods.
    pub refactorings: Option<u32>,
}

impl StepReport {
    /// This report followed by `next`, over consecutive substeps:
    /// iterations and internal steps add up, the residual is the larger,
    /// an unconverged solve in either is kept.
    pub fn then(self, next: StepReport) -> StepReport {
        let add = |a: Option<u32>, b: Option<u32>| match (a, b) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(0) + b.unwrap_or(0)),
        };
        StepReport {
            iterations: add(self.iterations, next.iterations),
            residual: match (self.residual, next.residual) {
                (Some(a), Some(b)) => Some(a.max(b)),
                (a, b) => a.or(b),
            },
            unconverged: self.unconverged || next.unconverged,
            substeps: add(self.substeps, next.substeps),
            step_size: next.step_size.or(self.step_size),
            preconditioner: next.preconditioner.or(self.preconditioner),
            refactorings: add(self.refactorings, next.refactorings),
        }
    }
}

/// A time-stepping method.
pub trait Integrator: Send + std::fmt::Debug {
    /// Which method this is.
    fn kind(&self) -> IntegratorKind;
    /// Advance `position` (m) and `velocity` (m/s) from `time` by `dt` (s),
    /// the implicit methods with the tolerances of `solver`.
    fn step(
        &mut self,
        time: Real,
        dt: Real,
        position: &mut [Vec3],
        velocity: &mut [Vec3],
        system: &mut dyn Derivative,
        solver: &SolverSettings,
    ) -> Result<StepReport, SolverError>;
    /// Add what this integrator carries from one step to the next (its
    /// history) to `state`, for a checkpoint. Methods that start every step
    /// afresh keep nothing: the default adds nothing, and an integrator
    /// with a history must override this and [`Integrator::restore_history`].
    fn save_history(&self, _state: &mut WorldState) {}
    /// Take back the history [`Integrator::save_history`] saved, for
    /// `particles` particles.
    fn restore_history(
        &mut self,
        _state: &WorldState,
        _particles: usize,
    ) -> Result<(), StateError> {
        Ok(())
    }
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
    /// Adaptive Runge–Kutta (Dormand–Prince 5(4)), order 5, its internal
    /// steps chosen to keep the local error within `error_tolerance`.
    Rk45,
    /// Position (Störmer) Verlet, order 2.
    Verlet,
    /// Implicit (backward) Euler by Newton's method and preconditioned
    /// conjugate gradients, order 1: stable at any step, dissipates.
    ImplicitEuler,
    /// Backward Euler by the local/global iterations of the fast
    /// mass-spring solver (Liu et al. 2013), order 1.
    Projective,
}

impl IntegratorKind {
    /// Every integrator, in the order of the documentation.
    pub const ALL: [IntegratorKind; 8] = [
        IntegratorKind::Euler,
        IntegratorKind::SymplecticEuler,
        IntegratorKind::Midpoint,
        IntegratorKind::Rk4,
        IntegratorKind::Rk45,
        IntegratorKind::Verlet,
        IntegratorKind::ImplicitEuler,
        IntegratorKind::Projective,
    ];

    /// The name used in scene files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            IntegratorKind::Euler => "euler",
            IntegratorKind::SymplecticEuler => "symplectic_euler",
            IntegratorKind::Midpoint => "midpoint",
            IntegratorKind::Rk4 => "rk4",
            IntegratorKind::Rk45 => "rk45",
            IntegratorKind::Verlet => "verlet",
            IntegratorKind::ImplicitEuler => "implicit_euler",
            IntegratorKind::Projective => "projective",
        }
    }

    /// The integrator named `name` (as in scene files), if any.
    ///
    /// ```
    /// use sprung::IntegratorKind;
    ///
    /// assert_eq!(IntegratorKind::from_name("rk4"), Some(IntegratorKind::Rk4));
    /// assert_eq!(IntegratorKind::from_name("RK4"), None); // names are lower case
    /// for kind in IntegratorKind::ALL {
    ///     assert_eq!(IntegratorKind::from_name(kind.name()), Some(kind));
    ///     assert_eq!(kind.name().parse(), Ok(kind));
    /// }
    /// let error = "leapfrog".parse::<IntegratorKind>().unwrap_err();
    /// assert!(error.to_string().starts_with("unknown integrator \"leapfrog\" (known: euler, "));
    /// ```
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }

    /// The order of accuracy: global error ∝ dtᵖ.
    ///
    /// # Examples
    ///
    /// Halving the step divides the error by about `2^order`. A particle on a
    /// spring (`k = 100 N/m`, `m = 1 kg`) to a pinned one, released 0.2 m from
    /// rest, moves as `x(t) = 0.8 + 0.2 cos(10 t)`:
    ///
    /// ```
    /// use sprung::{BodyData, IntegratorKind, SpringData, Vec3, World};
    ///
    /// let error = |kind: IntegratorKind, dt: f64| {
    ///     let mut world = World::new(kind);
    ///     world.set_gravity(Vec3::ZERO);
    ///     let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]).with_pinned(vec![0]);
    ///     body.springs = vec![SpringData { rest_length: Some(0.8), ..SpringData::between(0, 1) }];
    ///     world.add_body("oscillator", body.with_stiffness(100.0)).unwrap();
    ///     for _ in 0..(1.0 / dt).round() as usize {
    ///         world.step(dt).unwrap();
    ///     }
    ///     (world.particles.position[1].x - (0.8 + 0.2 * 10_f64.cos())).abs()
    /// };
    /// use IntegratorKind::{Midpoint, Rk4, SymplecticEuler, Verlet};
    /// for kind in [SymplecticEuler, Midpoint, Verlet, Rk4] {
    ///     let ratio = error(kind, 0.01) / error(kind, 0.005);
    ///     let expected = 2_f64.powi(kind.order() as i32);
    ///     // Within 15 %: at these steps the error's next term still counts.
    ///     assert!((ratio / expected - 1.0).abs() < 0.15);
    /// }
    /// ```
    pub fn order(self) -> u32 {
        match self {
            IntegratorKind::Euler
            | IntegratorKind::SymplecticEuler
            | IntegratorKind::ImplicitEuler
            | IntegratorKind::Projective => 1,
            IntegratorKind::Midpoint | IntegratorKind::Verlet => 2,
            IntegratorKind::Rk4 => 4,
            IntegratorKind::Rk45 => 5,
        }
    }

    /// True for the methods that solve equations at each step (and read
    /// [`SolverSettings`]).
    ///
    /// ```
    /// use sprung::IntegratorKind;
    ///
    /// let all = IntegratorKind::ALL.into_iter();
    /// let implicit: Vec<_> = all.filter(|k| k.is_implicit()).collect();
    /// assert_eq!(implicit, [IntegratorKind::ImplicitEuler, IntegratorKind::Projective]);
    /// ```
    pub fn is_implicit(self) -> bool {
        matches!(
            self,
            IntegratorKind::ImplicitEuler | IntegratorKind::Projective
        )
    }

    /// Force evaluations per step of the explicit methods (the cost of a
    /// step, in force passes; for `rk45`, per internal step); for the
    /// implicit ones it depends on the iterations, and this gives the
    /// least, 1.
    pub fn evaluations_per_step(self) -> u32 {
        match self {
            IntegratorKind::Midpoint => 2,
            IntegratorKind::Rk4 => 4,
            IntegratorKind::Rk45 => 6,
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
            IntegratorKind::Rk45 => Box::new(RungeKutta45::default()),
            IntegratorKind::Verlet => Box::new(Verlet::default()),
            IntegratorKind::ImplicitEuler => Box::new(ImplicitEuler::default()),
            IntegratorKind::Projective => Box::new(Projective::default()),
        }
    }
}

impl std::fmt::Display for IntegratorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for IntegratorKind {
    type Err = crate::unknown::UnknownName;

    fn from_str(name: &str) -> Result<Self, Self::Err> {
        Self::from_name(name).ok_or_else(|| {
            crate::unknown::UnknownName::new("integrator", name, Self::ALL.map(|k| k.name()))
        })
    }
}

/// Resize a scratch buffer to `len` (allocates only when the size changes).
fn fit(buffer: &mut Vec<Vec3>, len: usize) {
    buffer.resize(len, Vec3::ZERO);
}
