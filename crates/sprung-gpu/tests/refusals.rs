//! What the GPU step refuses, and how it fails.

mod common;

use sprung::build::{self, ClothSprings};
use sprung::{
    Collider, ContactResponse, Gas, IntegratorKind, Path, Shape, StepError, Vec3, VolumeModel,
    World,
};
use sprung_gpu::{support, Gpu, GpuError, GpuWorld, Precision};

fn cloth(kind: IntegratorKind) -> World {
    let mut world = World::new(kind);
    let cloth = build::cloth(6, 6, 1.0, 1.0, ClothSprings::default()).unwrap();
    let cloth = cloth.with_stiffness(1000.0).with_pinned(vec![30, 35]);
    world.add_body("cloth", cloth).unwrap();
    world
}

/// The feature a refusal names.
fn lacks(world: &World) -> String {
    match support::check(world) {
        Err(GpuError::Unsupported(feature)) => feature,
        other => panic!("not refused: {other:?}"),
    }
}

#[test]
fn a_world_the_gpu_step_cannot_run_is_refused_with_the_feature_named() {
    assert!(support::check(&cloth(IntegratorKind::Rk4)).is_ok());
    assert!(lacks(&cloth(IntegratorKind::ImplicitEuler)).contains("implicit_euler integrator"));
    assert!(lacks(&cloth(IntegratorKind::Projective)).contains("projective integrator"));

    let mut auto = cloth(IntegratorKind::Verlet);
    auto.settings.substeps = sprung::Substeps::Auto;
    assert!(lacks(&auto).contains("substeps = \"auto\""));

    let mut gas = World::new(IntegratorKind::SymplecticEuler);
    let mut ball = build::ring(12, 0.5).unwrap();
    ball.gas = Some(Gas::new(1.0, 0.0));
    gas.add_body("ball", ball).unwrap();
    assert!(support::check(&gas).is_ok());
    gas.bodies[0].gas.as_mut().unwrap().volume_model = VolumeModel::BoundingBox;
    assert!(lacks(&gas).contains("bounding-box"));

    let mut moving = cloth(IntegratorKind::SymplecticEuler);
    let floor = Shape::plane(Vec3::ZERO, Vec3::Y).unwrap();
    let response = ContactResponse::Projection {
        restitution: 0.0,
        friction: 0.0,
    };
    let path = Path::new(vec![(0.0, Vec3::ZERO), (1.0, Vec3::Y)]).unwrap();
    moving
        .colliders
        .push(Collider::new(floor, response).unwrap().with_path(path));
    assert_eq!(lacks(&moving), "moving colliders");

    let mut sphere = cloth(IntegratorKind::SymplecticEuler);
    let ball = Shape::sphere(Vec3::ZERO, 0.1).unwrap();
    sphere
        .colliders
        .push(Collider::new(ball, response).unwrap());
    assert!(lacks(&sphere).contains("set ccd = false"));
    sphere.contacts.settings.ccd = false;
    assert!(support::check(&sphere).is_ok());

    let mut touching = cloth(IntegratorKind::SymplecticEuler);
    let other = build::cloth(3, 3, 0.5, 0.5, ClothSprings::default()).unwrap();
    touching.add_body("other", other).unwrap();
    touching.contacts.settings.ccd = false;
    assert_eq!(lacks(&touching), "body contacts");
}

/// A step far above the stable one: the GPU stops at the end of the step
/// that blew up, and the engine's guard names it, its particle and why,
/// as on the CPU; the world's clock stands at that step.
#[test]
fn a_blow_up_stops_at_its_step_and_names_it() {
    let Some(gpu) = common::gpu() else { return };
    let stable = cloth(IntegratorKind::SymplecticEuler).stable_time_step();
    let mut cpu = cloth(IntegratorKind::SymplecticEuler);
    let on_cpu = (0..200)
        .find_map(|_| match cpu.step(20.0 * stable) {
            Err(StepError::BlowUp { step, .. }) => Some(step),
            _ => None,
        })
        .expect("the engine blows up within 200 steps");
    let mut precisions = vec![Precision::F32];
    if common::has_f64(&gpu) {
        precisions.push(Precision::F64);
    }
    for precision in precisions {
        let mut world = cloth(IntegratorKind::SymplecticEuler);
        let mut step =
            GpuWorld::in_precision(gpu.clone(), &world, 20.0 * stable, precision).unwrap();
        step.step(200);
        match step.read_into(&mut world) {
            Err(GpuError::Step(StepError::BlowUp {
                step,
                dt,
                stable_dt,
                ..
            })) => {
                // The state grows by a large factor a step: f32 and f64
                // pass the limit (10⁶ m or m/s) at the same step.
                assert_eq!(step, on_cpu, "{precision}");
                assert_eq!((dt, stable_dt), (20.0 * stable, stable));
                assert_eq!(world.steps(), step);
            }
            other => panic!("{precision}: not a blow-up: {other:?}"),
        }
    }
}

/// No backend: a clear error, not a panic.
#[test]
fn no_adapter_is_a_clear_error() {
    let error = Gpu::with_backends(wgpu::Backends::empty()).unwrap_err();
    assert!(matches!(error, GpuError::NoAdapter(_)), "{error:?}");
    assert!(error.to_string().contains("mesa-vulkan-drivers"), "{error}");
}
