//! The gas inside a pressurised ring (docs/physics.md §4, §7): it settles
//! at the radius where pressure balances the springs; on the floor it
//! keeps its area only with gas; and the `nRT` schedule ramps, follows
//! keyframes and leaks as specified.
//!
//! Ring notation: `N` particles of mass `m`, springs of stiffness `k` and
//! rest length `L0 = 2 R0 s` on a circle of radius `R0`, `s = sin(π/N)`.
//! At the regular N-gon of circumradius `R` the gas pushes each vertex out
//! with `(nRT/A) L cos(π/N) = 2 nRT / (N R)` (`A = N R² s cos(π/N)`,
//! `L = 2 R s`), and the two springs pull it in with
//! `2 k (L - L0) s = 4 k s² (R - R0)`.

mod common;

use std::f64::consts::PI;

use common::gas::{gas_force, run_until, weightless};
use sprung::build;
use sprung::{BodyData, Collider, ContactResponse, Gas, IntegratorKind, Real, Shape, Vec3, World};

/// A pressurised ring's parameters.
#[derive(Debug, Clone, Copy)]
struct Ring {
    /// Particles.
    n: usize,
    /// Radius at rest (m).
    r0: Real,
    /// Mass of each particle (kg).
    mass: Real,
    /// Spring stiffness (N/m).
    k: Real,
    /// nRT (J) after the ramp.
    nrt: Real,
}

/// The three parameter sets of the equilibrium claims (docs/physics.md §7).
const RINGS: [Ring; 3] = [
    Ring {
        n: 17,
        r0: 1.0,
        mass: 0.1,
        k: 1000.0,
        nrt: 300.0,
    },
    Ring {
        n: 8,
        r0: 0.5,
        mass: 0.05,
        k: 200.0,
        nrt: 20.0,
    },
    Ring {
        n: 40,
        r0: 2.0,
        mass: 0.02,
        k: 5000.0,
        nrt: 5000.0,
    },
];

impl Ring {
    fn sin(&self) -> Real {
        (PI / self.n as Real).sin()
    }

    /// Outward pressure force minus inward spring pull on a vertex of the
    /// regular polygon of circumradius `r`, as docs/physics.md §7 writes it (N).
    fn balance(&self, r: Real, nrt: Real) -> Real {
        let (n, v) = (self.n as Real, PI / self.n as Real);
        let side = 2.0 * r * v.sin();
        let rest = 2.0 * self.r0 * v.sin();
        let area = 0.5 * n * r * r * (2.0 * v).sin();
        nrt / area * side * v.cos() - 2.0 * self.k * (side - rest) * v.sin()
    }

    /// The equilibrium radius for `nrt` by bisection on [`Ring::balance`]:
    /// positive at `R0` (no spring pull yet), negative once the springs
    /// win; 200 halvings reach the last bit.
    fn equilibrium(&self, nrt: Real) -> Real {
        let (mut low, mut high) = (self.r0, 2.0 * self.r0);
        assert!(self.balance(low, nrt) > 0.0);
        while self.balance(high, nrt) > 0.0 {
            high *= 2.0;
        }
        for _ in 0..200 {
            let mid = 0.5 * (low + high);
            if self.balance(mid, nrt) > 0.0 {
                low = mid;
            } else {
                high = mid;
            }
        }
        0.5 * (low + high)
    }

    /// Radial stiffness of the breathing mode per vertex at radius `r`
    /// (N/m): `-d/dR` of `2 nRT/(N R) - 4 k s² (R - R0)`.
    fn radial_stiffness(&self, r: Real, nrt: Real) -> Real {
        4.0 * self.k * self.sin().powi(2) + 2.0 * nrt / (self.n as Real * r * r)
    }

    /// Spring damping (N·s/m) that gives the breathing mode at `nrt` the
    /// damping ratio `zeta`: the springs' dashpots resist `dR/dt` with
    /// `4 c s² dR/dt` per vertex (the spring stretches at `2 s dR/dt`), so
    /// `4 c s² = 2 ζ √(K m)`.
    fn damping_for(&self, zeta: Real, nrt: Real) -> Real {
        let r = self.equilibrium(nrt);
        let omega = (self.radial_stiffness(r, nrt) / self.mass).sqrt();
        2.0 * zeta * omega * self.mass / (4.0 * self.sin().powi(2))
    }

    /// The ring as a body, with spring damping `damping` and gas `gas`.
    fn body(&self, damping: Real, gas: Option<Gas>) -> BodyData {
        let mut body = build::ring(self.n, self.r0)
            .expect("valid ring")
            .with_mass(self.mass)
            .with_stiffness(self.k)
            .with_damping(damping);
        body.gas = gas;
        body
    }
}

/// Distances (m) of body 0's particles from its centroid.
fn radii(world: &World) -> Vec<Real> {
    let centre = world.centroid(0).expect("body 0");
    world
        .particles
        .position
        .iter()
        .map(|x| x.distance(centre))
        .collect()
}

// ------------------------------------------------------ ring equilibrium

#[test]
fn bisection_matches_the_closed_form_radius() {
    // With the balance written out, 2 nRT/(N R) = 4 k s² (R - R0): the
    // quadratic R² - R0 R - C = 0, C = nRT / (2 k N s²), so
    // R = (R0 + √(R0² + 4C)) / 2. Bisection to the last bit agrees to
    // round-off (1e-12 relative).
    for ring in RINGS {
        let c = ring.nrt / (2.0 * ring.k * ring.n as Real * ring.sin().powi(2));
        let closed = 0.5 * (ring.r0 + (ring.r0 * ring.r0 + 4.0 * c).sqrt());
        let r = ring.equilibrium(ring.nrt);
        assert!(
            (r / closed - 1.0).abs() <= 1e-12,
            "{ring:?}: {r} vs {closed}"
        );
    }
}

#[test]
fn pressure_force_on_a_regular_polygon_is_2_nrt_over_n_r_radially() {
    // docs/physics.md §7: (nRT/A) L cos(π/N) outward on every vertex, which is
    // 2 nRT / (N R). One force evaluation, exact to round-off.
    let (n, r, nrt) = (11, 0.8, 3.0);
    let mut ring = build::ring(n, r).expect("valid ring");
    ring.gas = Some(Gas::new(nrt, 0.0));
    let world = weightless(IntegratorKind::SymplecticEuler, ring);
    let expected = 2.0 * nrt / (n as Real * r);
    for (x, f) in world.particles.position.iter().zip(gas_force(&world)) {
        let radial = *x / r;
        assert!(
            (f - expected * radial).length() <= 1e-12 * expected,
            "force {f} at {x}, expected {expected} outward"
        );
    }
}

#[test]
fn pressurised_ring_settles_at_the_balance_radius() {
    // Starting from rest at R0 with nRT ramped over `ramp`, the ring stays a
    // regular polygon (every force is symmetric), so only the breathing
    // mode moves: m R'' = 2 nRT/(N R) - 4 k s² (R - R0) - 4 c s² R', which
    // the damping makes critical (ζ = 1). After the ramp the remaining
    // motion decays as (1 + ω t) e^{-ω t}; we wait 40/ω, which leaves
    // 41 e^{-40} ≈ 2e-16 of the initial offset. An equilibrium does not
    // depend on the integrator or dt (a = 0, v = 0 is a fixed point of
    // each), so the 0.2 % asked for is loose by design. The check that the
    // ring has really settled is 1e-9: round-off feeds the undamped,
    // non-breathing modes ~ε |x| per step, which adds up to at most n ε |x|
    // ≈ 1e-11 |x| over the n ≲ 2e4 steps (Verlet's x⁺ = 2x - x⁻ + a dt²
    // comes closest to that).
    for ring in RINGS {
        let r = ring.equilibrium(ring.nrt);
        let omega = (ring.radial_stiffness(r, ring.nrt) / ring.mass).sqrt();
        let ramp = 10.0 / omega;
        let damping = ring.damping_for(1.0, ring.nrt);
        for kind in [
            IntegratorKind::SymplecticEuler,
            IntegratorKind::Verlet,
            IntegratorKind::Rk4,
        ] {
            let body = ring.body(damping, Some(Gas::new(ring.nrt, ramp)));
            let mut world = weightless(kind, body);
            let dt = 0.5 * world.stable_time_step();
            run_until(&mut world, dt, ramp + 40.0 / omega);
            let what = format!("{ring:?}, {kind}");
            for radius in radii(&world) {
                let error = (radius / r - 1.0).abs();
                assert!(error <= 2e-3, "{what}: radius {radius}, expected {r}");
                assert!(error <= 1e-9, "{what}: radius {radius} not settled at {r}");
            }
            // Area ∝ R² and P ∝ 1/R²: twice the radius tolerance.
            let n = ring.n as Real;
            let area = 0.5 * n * r * r * (2.0 * PI / n).sin();
            let measured = world.volume(0).expect("closed");
            assert!(
                (measured / area - 1.0).abs() <= 4e-3,
                "{what}: area {measured} vs {area}"
            );
            let pressure = world.pressure(0).expect("a gas");
            assert!(
                (pressure * area / ring.nrt - 1.0).abs() <= 4e-3,
                "{what}: pressure {pressure} vs {}",
                ring.nrt / area
            );
        }
    }
}

// ------------------------------------------------------ floor

/// The textbook ball: a ring of 17 particles, radius 1 m, 1 kg in all,
/// springs of 1000 N/m, centred 1.3 m above a projection floor (no bounce,
/// friction 0.5) under gravity, with air drag 0.5 N·s/m per particle and
/// the gas `gas`. Returns the area after `duration` seconds and the
/// kinetic energy then.
fn dropped_ring(gas: Option<Gas>, duration: Real) -> (Real, Real) {
    let ring = Ring {
        n: 17,
        r0: 1.0,
        mass: 1.0 / 17.0,
        k: 1000.0,
        nrt: 0.0,
    };
    let body = ring
        .body(1.0, gas)
        .placed(1.0, Vec3::ZERO, Vec3::new(0.0, 1.3, 0.0));
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_air_drag(0.5);
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).expect("valid plane");
    let response = ContactResponse::Projection {
        restitution: 0.0,
        friction: 0.5,
    };
    world
        .colliders
        .push(Collider::new(floor, response).expect("valid response"));
    world.add_body("ball", body).expect("valid ball");
    let dt = 0.25 * world.stable_time_step();
    run_until(&mut world, dt, duration);
    (world.volume(0).expect("closed"), world.energies().kinetic)
}

#[test]
fn ring_on_the_floor_keeps_its_area_only_with_gas() {
    // Air drag damps every motion at c_air/2m = 4.25 /s at least (a free
    // fall reaches its terminal speed m g / c_air = 1.15 m/s in ~0.1 s, so
    // the ball lands within ~1.5 s); after 10 s whatever the landing left
    // is down by e^{-30} or more: settled, which the kinetic energy
    // (below 1e-6 M g R0 = 1e-5 J) confirms.
    let (n, r0) = (17, 1.0);
    let rest_area = 0.5 * n as Real * r0 * r0 * (2.0 * PI / n as Real).sin();
    let duration = 10.0;

    // Without gas nothing holds the loop up: a chain of point masses has
    // no bending stiffness, so it folds onto the floor.
    let (area, kinetic) = dropped_ring(None, duration);
    assert!(kinetic < 1e-5, "no gas: not settled ({kinetic} J)");
    assert!(
        area < 0.5 * rest_area,
        "no gas: area {area} m², more than half of {rest_area} m²"
    );

    // With nRT = 300 J the free ring would settle at radius R* (area A*).
    // On the floor it carries its weight M g = 9.81 N on a flat of length
    // ℓ ≈ M g / P* ≈ 0.15 m (P* = nRT/A* ≈ 66 N/m); flattening a circle of
    // fixed perimeter over a half-angle α = ℓ / 2R* removes α³/3π ≈ 2e-5 of
    // its area, and the weight varies the tension (≈ 78 N) by up to
    // M g / 2, changing the strain by ~1 %: a few % at most. 10 % holds
    // with room to spare.
    let nrt = 300.0;
    let free = Ring {
        n,
        r0,
        mass: 1.0 / 17.0,
        k: 1000.0,
        nrt,
    };
    let r = free.equilibrium(nrt);
    let free_area = 0.5 * n as Real * r * r * (2.0 * PI / n as Real).sin();
    let (area, kinetic) = dropped_ring(Some(Gas::new(nrt, 0.5)), duration);
    assert!(kinetic < 1e-5, "with gas: not settled ({kinetic} J)");
    assert!(
        (area / free_area - 1.0).abs() <= 0.1,
        "with gas: area {area} m², free equilibrium {free_area} m²"
    );
}

// ------------------------------------------------------ schedule

#[test]
fn nrt_ramps_follows_keyframes_holds_and_leaks() {
    // Ramp 0 → 100 J over 2 s, then 300 J at 4 s, 50 J at 6 s, held; a leak
    // of 0.5 /s from 7 s. Every value is a short formula: 1e-12 relative.
    let gas = Gas {
        keyframes: vec![(4.0, 300.0), (6.0, 50.0)],
        leak_rate: 0.5,
        leak_start: 7.0,
        ..Gas::new(100.0, 2.0)
    };
    gas.validate().expect("valid schedule");
    let expected = |t: Real| -> Real {
        let scheduled = if t < 2.0 {
            100.0 * t / 2.0
        } else if t < 4.0 {
            100.0 + (t - 2.0) / 2.0 * 200.0
        } else if t < 6.0 {
            300.0 - (t - 4.0) / 2.0 * 250.0
        } else {
            50.0
        };
        scheduled
            * if t > 7.0 {
                (-0.5 * (t - 7.0)).exp()
            } else {
                1.0
            }
    };
    for i in 0..=100 {
        let t = 0.1 * i as Real;
        let value = gas.nrt_at(t);
        assert!(
            (value - expected(t)).abs() <= 1e-12 * expected(t).max(1.0),
            "t = {t}: nRT {value}, expected {}",
            expected(t)
        );
    }
    // Continuous at every corner: the jump across ±1e-9 s is at most the
    // steepest slope (125 J/s) times 2e-9 s.
    for corner in [2.0, 4.0, 6.0, 7.0] {
        let jump = (gas.nrt_at(corner + 1e-9) - gas.nrt_at(corner - 1e-9)).abs();
        assert!(
            jump <= 125.0 * 2e-9 * (1.0 + 1e-6),
            "jump of {jump} J at t = {corner}"
        );
    }
    // No ramp: full nRT from t = 0.
    assert_eq!(Gas::new(7.0, 0.0).nrt_at(0.0), 7.0);
    // A leak alone: nRT e^{-λ (t - t0)}.
    let leaky = Gas {
        leak_rate: 0.3,
        leak_start: 1.0,
        ..Gas::new(10.0, 0.0)
    };
    for t in [0.5, 1.0, 2.0, 5.0, 20.0] {
        let expected = 10.0 * (-0.3 * (t - 1.0_f64).max(0.0)).exp();
        assert!((leaky.nrt_at(t) / expected - 1.0).abs() <= 1e-12, "t = {t}");
    }
}

#[test]
fn leaking_ring_deflates_monotonically_lagging_the_quasi_static_radius() {
    // The ring of the equilibrium test (N = 17, m = 0.1 kg, k = 1000 N/m,
    // nRT = 300 J ramped over 0.5 s), with its breathing mode overdamped
    // (ζ = 1.5 at the start; ζ grows as the gas leaks and the mode
    // softens). From t0 = 3 s the gas leaks at λ = 0.2 /s. An overdamped
    // oscillator has a positive impulse response, so driven by the
    // monotonically falling equilibrium radius R*(t) it falls monotonically
    // too; before t0 it approached R* from below at the slow rate
    // ω (ζ - √(ζ² - 1)) ≈ 15 /s, leaving e^{-37} of the ramp.
    //
    // Quasi-statically it lags behind R*: with R = R* + δ,
    // m δ'' + Γ δ' + K δ = -Γ R*' - m R*'' (Γ = 4 c s², K the radial
    // stiffness), so δ = Γ |R*'| / K up to relative corrections λ Γ / K
    // ≈ 1.5 % (it adds: δ ≈ (Γ |R*'| / K)(1 + λ Γ / K)) and λ m / Γ ≈ 0.2 %,
    // and δ / R ≈ 2e-3 of nonlinearity, once the start-up transient
    // (e^{-15 t}) is gone: checked within 5 % from t0 + 1 s. With C = nRT / (2 k N s²), R* = (R0 + √(R0² + 4C)) / 2 and
    // R*' = -λ C / √(R0² + 4C).
    let ring = Ring {
        n: 17,
        r0: 1.0,
        mass: 0.1,
        k: 1000.0,
        nrt: 300.0,
    };
    let (leak_start, leak_rate, ramp) = (3.0, 0.2, 0.5);
    let damping = ring.damping_for(1.5, ring.nrt);
    let gas = Gas {
        leak_rate,
        leak_start,
        ..Gas::new(ring.nrt, ramp)
    };
    let mut world = weightless(
        IntegratorKind::SymplecticEuler,
        ring.body(damping, Some(gas.clone())),
    );
    let dt = 0.5 * world.stable_time_step();
    run_until(&mut world, dt, leak_start);
    let mut previous = world.volume(0).expect("closed");
    let s2 = ring.sin().powi(2);
    let mut checked = 0;
    for sample in 1..=100 {
        let t = leak_start + 0.05 * sample as Real;
        run_until(&mut world, dt, t);
        let area = world.volume(0).expect("closed");
        assert!(
            area < previous,
            "t = {t}: area {area} did not fall below {previous}"
        );
        previous = area;
        if t >= leak_start + 1.0 {
            let nrt = gas.nrt_at(world.time());
            let c = nrt / (2.0 * ring.k * ring.n as Real * s2);
            let root = (ring.r0 * ring.r0 + 4.0 * c).sqrt();
            let target = 0.5 * (ring.r0 + root);
            let speed = leak_rate * c / root;
            let lag = 4.0 * damping * s2 * speed / ring.radial_stiffness(target, nrt);
            let mean_radius = radii(&world).iter().sum::<Real>() / ring.n as Real;
            let measured = mean_radius - target;
            assert!(
                (measured / lag - 1.0).abs() <= 0.05,
                "t = {t}: R - R* = {measured:.4e} m, predicted lag {lag:.4e} m"
            );
            checked += 1;
        }
    }
    assert_eq!(checked, 81);
}
