//! What the gas inside a soft body conserves (docs/physics.md §4, §7):
//! pressure forces on a closed surface have no resultant and no torque,
//! so springs and gas conserve momentum; the undamped pressurised ball
//! conserves `E_k + E_s + E_gas` within the band its integrator allows.

mod common;

use common::gas::{gas_force, run_until, weightless};
use common::Rng;
use sprung::build::{self, SurfaceSprings};
use sprung::{BodyData, Gas, IntegratorKind, Real, Vec3, World};

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
