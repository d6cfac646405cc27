//! The GPU: an adapter and a device from wgpu, on the native backends
//! (Vulkan, Metal, DX12; `WGPU_BACKEND` chooses among them, as wgpu reads it),
//! or in a browser its WebGPU.

use std::sync::{Arc, Mutex};

use crate::GpuError;

/// A GPU device and its queue, with the adapter's name. Cloning shares the
/// device.
#[derive(Debug, Clone)]
pub struct Gpu {
    /// The device the buffers and kernels live on.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// The adapter the device came from.
    pub info: wgpu::AdapterInfo,
    /// The first error the device raised outside an error scope (wgpu's
    /// default would panic), for the next read-back to report.
    failed: Arc<Mutex<Option<String>>>,
}

impl Gpu {
    /// The first adapter of the native backends, or of those
    /// `WGPU_BACKEND` names (`vulkan`, `metal`, `dx12`).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new() -> Result<Gpu, GpuError> {
        Gpu::with_backends(wgpu::Backends::PRIMARY.with_env())
    }

    /// The first adapter of `backends` (a discrete GPU first), with a
    /// device allowing its largest storage buffers.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn with_backends(backends: wgpu::Backends) -> Result<Gpu, GpuError> {
        pollster::block_on(Gpu::request(backends))
    }

    /// The browser's WebGPU adapter and a device (resolves on the page's
    /// event loop; a browser without WebGPU gives [`GpuError::NoAdapter`]).
    #[cfg(target_arch = "wasm32")]
    pub async fn in_browser() -> Result<Gpu, GpuError> {
        Gpu::request(wgpu::Backends::BROWSER_WEBGPU).await
    }

    /// The first adapter of `backends` and a device, awaited.
    async fn request(backends: wgpu::Backends) -> Result<Gpu, GpuError> {
        let mut descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        descriptor.backends = backends;
        descriptor.flags = wgpu::InstanceFlags::empty().with_env();
        let instance = wgpu::Instance::new(descriptor);
        let options = wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            ..Default::default()
        };
        let adapter = instance
            .request_adapter(&options)
            .await
            .map_err(|e| GpuError::NoAdapter(format!("backends {backends:?}: {e}")))?;
        let info = adapter.get_info();
        let available = adapter.limits();
        let limits = wgpu::Limits {
            // The kernels bind 8, WebGPU's least limit.
            max_storage_buffers_per_shader_stage: 8,
            max_storage_buffer_binding_size: available.max_storage_buffer_binding_size,
            max_buffer_size: available.max_buffer_size,
            max_compute_workgroups_per_dimension: available.max_compute_workgroups_per_dimension,
            ..wgpu::Limits::downlevel_defaults()
        };
        // f64 where the adapter has it (the kernels in f32 do not use it).
        let features = adapter.features() & wgpu::Features::SHADER_F64;
        let descriptor = wgpu::DeviceDescriptor {
            label: Some("sprung"),
            required_features: features,
            required_limits: limits,
            ..Default::default()
        };
        let (device, queue) =
            adapter
                .request_device(&descriptor)
                .await
                .map_err(|e| GpuError::NoDevice {
                    adapter: info.name.clone(),
                    reason: e.to_string(),
                })?;
        let failed = Arc::new(Mutex::new(None));
        let first = Arc::clone(&failed);
        device.on_uncaptured_error(Arc::new(move |error: wgpu::Error| {
            if let Ok(mut slot) = first.lock() {
                slot.get_or_insert_with(|| error.to_string());
            }
        }));
        Ok(Gpu {
            device,
            queue,
            info,
            failed,
        })
    }

    /// Whether the device runs the kernels in f64 (wgpu's `SHADER_F64`).
    pub fn has_f64(&self) -> bool {
        self.device.features().contains(wgpu::Features::SHADER_F64)
    }

    /// The first error the device raised since it was made, if any.
    pub fn failure(&self) -> Option<String> {
        self.failed.lock().ok().and_then(|slot| slot.clone())
    }

    /// The adapter's name, kind and backend: "llvmpipe (LLVM 15.0.6, 256
    /// bits), Cpu, Vulkan".
    pub fn name(&self) -> String {
        let info = &self.info;
        format!("{}, {:?}, {}", info.name, info.device_type, info.backend)
    }

    /// The largest storage buffer the device binds (bytes).
    pub fn max_binding(&self) -> u64 {
        let limits = self.device.limits();
        limits
            .max_storage_buffer_binding_size
            .min(limits.max_buffer_size)
    }
}

/// The adapter the GPU step would run on, named ([`Gpu::name`]), or why
/// there is none.
#[cfg(not(target_arch = "wasm32"))]
pub fn adapter_summary() -> Result<String, GpuError> {
    Gpu::new().map(|gpu| gpu.name())
}
