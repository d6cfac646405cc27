//! The web viewer has no GPU step yet (it would run through the browser's
//! WebGPU): `--device gpu` is a native option.

use sprung::{Real, World};

/// No GPU in the web viewer.
#[derive(Debug)]
pub struct GpuRun;

impl GpuRun {
    /// Always why not.
    pub fn new() -> Result<GpuRun, String> {
        Err("the web viewer has no GPU step yet".into())
    }

    /// Nothing to forget.
    pub fn invalidate(&mut self) {}

    /// Never steps: the engine does.
    pub fn step(&mut self, _: &mut World, _: Real, _: usize) -> Option<Result<(), String>> {
        None
    }
}
