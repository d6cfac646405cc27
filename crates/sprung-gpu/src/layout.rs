//! A world's particles, springs and colliders laid out as the kernels read
//! them (`kernels.wgsl`): four reals to a particle (f64 here, written in
//! the run's precision when the buffers are made), and each particle's
//! springs in a compressed adjacency.

use bytemuck::{Pod, Zeroable};
use sprung::forces::{AirDrag, Gravity};
use sprung::{ContactResponse, Shape, World};

use crate::gas::{GasLayout, MAX_GAS_BODIES, PART};
use crate::precision::Precision;
use crate::support::MAX_COLLIDERS;
use crate::wind::{WindLayout, MAX_MODES};

/// One spring as one of its ends sees it (`Link` in the kernels): 8
/// bytes, so that a million-particle cloth's 12.6 million fit in a
/// 128 MiB binding (lavapipe's largest).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, Pod, Zeroable)]
pub struct Link {
    /// The particle at the other end.
    pub other: u32,
    /// The spring, in [`Layout::springs`].
    pub spring: u32,
}

/// A spring's constants (`Spring` in the kernels, in their precision).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    /// Rest length (m).
    pub rest: f64,
    /// Stiffness (N/m).
    pub stiffness: f64,
    /// Damping along the spring (N·s/m).
    pub damping: f64,
}

/// A collider as the kernels read it (`Collider` in the kernels).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GpuCollider {
    /// Plane: a point on it (m); sphere: the centre (m) and radius (m, w).
    pub point: [f64; 4],
    /// Plane: the unit outward normal.
    pub normal: [f64; 4],
    /// Projection: restitution, friction; penalty: stiffness (N/m),
    /// damping (N·s/m), friction.
    pub coefficients: [f64; 4],
    /// Shape (0 plane, 1 sphere) and response (0 projection, 1 penalty).
    pub kind: [u32; 4],
}

/// The kernels' uniform block (`Params` in the kernels), its values in
/// f64 until [`Params::bytes`] writes them in the kernels' precision.
#[derive(Debug, Clone, Copy)]
pub struct Params {
    /// Particles.
    pub count: u32,
    /// Colliders in use of [`Params::collider`].
    pub colliders: u32,
    /// Workgroups along x of the particles' dispatch grid (each of 64).
    pub row: u32,
    /// Workgroups along x of the gas elements' dispatch grid.
    pub gas_row: u32,
    /// Gas elements, padded ([`GasLayout::elements`]).
    pub elements: u32,
    /// Gas bodies.
    pub gas_bodies: u32,
    /// Partial volumes (the pressures follow them).
    pub parts: u32,
    /// Where the gas elements' ranges start in the packed `faces` buffer
    /// (set when the buffers are made).
    pub element_first_at: u32,
    /// Where the wind elements' ranges start in the packed `faces` buffer
    /// (set when the buffers are made).
    pub wind_first_at: u32,
    /// Gravity's acceleration (m/s², xyz) and the air drag coefficient
    /// (N·s/m, w).
    pub gravity: [f64; 4],
    /// The (sub)step (s).
    pub h: f64,
    /// The blow-up distance squared (m²).
    pub max_distance_squared: f64,
    /// The blow-up speed squared (m²/s²).
    pub max_speed_squared: f64,
    /// The colliders, in the world's order.
    pub collider: [GpuCollider; MAX_COLLIDERS],
    /// Per gas body, its first partial volume and how many; two bodies a
    /// vector.
    pub gas: [[u32; 4]; MAX_GAS_BODIES / 2],
    /// The wind's model and modes in use ([`WindLayout::kind`]).
    pub wind_kind: [u32; 4],
    /// Its coefficients ([`WindLayout::coefficients`]).
    pub wind: [f64; 4],
    /// Its modes ([`WindLayout::modes`]).
    pub modes: [[f64; 4]; 2 * MAX_MODES],
}

impl Params {
    /// The block's bytes with its real numbers in `precision`: the
    /// vectors of reals first, then the unsigned words (after a multiple
    /// of 32 bytes), so that f32 and f64 lay out alike (`Params` in the
    /// kernels; why the reals come first is said there).
    pub fn bytes(&self, precision: Precision) -> Vec<u8> {
        let mut words: Vec<u32> = vec![
            self.count,
            self.colliders,
            self.row,
            self.gas_row,
            self.elements,
            self.gas_bodies,
            self.parts,
            self.element_first_at,
            self.wind_first_at,
            0,
            0,
            0,
        ];
        words.extend(self.wind_kind);
        words.extend(self.gas.iter().flatten());
        words.extend(self.collider.iter().flat_map(|c| c.kind));
        let mut bytes = Vec::new();
        let limits = [
            self.h,
            self.max_distance_squared,
            self.max_speed_squared,
            0.0,
        ];
        let mut reals = Vec::new();
        reals.extend(self.gravity);
        reals.extend(limits);
        reals.extend(self.wind);
        reals.extend(self.modes.iter().flatten());
        reals.extend(self.collider.iter().flat_map(|c| c.point));
        reals.extend(self.collider.iter().flat_map(|c| c.normal));
        reals.extend(self.collider.iter().flat_map(|c| c.coefficients));
        precision.extend(&mut bytes, &reals);
        bytes.extend_from_slice(bytemuck::cast_slice(&words));
        bytes
    }
}

/// A world as the kernels read it.
#[derive(Debug, Clone)]
pub struct Layout {
    /// Positions (m) with the inverse mass (1/kg) as w.
    pub position: Vec<[f64; 4]>,
    /// Velocities (m/s) with the mass (kg) as w.
    pub velocity: Vec<[f64; 4]>,
    /// Particle `i`'s springs are `links[first[i]..first[i + 1]]`.
    pub first: Vec<u32>,
    /// Every spring once for each end it pushes (twice, or once for a
    /// one-sided spring), by particle, in the springs' order.
    pub links: Vec<Link>,
    /// Every spring's constants, in the world's order.
    pub springs: Vec<Spring>,
    /// The gas bodies.
    pub gas: GasLayout,
    /// The wind.
    pub wind: WindLayout,
    /// The uniform block, for a (sub)step of `h`.
    pub params: Params,
}

/// A compressed adjacency of `n` particles: `entries` are (particle,
/// item) pairs; particle `i`'s items are `items[first[i]..first[i + 1]]`,
/// in the entries' order. Returns `(first, items)`.
pub fn adjacency<T: Copy>(n: usize, entries: &[(u32, T)]) -> (Vec<u32>, Vec<T>) {
    let mut first = vec![0u32; n + 1];
    for &(particle, _) in entries {
        first[particle as usize + 1] += 1;
    }
    for i in 0..n {
        first[i + 1] += first[i];
    }
    let mut next = first.clone();
    let mut items: Vec<Option<T>> = vec![None; entries.len()];
    for &(particle, item) in entries {
        items[next[particle as usize] as usize] = Some(item);
        next[particle as usize] += 1;
    }
    (first, items.into_iter().flatten().collect())
}

/// Workgroups of 64 along x of the dispatch grid that covers `count`
/// particles (at most 65 535 per dimension).
pub fn grid(count: u32) -> (u32, u32) {
    let groups = count.div_ceil(64).max(1);
    let row = groups.min(65_535);
    (row, groups.div_ceil(row))
}

impl Layout {
    /// `world`'s state and springs for (sub)steps of `h` (s). The world is
    /// one [`crate::support::check`] accepts.
    pub fn of(world: &World, h: f64) -> Layout {
        let particles = &world.particles;
        let n = particles.len();
        let position = (0..n)
            .map(|i| {
                let p = particles.position[i];
                [p.x, p.y, p.z, particles.inverse_mass[i]]
            })
            .collect();
        let velocity = (0..n)
            .map(|i| {
                let u = particles.velocity[i];
                [u.x, u.y, u.z, particles.mass[i]]
            })
            .collect();
        let springs = &world.springs;
        let (ends_a, ends_b) = (springs.first(), springs.second());
        let mut ends = Vec::with_capacity(2 * springs.len());
        for s in 0..springs.len() {
            if springs.is_broken(s) {
                continue;
            }
            let spring = s as u32;
            if !springs.one_sided[s] {
                ends.push((
                    ends_a[s],
                    Link {
                        other: ends_b[s],
                        spring,
                    },
                ));
            }
            ends.push((
                ends_b[s],
                Link {
                    other: ends_a[s],
                    spring,
                },
            ));
        }
        let (first, links) = adjacency(n, &ends);
        let constants = (0..springs.len()).map(|s| Spring {
            rest: springs.rest_length[s],
            stiffness: springs.stiffness[s],
            damping: springs.damping[s],
        });
        let gravity = world
            .forces
            .get::<Gravity>()
            .map_or(sprung::Vec3::ZERO, |g| g.acceleration);
        let drag = world.forces.get::<AirDrag>().map_or(0.0, |d| d.coefficient);
        let mut collider = [GpuCollider::default(); MAX_COLLIDERS];
        for (slot, c) in collider.iter_mut().zip(&world.colliders) {
            *slot = match c.shape {
                Shape::Plane { point, normal } => GpuCollider {
                    point: point.extend(0.0).into(),
                    normal: normal.extend(0.0).into(),
                    ..GpuCollider::default()
                },
                Shape::Sphere { centre, radius } => GpuCollider {
                    point: centre.extend(radius).into(),
                    kind: [1, 0, 0, 0],
                    ..GpuCollider::default()
                },
            };
            match c.response {
                ContactResponse::Projection {
                    restitution,
                    friction,
                } => slot.coefficients = [restitution, friction, 0.0, 0.0],
                ContactResponse::Penalty {
                    stiffness,
                    damping,
                    friction,
                } => {
                    slot.coefficients = [stiffness, damping, friction, 0.0];
                    slot.kind[1] = 1;
                }
            }
        }
        let (row, _) = grid(n as u32);
        let gas = GasLayout::of(world);
        let wind = WindLayout::of(world);
        let elements = gas.elements.len() as u32;
        let mut spans = [[0u32; 4]; MAX_GAS_BODIES / 2];
        for (k, body) in gas.bodies.iter().enumerate().take(MAX_GAS_BODIES) {
            spans[k / 2][2 * (k % 2)] = body.first;
            spans[k / 2][2 * (k % 2) + 1] = body.parts;
        }
        let params = Params {
            count: n as u32,
            colliders: world.colliders.len().min(MAX_COLLIDERS) as u32,
            row,
            gas_row: grid(elements).0,
            elements,
            gas_bodies: gas.bodies.len() as u32,
            parts: elements / PART as u32,
            element_first_at: 0,
            wind_first_at: 0,
            gravity: gravity.extend(drag).into(),
            h,
            max_distance_squared: world.settings.max_distance.powi(2),
            max_speed_squared: world.settings.max_speed.powi(2),
            collider,
            gas: spans,
            wind_kind: wind.kind,
            wind: wind.coefficients,
            modes: wind.modes,
        };
        Layout {
            position,
            velocity,
            first,
            links,
            springs: constants.collect(),
            gas,
            wind,
            params,
        }
    }
}
