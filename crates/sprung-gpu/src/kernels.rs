//! The buffers, bind groups and pipelines of `kernels.wgsl` for one world.

use wgpu::util::DeviceExt;

use crate::layout::{Layout, Params};
use crate::{Gpu, GpuError};

/// The kernels of `kernels.wgsl`, each a pipeline.
#[derive(Debug)]
pub struct Pipelines {
    pub forces: wgpu::ComputePipeline,
    pub volume_parts: wgpu::ComputePipeline,
    pub pressures: wgpu::ComputePipeline,
    pub symplectic: wgpu::ComputePipeline,
    pub verlet_start: wgpu::ComputePipeline,
    pub verlet: wgpu::ComputePipeline,
    pub rk4_begin: wgpu::ComputePipeline,
    pub rk4_stages: [wgpu::ComputePipeline; 3],
    pub rk4_end: wgpu::ComputePipeline,
    pub tick: wgpu::ComputePipeline,
}

/// A world's buffers on the GPU, bound, with the pipelines that read them.
#[derive(Debug)]
pub struct Kernels {
    /// Positions (m) with inverse masses, velocities (m/s) with masses.
    pub position: wgpu::Buffer,
    pub velocity: wgpu::Buffer,
    /// Steps taken and the first that blew up.
    pub status: wgpu::Buffer,
    /// Positions, velocities and status copied here to be read.
    pub readback: wgpu::Buffer,
    /// What changes from one force evaluation to the next (time, nRT):
    /// one slot of `stride` bytes an evaluation, `slots` of them.
    pub stage: wgpu::Buffer,
    pub stride: u64,
    pub slots: u64,
    /// Group 0: every buffer; group 1: the stage, at a dynamic offset.
    pub state_group: wgpu::BindGroup,
    pub stage_group: wgpu::BindGroup,
    pub pipelines: Pipelines,
}

/// Bytes of one stage slot (`Stage` in the kernels).
pub const STAGE_BYTES: u64 = 256;

fn storage(gpu: &Gpu, label: &str, contents: &[u8], limit: u64) -> Result<wgpu::Buffer, GpuError> {
    let bytes = contents.len() as u64;
    if bytes > limit {
        return Err(GpuError::TooLarge { bytes, limit });
    }
    let usage =
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let descriptor = wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents,
        usage,
    };
    Ok(gpu.device.create_buffer_init(&descriptor))
}

/// The bytes of `items`, at least one item's worth: a binding may not be
/// empty.
fn bytes<T: bytemuck::Pod>(items: &[T]) -> Vec<u8> {
    if items.is_empty() {
        vec![0; size_of::<T>().max(4)]
    } else {
        bytemuck::cast_slice(items).to_vec()
    }
}

fn entry(binding: u32, ty: wgpu::BufferBindingType, dynamic: bool) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: dynamic,
            min_binding_size: None,
        },
        count: None,
    }
}

impl Kernels {
    /// `layout` on `gpu`, with room for `slots` force evaluations' stages
    /// a submission.
    pub fn new(gpu: &Gpu, layout: &Layout, slots: u64) -> Result<Kernels, GpuError> {
        let device = &gpu.device;
        let limit = gpu.max_binding();
        let count = layout.position.len().max(1);
        let zeros = |n: usize| vec![[0f32; 4]; n];
        let gas = &layout.gas;
        let parts = gas.elements.len() / crate::gas::PART + gas.bodies.len();
        let buffers = [
            ("position", bytes(&layout.position)),
            ("velocity", bytes(&layout.velocity)),
            ("force", bytes(&zeros(count))),
            ("first", bytes(&layout.first)),
            ("links", bytes(&layout.links)),
            ("scratch", bytes(&zeros(4 * count))),
            ("status", bytes(&[0u32, u32::MAX])),
            ("springs", bytes(&layout.springs)),
            ("elements", bytes(&gas.elements)),
            ("element_first", bytes(&gas.element_first)),
            ("element_links", bytes(&gas.element_links)),
            ("gas_sums", bytes(&vec![0f32; parts])),
            ("wind_elements", bytes(&layout.wind.elements)),
            ("wind_first", bytes(&layout.wind.first)),
            ("wind_links", bytes(&layout.wind.links)),
        ];
        let mut made = Vec::with_capacity(buffers.len());
        for (label, contents) in &buffers {
            made.push(storage(gpu, label, contents, limit)?);
        }
        let params: [Params; 1] = [layout.params];
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: bytemuck::cast_slice(&params),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let stride = STAGE_BYTES.max(device.limits().min_uniform_buffer_offset_alignment.into());
        let stage = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("stage"),
            size: stride * slots,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: 32 * count as u64 + 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        use wgpu::BufferBindingType::{Storage, Uniform};
        let (read_write, read) = (Storage { read_only: false }, Storage { read_only: true });
        // Binding k + 1 holds buffers[k]; those the kernels only read are
        // bound read-only.
        let only_read = [
            "first",
            "links",
            "springs",
            "elements",
            "element_first",
            "element_links",
            "wind_elements",
            "wind_first",
            "wind_links",
        ];
        let mut entries = vec![entry(0, Uniform, false)];
        for (k, (label, _)) in buffers.iter().enumerate() {
            let ty = if only_read.contains(label) {
                read
            } else {
                read_write
            };
            entries.push(entry(k as u32 + 1, ty, false));
        }
        let state_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprung state"),
            entries: &entries,
        });
        let stage_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprung stage"),
            entries: &[entry(0, Uniform, true)],
        });
        let bound: Vec<wgpu::BindGroupEntry> = std::iter::once(&uniform)
            .chain(&made)
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let state_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sprung state"),
            layout: &state_layout,
            entries: &bound,
        });
        let stage_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sprung stage"),
            layout: &stage_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: wgpu::BindingResource::Buffer(wgpu::BufferBinding {
                    buffer: &stage,
                    offset: 0,
                    size: wgpu::BufferSize::new(STAGE_BYTES),
                }),
            }],
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sprung step"),
            bind_group_layouts: &[Some(&state_layout), Some(&stage_layout)],
            immediate_size: 0,
        });
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("kernels.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("kernels.wgsl").into()),
        });
        let kernel = |name: &str| {
            device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(name),
                layout: Some(&pipeline_layout),
                module: &module,
                entry_point: Some(name),
                compilation_options: Default::default(),
                cache: None,
            })
        };
        let pipelines = Pipelines {
            forces: kernel("forces"),
            volume_parts: kernel("volume_parts"),
            pressures: kernel("pressures"),
            symplectic: kernel("symplectic"),
            verlet_start: kernel("verlet_start"),
            verlet: kernel("verlet"),
            rk4_begin: kernel("rk4_begin"),
            rk4_stages: [
                kernel("rk4_stage1"),
                kernel("rk4_stage2"),
                kernel("rk4_stage3"),
            ],
            rk4_end: kernel("rk4_end"),
            tick: kernel("tick"),
        };
        // The bind group keeps the other buffers alive.
        let status = made.remove(6);
        let velocity = made.remove(1);
        let position = made.remove(0);
        Ok(Kernels {
            position,
            velocity,
            status,
            readback,
            stage,
            stride,
            slots,
            state_group,
            stage_group,
            pipelines,
        })
    }
}
