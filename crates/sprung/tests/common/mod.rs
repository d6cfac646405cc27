//! Helpers shared by the physics-claim tests: small worlds with known exact
//! solutions (docs/physics.md §7), a deterministic random source, and the signal
//! measurements (zero crossings, peaks) the tests read frequencies and decay
//! rates from.
//!
//! Each test file includes this module, and none uses every helper.
#![allow(dead_code)]

pub mod colliders;
pub mod gas;
pub mod wind;

use sprung::{build, BodyData, IntegratorKind, Real, SpringData, Vec3, World};

/// Rest length of the oscillator's spring (m). The free particle must stay
/// on the +x side of the pinned one (|displacement| < REST) for the spring
/// force to be the linear `-k u`.
pub const REST: Real = 1.0;

/// The single oscillator of docs/physics.md §7: particle 0 pinned at the origin,
/// particle 1 of mass `mass` (kg) at `(REST + u0, 0, 0)` with velocity
/// `(v0, 0, 0)`, joined by a spring of stiffness `stiffness` (N/m), damping
/// `damping` (N·s/m) and rest length [`REST`]. No gravity: the displacement
/// `u = x - REST` obeys `m u'' = -k u - c u'` exactly.
pub fn oscillator(
    kind: IntegratorKind,
    mass: Real,
    stiffness: Real,
    damping: Real,
    u0: Real,
    v0: Real,
) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    let mut body = BodyData::from_positions(vec![Vec3::ZERO, Vec3::new(REST + u0, 0.0, 0.0)])
        .with_mass(mass)
        .with_pinned(vec![0]);
    body.velocity = vec![Vec3::ZERO, Vec3::new(v0, 0.0, 0.0)];
    body.springs.push(SpringData {
        rest_length: Some(REST),
        stiffness,
        damping,
        ..SpringData::between(0, 1)
    });
    world
        .add_body("oscillator", body)
        .expect("valid oscillator");
    world
}

/// Displacement of the oscillator's free particle from rest (m).
pub fn displacement(world: &World) -> Real {
    world.particles.position[1].x - REST
}

/// Velocity of the oscillator's free particle along the spring (m/s).
pub fn velocity(world: &World) -> Real {
    world.particles.velocity[1].x
}

/// Exact undamped oscillator state `(u, v)` at time `t` (s) from `(u0, v0)`
/// at time 0, with angular frequency `omega` (rad/s).
pub fn exact_oscillator(u0: Real, v0: Real, omega: Real, t: Real) -> (Real, Real) {
    let (s, c) = (omega * t).sin_cos();
    (u0 * c + v0 / omega * s, -u0 * omega * s + v0 * c)
}

/// Distance in phase space between `(u, v)` and `(u_ref, v_ref)`, with the
/// velocity scaled by `1/omega` so both coordinates are lengths (m).
pub fn phase_space_distance(
    (u, v): (Real, Real),
    (u_ref, v_ref): (Real, Real),
    omega: Real,
) -> Real {
    (u - u_ref).hypot((v - v_ref) / omega)
}

/// A chain of `free` particles of mass `mass` (kg) along x, `spacing` (m)
/// apart, between two pinned end particles (indices 0 and `free + 1`), with
/// springs of stiffness `stiffness` (N/m) between neighbours. No gravity.
pub fn fixed_fixed_chain(
    kind: IntegratorKind,
    free: usize,
    mass: Real,
    stiffness: Real,
    spacing: Real,
) -> World {
    let count = free + 2;
    let position = (0..count)
        .map(|i| Vec3::new(spacing * i as Real, 0.0, 0.0))
        .collect();
    let mut body = BodyData::from_positions(position)
        .with_mass(mass)
        .with_pinned(vec![0, count - 1]);
    body.springs = (1..count).map(|i| SpringData::between(i - 1, i)).collect();
    let body = body.with_stiffness(stiffness);
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body("chain", body).expect("valid chain");
    world
}

/// A rope (particle 0 pinned at the origin, `free` particles below it along
/// -y, `spacing` (m) apart) with uniform `mass` (kg) and `stiffness` (N/m).
pub fn rope(free: usize, mass: Real, stiffness: Real, spacing: Real) -> BodyData {
    build::rope(free + 1, spacing * free as Real)
        .expect("valid rope")
        .with_mass(mass)
        .with_stiffness(stiffness)
}

/// A small deterministic random source (xorshift64*), so the tests need no
/// dependency and always see the same numbers.
pub struct Rng(u64);

impl Rng {
    /// A generator started from `seed` (any value but 0 works).
    pub fn new(seed: u64) -> Self {
        Rng(seed.max(1))
    }

    /// A number uniform in [-1, 1).
    pub fn symmetric(&mut self) -> Real {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        2.0 * (bits as Real / (1u64 << 53) as Real) - 1.0
    }

    /// A whole number uniform in `0..n` (`n > 0`).
    pub fn below(&mut self, n: usize) -> usize {
        let unit = 0.5 * (self.symmetric() + 1.0);
        ((unit * n as Real) as usize).min(n - 1)
    }

    /// A random numbering of `n` particles (a permutation of `0..n`), as
    /// [`BodyData::renumbered`] takes it.
    pub fn numbering(&mut self, n: usize) -> Vec<usize> {
        let mut number: Vec<usize> = (0..n).collect();
        for k in (1..n).rev() {
            number.swap(k, self.below(k + 1));
        }
        number
    }

    /// A vector with components uniform in [-scale, scale).
    pub fn vector(&mut self, scale: Real) -> Vec3 {
        scale * Vec3::new(self.symmetric(), self.symmetric(), self.symmetric())
    }
}

/// Times (s) at which the uniformly sampled signal `values` (taken every
/// `dt` seconds from time 0) crosses zero upwards. Each crossing is located
/// on the cubic through the four samples around it (Lagrange interpolation,
/// error `O(dt⁴ f'''')`, and `f''''` vanishes with `f` at the root of a
/// sinusoid), so the crossing time of a sampled sinusoid is exact to far
/// better than the period errors the tests look for.
pub fn upward_crossings(values: &[Real], dt: Real) -> Vec<Real> {
    let mut times = Vec::new();
    for i in 1..values.len().saturating_sub(2) {
        let (f0, f1, f2, f3) = (values[i - 1], values[i], values[i + 1], values[i + 2]);
        if !(f1 <= 0.0 && f2 > 0.0) {
            continue;
        }
        // The cubic through (-1, f0), (0, f1), (1, f2), (2, f3).
        let cubic = |s: Real| {
            -f0 * s * (s - 1.0) * (s - 2.0) / 6.0 + f1 * (s + 1.0) * (s - 1.0) * (s - 2.0) / 2.0
                - f2 * (s + 1.0) * s * (s - 2.0) / 2.0
                + f3 * (s + 1.0) * s * (s - 1.0) / 6.0
        };
        let (mut low, mut high) = (0.0, 1.0);
        for _ in 0..60 {
            let mid = 0.5 * (low + high);
            if cubic(mid) <= 0.0 {
                low = mid;
            } else {
                high = mid;
            }
        }
        times.push((i as Real + 0.5 * (low + high)) * dt);
    }
    times
}

/// Mean period (s) between the first and the last upward zero crossing of
/// `values` sampled every `dt` seconds.
pub fn mean_period(values: &[Real], dt: Real) -> Real {
    let crossings = upward_crossings(values, dt);
    assert!(
        crossings.len() >= 3,
        "too few zero crossings to measure a period: {}",
        crossings.len()
    );
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as Real
}

/// Local maxima `(time, value)` of `values` sampled every `dt` seconds, each
/// refined on the parabola through the three samples around it.
pub fn peaks(values: &[Real], dt: Real) -> Vec<(Real, Real)> {
    let mut found = Vec::new();
    for i in 1..values.len().saturating_sub(1) {
        let (a, b, c) = (values[i - 1], values[i], values[i + 1]);
        if b > a && b >= c {
            let offset = 0.5 * (a - c) / (a - 2.0 * b + c);
            found.push(((i as Real + offset) * dt, b - 0.25 * (a - c) * offset));
        }
    }
    found
}

/// The closed surface of the axis-aligned box with corner `low` (m) and edge
/// lengths `size` (m): its 8 corners (corner `i` has bit 0 of `i` for x,
/// bit 1 for y, bit 2 for z) and 12 triangles, counter-clockwise seen from
/// outside. Each face is the quad with corners `(0,0), (1,0), (1,1), (0,1)`
/// in its two in-plane axes `(u, v) = (a+1, a+2) mod 3`, whose normal
/// `e_u × e_v = e_a` points out on the high side (the order is reversed on
/// the low side), split along its `(0,0)-(1,1)` diagonal.
pub fn box_surface(low: Vec3, size: Vec3) -> (Vec<Vec3>, Vec<[usize; 3]>) {
    let corners = (0..8)
        .map(|i: usize| {
            let bit = |axis: usize| ((i >> axis) & 1) as Real;
            low + size * Vec3::new(bit(0), bit(1), bit(2))
        })
        .collect();
    let mut faces = Vec::with_capacity(12);
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in 0..2usize {
            let corner = |bu: usize, bv: usize| (side << axis) | (bu << u) | (bv << v);
            let mut quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            if side == 0 {
                quad.reverse();
            }
            faces.push([quad[0], quad[1], quad[2]]);
            faces.push([quad[0], quad[2], quad[3]]);
        }
    }
    (corners, faces)
}

/// `faces` with `u32` indices, as [`sprung::surface`] takes them.
pub fn faces_u32(faces: &[[usize; 3]]) -> Vec<[u32; 3]> {
    faces.iter().map(|f| f.map(|i| i as u32)).collect()
}

/// `segments` with `u32` indices, as [`sprung::surface`] takes them.
pub fn segments_u32(segments: &[[usize; 2]]) -> Vec<[u32; 2]> {
    segments.iter().map(|s| s.map(|i| i as u32)).collect()
}

/// Assert a particle rests in a penalty contact of stiffness `stiffness`
/// (N/m) at `depth` (m) = `expected` = m g / k_c, and that `contact` (J), the
/// world's contact energy, is ½ k_c depth². At rest every integrator's fixed
/// point is the force balance k_c depth = m g, to round-off (~1e-13
/// relative): we claim 1e-9 for the depth and 1e-8 for the energy.
pub fn assert_penalty_rest(
    label: &str,
    depth: Real,
    expected: Real,
    contact: Real,
    stiffness: Real,
) {
    assert!(
        (depth / expected - 1.0).abs() <= 1e-9,
        "{label}: depth {depth:.9e} m, expected m g / k_c = {expected:.9e} m"
    );
    let expected_energy = 0.5 * stiffness * expected * expected;
    assert!(
        (contact / expected_energy - 1.0).abs() <= 1e-8,
        "{label}: contact energy {contact:.6e} J, expected ½ k_c d² = {expected_energy:.6e} J"
    );
}

/// How deep (m) the deepest particle of any body lies inside another
/// closed body of `world`, beyond the surface (0 when none is inside).
pub fn deepest_inside_another(world: &World) -> Real {
    sprung::contact::inside::deepest_interpenetration(&world.bodies, &world.particles.position)
}

/// A world without gravity stepped by `kind`, holding `body` as `name`.
pub fn weightless(kind: IntegratorKind, name: &str, body: BodyData) -> World {
    let mut world = World::new(kind);
    world.set_gravity(Vec3::ZERO);
    world.add_body(name, body).expect("a valid body");
    world
}

/// A force that adds nothing and calls its closure at every evaluation (to
/// count the evaluations, or see which thread runs them).
pub struct Watcher(pub Box<dyn FnMut() + Send + Sync>);

impl std::fmt::Debug for Watcher {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Watcher")
    }
}

impl sprung::forces::Force for Watcher {
    fn name(&self) -> &'static str {
        "watcher"
    }
    fn accumulate(&mut self, _: &sprung::forces::ForceContext, _: &mut [Vec3]) {
        (self.0)();
    }
    fn add_stiffness(
        &self,
        _: &sprung::forces::ForceContext,
        _: &mut sprung::forces::StiffnessBounds,
    ) {
    }
    fn energy_name(&self) -> Option<&'static str> {
        None
    }
    fn add_potential_energy(&self, _: &sprung::forces::ForceContext, _: &mut Real) {}
    fn linearize(&mut self, _: &sprung::forces::ForceContext) -> sprung::forces::Linearization {
        sprung::forces::Linearization::Exact
    }
    fn add_jacobian_products(
        &self,
        _: &sprung::forces::ForceContext,
        _: sprung::forces::JacobianScale,
        _: &[Vec3],
        _: &mut [Vec3],
    ) {
    }
    fn add_jacobian_diagonal(
        &self,
        _: &sprung::forces::ForceContext,
        _: sprung::forces::JacobianScale,
        _: &mut [Vec3],
    ) {
    }
}
