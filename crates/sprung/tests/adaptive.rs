//! Time steps that adapt (docs/physics.md §6): the embedded Runge–Kutta pair
//! `rk45` (Dormand–Prince 5(4)) chooses its own internal steps, and
//! `substeps = "auto"` splits each step of the explicit integrators into as
//! many as the stability estimate asks. Claims: on motions that are fast
//! for a moment and slow the rest of the time (a bounce on a stiff floor, a
//! Kepler orbit of eccentricity 0.9), `rk45` reaches a given accuracy with
//! fewer force evaluations than fixed-step RK4 needs for the same
//! accuracy; its error follows its tolerance; automatic substeps turn a
//! run that blows up into a stable one.

mod common;

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use common::{rope, Watcher};
use sprung::forces::{Force, ForceContext, JacobianScale, Linearization, StiffnessBounds};
use sprung::{
    BodyData, Collider, ContactResponse, IntegratorKind, Real, Shape, StepError, Substeps, Vec3,
    World,
};

/// An inverse-square attraction of every particle towards the origin,
/// `f = -μ m r̂ / r²` (μ in m³/s²), with its potential `-μ m / r`.
#[derive(Debug)]
struct Sun {
    mu: Real,
}

impl Force for Sun {
    fn name(&self) -> &'static str {
        "sun"
    }
    fn accumulate(&mut self, context: &ForceContext, force: &mut [Vec3]) {
        for ((f, x), &m) in force.iter_mut().zip(context.position).zip(context.mass) {
            let r = x.length();
            *f -= self.mu * m / (r * r * r) * *x;
        }
    }
    /// Not counted: rk45 chooses the orbit's steps.
    fn add_stiffness(&self, _: &ForceContext, _: &mut StiffnessBounds) {}
    fn energy_name(&self) -> Option<&'static str> {
        Some("gravity")
    }
    fn add_potential_energy(&self, context: &ForceContext, energy: &mut Real) {
        for (x, &m) in context.position.iter().zip(context.mass) {
            *energy -= self.mu * m / x.length();
        }
    }
    fn linearize(&mut self, _: &ForceContext) -> Linearization {
        Linearization::Explicit
    }
    fn add_jacobian_products(
        &self,
        _: &ForceContext,
        _: JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }
    fn add_jacobian_diagonal(&self, _: &ForceContext, _: JacobianScale, _: &mut [Vec3]) {}
}

/// A world with one particle and a force counter, stepped by `kind`.
fn counted(kind: IntegratorKind, particle: BodyData) -> (World, Arc<AtomicUsize>) {
    let mut world = World::new(kind);
    world.add_body("p", particle).expect("valid particle");
    let count = Arc::new(AtomicUsize::new(0));
    let counter = Arc::clone(&count);
    world.forces.push(Box::new(Watcher(Box::new(move || {
        counter.fetch_add(1, Ordering::Relaxed);
    }))));
    (world, count)
}

/// A Kepler orbit of eccentricity 0.9 (μ = 1 m³/s², semi-major axis 1 m,
/// period 2π s), from aphelion: after one period the particle is back.
/// Returns the distance from its start (m) and the force evaluations.
fn kepler(kind: IntegratorKind, dt: Real, tolerance: Real) -> (Real, usize) {
    let e = 0.9;
    let start = Vec3::new(1.0 + e, 0.0, 0.0);
    let speed = ((1.0 - e) / (1.0 + e)).sqrt();
    let mut particle = BodyData::from_positions(vec![start]);
    particle.velocity = vec![Vec3::new(0.0, speed, 0.0)];
    let (mut world, count) = counted(kind, particle);
    world.set_gravity(Vec3::ZERO);
    world.forces.push(Box::new(Sun { mu: 1.0 }));
    world.settings.solver.error_tolerance = tolerance;
    let period = std::f64::consts::TAU;
    let steps = (period / dt).round() as usize;
    for _ in 0..steps {
        world.step(period / steps as Real).expect("stable");
    }
    (
        world.particles.position[0].distance(start),
        count.load(Ordering::Relaxed),
    )
}

/// A 1 kg particle dropped from 1 m onto a penalty floor of 1e5 N/m
/// (bounces last about 10 ms, the flights about 0.9 s) for 2 s. Returns the
/// final height (m) and the force evaluations.
fn bounce(kind: IntegratorKind, dt: Real, tolerance: Real) -> (Real, usize) {
    let particle = BodyData::from_positions(vec![Vec3::new(0.0, 1.0, 0.0)]);
    let (mut world, count) = counted(kind, particle);
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let penalty = ContactResponse::Penalty {
        stiffness: 1e5,
        damping: 0.0,
        friction: 0.0,
    };
    world
        .colliders
        .push(Collider::new(floor, penalty).expect("valid response"));
    world.settings.solver.error_tolerance = tolerance;
    for _ in 0..(2.0 / dt).round() as usize {
        world.step(dt).expect("stable");
    }
    (world.particles.position[0].y, count.load(Ordering::Relaxed))
}

/// The fewest force evaluations with which `run(dt or tolerance)` reaches
/// `accuracy` (its error against `reference`), halving the parameter from
/// `first`: returns the evaluations of the first parameter that does.
fn evaluations_for(
    accuracy: Real,
    first: Real,
    run: impl Fn(Real) -> (Real, usize),
    error: impl Fn(Real) -> Real,
) -> usize {
    let mut parameter = first;
    for _ in 0..40 {
        let (value, evaluations) = run(parameter);
        if error(value) <= accuracy {
            return evaluations;
        }
        parameter *= 0.5;
    }
    panic!("never reached {accuracy}");
}

#[test]
fn rk45_needs_fewer_force_evaluations_than_rk4_for_the_same_accuracy_on_an_eccentric_orbit() {
    // The exact orbit returns to its start after one period. RK4 needs a
    // step small enough for the perihelion pass (r = 0.1 m, where the
    // motion is 19 times faster than at aphelion) all the way round; rk45
    // takes short steps only there.
    for accuracy in [1e-3, 1e-6] {
        let rk4 = evaluations_for(
            accuracy,
            0.1,
            |dt| kepler(IntegratorKind::Rk4, dt, 1e-6),
            |distance| distance,
        );
        let rk45 = evaluations_for(
            accuracy,
            1e-3,
            |tolerance| kepler(IntegratorKind::Rk45, std::f64::consts::TAU / 8.0, tolerance),
            |distance| distance,
        );
        assert!(
            rk45 < rk4,
            "accuracy {accuracy} m: rk45 {rk45} evaluations, rk4 {rk4}"
        );
    }
}

#[test]
fn rk45_needs_fewer_force_evaluations_than_rk4_for_the_same_accuracy_on_a_bouncing_ball() {
    // The reference: RK4 at 2e-6 s (its error ~dt⁴ is far below the
    // accuracies asked). The floor's stiffness makes the bounces fast.
    let (reference, _) = bounce(IntegratorKind::Rk4, 2e-6, 1e-6);
    for accuracy in [1e-3, 1e-5] {
        let rk4 = evaluations_for(
            accuracy,
            1e-2,
            |dt| bounce(IntegratorKind::Rk4, dt, 1e-6),
            |height| (height - reference).abs(),
        );
        let rk45 = evaluations_for(
            accuracy,
            1e-3,
            |tolerance| bounce(IntegratorKind::Rk45, 0.1, tolerance),
            |height| (height - reference).abs(),
        );
        assert!(
            rk45 < rk4,
            "accuracy {accuracy} m: rk45 {rk45} evaluations, rk4 {rk4}"
        );
    }
}

#[test]
fn rk45_error_follows_its_tolerance() {
    // The global error over one orbit shrinks as the tolerance does (the
    // controller holds the local error at the tolerance; the global error
    // is a sum of them): ten times tighter, several times smaller.
    let (loose, _) = kepler(IntegratorKind::Rk45, std::f64::consts::TAU / 8.0, 1e-5);
    let (tight, _) = kepler(IntegratorKind::Rk45, std::f64::consts::TAU / 8.0, 1e-7);
    assert!(
        tight < loose / 10.0,
        "tolerance 1e-5: {loose} m; 1e-7: {tight} m"
    );
    assert!(tight < 1e-4, "tolerance 1e-7: {tight} m");
}

#[test]
fn automatic_substeps_turn_a_blow_up_into_a_stable_run() {
    // The stiff rope of the blow-up tests (20 masses of 10 g, 1e4 N/m) with
    // symplectic Euler at ten times its stable step blows up; with
    // `substeps = "auto"` each step is split into ⌈10 / 0.9⌉ = 12 (the
    // estimate times 0.9), and the energy stays within symplectic Euler's
    // bounded band.
    let build = |substeps: Substeps| {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world
            .add_body("rope", rope(20, 0.01, 1e4, 0.1))
            .expect("valid rope");
        world.settings.substeps = substeps;
        world
    };
    let mut plain = build(Substeps::Fixed(1));
    let dt = 10.0 * plain.stable_time_step();
    let blew_up = (0..200).any(|_| matches!(plain.step(dt), Err(StepError::BlowUp { .. })));
    assert!(blew_up, "expected the plain run to blow up");
    let mut auto = build(Substeps::Auto);
    let start = auto.energies().total();
    let start_gravity = auto.energies().get("gravity").expect("a standard term");
    let (mut worst, mut exchanged): (Real, Real) = (0.0, 0.0);
    for step in 1..=2000 {
        let report = auto.step(dt).unwrap_or_else(|e| panic!("step {step}: {e}"));
        assert_eq!(report.substeps, Some(12), "step {step}");
        let energies = auto.energies();
        worst = worst.max((energies.total() - start).abs());
        let gravity = energies.get("gravity").expect("a standard term");
        exchanged = exchanged.max((gravity - start_gravity).abs());
    }
    // Symplectic Euler keeps the energy in a band about h/2 times the
    // energy that oscillates (h = ω dt ≤ 1.8 at 0.9 of the stable step, for
    // the fastest mode only); the energy exchanged with gravity bounds what
    // oscillates. Measured: 7 % of it; we claim under half.
    assert!(
        worst <= 0.5 * exchanged,
        "energy off by {worst} J, {exchanged} J exchanged"
    );
}
