//! What the GPU step refuses, and how it fails.

mod common;

use sprung::build::{self, ClothSprings};
use sprung::{Collider, ContactResponse, Gas, IntegratorKind, Path, Shape, Vec3, World};
use sprung_gpu::{support, Gpu, GpuError, GpuWorld};

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
    assert_eq!(lacks(&gas), "gas pressure");

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

/// A step far above the stable one: the guard stops the run at the step
/// the state blew up, and the world keeps the state it had, with its
/// clock where it was.
#[test]
fn a_blow_up_names_its_step_and_leaves_the_world_as_it_was() {
    let Some(gpu) = common::gpu() else { return };
    let mut world = cloth(IntegratorKind::SymplecticEuler);
    let stable = world.stable_time_step();
    let before = world.particles.position.clone();
    let mut step = GpuWorld::on(gpu, &world, 20.0 * stable).unwrap();
    step.step(200);
    match step.read_into(&mut world) {
        Err(GpuError::BlowUp { step, stable_dt }) => {
            assert!((2..200).contains(&step), "step {step}");
            assert_eq!(stable_dt, stable);
        }
        other => panic!("not a blow-up: {other:?}"),
    }
    assert_eq!(world.particles.position, before);
    assert_eq!((world.steps(), world.time()), (0, 0.0));
}

/// No backend: a clear error, not a panic.
#[test]
fn no_adapter_is_a_clear_error() {
    let error = Gpu::with_backends(wgpu::Backends::empty()).unwrap_err();
    assert!(matches!(error, GpuError::NoAdapter(_)), "{error:?}");
    assert!(error.to_string().contains("mesa-vulkan-drivers"), "{error}");
}
