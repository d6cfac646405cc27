//! The one list of forces of a world.

use super::{
    Force, ForceContext, ImpulseContext, JacobianScale, Jacobians, Linearization, StiffnessBounds,
};
use crate::measure::{Energies, STANDARD_TERMS};
use crate::parallel;
use crate::springs::Springs;
use crate::units::Vec3;

/// Every force acting in a world, in the order they are added.
///
/// The explicit step ([`ForceList::accumulate`]), the stable-step estimate
/// ([`ForceList::add_stiffness`]), the energy ([`ForceList::add_energy`]),
/// the implicit solvers ([`ForceList::linearize`] and the Jacobian
/// products) and the friction stage ([`ForceList::apply_impulses`]) all
/// walk this list.
/// Built-in forces are reached by type: `world.forces.get_mut::<Wind>()`;
/// [`ForceList::set`] keeps at most one force of a type, [`ForceList::push`]
/// adds any number.
///
/// ```
/// use sprung::forces::{AirDrag, Gravity, MouseSpring};
/// use sprung::{IntegratorKind, Vec3, World};
///
/// let mut world = World::new(IntegratorKind::Verlet);
/// let built_in = world.forces.len(); // gravity, springs, gas, contacts
/// world.forces.set(AirDrag { coefficient: 0.1 });
/// world.forces.set(AirDrag { coefficient: 0.2 }); // replaces the first
/// assert_eq!(world.forces.len(), built_in + 1);
/// assert_eq!(world.forces.get::<AirDrag>().unwrap().coefficient, 0.2);
/// world.forces.get_mut::<Gravity>().unwrap().acceleration.y = -1.62;
/// assert_eq!(world.gravity(), Vec3::new(0.0, -1.62, 0.0));
/// // Two hands at once: `push` keeps both.
/// let hand = |particle| {
///     MouseSpring { particle, target: Vec3::ZERO, stiffness: 1.0, damping: 0.0 }
/// };
/// world.forces.push(Box::new(hand(0)));
/// world.forces.push(Box::new(hand(1)));
/// assert_eq!(world.forces.len(), built_in + 3);
/// assert_eq!(world.forces.remove::<MouseSpring>().map(|h| h.particle), Some(0));
/// ```
#[derive(Debug, Default)]
pub struct ForceList {
    forces: Vec<Box<dyn Force>>,
}

impl ForceList {
    /// An empty list.
    pub fn new() -> Self {
        ForceList::default()
    }

    /// Add `force` at the end of the list (any number of one type).
    pub fn push(&mut self, force: Box<dyn Force>) {
        self.forces.push(force);
    }

    /// Put `force` in place of the first force of its type, or at the end
    /// if there is none.
    pub fn set<F: Force>(&mut self, force: F) {
        match self.position::<F>() {
            Some(index) => self.forces[index] = Box::new(force),
            None => self.forces.push(Box::new(force)),
        }
    }

    /// Take the first force of type `F` out of the list.
    pub fn remove<F: Force>(&mut self) -> Option<F> {
        let index = self.position::<F>()?;
        let any: Box<dyn std::any::Any> = self.forces.remove(index);
        any.downcast::<F>().ok().map(|force| *force)
    }

    /// Index of the first force of type `F`.
    fn position<F: Force>(&self) -> Option<usize> {
        self.forces
            .iter()
            .position(|force| (force.as_ref() as &dyn std::any::Any).is::<F>())
    }

    /// The first force of type `F`, if any.
    pub fn get<F: Force>(&self) -> Option<&F> {
        self.forces
            .iter()
            .find_map(|force| (force.as_ref() as &dyn std::any::Any).downcast_ref::<F>())
    }

    /// The first force of type `F`, if any, to change.
    pub fn get_mut<F: Force>(&mut self) -> Option<&mut F> {
        self.forces
            .iter_mut()
            .find_map(|force| (force.as_mut() as &mut dyn std::any::Any).downcast_mut::<F>())
    }

    /// The forces, in order.
    pub fn iter(&self) -> impl Iterator<Item = &dyn Force> {
        self.forces.iter().map(|force| force.as_ref())
    }

    /// Number of forces.
    pub fn len(&self) -> usize {
        self.forces.len()
    }

    /// True when the list is empty.
    pub fn is_empty(&self) -> bool {
        self.forces.is_empty()
    }

    /// Set `force` to the sum of every force at the state of `context` (N):
    /// the first force written ([`Force::write`]) or the entries cleared,
    /// then every other force added, in order.
    pub fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        let written = self
            .forces
            .first_mut()
            .is_some_and(|first| first.write(context, force));
        if !written {
            parallel::for_each_span(&mut *force, |_, force| force.fill(Vec3::ZERO));
        }
        for f in self.forces.iter_mut().skip(usize::from(written)) {
            f.accumulate(context, force);
        }
    }

    /// Add every force's share of the stable-step bounds at `context`
    /// ([`Force::add_stiffness`]).
    pub fn add_stiffness(&self, context: &ForceContext, bounds: &mut StiffnessBounds) {
        for f in &self.forces {
            f.add_stiffness(context, bounds);
        }
    }

    /// Add every force's potential energy at `context` to its term of
    /// `energies` (J).
    pub fn add_energy(&self, context: &ForceContext, energies: &mut Energies) {
        for f in &self.forces {
            if let Some(name) = f.energy_name() {
                f.add_potential_energy(context, energies.term_mut(name));
            }
        }
    }

    /// The names of the energy's potential terms: the standard ones
    /// ([`STANDARD_TERMS`]), then those of the forces in the list that
    /// give another, in order (each once).
    pub fn energy_names(&self) -> Vec<&'static str> {
        let mut names = STANDARD_TERMS.to_vec();
        for name in self.forces.iter().filter_map(|f| f.energy_name()) {
            if !names.contains(&name) {
                names.push(name);
            }
        }
        names
    }

    /// The springs of the first force that is a sum of springs
    /// ([`Force::springs`]), for the solvers that stand in for them.
    pub fn springs<'a>(&self, context: &ForceContext<'a>) -> Option<&'a Springs> {
        self.forces.iter().find_map(|f| f.springs(context))
    }

    /// The friction stage: every force's impulses, in order
    /// ([`Force::apply_impulses`]).
    pub fn apply_impulses(&mut self, context: &mut ImpulseContext) {
        for f in &mut self.forces {
            f.apply_impulses(context);
        }
    }

    /// The sum of the forces' uniform accelerations (m/s²,
    /// [`Force::uniform_acceleration`]): gravity's.
    pub fn uniform_acceleration(&self) -> Vec3 {
        self.forces
            .iter()
            .fold(Vec3::ZERO, |sum, f| sum + f.uniform_acceleration())
    }

    /// The forces whose Jacobians `which` asks for at `context`.
    fn linearized<'s>(
        &'s self,
        context: &'s ForceContext,
        which: Jacobians,
    ) -> impl Iterator<Item = &'s dyn Force> {
        self.forces
            .iter()
            .map(|f| f.as_ref())
            .filter(move |f| asked_for(*f, context, which))
    }

    /// Linearise the forces `which` asks for at `context`; the least exact
    /// [`Linearization`] among those with Jacobian products
    /// ([`Linearization::has_products`]), or [`Linearization::Zero`] when
    /// none has: then [`ForceList::jacobian_products`] is zero.
    pub fn linearize(&mut self, context: &ForceContext, which: Jacobians) -> Linearization {
        self.forces
            .iter_mut()
            .filter(|f| asked_for(f.as_ref(), context, which))
            .map(|f| f.linearize(context))
            .filter(|l| l.has_products())
            .max()
            .unwrap_or(Linearization::Zero)
    }

    /// Set `out` to the sum of the Jacobian products with `p` of the forces
    /// `which` asks for (see [`Force::add_jacobian_products`]).
    pub fn jacobian_products(
        &self,
        context: &ForceContext,
        which: Jacobians,
        scale: JacobianScale,
        p: &[Vec3],
        out: &mut [Vec3],
    ) {
        parallel::for_each_span(&mut *out, |_, out| out.fill(Vec3::ZERO));
        for f in self.linearized(context, which) {
            f.add_jacobian_products(context, scale, p, out);
        }
    }

    /// Set `diagonal` to the sum of the Jacobian diagonals of the forces
    /// `which` asks for (see [`Force::add_jacobian_diagonal`]).
    pub fn jacobian_diagonal(
        &self,
        context: &ForceContext,
        which: Jacobians,
        scale: JacobianScale,
        diagonal: &mut [Vec3],
    ) {
        parallel::for_each_span(&mut *diagonal, |_, diagonal| diagonal.fill(Vec3::ZERO));
        for f in self.linearized(context, which) {
            f.add_jacobian_diagonal(context, scale, diagonal);
        }
    }
}

/// Whether `which` asks for the Jacobians of `force` at `context`: all,
/// or all but those of the forces that are sums of springs.
fn asked_for(force: &dyn Force, context: &ForceContext, which: Jacobians) -> bool {
    which == Jacobians::All || force.springs(context).is_none()
}
