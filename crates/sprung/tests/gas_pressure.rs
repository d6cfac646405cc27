//! The gas inside a soft body (docs/physics.md §4, §7): a pressurised ring
//! settles at the radius where pressure balances the springs; pressure
//! forces on a closed surface have no resultant and no torque, so springs
//! and gas conserve momentum; the undamped pressurised ball conserves
//! `E_k + E_s + E_gas` within the band its integrator allows; a ring on the
//! floor keeps its area only with gas; the `nRT` schedule ramps, follows
//! keyframes and leaks as specified; and bad gas parameters are refused.
//!
//! Ring notation: `N` particles of mass `m`, springs of stiffness `k` and
//! rest length `L0 = 2 R0 s` on a circle of radius `R0`, `s = sin(π/N)`.
//! At the regular N-gon of circumradius `R` the gas pushes each vertex out
//! with `(nRT/A) L cos(π/N) = 2 nRT / (N R)` (`A = N R² s cos(π/N)`,
//! `L = 2 R s`), and the two springs pull it in with
//! `2 k (L - L0) s = 4 k s² (R - R0)`.

mod common;

use std::f64::consts::PI;

use common::Rng;
use sprung::build::{self, SurfaceSprings};
use sprung::forces::{Force, GasPressure};
use sprung::{
    BodyData, BuildError, Collider, ContactResponse, Gas, IntegratorKind, Real, Shape, Vec3, World,
};

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

/// A world without gravity holding `body` as body 0.
fn weightless(kind: IntegratorKind, body: BodyData) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("body", body).expect("valid body");
    world
}

/// Step `world` by `dt` until its time reaches `until` (s).
fn run_until(world: &mut World, dt: Real, until: Real) {
    while world.time() < until - 0.5 * dt {
        world.step(dt).expect("stable");
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

/// The gas pressure force alone at the world's state (N per particle).
fn gas_force(world: &World) -> Vec<Vec3> {
    let context = world.force_context();
    let mut force = vec![Vec3::ZERO; world.particles.len()];
    GasPressure::new().accumulate(&context, &mut force);
    force
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

// ------------------------------------------------------ momentum

/// An icosphere of radius 1 with every vertex moved by up to ±0.1 m in each
/// coordinate, then moved to `offset`: an irregular closed surface.
fn lumpy_ball(rng: &mut Rng, subdivisions: usize, offset: Vec3) -> BodyData {
    let mut body =
        build::icosphere(1.0, subdivisions, SurfaceSprings::default()).expect("valid sphere");
    body.position
        .iter_mut()
        .for_each(|p| *p += rng.vector(0.1) + offset);
    body
}

/// A ring of 23 particles, radius 1, each moved by up to ±0.15 m in x and y,
/// then to `offset`.
fn lumpy_ring(rng: &mut Rng, offset: Vec3) -> BodyData {
    let mut body = build::ring(23, 1.0).expect("valid ring");
    body.position.iter_mut().for_each(|p| {
        *p += Vec3::new(rng.symmetric(), rng.symmetric(), 0.0) * 0.15 + offset;
    });
    body
}

#[test]
fn pressure_forces_on_a_closed_surface_have_no_resultant_and_no_torque() {
    // Σ_f A_f n_f = 0 over any closed polyhedron (each directed edge's
    // contribution ½ a × b cancels with its reverse) and Σ_e l_e n_e = 0
    // around a closed loop; the gas gives each face P A_f n_f, shared
    // equally, so the forces sum to zero. The torque Σ x_i × f_i equals
    // P Σ_f c_f × A_f n_f (c_f the face centroid), the exact ∮ x × P n dS
    // over the flat faces, which is ∫ ε_ijk ∂_k x_j dV = 0 by the divergence
    // theorem. Both hold for any shape; 1e-9 of Σ |f| (resp. Σ |x - c| |f|)
    // covers round-off, which is ~1e-15 here (a few ε per face, 320 faces,
    // coordinates a few times the edge length).
    let mut rng = Rng::new(2024);
    for (what, body) in [
        (
            "lumpy icosphere",
            lumpy_ball(&mut rng, 2, Vec3::new(5.0, -3.0, 2.0)),
        ),
        (
            "lumpy ring",
            lumpy_ring(&mut rng, Vec3::new(-4.0, 7.0, 0.0)),
        ),
    ] {
        let mut body = body;
        body.gas = Some(Gas::new(10.0, 0.0));
        let world = weightless(IntegratorKind::SymplecticEuler, body);
        let force = gas_force(&world);
        let centre = world.centroid(0).expect("body 0");
        let x = &world.particles.position;
        let scale: Real = force.iter().map(|f| f.length()).sum();
        assert!(scale > 0.0);
        let total: Vec3 = force.iter().sum();
        assert!(
            total.length() <= 1e-9 * scale,
            "{what}: Σ f = {total}, Σ |f| = {scale}"
        );
        let torque: Vec3 = x
            .iter()
            .zip(&force)
            .map(|(x, f)| (*x - centre).cross(*f))
            .sum();
        let torque_scale: Real = x
            .iter()
            .zip(&force)
            .map(|(x, f)| (*x - centre).length() * f.length())
            .sum();
        assert!(
            torque.length() <= 1e-9 * torque_scale,
            "{what}: Σ x × f = {torque}, Σ |x||f| = {torque_scale}"
        );
    }
}

/// Spring stiffness (N/m) and damping (N·s/m) of [`stirred`] bodies.
const STIRRED_STIFFNESS: Real = 200.0;
const STIRRED_DAMPING: Real = 0.5;

/// A lumpy ball or ring with gas, springs ([`STIRRED_STIFFNESS`],
/// [`STIRRED_DAMPING`]), particles of 0.05 kg and random velocities around a
/// common drift, with no gravity.
fn stirred(kind: IntegratorKind, body: BodyData, seed: u64) -> World {
    let mut rng = Rng::new(seed);
    let drift = Vec3::new(0.3, -0.2, 0.1);
    let planar = body.faces.is_empty();
    let mut body = body
        .with_mass(0.05)
        .with_stiffness(STIRRED_STIFFNESS)
        .with_damping(STIRRED_DAMPING);
    body.velocity = (0..body.particle_count())
        .map(|_| {
            let v = drift + rng.vector(1.0);
            if planar {
                v * Vec3::new(1.0, 1.0, 0.0)
            } else {
                v
            }
        })
        .collect();
    body.gas = Some(Gas::new(20.0, 0.0));
    weightless(kind, body)
}

#[test]
fn springs_and_gas_conserve_linear_momentum() {
    // Every integrator's update is a linear combination of force
    // evaluations, each summing to zero (springs pairwise, gas over the
    // closed surface), so Σ m v is constant up to round-off: ~1e-16 per
    // addition, and for Verlet, whose velocity is a difference of positions
    // over 2 dt, ε |x| / (|v| dt) ≈ 1e-13. Hence 1e-10 of Σ m |v|.
    let mut rng = Rng::new(99);
    for kind in IntegratorKind::ALL {
        for (what, body) in [
            (
                "lumpy icosphere",
                lumpy_ball(&mut rng, 2, Vec3::new(1.0, 2.0, -1.0)),
            ),
            (
                "lumpy ring",
                lumpy_ring(&mut rng, Vec3::new(0.5, -1.0, 0.0)),
            ),
        ] {
            let mut world = stirred(kind, body, 7);
            // Implicit Euler changes the momentum by minus the sum of its
            // linear solve's residual at each step (the Jacobian products
            // of springs sum to zero; the gas is explicit): ask for 1e-12.
            world.settings.solver.tolerance = 1e-12;
            let before = world.linear_momentum();
            let scale: Real = world
                .particles
                .velocity
                .iter()
                .zip(&world.particles.mass)
                .map(|(v, &m)| m * v.length())
                .sum();
            let initial = world.particles.velocity.clone();
            // Explicit Euler multiplies a mode's energy by 1 - 2ζh + h² per
            // step: it decays only for h < 2ζ. The dashpots give mode j the
            // damping ratio ζ_j = c ω_j / 2k, so Euler needs dt < c/k
            // (2.5e-3 s, below a quarter of the ring's stable step) and takes
            // half of it; the undamped (transverse) modes still grow as
            // (1 + h²)ⁿ, slowly at that step.
            let mut dt = 0.25 * world.stable_time_step();
            if kind == IntegratorKind::Euler {
                dt = dt.min(0.5 * STIRRED_DAMPING / STIRRED_STIFFNESS);
            }
            let steps = 1000;
            let mut impulse = 0.0;
            for _ in 0..steps {
                impulse += gas_force(&world).iter().map(|f| f.length()).sum::<Real>() * dt;
                if let Err(e) = world.step(dt) {
                    panic!("{what}, {kind}: {e}");
                }
            }
            let change = (world.linear_momentum() - before).length() / scale;
            assert!(
                change <= 1e-10,
                "{what}, {kind}: momentum changed by {change:.3e} of Σ m|v|"
            );
            // The claim means something only if the gas did push: still
            // inflated, with a total impulse Σ |f| dt comparable to Σ m|v|.
            assert!(
                world.pressure(0).is_some(),
                "{what}, {kind}: volume not positive"
            );
            assert!(
                impulse > 0.1 * scale,
                "{what}, {kind}: the gas hardly acted ({impulse} vs {scale})"
            );
            let stirred = world
                .particles
                .velocity
                .iter()
                .zip(&initial)
                .map(|(v, v0)| (*v - *v0).length())
                .fold(0.0, Real::max);
            assert!(stirred > 0.1, "{what}, {kind}: velocities hardly changed");
        }
    }
}

#[test]
fn springs_and_gas_conserve_angular_momentum_with_symplectic_euler() {
    // Symplectic Euler: v⁺ = v + a(x, v) dt, x⁺ = x + v⁺ dt, so
    // Σ m x⁺ × v⁺ = Σ m x × v⁺ = Σ m x × v + dt Σ x × f(x, v). Spring forces
    // (with their dashpots) act along the line between their two particles
    // and the gas torque is zero (see above), so angular momentum is
    // conserved to round-off: ~ε Σ m |x||v| per step, 1e-10 after 1000.
    let mut rng = Rng::new(5);
    for (what, body) in [
        (
            "lumpy icosphere",
            lumpy_ball(&mut rng, 2, Vec3::new(0.5, -0.3, 0.2)),
        ),
        ("lumpy ring", lumpy_ring(&mut rng, Vec3::new(0.2, 0.4, 0.0))),
    ] {
        let mut world = stirred(IntegratorKind::SymplecticEuler, body, 13);
        let angular = |world: &World| -> Vec3 {
            let p = &world.particles;
            p.position
                .iter()
                .zip(&p.velocity)
                .zip(&p.mass)
                .map(|((x, v), &m)| m * x.cross(*v))
                .sum()
        };
        let p = &world.particles;
        let scale: Real = p
            .position
            .iter()
            .zip(&p.velocity)
            .zip(&p.mass)
            .map(|((x, v), &m)| m * x.length() * v.length())
            .sum();
        let before = angular(&world);
        let dt = 0.25 * world.stable_time_step();
        for _ in 0..1000 {
            world.step(dt).expect("stable");
        }
        let change = (angular(&world) - before).length() / scale;
        assert!(
            change <= 1e-10,
            "{what}: angular momentum changed by {change:.3e} of Σ m|x||v|"
        );
        assert!(world.pressure(0).is_some(), "{what}: volume not positive");
    }
}

// ------------------------------------------------------ energy

/// A block-Gershgorin bound (rad/s) on the highest angular frequency of the
/// undamped ball (uniform mass `mass`) linearised at its current state:
/// `ω² ≤ max_i Σ_j ‖K_ij‖ / m`. Springs: the world's stable step is
/// `2 / ω_springs` with exactly this bound for their axial stiffness, and a
/// spring under tension T adds T/L across its axis, so its block norm stays
/// k while T/L ≤ k (strain below 100 %). Gas, `E = -nRT ln V`:
/// `K = -P ∇²V + (P/V) ∇V ∇Vᵀ`. With `∇_i V = g_i = ⅓ Σ_{f∋i} A_f n_f` and
/// `∂(A_f n_f)/∂x_j` a cross product with ½ the opposite edge, row i of
/// the first term is at most `(P/6) Σ_{f∋i} perimeter_f`, of the second
/// `(P/V) |g_i| Σ_j |g_j|`.
fn highest_frequency_bound(world: &World, mass: Real) -> Real {
    let omega_springs = 2.0 / world.stable_time_step();
    let x = &world.particles.position;
    let body = &world.bodies[0];
    let pressure = world.pressure(0).expect("a gas");
    let volume = world.volume(0).expect("closed");
    let n = x.len();
    let mut g = vec![Vec3::ZERO; n];
    let mut perimeters = vec![0.0; n];
    for &[a, b, c] in &body.faces {
        let (a, b, c) = (a as usize, b as usize, c as usize);
        let normal = 0.5 * (x[b] - x[a]).cross(x[c] - x[a]) / 3.0;
        let perimeter = x[a].distance(x[b]) + x[b].distance(x[c]) + x[c].distance(x[a]);
        for i in [a, b, c] {
            g[i] += normal;
            perimeters[i] += perimeter;
        }
    }
    let g_sum: Real = g.iter().map(|v| v.length()).sum();
    let gas_row = (0..n)
        .map(|i| pressure / 6.0 * perimeters[i] + pressure / volume * g[i].length() * g_sum)
        .fold(0.0, Real::max);
    (omega_springs * omega_springs + gas_row / mass).sqrt()
}

#[test]
fn undamped_pressurised_ball_conserves_energy_within_the_integrators_band() {
    // An icosphere (s = 1, 42 particles of 0.05 kg, edge and bending
    // springs of 1000 N/m) with a constant nRT (no ramp, no gravity) is
    // first brought to rest at its equilibrium under air drag
    // (c_air/2m = 20 /s for 2 s: any mode above 20 rad/s is down by e^{-40};
    // checked below through the kinetic energy). The drag is then removed
    // and the particles given a breathing velocity (0.05 m/s outward) plus
    // random ones (±0.05 m/s). Starting at the equilibrium, the energy of
    // the oscillation is exactly the kinetic energy given, E_osc = E_k(0).
    //
    // Per linear mode of frequency ω_j, with h_j = ω_j dt:
    // - position Verlet (with the engine's velocity, carried to the end of
    //   the step) gives E/E_0 - 1 ∈ [-h⁴/12, h² + h⁴/3] (its energy is the
    //   quadratic form diag(1 + h⁴/4, 1 + ¾h² - h⁴/4) + off-diagonal h³/2
    //   of the phase, scaled by at most 1/(1 - h²/4)): bounded, no drift;
    // - RK4 multiplies a mode's energy by exactly |R(ih)|² = 1 - h⁶/72 +
    //   h⁸/576 per step (the map is a scaled rotation), so after n steps the
    //   loss is at most n h⁶/72 of it.
    // With h_j ≤ h = ω_bound dt for every mode, the total obeys the same
    // bands relative to E_osc: [-h⁴/12, h² + h⁴/3] for Verlet, [-n h⁶/72, 0]
    // for RK4. The amplitudes (~1e-3 m against ~0.6 m edges) make
    // anharmonic corrections ~1e-3 of these, which the margins below cover
    // (h⁴ instead of h⁴/12 under Verlet, h² + h⁴ above it; 1 % of the RK4
    // loss above E_0).
    let (mass, stiffness, nrt) = (0.05, 1000.0, 2000.0);
    let h: Real = 0.1;
    for kind in [IntegratorKind::Verlet, IntegratorKind::Rk4] {
        let mut ball = build::icosphere(1.0, 1, SurfaceSprings::default())
            .expect("valid sphere")
            .with_mass(mass)
            .with_stiffness(stiffness);
        ball.gas = Some(Gas::new(nrt, 0.0));
        let mut world = weightless(kind, ball);
        world.set_air_drag(2.0 * mass * 20.0);
        let dt = 0.25 * world.stable_time_step();
        run_until(&mut world, dt, 2.0);
        world.set_air_drag(0.0);
        let residual = world.energies().kinetic;

        let mut rng = Rng::new(17);
        let centre = world.centroid(0).expect("body 0");
        let count = world.particles.len();
        let mut velocity: Vec<Vec3> = world
            .particles
            .position
            .iter()
            .map(|x| 0.05 * (*x - centre).normalize() + rng.vector(0.05))
            .collect();
        let mean = velocity.iter().sum::<Vec3>() / count as Real;
        velocity.iter_mut().for_each(|v| *v -= mean);
        world.particles.velocity = velocity;
        let oscillation = world.energies().kinetic;
        // Settled: the pre-run left a kinetic energy below 1e-12 E_osc. An
        // underdamped mode holds as much potential as kinetic energy on
        // average; an overdamped one (ω < c_air/2m) creeps at ω² m / c_air,
        // so its kinetic share is (ω m / c_air)²: for its potential energy
        // to reach even 1e-3 E_osc (a tenth of the Verlet band) that share
        // would have to be below 1e-9, i.e. ω < 1.3e-3 rad/s, which only the
        // rigid motions have, and those the gas and springs never excite
        // (no resultant, no torque) from rest.
        assert!(
            residual <= 1e-12 * oscillation,
            "{kind}: not settled ({residual} J)"
        );

        let omega = highest_frequency_bound(&world, mass);
        let dt = h / omega;
        let initial = world.energies().total();
        let steps = (1.2 / dt).round() as usize;
        let (mut low, mut high): (Real, Real) = (0.0, 0.0);
        let (mut gas_low, mut gas_high) = (Real::MAX, Real::MIN);
        for _ in 0..steps {
            world.step(dt).expect("stable");
            let energies = world.energies();
            let change = (energies.total() - initial) / oscillation;
            (low, high) = (low.min(change), high.max(change));
            let gas = energies.get("gas").expect("a standard term");
            (gas_low, gas_high) = (gas_low.min(gas), gas_high.max(gas));
        }
        let (floor, ceiling) = match kind {
            IntegratorKind::Verlet => (-h.powi(4), h * h * (1.0 + h * h)),
            _ => {
                let loss = steps as Real * h.powi(6) / 72.0;
                (-loss, 0.01 * loss)
            }
        };
        assert!(
            low >= floor && high <= ceiling,
            "{kind}: (E - E0)/E_osc in [{low:.3e}, {high:.3e}], band [{floor:.3e}, {ceiling:.3e}] (ω dt = {h}, {steps} steps)"
        );
        // The gas energy swings far more than the band: had E_gas or the
        // force been wrong, the total would have left it.
        assert!(
            gas_high - gas_low > 100.0 * (ceiling - floor) * oscillation,
            "{kind}: E_gas only swung by {:.3e} J",
            gas_high - gas_low
        );
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

// ------------------------------------------------------ bad input

#[test]
fn bad_gas_parameters_are_refused() {
    let cases: Vec<(Gas, &str)> = vec![
        (Gas::new(-1.0, 0.0), "gas.nrt"),
        (Gas::new(Real::NAN, 0.0), "gas.nrt"),
        (Gas::new(1.0, -0.5), "gas.ramp_time"),
        (
            Gas {
                leak_rate: -0.1,
                ..Gas::new(1.0, 0.0)
            },
            "gas.leak_rate",
        ),
        // A keyframe during the ramp, at its end, or not after the previous.
        (
            Gas {
                keyframes: vec![(0.5, 2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(1.0, 2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(2.0, 2.0), (2.0, 3.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(3.0, 2.0), (2.5, 3.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
        (
            Gas {
                keyframes: vec![(2.0, -2.0)],
                ..Gas::new(1.0, 1.0)
            },
            "gas.schedule",
        ),
    ];
    for (gas, field) in cases {
        let mut ring = build::ring(8, 1.0)
            .expect("valid ring")
            .with_stiffness(10.0);
        ring.gas = Some(gas.clone());
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        let error = world.add_body("ring", ring).expect_err("must be refused");
        assert!(world.bodies.is_empty() && world.particles.is_empty());
        assert!(
            matches!(error, BuildError::OutOfRange { field: f, .. } if f == field),
            "{gas:?}: {error:?}"
        );
        assert!(error.to_string().contains(&format!("`{field}`")), "{error}");
    }
}

#[test]
fn a_gas_ball_after_other_bodies_feels_the_same_pressure() {
    // Claim: a body's pressure goes to its own particles wherever they
    // start in the world (small surfaces are added into the body's own
    // entries). The same ball alone and after a rope far away (its
    // particles first in the world) moves to the same bits.
    let ball = || {
        let mut ball = build::icosphere(0.5, 2, SurfaceSprings::default())
            .expect("icosphere")
            .with_total_mass(1.0)
            .with_stiffness(500.0)
            .with_damping(0.1);
        ball.gas = Some(Gas::new(50.0, 0.0));
        ball
    };
    let run = |others: bool| {
        let mut world = World::new(IntegratorKind::SymplecticEuler);
        world.set_gravity(Vec3::ZERO);
        if others {
            let rope = build::rope(7, 1.0).expect("rope").placed(
                1.0,
                Vec3::ZERO,
                Vec3::new(50.0, 0.0, 0.0),
            );
            world.add_body("rope", rope).expect("rope");
        }
        let id = world.add_body("ball", ball()).expect("ball");
        for _ in 0..50 {
            world.step(1e-3).expect("steps");
        }
        world.particles.position[world.bodies[id].particles.clone()].to_vec()
    };
    let (alone, after) = (run(false), run(true));
    assert_eq!(alone, after);
    // And the gas did push: the ball grew from its rest radius.
    let centre = alone.iter().sum::<Vec3>() / alone.len() as f64;
    assert!(
        alone.iter().all(|p| p.distance(centre) > 0.5),
        "the gas pushed out"
    );
}

#[test]
fn body_ranges_changed_by_hand_take_the_world_wide_path_to_the_same_forces() {
    // Claim: a body's pressure forces do not depend on how the bodies'
    // particle ranges read, as long as the faces are right. Two gas balls,
    // their ranges then edited by hand (public fields) so that they
    // overlap, and so that one runs beyond the world's particles: no
    // panic, and the same forces to the bit as with the ranges the world
    // gave (each particle still gets its own body's faces, in order).
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    for (name, x) in [("left", -1.0), ("right", 1.0)] {
        let mut ball = build::icosphere(0.5, 2, SurfaceSprings::default())
            .expect("icosphere")
            .placed(1.0, Vec3::ZERO, Vec3::new(x, 0.0, 0.0));
        ball.gas = Some(Gas::new(50.0, 0.0));
        world.add_body(name, ball).expect("ball");
    }
    let expected = gas_force(&world);
    assert!(expected.iter().any(|f| f.length() > 0.0));
    let given = world.bodies[1].particles.clone();
    world.bodies[1].particles = given.start - 10..given.end;
    assert_eq!(gas_force(&world), expected, "overlapping ranges");
    world.bodies[1].particles = given.start..given.end + 10;
    assert_eq!(gas_force(&world), expected, "a range beyond the particles");
}
