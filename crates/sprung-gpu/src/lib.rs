//! sprung's explicit step on the GPU, through wgpu: Vulkan, Metal, DX12 and
//! WebGPU from one code base, WGSL compute kernels (`kernels.wgsl`). Mesa's
//! software Vulkan driver (lavapipe) runs the same kernels on a CPU, which
//! is how the tests run them without a GPU.
//!
//! A [`GpuWorld`] is made from a [`World`](sprung::World) the GPU step can
//! run ([`support::check`]: springs, gravity, air drag, static plane and
//! sphere colliders; symplectic Euler, Verlet and RK4), holds the state on
//! the GPU between steps, in f32 (or f64 where the adapter has it:
//! [`Precision`]), and writes it back into the world only when asked
//! ([`GpuWorld::read_into`]). Springs are gathered per particle
//! over a compressed adjacency, with no atomic additions, so two runs give
//! the same bits.
//!
//! ```no_run
//! use sprung::build::{self, ClothSprings};
//! use sprung::{IntegratorKind, World};
//! use sprung_gpu::GpuWorld;
//!
//! let mut world = World::new(IntegratorKind::SymplecticEuler);
//! let cloth = build::cloth(8, 8, 1.0, 1.0, ClothSprings::default()).unwrap();
//! world.add_body("cloth", cloth.with_stiffness(100.0).with_pinned(vec![56, 63])).unwrap();
//! let mut gpu = GpuWorld::new(&world, 1e-3).unwrap();
//! gpu.step(100); // 100 steps of 1 ms, on the GPU
//! gpu.read_into(&mut world).unwrap(); // positions and velocities back, the clock on
//! assert!((world.time() - 0.1).abs() < 1e-12);
//! ```

mod device;
pub mod gas;
mod kernels;
mod layout;
mod precision;
mod step;
pub mod support;
pub mod wind;

#[cfg(not(target_arch = "wasm32"))]
pub use device::adapter_summary;
pub use device::Gpu;
pub use layout::{grid, GpuCollider, Layout, Link, Params, Spring};
pub use precision::Precision;
pub use step::GpuWorld;

/// What can go wrong on the GPU path.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    /// No GPU adapter: no Vulkan, Metal or DX12 driver (on Linux, install
    /// Mesa's `mesa-vulkan-drivers` for a software one).
    #[error("no GPU adapter found ({0}); on Linux, Mesa's software Vulkan driver (Debian: mesa-vulkan-drivers) runs the GPU step on the CPU")]
    NoAdapter(String),
    /// The adapter refused a device with the limits the step needs.
    #[error("the GPU adapter \"{adapter}\" refused a device: {reason}")]
    NoDevice {
        /// The adapter's name.
        adapter: String,
        /// wgpu's reason.
        reason: String,
    },
    /// The world asks for something the GPU step lacks.
    #[error("the GPU step lacks {0}: run this scene with --device cpu")]
    Unsupported(String),
    /// f64 was asked for on an adapter without it (wgpu's `SHADER_F64`).
    #[error(
        "the GPU adapter \"{0}\" has no f64 (SHADER_F64): run in f32 (--device gpu) or on the CPU"
    )]
    NoF64(String),
    /// The world is larger than the adapter's buffers.
    #[error("the world needs a GPU buffer of {bytes} bytes, above the adapter's limit of {limit}")]
    TooLarge {
        /// The largest buffer the world needs (bytes).
        bytes: u64,
        /// The adapter's limit (bytes).
        limit: u64,
    },
    /// The GPU step's state blew up: a particle past the world's
    /// `max_distance` or `max_speed`, or not finite.
    #[error("the state blew up on the GPU at step {step} (a particle past max_distance or max_speed, or not finite); lower dt (the stable step is about {stable_dt:.3e} s)")]
    BlowUp {
        /// The first step (counted from the world's start) whose state blew up.
        step: u64,
        /// The explicit methods' stable time step of the world before the
        /// run (s).
        stable_dt: f64,
    },
    /// The device was lost or a read-back failed.
    #[error("the GPU failed: {0}")]
    Device(String),
    /// The engine refused the steps (its own guard).
    #[error(transparent)]
    Step(#[from] sprung::StepError),
}
