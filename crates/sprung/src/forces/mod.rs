//! Forces: small types that add their contribution to the force buffer, and
//! their derivatives for the implicit solvers.
//!
//! Every force of a world lives in one [`ForceList`] (`World::forces`):
//! gravity, the springs, the gas, air drag, wind, the user's hand, penalty
//! contacts and anything a user adds. The explicit step, the energy, the
//! implicit solvers and the threads all walk that list, so a force is
//! written once and works everywhere.
//!
//! Each force sees the trial state through a [`ForceContext`] (integrators
//! evaluate forces at intermediate states, so forces never read the world's
//! stored positions directly) and
//!
//! - adds its force (N) into a buffer ([`Force::accumulate`]);
//! - adds its share of the stable-step bounds ([`Force::add_stiffness`]),
//!   which the stable-step estimate and `substeps = "auto"` walk the list
//!   for;
//! - names its potential-energy term and adds its energy (J) to it
//!   ([`Force::energy_name`], [`Force::add_potential_energy`]): the
//!   energy's terms, the columns of `diagnostics.csv` and the plots come
//!   from the list;
//! - for the implicit solvers, linearises itself at a state
//!   ([`Force::linearize`]) and then gives the products of its Jacobians
//!   with any vector, `α ∂f/∂x·p + β ∂f/∂v·p` ([`Force::add_jacobian_products`]),
//!   and the diagonal of those Jacobians ([`Force::add_jacobian_diagonal`])
//!   for the preconditioner.
//!
//! None of these has a default: a force says how stiff it is, what energy
//! it has and how it takes part in an implicit solve ([`Linearization`]),
//! so none is left out by accident. What only some forces do has a
//! default that does nothing: the springs the projective solver stands in
//! for ([`Force::springs`]), impulses in the friction stage
//! ([`Force::apply_impulses`]), and a uniform acceleration
//! ([`Force::uniform_acceleration`], gravity's).
//!
//! To add a force: a type implementing [`Force`] in its own file here, added
//! with `world.forces.push(...)` (or [`ForceList::set`] for one of a kind).

mod applied;
mod body_contacts;
mod bounds;
mod colliders;
mod drag;
mod faces;
mod gravitation;
mod gravity;
mod jacobian;
mod list;
mod mouse;
mod pressure;
mod spring;
mod wind;
mod wind_field;

pub use crate::contact::ImpulseContext;
pub use applied::AppliedForces;
pub use body_contacts::BodyContacts;
pub use bounds::StiffnessBounds;
pub use colliders::ColliderContacts;
pub use drag::AirDrag;
pub use gravitation::{
    gravitating_pairs, gravitating_particles, Gravitation, GRAVITATIONAL_CONSTANT, MAX_GRAVITATING,
};
pub use gravity::Gravity;
pub(crate) use jacobian::NormalPush;
pub use list::ForceList;
pub use mouse::MouseSpring;
pub use pressure::{pressure, GasPressure};
#[doc(hidden)]
pub use spring::pulls_alone;
pub(crate) use spring::SpringJacobian;
pub use spring::{spring_energy, SpringForce};
pub use wind::{Wind, WindModel, AIR_DENSITY};
pub use wind_field::{Gusts, Turbulence, TurbulentMode, WindField};

use crate::body::Body;
use crate::colliders::Collider;
use crate::contact::Contacts;
use crate::model::{Model, State};
use crate::springs::Springs;
use crate::units::{Real, Vec3};

/// The state a force is evaluated at, and the world it belongs to.
#[derive(Debug, Clone, Copy)]
pub struct ForceContext<'a> {
    /// Simulated time (s).
    pub time: Real,
    /// Trial positions (m).
    pub position: &'a [Vec3],
    /// Trial velocities (m/s).
    pub velocity: &'a [Vec3],
    /// Particle masses (kg).
    pub mass: &'a [Real],
    /// Inverse masses (1/kg), zero for pinned particles.
    pub inverse_mass: &'a [Real],
    /// The world's springs.
    pub springs: &'a Springs,
    /// The world's bodies.
    pub bodies: &'a [Body],
    /// The world's colliders (penalty contacts read them).
    pub colliders: &'a [Collider],
    /// Contact between bodies: settings and the step's candidate pairs.
    pub contacts: &'a Contacts,
}

impl<'a> ForceContext<'a> {
    /// What a force sees: `model`'s data at `state`.
    pub fn new(model: Model<'a>, state: State<'a>) -> Self {
        ForceContext {
            time: state.time,
            position: state.position,
            velocity: state.velocity,
            mass: model.mass,
            inverse_mass: model.inverse_mass,
            springs: model.springs,
            bodies: model.bodies,
            colliders: model.colliders,
            contacts: model.contacts,
        }
    }
}

/// The weights of a Jacobian product: `position ∂f/∂x·p + velocity ∂f/∂v·p`.
///
/// Implicit Euler's matrix `M - dt ∂f/∂v - dt² ∂f/∂x` takes the products
/// with `position = dt²`, `velocity = dt` (and subtracts them).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JacobianScale {
    /// Weight of the position Jacobian `∂f/∂x` (N/m per unit of `p`).
    pub position: Real,
    /// Weight of the velocity Jacobian `∂f/∂v` (N·s/m per unit of `p`).
    pub velocity: Real,
}

/// Whose Jacobians a solver asks the force list for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Jacobians {
    /// Every force's (implicit Euler).
    All,
    /// Every force's but the springs' (the projective solver stands in for
    /// the springs with its constant matrix `M + dt² L`).
    AllButSprings,
}

/// How a force takes part in an implicit solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Linearization {
    /// Its Jacobian is zero at this state: the force depends on neither
    /// the positions nor the velocities (gravity, applied forces), or acts
    /// on no particle now (a contact force with nothing touching).
    Zero,
    /// Its Jacobian products are exact (drag, the hand).
    Exact,
    /// Its Jacobian products are a symmetric, definite approximation of the
    /// exact ones (springs under compression, the curvature of a sphere
    /// collider, friction left out): the linear solve converges, and more
    /// Newton iterations still reach the exact backward-Euler solution
    /// because the residual uses the exact force.
    Approximate,
    /// It has no Jacobian products: within one linearised step it acts with
    /// its value at the start of the step (gas pressure, wind). Further
    /// Newton iterations re-evaluate it.
    Explicit,
}

impl Linearization {
    /// Whether the force adds Jacobian products: not when they are zero
    /// ([`Linearization::Zero`]) or left out ([`Linearization::Explicit`]).
    pub fn has_products(self) -> bool {
        matches!(self, Linearization::Exact | Linearization::Approximate)
    }
}

/// A force acting on the particles.
///
/// A force answers for itself everywhere the step needs it: its force
/// ([`Force::accumulate`]), its share of the explicit methods' stable step
/// ([`Force::add_stiffness`]), its potential energy under its own name
/// ([`Force::energy_name`], [`Force::add_potential_energy`]) and its
/// Jacobians for the implicit solvers ([`Force::linearize`] and the
/// products). None of these has a default, so a force cannot be left out
/// of the stable step or the energy by accident: a force that is not stiff
/// says so with an empty [`Force::add_stiffness`].
///
/// `Any` lets a [`ForceList`] hand back a force of a given type
/// ([`ForceList::get`]), so a user can reach the wind or the hand by type.
///
/// A force of one's own, a spring of zero rest length tying particle 0 to
/// a point (its stiffness bound is `k / m` on that particle):
///
/// ```
/// use sprung::forces::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
/// use sprung::{Real, Vec3};
///
/// #[derive(Debug)]
/// struct Tether { anchor: Vec3, stiffness: Real }
///
/// impl Force for Tether {
///     fn name(&self) -> &'static str { "tether" }
///     fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
///         force[0] += self.stiffness * (self.anchor - context.position[0]);
///     }
///     fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
///         bounds.stiffness[0] += self.stiffness * context.inverse_mass[0];
///     }
///     fn energy_name(&self) -> Option<&'static str> { Some("tether") }
///     fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
///         *energy += 0.5 * self.stiffness * context.position[0].distance_squared(self.anchor);
///     }
///     fn linearize(&mut self, _: &ForceContext) -> Linearization { Linearization::Exact }
///     fn add_jacobian_products(&self, _: &ForceContext, scale: JacobianScale, p: &[Vec3], out: &mut [Vec3]) {
///         out[0] -= scale.position * self.stiffness * p[0];
///     }
///     fn add_jacobian_diagonal(&self, _: &ForceContext, scale: JacobianScale, diagonal: &mut [Vec3]) {
///         diagonal[0] -= Vec3::splat(scale.position * self.stiffness);
///     }
/// }
///
/// let mut world = sprung::World::new(sprung::IntegratorKind::SymplecticEuler);
/// world.add_body("bob", sprung::BodyData::from_positions(vec![Vec3::ZERO])).unwrap();
/// world.forces.push(Box::new(Tether { anchor: Vec3::X, stiffness: 400.0 }));
/// // ω = √(k/m) = 20 rad/s: the stable step is 2/ω.
/// assert!((world.stable_time_step() - 0.1).abs() < 1e-15);
/// assert_eq!(world.energies().get("tether"), Some(200.0));
/// ```
///
/// Without [`Force::add_stiffness`] it does not compile:
///
/// ```compile_fail
/// use sprung::forces::{Force, ForceContext, JacobianScale, Linearization};
/// use sprung::{Real, Vec3};
///
/// #[derive(Debug)]
/// struct Tether { anchor: Vec3, stiffness: Real }
///
/// impl Force for Tether {
///     fn name(&self) -> &'static str { "tether" }
///     fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
///         force[0] += self.stiffness * (self.anchor - context.position[0]);
///     }
///     fn energy_name(&self) -> Option<&'static str> { Some("tether") }
///     fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
///         *energy += 0.5 * self.stiffness * context.position[0].distance_squared(self.anchor);
///     }
///     fn linearize(&mut self, _: &ForceContext) -> Linearization { Linearization::Exact }
///     fn add_jacobian_products(&self, _: &ForceContext, scale: JacobianScale, p: &[Vec3], out: &mut [Vec3]) {
///         out[0] -= scale.position * self.stiffness * p[0];
///     }
///     fn add_jacobian_diagonal(&self, _: &ForceContext, scale: JacobianScale, diagonal: &mut [Vec3]) {
///         diagonal[0] -= Vec3::splat(scale.position * self.stiffness);
///     }
/// }
/// ```
pub trait Force: Send + Sync + std::fmt::Debug + std::any::Any {
    /// A short name for messages.
    fn name(&self) -> &'static str;
    /// Add this force (N) to `force`, one entry per particle. `&mut self`
    /// lets a force keep scratch buffers (per-particle normals, say) sized
    /// on first use, so a step allocates nothing.
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]);
    /// Write this force (N) into `force` in place of what is there, when it
    /// can do so in the same pass as adding it, and say so; `false` (the
    /// default): it wrote nothing. The first force of a [`ForceList`] that
    /// writes saves the pass that clears the forces.
    fn write(&mut self, context: &ForceContext, force: &mut [Vec3]) -> bool {
        let _ = (context, force);
        false
    }
    /// Add this force's share of the bounds the explicit methods' stable
    /// step is computed from, at the state of `context`: for each particle
    /// `i`, to `bounds.stiffness[i]` (1/s²) the sum over `j` of
    /// `|K_ij| / √(m_i m_j)` (`K = -∂f/∂x`, N/m) and to
    /// `bounds.damping[i]` (1/s) the same for `D = -∂f/∂v` (N·s/m): the
    /// rows of the mass-scaled Jacobians, whose largest eigenvalues
    /// Gershgorin's theorem bounds by them (see [`StiffnessBounds`]). The
    /// stable-step estimate and `substeps = "auto"` walk the list, so a
    /// stiff force that adds nothing here lets them take steps it blows up
    /// at. A force that is neither stiff nor damping (gravity, gas pressure)
    /// adds nothing, with an empty body.
    fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds);
    /// The name of this force's potential-energy term (a column of
    /// `diagnostics.csv`: `"spring"`, `"gravity"`, ...; forces that give
    /// the same name add into one term), or `None` for a force without a
    /// potential (drag, wind, the hand).
    fn energy_name(&self) -> Option<&'static str>;
    /// Add this force's potential energy (J) at `context` to `energy`, the
    /// running value of its term ([`Force::energy_name`]); a force without
    /// a potential adds nothing.
    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real);
    /// Prepare the Jacobians at the state of `context` (cache what the
    /// products need) and say how exact they are.
    fn linearize(&mut self, context: &ForceContext) -> Linearization;
    /// Add `scale.position ∂f/∂x·p + scale.velocity ∂f/∂v·p` to `out`, one
    /// entry per particle, with the Jacobians at the state of the last
    /// [`Force::linearize`] (the same `context`).
    fn add_jacobian_products(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    );
    /// Add the diagonal entries of `scale.position ∂f/∂x + scale.velocity
    /// ∂f/∂v` (the x, y, z entries of each particle's own 3×3 block) to
    /// `diagonal`, at the state of the last [`Force::linearize`].
    fn add_jacobian_diagonal(
        &self,
        context: &ForceContext,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    );
    /// The springs this force is the sum of, for the solvers that stand in
    /// for springs with the constant matrix `M + dt² L` of their graph
    /// Laplacian (the projective solver, the Laplacian preconditioner): the
    /// spring force gives the world's springs, and the projective solver
    /// then leaves its Jacobians out ([`Jacobians::AllButSprings`]). `None`
    /// (the default) for every other force.
    fn springs<'a>(&self, context: &ForceContext<'a>) -> Option<&'a Springs> {
        let _ = context;
        None
    }
    /// The friction stage: change the velocities (and positions) at the
    /// end of a (sub)step by this force's impulses (Coulomb friction between
    /// bodies, on the touches the contact force last pushed). Nothing by
    /// default.
    fn apply_impulses(&mut self, context: &mut ImpulseContext) {
        let _ = context;
    }
    /// The acceleration (m/s²) this force gives every particle alike,
    /// whatever its mass and state: gravity's; zero (the default) for any
    /// other force. The world's checks read the sum over the list
    /// ([`crate::World::gravity`]): the energy a body can gain falling
    /// across the world, and the speed below which a rigid body rests.
    fn uniform_acceleration(&self) -> Vec3 {
        Vec3::ZERO
    }
}
