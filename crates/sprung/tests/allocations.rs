//! A step allocates nothing once the world has run a step: integrators,
//! forces and the stable-step estimate of `substeps = "auto"` keep their
//! buffers. Counted by a global allocator that counts every allocation of
//! the thread under test (the claim is about the step, not about other
//! tests running beside it).

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use sprung::build::{self, ClothSprings};
use sprung::integrate::Preconditioner;
use sprung::{Collider, ContactResponse, IntegratorKind, Shape, Substeps, Vec3, World};

/// The system allocator, counting the allocations of each thread.
struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

// SAFETY: every call is passed to the system allocator unchanged; the
// count is a thread-local cell, which allocates nothing.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: the caller's contract is the system allocator's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|count| count.set(count.get() + 1));
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// Allocations on this thread so far.
fn allocations() -> u64 {
    ALLOCATIONS.with(Cell::get)
}

#[test]
fn automatic_substeps_allocate_nothing_a_step() {
    // A 16 × 16 cloth (one thread: below the parallel chunk) of stiff
    // springs over a penalty floor, at a step 20 times its stable step:
    // `substeps = "auto"` splits every step, walking the force list for
    // the bounds each time. Claim: after the first step, 50 more steps
    // allocate nothing (before the bounds were kept by the world, each
    // step allocated two vectors for them).
    for kind in [IntegratorKind::SymplecticEuler, IntegratorKind::Rk4] {
        let cloth = build::cloth(16, 16, 1.0, 1.0, ClothSprings::default())
            .expect("valid cloth")
            .with_total_mass(0.2)
            .with_stiffness(2000.0)
            .with_damping(0.1)
            .with_pinned(vec![0, 15]);
        let mut world = World::new(kind);
        world.add_body("cloth", cloth).expect("valid body");
        let floor = Shape::plane(Vec3::new(0.0, -0.5, 0.0), Vec3::Y).expect("valid plane");
        let penalty = ContactResponse::Penalty {
            stiffness: 1e3,
            damping: 1.0,
            friction: 0.0,
        };
        world
            .colliders
            .push(Collider::new(floor, penalty).expect("valid collider"));
        world.settings.substeps = Substeps::Auto;
        let dt = 20.0 * world.stable_time_step();
        let report = world.step(dt).expect("stable");
        assert!(
            report.substeps.is_some_and(|n| n >= 20),
            "{kind}: {report:?}"
        );
        let before = allocations();
        for _ in 0..50 {
            world.step(dt).expect("stable");
        }
        assert_eq!(allocations() - before, 0, "{kind}: allocations in 50 steps");
    }
}

#[test]
fn a_factored_step_allocates_nothing() {
    // Once the pattern and its symbolic analysis are made (the first
    // factored step), filling and factoring the matrix and the
    // back-substitutions reuse their buffers. Run in a pool of one thread,
    // so the step's work is on this thread and counted.
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a thread pool");
    for preconditioner in [Preconditioner::Stiffness, Preconditioner::Auto] {
        // The stiff cloth of issue 35 (0.2 kg, 2·10⁴ N/m) at 16², laid
        // flat, swinging down at the frame step: auto takes the factor
        // within its first steps.
        let cloth = build::cloth(16, 16, 1.0, 1.0, ClothSprings::default())
            .expect("valid cloth")
            .with_mass(0.2 / 256.0)
            .with_stiffness(2e4)
            .with_damping(0.5)
            .with_pinned(vec![240, 255])
            .placed(1.0, Vec3::new(-90.0, 0.0, 0.0), Vec3::ZERO);
        let mut world = World::new(IntegratorKind::ImplicitEuler);
        world.add_body("cloth", cloth).expect("valid body");
        world.settings.solver.preconditioner = preconditioner;
        pool.install(|| {
            for _ in 0..10 {
                world.step(1.0 / 60.0).expect("stable");
            }
            let before = allocations();
            for _ in 0..10 {
                world.step(1.0 / 60.0).expect("stable");
            }
            let allocated = allocations() - before;
            assert_eq!(allocated, 0, "{preconditioner:?}");
        });
    }
}
