//! Mutual gravitation: two bodies on Kepler orbits against the exact
//! periods and perihelion, with energy, momentum and the centre of mass
//! conserved.

mod common;

use sprung::forces::Gravitation;
use sprung::{BodyData, IntegratorKind, Real, Vec3, World};

/// Units where `G (M + m) = 1`: `G = 1`, a sun of 1 kg less the planet.
const PLANET: Real = 1e-3;
const SUN: Real = 1.0 - PLANET;

/// A planet at perihelion distance `perihelion` (m) on an orbit of
/// eccentricity `e`, the sun opposite, the centre of mass at rest at the
/// origin; RK4.
fn kepler(perihelion: Real, e: Real) -> World {
    // Relative speed at perihelion: √(G(M+m)(1+e)/r_p).
    let speed = ((1.0 + e) / perihelion).sqrt();
    let mut world = World::new(IntegratorKind::Rk4);
    world.set_gravity(Vec3::ZERO);
    world.forces.set(Gravitation::new(1.0, 0.0).unwrap());
    for (name, mass, share) in [("sun", SUN, -PLANET), ("planet", PLANET, SUN)] {
        let mut body =
            BodyData::from_positions(vec![Vec3::new(share * perihelion, 0.0, 0.0)]).with_mass(mass);
        body.velocity = vec![Vec3::new(0.0, share * speed, 0.0)];
        world.add_body(name, body).unwrap();
    }
    world
}

/// The planet's distance from the sun (m).
fn separation(world: &World) -> Real {
    world.particles.position[1].distance(world.particles.position[0])
}

/// Run `world` for `duration` s at `dt`: the planet's relative x and the
/// separation at every step, checking energy, momentum and the centre of
/// mass after each.
fn orbit(world: &mut World, dt: Real, duration: Real) -> (Vec<Real>, Vec<Real>) {
    let energy = world.energies().total();
    // The scale of the momenta: the planet's at perihelion.
    let momentum_scale = PLANET * world.particles.velocity[1].length();
    let (mut x, mut r) = (vec![], vec![]);
    for _ in 0..(duration / dt).round() as usize {
        let p = &world.particles;
        x.push(p.position[1].y - p.position[0].y);
        r.push(separation(world));
        world.step(dt).unwrap();
        // RK4 at dt ≪ the perihelion passage: its error per orbit is about
        // (ω dt)⁴ ≈ 1e-10, far inside the 1e-6.
        let now = world.energies().total();
        assert!(
            (now - energy).abs() <= 1e-6 * energy.abs(),
            "energy {now} J, from {energy} J"
        );
        let p = &world.particles;
        let momentum = PLANET * p.velocity[1] + SUN * p.velocity[0];
        assert!(
            momentum.length() <= 1e-6 * momentum_scale,
            "momentum {momentum}"
        );
        let centre = PLANET * p.position[1] + SUN * p.position[0];
        // Rounding only (the two pulls are opposite up to the rounding of
        // their products, G m_i (m_j p) against G m_j (m_i p)): 1e-12 m over
        // a 1 m orbit.
        assert!(
            centre.length() <= 1e-12,
            "the centre of mass moved to {centre}"
        );
    }
    (x, r)
}

#[test]
fn a_circular_orbit_keeps_its_period() {
    // r = 1, G(M+m) = 1: T = 2π exactly.
    let mut world = kepler(1.0, 0.0);
    let dt = 1e-3;
    let (y, r) = orbit(&mut world, dt, 3.2 * std::f64::consts::TAU);
    let period = common::mean_period(&y, dt);
    let exact = std::f64::consts::TAU;
    assert!(
        (period - exact).abs() <= 1e-3 * exact,
        "period {period} s, exact {exact} s"
    );
    let spread = r.iter().fold(0.0 as Real, |w, &r| w.max((r - 1.0).abs()));
    assert!(spread <= 1e-6, "the circle's radius strayed by {spread} m");
}

#[test]
fn an_eccentric_orbit_returns_to_its_perihelion_on_time() {
    // e = 0.5, a = 1: perihelion 0.5 m, aphelion 1.5 m, T = 2π a^{3/2} = 2π.
    let mut world = kepler(0.5, 0.5);
    let dt = 2e-4;
    let exact = std::f64::consts::TAU;
    let (_, r) = orbit(&mut world, dt, 2.5 * exact);
    // Perihelia are the minima of the separation, refined on a parabola.
    let negated: Vec<Real> = r.iter().map(|r| -r).collect();
    let minima = common::peaks(&negated, dt);
    assert!(minima.len() >= 2, "found {} perihelia", minima.len());
    let aphelion = r.iter().fold(0.0 as Real, |w, &r| w.max(r));
    for &(time, value) in &minima {
        assert!(
            (-value - 0.5).abs() <= 1e-3 * 0.5,
            "perihelion {} m at {time} s",
            -value
        );
    }
    assert!(
        (aphelion - 1.5).abs() <= 1e-3 * 1.5,
        "aphelion {aphelion} m"
    );
    let period = minima[1].0 - minima[0].0;
    assert!(
        (period - exact).abs() <= 1e-3 * exact,
        "period {period} s, exact {exact} s"
    );
}

#[test]
fn softening_levels_off_the_pull_and_bodies_can_opt_out() {
    // Two 1 kg particles 1 m apart with ε = 1 m: the pull is G/(1+1)^{3/2}.
    let mut world = World::new(IntegratorKind::SymplecticEuler);
    world.set_gravity(Vec3::ZERO);
    world.forces.set(Gravitation::new(2.0, 1.0).unwrap());
    for (name, x) in [("a", 0.0), ("b", 1.0)] {
        let body = BodyData::from_positions(vec![Vec3::new(x, 0.0, 0.0)]);
        world.add_body(name, body).unwrap();
    }
    let mut third = BodyData::from_positions(vec![Vec3::new(0.0, 1.0, 0.0)]);
    third.gravitating = false;
    world.add_body("aloof", third).unwrap();
    world.evaluate_forces();
    let expected = 2.0 / Real::powf(2.0, 1.5);
    let f = &world.particles.force;
    assert!((f[0].x - expected).abs() <= 1e-15 && (f[1].x + expected).abs() <= 1e-15);
    assert_eq!(f[2], Vec3::ZERO, "a body that opts out feels nothing");
    assert_eq!(f[0].y, 0.0, "and pulls nothing");
    // Energy -G m m / √(r² + ε²) = -2/√2.
    let energy = world
        .energies()
        .get("gravitation")
        .expect("a standard term");
    assert!((energy + 2.0 / Real::sqrt(2.0)).abs() <= 1e-15, "{energy}");
    assert!(Gravitation::new(1.0, -1.0).is_err());
}
