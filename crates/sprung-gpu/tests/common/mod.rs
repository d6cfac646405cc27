//! What the GPU tests share: the GPU, or a skip where there is none.

use sprung_gpu::Gpu;

/// The GPU, or `None` (the test passes, saying why) where this machine
/// has no adapter and `SPRUNG_GPU_TESTS` is not `require`. The test
/// command (`scripts/test.sh`) installs Mesa's software Vulkan driver and
/// sets `require`, so there these tests always run.
pub fn gpu() -> Option<Gpu> {
    match Gpu::new() {
        Ok(gpu) => Some(gpu),
        Err(error) if std::env::var("SPRUNG_GPU_TESTS").as_deref() != Ok("require") => {
            eprintln!("skipped: {error}");
            None
        }
        Err(error) => panic!("SPRUNG_GPU_TESTS=require, but {error}"),
    }
}

/// Whether `gpu` runs f64 (lavapipe does); where it does not, an f64
/// test passes saying so, unless `SPRUNG_GPU_TESTS` is `require`.
pub fn has_f64(gpu: &Gpu) -> bool {
    if gpu.has_f64() {
        return true;
    }
    if std::env::var("SPRUNG_GPU_TESTS").as_deref() == Ok("require") {
        panic!("SPRUNG_GPU_TESTS=require, but {} has no f64", gpu.name());
    }
    eprintln!("skipped: {} has no f64", gpu.name());
    false
}
