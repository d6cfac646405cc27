//! The GPU step against the engine's: the same scenes, each integrator.

mod common;

use sprung::build::{self, ClothSprings, SurfaceSprings};
use sprung::forces::AirDrag;
use sprung::{BodyData, Collider, ContactResponse, Gas, IntegratorKind, Shape, Vec3, World};
use sprung_gpu::GpuWorld;

const KINDS: [IntegratorKind; 3] = [
    IntegratorKind::SymplecticEuler,
    IntegratorKind::Verlet,
    IntegratorKind::Rk4,
];

/// A 24² cloth, 1 m square, 0.1 kg, 200 N/m springs, held flat by two
/// corners and let go to swing down, with air drag.
fn hung(kind: IntegratorKind) -> World {
    let n = 24;
    let cloth = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .unwrap()
        .with_total_mass(0.1)
        .with_stiffness(200.0)
        .with_damping(0.02)
        .with_pinned(vec![n * (n - 1), n * n - 1])
        .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
    let mut world = World::new(kind);
    world.add_body("cloth", cloth).unwrap();
    world.forces.set(AirDrag { coefficient: 1e-3 });
    world
}

/// The same cloth flat, dropped from 0.5 m onto a sphere (projection,
/// with friction and restitution) over a penalty floor.
fn dropped(kind: IntegratorKind) -> World {
    let n = 24;
    let cloth = build::cloth(n, n, 1.0, 1.0, ClothSprings::default())
        .unwrap()
        .with_total_mass(0.1)
        .with_stiffness(200.0)
        .with_damping(0.02)
        .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::new(-0.5, 0.5, 0.5));
    let mut world = World::new(kind);
    world.add_body("cloth", cloth).unwrap();
    let sphere = Shape::sphere(Vec3::ZERO, 0.25).unwrap();
    let floor = Shape::plane(Vec3::new(0.0, -0.3, 0.0), Vec3::Y).unwrap();
    let projection = ContactResponse::Projection {
        restitution: 0.0,
        friction: 0.3,
    };
    let penalty = ContactResponse::Penalty {
        stiffness: 2000.0,
        damping: 1.0,
        friction: 0.2,
    };
    world
        .colliders
        .push(Collider::new(sphere, penalty).unwrap());
    world
        .colliders
        .push(Collider::new(floor, projection).unwrap());
    // The GPU step has no continuous collision detection.
    world.contacts.settings.ccd = false;
    world
}

/// A ball of gas, 0.3 m across, 0.2 kg, 300 N/m springs, its nRT ramped
/// to 40 J over 0.1 s so that it swells while it falls: a 3D icosphere
/// (two subdivisions, 162 particles) or a 2D ring of 32.
fn gas_ball(kind: IntegratorKind, three_d: bool) -> World {
    let body = if three_d {
        build::icosphere(0.15, 2, SurfaceSprings::default()).unwrap()
    } else {
        build::ring(32, 0.15).unwrap()
    };
    let ball = BodyData {
        gas: Some(Gas::new(40.0, 0.1)),
        ..body
            .with_total_mass(0.2)
            .with_stiffness(300.0)
            .with_damping(0.02)
    };
    let mut world = World::new(kind);
    world.add_body("ball", ball).unwrap();
    world
}

/// The largest distance (m) between the particles of two worlds.
fn farthest(a: &World, b: &World) -> f64 {
    let pairs = a.particles.position.iter().zip(&b.particles.position);
    pairs.map(|(p, q)| (*p - *q).length()).fold(0.0, f64::max)
}

/// `world` after `steps` steps of `dt` (s) on the engine.
fn on_cpu(mut world: World, dt: f64, steps: u64) -> World {
    for _ in 0..steps {
        world.step(dt).unwrap();
    }
    world
}

/// `world` after `steps` steps of `dt` (s) on the GPU, read back.
fn on_gpu(gpu: &sprung_gpu::Gpu, mut world: World, dt: f64, steps: u64) -> World {
    let mut step = GpuWorld::on(gpu.clone(), &world, dt).unwrap();
    step.step(steps);
    step.read_into(&mut world).unwrap();
    assert_eq!(world.steps(), steps);
    world
}

/// The cloth swinging down, 0.4 s (0.45 m for its farthest particle).
/// f32 rounds each coordinate to within 2⁻²⁴ of itself (6·10⁻⁸ m at
/// 1 m) at each of the 2000 steps; the swing is stable, so those errors
/// add up as a random walk, about √2000 · 6·10⁻⁸ ≈ 3·10⁻⁶ m (measured:
/// 0.8 to 1.0·10⁻⁶ m); 10⁻⁵ m leaves a factor of 3 over that and is 45 000
/// times smaller than the swing: a spring's force 1% off moves the cloth by
/// millimetres.
#[test]
fn a_swinging_cloth_follows_the_engine_within_f32_round_off() {
    let Some(gpu) = common::gpu() else { return };
    let (dt, steps) = (2e-4, 2000);
    for kind in KINDS {
        let cpu = on_cpu(hung(kind), dt, steps);
        let gpu = on_gpu(&gpu, hung(kind), dt, steps);
        let swing = farthest(&hung(kind), &cpu);
        assert!(swing > 0.4, "{kind}: the cloth swung {swing} m");
        let off = farthest(&cpu, &gpu);
        assert!(off < 1e-5, "{kind}: {off} m from the engine");
        assert_eq!(gpu.time(), cpu.time());
    }
}

/// Gas balls swelling as they fall, 0.4 s: the exact volume summed on the
/// GPU in a fixed order, the pressure on each face. The swelling is
/// stable, so the round-off adds as in the swinging cloth (10⁻⁵ m, the
/// same reasoning; measured: 4 to 6·10⁻⁷ m for the 3D ball, which swells
/// by 31% in volume, 3.2·10⁻⁶ m for the ring, which swells 17-fold in
/// area).
#[test]
fn gas_balls_swell_as_on_the_engine_within_f32_round_off() {
    let Some(gpu) = common::gpu() else { return };
    for three_d in [true, false] {
        for kind in KINDS {
            let make = || gas_ball(kind, three_d);
            let dt = 0.5 * make().stable_time_step();
            let steps = (0.4 / dt) as u64;
            let cpu = on_cpu(make(), dt, steps);
            let gpu = on_gpu(&gpu, make(), dt, steps);
            let volume = |w: &World| w.bodies[0].enclosed_volume(&w.particles.position).unwrap();
            let grown = volume(&cpu) / volume(&make());
            assert!(grown > 1.2, "{kind}: the ball grew {grown} times");
            let off = farthest(&cpu, &gpu);
            assert!(off < 1e-5, "{kind}, 3D {three_d}: {off} m from the engine");
        }
    }
}

/// The cloth dropped flat onto the sphere, 0.3 s: it meets the sphere at
/// 0.23 s and folds over it. Folding is unstable (which way a flat sheet
/// buckles turns on its smallest differences), so f32 round-off grows
/// there beyond any per-step bound; the claim is that the GPU departs from
/// the engine by no more than the engine departs from itself when its
/// start is rounded once at f32's precision (each coordinate moved by
/// 2⁻²⁴ of itself, alternately up and down). Measured: the GPU 0.4 to
/// 0.8 mm, the rounded start 3 to 6 mm.
#[test]
fn a_cloth_dropped_on_colliders_departs_no_more_than_a_rounded_start() {
    let Some(gpu) = common::gpu() else { return };
    let (dt, steps) = (2e-4, 1500);
    for kind in KINDS {
        let cpu = on_cpu(dropped(kind), dt, steps);
        let gpu = on_gpu(&gpu, dropped(kind), dt, steps);
        let mut rounded = dropped(kind);
        for (k, p) in rounded.particles.position.iter_mut().enumerate() {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            *p *= 1.0 + sign * 2f64.powi(-24);
        }
        let rounded = on_cpu(rounded, dt, steps);
        let (off, spread) = (farthest(&cpu, &gpu), farthest(&cpu, &rounded));
        assert!(
            off <= spread,
            "{kind}: {off} m from the engine, which departs {spread} m from itself"
        );
        // Every particle is out of the projection floor (penalty lets the
        // sphere be entered), and the sheet lies on the sphere.
        let lowest = gpu
            .particles
            .position
            .iter()
            .map(|p| p.y)
            .fold(f64::MAX, f64::min);
        assert!(
            lowest >= -0.3,
            "{kind}: a particle at {lowest} m, below the floor"
        );
        let centre = gpu.particles.position.iter().sum::<Vec3>() / gpu.particles.len() as f64;
        assert!(
            centre.y < 0.25 && centre.y > 0.0,
            "{kind}: the centre at {centre}"
        );
    }
}

/// Two runs of the same world on the GPU end in the same bits: the
/// springs are gathered per particle, in a fixed order, with no atomic
/// additions.
#[test]
fn two_runs_on_the_gpu_give_the_same_bits() {
    let Some(gpu) = common::gpu() else { return };
    for kind in KINDS {
        let runs: Vec<World> = (0..2)
            .map(|_| on_gpu(&gpu, dropped(kind), 2e-4, 1300))
            .collect();
        let bits = |w: &World| -> Vec<u64> {
            let x = w.particles.position.iter().chain(&w.particles.velocity);
            x.flat_map(|p| p.to_array().map(f64::to_bits)).collect()
        };
        assert_eq!(bits(&runs[0]), bits(&runs[1]), "{kind}");
    }
}
