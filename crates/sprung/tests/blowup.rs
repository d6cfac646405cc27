//! Stability (docs/physics.md §6): explicit methods are stable only below about
//! `2 / ω_max`, with `ω_max ≈ 2 √(k/m)` for a chain. The engine estimates
//! that step, stops a run that blows up with the step number and the
//! estimate, and refuses time steps that are not positive and finite.

mod common;

use std::f64::consts::PI;

use common::{rope, Rng};
use sprung::error::BlowUpReason;
use sprung::{BodyData, IntegratorKind, Real, SpringData, StepError, Vec3, World};

const FREE: usize = 20; // free masses below the pinned top
const MASS: Real = 0.01; // kg
const STIFFNESS: Real = 1e4; // N/m: √(k/m) = 1000 rad/s
const SPACING: Real = 0.1; // m

/// `1 / √(k/m)` (s): docs/physics.md's `2 / ω_max` with `ω_max = 2 √(k/m)`.
fn analytical_stable_dt() -> Real {
    1.0 / (STIFFNESS / MASS).sqrt()
}

/// A stiff hanging rope of [`FREE`] masses, with `gravity`.
fn stiff_rope(kind: IntegratorKind, gravity: Vec3) -> World {
    let mut world = World::new(kind);
    world.set_gravity(gravity);
    world
        .add_body("rope", rope(FREE, MASS, STIFFNESS, SPACING))
        .expect("valid rope");
    world
}

#[test]
fn stable_time_step_of_a_uniform_chain_is_one_over_sqrt_k_over_m() {
    let world = stiff_rope(IntegratorKind::SymplecticEuler, Vec3::ZERO);
    let estimate = world.stable_time_step();
    // `measure::stable_time_step` bounds ω_max² by Gershgorin's row sums of
    // M^-½ K M^-½. An interior particle of a uniform chain has two springs,
    // each adding k (1/m + 1/m): ω_max = √(4 k/m) = 2 √(k/m) exactly, so
    // the estimate is 1/√(k/m) to round-off (1e-12 relative).
    let expected = analytical_stable_dt();
    assert!(
        (estimate / expected - 1.0).abs() <= 1e-12,
        "estimate {estimate:e} s, expected 1/√(k/m) = {expected:e} s"
    );
    // It is conservative: the true ω_max of a fixed-free chain of N masses
    // is 2 √(k/m) sin((2N - 1) π / (2 (2N + 1))), slightly below the bound.
    let exact_omega_max = 2.0
        * (STIFFNESS / MASS).sqrt()
        * ((2 * FREE - 1) as Real * PI / (2.0 * (2 * FREE + 1) as Real)).sin();
    assert!(estimate <= 2.0 / exact_omega_max);
}

#[test]
fn stable_time_step_is_the_gershgorin_bound_for_unequal_masses() {
    // A uniform chain cannot tell the coupling term of the bound from 1/m_i.
    // Two free particles, m1 = 1 kg and m2 = 4 kg, on one spring k: the
    // mass-scaled stiffness matrix is k [[1/m1, -1/√(m1 m2)], [., 1/m2]], its
    // Gershgorin row sums k (1/m1 + 1/√(m1 m2)) = 1.5 k and 0.75 k, so the
    // documented estimate is 2 / √(1.5 k) (plus the same bound for the
    // damping: 2 / (√(1.5 k) + 1.5 c)). The exact ω² = k (1/m1 + 1/m2)
    // = 1.25 k, so the estimate is conservative.
    let (stiffness, damping): (Real, Real) = (100.0, 0.5);
    for c in [0.0, damping] {
        let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::X]);
        body.mass = vec![1.0, 4.0];
        body.springs.push(SpringData {
            stiffness,
            damping: c,
            ..SpringData::between(0, 1)
        });
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.add_body("pair", body).expect("valid pair");
        let estimate = world.stable_time_step();
        let expected = 2.0 / ((1.5 * stiffness).sqrt() + 1.5 * c);
        // 1e-12: the same arithmetic up to round-off.
        assert!(
            (estimate / expected - 1.0).abs() <= 1e-12,
            "c = {c}: estimate {estimate:e} s, expected {expected:e} s"
        );
        assert!(estimate <= 2.0 / (1.25 * stiffness).sqrt());
    }
}

#[test]
fn air_drag_limits_the_stable_step_and_the_estimate_says_so() {
    // One free particle of 1 g under air drag c = 2 N·s/m, nothing else:
    // symplectic Euler multiplies its velocity by 1 - (c/m) dt each step,
    // stable only below dt = 2 m / c = 1e-3 s. Claim: the estimate is that
    // step (to round-off, 1e-12), the same for a simple wind of the same
    // coefficient, and a run just above it grows (|1 - 2.2| > 1) while
    // one just below it decays: the estimate is the true limit here.
    let particle = || {
        let mut body = BodyData::from_positions(vec![Vec3::ZERO]);
        body.mass = vec![1e-3];
        body.velocity = vec![Vec3::X];
        body
    };
    let dusty = || {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        world.set_air_drag(2.0);
        world.add_body("dust", particle()).expect("valid body");
        world
    };
    let estimate = dusty().stable_time_step();
    assert!(
        (estimate / 1e-3 - 1.0).abs() <= 1e-12,
        "estimate {estimate:e} s"
    );
    for (dt, grows) in [(1.1e-3, true), (0.9e-3, false)] {
        let mut world = dusty();
        for _ in 0..50 {
            let _ = world.step(dt);
        }
        let speed = world.particles.velocity[0].length();
        assert_eq!(
            speed > 1.0 || !speed.is_finite(),
            grows,
            "dt {dt}: speed {speed}"
        );
    }
    let mut windy = World::new(IntegratorKind::SymplecticEuler);
    windy.set_gravity(Vec3::ZERO);
    let field = sprung::forces::WindField::uniform(Vec3::ZERO);
    let model = sprung::forces::WindModel::Simple { coefficient: 2.0 };
    windy
        .forces
        .set(sprung::forces::Wind::new(field, model).expect("a valid wind"));
    windy.add_body("dust", particle()).expect("valid body");
    let estimate = windy.stable_time_step();
    assert!(
        (estimate / 1e-3 - 1.0).abs() <= 1e-12,
        "wind: estimate {estimate:e} s"
    );
}

#[test]
fn explicit_euler_far_above_the_stable_step_blows_up_with_a_clear_error() {
    let mut world = stiff_rope(IntegratorKind::Euler, Vec3::new(0.0, -9.81, 0.0));
    let dt = 10.0 * analytical_stable_dt();
    // At ω_max dt = 20 the top mode grows by |1 + 20i| = 20 per step: from
    // the sag (~1e-4 m) to the 1e6 m (or 1e6 m/s) limit takes ~10 steps.
    let error = (0..1000)
        .find_map(|_| world.step(dt).err())
        .expect("explicit Euler at 10 times the stable step blows up");
    let StepError::BlowUp {
        step,
        time,
        particle,
        reason,
        dt: reported_dt,
        stable_dt,
        ..
    } = error.clone()
    else {
        panic!("expected a blow-up, got {error:?}");
    };
    assert!(step > 0, "step {step}");
    assert_eq!(
        step,
        world.steps(),
        "the step that blew up is the last taken"
    );
    assert_eq!(time, world.time());
    assert!(particle > 0 && particle <= FREE, "particle {particle}");
    match reason {
        BlowUpReason::NonFinite => {}
        BlowUpReason::TooFar(d) => assert!(d > world.settings.max_distance),
        BlowUpReason::TooFast(v) => assert!(v > world.settings.max_speed),
        BlowUpReason::OutOfShape { .. } => panic!("a chain without contact is never guarded"),
    }
    assert_eq!(reported_dt, dt);
    assert!(stable_dt.is_finite() && stable_dt < dt);
    // The estimate reported is the chain's 1/√(k/m), as above (1e-12).
    assert!(
        (stable_dt / analytical_stable_dt() - 1.0).abs() <= 1e-12,
        "stable_dt = {stable_dt:e} s, expected 1/√(k/m) = {:e} s",
        analytical_stable_dt()
    );
    let message = error.to_string();
    assert!(
        message.contains(&format!("step {step}")),
        "message does not name the step: {message}"
    );
}

#[test]
fn invalid_time_steps_are_refused_and_change_nothing() {
    let mut world = stiff_rope(IntegratorKind::SymplecticEuler, Vec3::new(0.0, -9.81, 0.0));
    let before = world.particles.position.clone();
    for dt in [0.0, -1e-3, Real::NAN, Real::INFINITY, Real::NEG_INFINITY] {
        match world.step(dt) {
            Err(StepError::InvalidTimeStep { dt: reported }) => {
                assert!(reported == dt || (reported.is_nan() && dt.is_nan()));
            }
            other => panic!("dt = {dt}: expected InvalidTimeStep, got {other:?}"),
        }
        let message = world.step(dt).unwrap_err().to_string();
        assert!(message.contains("dt"), "dt = {dt}: {message}");
    }
    assert_eq!(world.steps(), 0);
    assert_eq!(world.time(), 0.0);
    assert_eq!(world.particles.position, before);
}

/// A weightless rope with random longitudinal displacements (every mode
/// excited), stepped with symplectic Euler at `factor` times the engine's
/// stable step estimate for up to `steps` steps. Returns the blow-up error,
/// if any, and the largest `E / E0` seen.
fn symplectic_euler_at(factor: Real, steps: usize) -> (Option<StepError>, Real) {
    let mut world = stiff_rope(IntegratorKind::SymplecticEuler, Vec3::ZERO);
    let mut rng = Rng::new(3);
    // Along the rope (y) and 1 % of the spacing: the forces stay exactly
    // linear, and the energy splits into independent mode energies.
    for x in world.particles.position.iter_mut().skip(1) {
        x.y += 1e-3 * rng.symmetric();
    }
    let initial = world.energies().total();
    let dt = factor * world.stable_time_step();
    let mut highest: Real = 1.0;
    for _ in 0..steps {
        if let Err(error) = world.step(dt) {
            return (Some(error), highest);
        }
        highest = highest.max(world.energies().total() / initial);
    }
    (None, highest)
}

#[test]
fn symplectic_euler_is_bounded_just_below_the_estimate_and_blows_up_above() {
    // Below: every mode n has h = ω_n dt < 2, where symplectic Euler
    // conserves a modified energy Q_n = u² + (v/ω)² - h u v/ω (in units of
    // ½ k_n) with E_n (1 - h/2) ≤ Q_n ≤ E_n (1 + h/2) (conservation.rs); so
    // E(t) / E(0) ≤ (1 + h_max/2) / (1 - h_max/2), with
    // h_max = 0.99 · 2 sin((2N - 1) π / (2 (2N + 1))) ≈ 1.974 for the
    // fixed-free chain: a bound of ~154 that an unstable mode would cross
    // within a few dozen steps. 20 000 steps are ~240 periods of the
    // slowest mode.
    let factor = 0.99;
    let h_max = factor * 2.0 * ((2 * FREE - 1) as Real * PI / (2.0 * (2 * FREE + 1) as Real)).sin();
    let bound = (1.0 + h_max / 2.0) / (1.0 - h_max / 2.0);
    let (error, highest) = symplectic_euler_at(factor, 20_000);
    assert!(error.is_none(), "blew up below the estimate: {error:?}");
    assert!(
        highest <= bound,
        "E/E0 reached {highest:.3}, bound (1 + h/2)/(1 - h/2) = {bound:.3}"
    );
    // Above: at 1.5 times the estimate the top mode has h ≈ 2.99 > 2 and
    // grows by the root of λ² - (2 - h²) λ + 1 = 0, |λ| ≈ 6.8, per step:
    // from even 1e-16 m to the 1e6 m limit in under 30 steps.
    let (error, _) = symplectic_euler_at(1.5, 100);
    match error {
        Some(StepError::BlowUp { step, .. }) => assert!(step <= 30, "blew up late: {step}"),
        other => panic!("expected a blow-up at 1.5 times the estimate, got {other:?}"),
    }
}

#[test]
fn the_blow_up_message_names_the_body_of_the_particle() {
    // Two bodies; the second is a stiff chain driven far above its stable
    // step, so the particle that runs away belongs to body "chain".
    let mut world = World::new(IntegratorKind::Euler);
    world
        .add_body(
            "still",
            BodyData::from_positions(vec![Vec3::new(5.0, 0.0, 0.0)]).with_pinned(vec![0]),
        )
        .expect("valid");
    world
        .add_body(
            "chain",
            sprung::build::rope(6, 1.0)
                .expect("rope")
                .with_mass(0.01)
                .with_stiffness(1000.0),
        )
        .expect("valid");
    let error = (0..1000)
        .find_map(|_| world.step(0.02).err())
        .expect("blows up");
    let message = error.to_string();
    assert!(
        message.contains("(body \"chain\", its particle "),
        "{message}"
    );
}

#[test]
fn a_runaway_at_the_edge_of_the_numbers_is_reported_without_inf() {
    // A lone particle (nothing stiff: the stable estimate is infinite)
    // whose speed is set to 1e308 m/s along two axes: |v|² overflows, |v|
    // would be 1.4e308, still finite. The message gives finite figures
    // and no `inf`.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world
        .add_body("p", BodyData::from_positions(vec![Vec3::ZERO]))
        .unwrap();
    world.particles.velocity[0] = Vec3::new(1e308, 1e308, 0.0);
    // A step of 1e-303 s keeps it within max_distance (1.4e5 m).
    let error = world.step(1e-303).unwrap_err();
    let message = error.to_string();
    assert!(message.contains("ran away at 1.414e308 m/s"), "{message}");
    assert!(!message.contains("inf"), "{message}");
}

/// A change that puts particle `i` of a world out of bounds.
type Spoil = fn(&mut World, usize);

#[test]
fn the_guard_names_the_first_particle_out_of_bounds_and_why() {
    // A free rope without gravity at rest, one particle set out of bounds
    // after the step's integration cannot bring it back: a velocity at
    // 2x the speed limit stays above it (the springs' pull over one tiny
    // step is far smaller), a position at 2x the distance limit stays
    // beyond it, and a NaN or an infinity stays non-finite.
    let dt = 1e-9; // s
    let cases: [(usize, Spoil, &str); 4] = [
        (
            7,
            (|w, i| w.particles.velocity[i].x = 2.0 * w.settings.max_speed),
            "too fast",
        ),
        (
            FREE,
            (|w, i| w.particles.position[i].y = -2.0 * w.settings.max_distance),
            "too far",
        ),
        (3, (|w, i| w.particles.velocity[i].z = Real::NAN), "NaN"),
        (
            12,
            (|w, i| w.particles.position[i].x = Real::INFINITY),
            "infinite",
        ),
    ];
    for (particle, spoil, what) in cases {
        let mut world = stiff_rope(IntegratorKind::SymplecticEuler, Vec3::ZERO);
        spoil(&mut world, particle);
        let error = world.step(dt).expect_err(what);
        let StepError::BlowUp {
            particle: reported,
            reason,
            ..
        } = error
        else {
            panic!("{what}: expected a blow-up, got {error:?}");
        };
        // A NaN or an infinity spreads to the neighbours through their
        // springs within the step, so the first particle at fault is the
        // lower neighbour; the finite cases stay on their own particle.
        let first = if matches!(what, "NaN" | "infinite") {
            particle - 1
        } else {
            particle
        };
        assert_eq!(reported, first, "{what}");
        match (what, reason) {
            ("too fast", BlowUpReason::TooFast(v)) => assert!(v > world.settings.max_speed),
            ("too far", BlowUpReason::TooFar(d)) => assert!(d > world.settings.max_distance),
            ("NaN" | "infinite", BlowUpReason::NonFinite) => {}
            (_, reason) => panic!("{what}: reason {reason:?}"),
        }
    }
}

#[test]
fn the_guard_measures_the_distance_and_speed_not_each_coordinate() {
    // The guard first checks each coordinate against a bound below the
    // limit (`limit / 1.75`, so that three coordinates within it keep the
    // length within `√3 / 1.75` of the limit), and measures the length
    // exactly only where a coordinate is beyond that. A particle with one
    // coordinate at 0.9 of a limit is within it (a step of 1e-9 s moves
    // it by far less than the tenth of the limit left), and one with all
    // three at 0.58 of it is √3 · 0.58 = 1.005 times as far: only the
    // second stops the run (a bound per coordinate above 0.58 of the
    // limit, `limit / 1.7` say, would miss it).
    let dt = 1e-9; // s
    for (scale, stops) in [(0.9, false), (0.58, true)] {
        for what in ["distance", "speed"] {
            let mut world = stiff_rope(IntegratorKind::SymplecticEuler, Vec3::ZERO);
            let limit = match what {
                "distance" => world.settings.max_distance,
                _ => world.settings.max_speed,
            };
            let value = if stops {
                Vec3::splat(scale * limit)
            } else {
                Vec3::new(0.0, 0.0, scale * limit)
            };
            // The whole rope moved or set moving as one, so that no spring
            // is stretched by it.
            for i in 0..world.particles.len() {
                match what {
                    "distance" => world.particles.position[i] += value,
                    _ => world.particles.velocity[i] = value,
                }
            }
            let result = world.step(dt);
            match (stops, what, result) {
                (false, _, Ok(_)) => {}
                (
                    true,
                    "distance",
                    Err(StepError::BlowUp {
                        reason: BlowUpReason::TooFar(d),
                        ..
                    }),
                ) => {
                    assert!(d > limit, "{d} against {limit}")
                }
                (
                    true,
                    "speed",
                    Err(StepError::BlowUp {
                        reason: BlowUpReason::TooFast(v),
                        ..
                    }),
                ) => {
                    assert!(v > limit, "{v} against {limit}")
                }
                (_, _, result) => panic!("{what} at {scale} of the limit: {result:?}"),
            }
        }
    }
}
