//! The reference the cloth is measured against (`--compare`): the textbook
//! algorithm as a plain single-threaded loop over an array of particle
//! structs and an array of spring structs, in f64, on the same particles
//! and springs, stepped by symplectic Euler with gravity.

use std::time::Instant;

use sprung::{Real, World};

/// A particle as the textbook keeps it: everything in one struct.
#[derive(Debug, Clone, Copy)]
struct Particle {
    position: [Real; 3],
    velocity: [Real; 3],
    force: [Real; 3],
    inverse_mass: Real,
    mass: Real,
}

/// A spring as the textbook keeps it.
#[derive(Debug, Clone, Copy)]
struct Spring {
    first: usize,
    second: usize,
    rest_length: Real,
    stiffness: Real,
    damping: Real,
}

/// Seconds per step of the textbook loop on `world`'s particles and
/// springs at `dt`, over at least `steps` steps and `seconds` of wall
/// clock (the world is not changed).
pub fn seconds_per_step(world: &World, dt: Real, steps: u32, seconds: f64) -> f64 {
    let p = &world.particles;
    let mut particles: Vec<Particle> = (0..p.len())
        .map(|i| Particle {
            position: p.position[i].to_array(),
            velocity: p.velocity[i].to_array(),
            force: [0.0; 3],
            inverse_mass: p.inverse_mass[i],
            mass: p.mass[i],
        })
        .collect();
    let s = &world.springs;
    let springs: Vec<Spring> = (0..s.len())
        .map(|k| Spring {
            first: s.first()[k] as usize,
            second: s.second()[k] as usize,
            rest_length: s.rest_length[k],
            stiffness: s.stiffness[k],
            damping: s.damping[k],
        })
        .collect();
    let gravity = world.gravity().to_array();
    let start = Instant::now();
    let mut taken = 0u32;
    while taken < steps || start.elapsed().as_secs_f64() < seconds {
        step(&mut particles, &springs, gravity, dt);
        taken += 1;
    }
    let elapsed = start.elapsed().as_secs_f64();
    std::hint::black_box(&particles);
    elapsed / f64::from(taken)
}

/// One step: gravity, every spring's force (`k (d - L0) + c Δv·t` along the
/// axis `t`), then `v += f/m dt; x += v dt`.
fn step(particles: &mut [Particle], springs: &[Spring], gravity: [Real; 3], dt: Real) {
    for p in particles.iter_mut() {
        p.force = [
            gravity[0] * p.mass,
            gravity[1] * p.mass,
            gravity[2] * p.mass,
        ];
    }
    for s in springs {
        let (a, b) = (particles[s.first], particles[s.second]);
        let delta: [Real; 3] = std::array::from_fn(|k| a.position[k] - b.position[k]);
        let length = delta.iter().map(|d| d * d).sum::<Real>().sqrt();
        if length == 0.0 {
            continue;
        }
        let closing: Real = (0..3)
            .map(|k| (a.velocity[k] - b.velocity[k]) * delta[k])
            .sum::<Real>()
            / length;
        let tension = s.stiffness * (length - s.rest_length) + s.damping * closing;
        for (k, d) in delta.iter().enumerate() {
            let pull = tension * d / length;
            particles[s.first].force[k] -= pull;
            particles[s.second].force[k] += pull;
        }
    }
    for p in particles.iter_mut() {
        for k in 0..3 {
            p.velocity[k] += p.force[k] * p.inverse_mass * dt;
            p.position[k] += p.velocity[k] * dt;
        }
    }
}
