//! The buffers, bind groups and pipelines of `kernels.wgsl` for one world.

use wgpu::util::DeviceExt;

use crate::layout::{Layout, Link};
use crate::precision::Precision;
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
    /// The kernels' floating-point type.
    pub precision: Precision,
    pub stride: u64,
    pub slots: u64,
    /// Group 0: every buffer; group 1: the stage, at a dynamic offset.
    pub state_group: wgpu::BindGroup,
    pub stage_group: wgpu::BindGroup,
    pub pipelines: Pipelines,
    /// The other buffers (the bind group reads them), kept to be freed.
    others: Vec<wgpu::Buffer>,
}

impl Drop for Kernels {
    /// Free the buffers now: in a browser a dropped buffer would wait for
    /// the page's garbage collector.
    fn drop(&mut self) {
        let kept = [&self.position, &self.velocity, &self.status];
        let more = [&self.readback, &self.stage];
        for buffer in kept.into_iter().chain(more).chain(&self.others) {
            buffer.destroy();
        }
    }
}

/// Values in one stage slot (`Stage` in the kernels: sixteen vectors of
/// four).
pub const STAGE_VALUES: usize = 64;

/// A storage buffer the kernels write.
const READ_WRITE: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: false };
/// A storage buffer the kernels only read.
const READ: wgpu::BufferBindingType = wgpu::BufferBindingType::Storage { read_only: true };

/// A word's index, or the number of words when it is past `u32`.
fn word(index: usize) -> Result<u32, usize> {
    u32::try_from(index).map_err(|_| index)
}

/// The springs' adjacency as the kernels read it: particle `i`'s range,
/// then the (other end, spring) pairs, each range given as positions in
/// the same array. Errs with the words needed when they are past `u32`.
fn pack_adjacency(first: &[u32], links: &[Link]) -> Result<Vec<u32>, usize> {
    let base = first.len();
    let mut words = Vec::with_capacity(base + 2 * links.len());
    for &k in first {
        words.push(word(base + 2 * k as usize)?);
    }
    for link in links {
        words.extend([link.other, link.spring]);
    }
    Ok(words)
}

/// An element table and its ranges, packed after `words`: the elements
/// (four words each), then particle `i`'s range, then the lists, each as
/// positions in `words`. Returns where the ranges start.
fn pack_elements(
    words: &mut Vec<u32>,
    elements: &[[u32; 4]],
    first: &[u32],
    links: &[u32],
) -> Result<u32, usize> {
    let table = words.len();
    words.extend(elements.iter().flatten());
    let ranges = words.len();
    let lists = ranges + first.len();
    for &k in first {
        words.push(word(lists + k as usize)?);
    }
    for &element in links {
        words.push(word(table + 4 * element as usize)?);
    }
    word(ranges)
}

/// The gas elements then the wind elements, with their ranges, in one
/// array (`faces` in the kernels), and where each kind's ranges start.
fn pack_faces(layout: &Layout) -> Result<(Vec<u32>, (u32, u32)), usize> {
    let (gas, wind) = (&layout.gas, &layout.wind);
    let mut words = Vec::new();
    let gas_at = pack_elements(
        &mut words,
        &gas.elements,
        &gas.element_first,
        &gas.element_links,
    )?;
    // A wind element's fourth word: where its body's scale is in the
    // constants, after the springs.
    let springs = layout.springs.len();
    let elements = wind
        .elements
        .iter()
        .map(|&[a, b, c, body]| Ok([a, b, c, word(springs + body as usize)?]))
        .collect::<Result<Vec<[u32; 4]>, usize>>()?;
    let wind_at = pack_elements(&mut words, &elements, &wind.first, &wind.links)?;
    Ok((words, (gas_at, wind_at)))
}

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
    /// `layout` on `gpu` in `precision`, with room for `slots` force
    /// evaluations' stages a submission.
    pub fn new(
        gpu: &Gpu,
        layout: &Layout,
        slots: u64,
        precision: Precision,
    ) -> Result<Kernels, GpuError> {
        let device = &gpu.device;
        let limit = gpu.max_binding();
        let count = layout.position.len().max(1);
        // A binding may not be empty.
        let reals = |values: &[[f64; 4]]| match values {
            [] => precision.bytes(&[0.0; 4]),
            _ => precision.bytes(values.as_flattened()),
        };
        let gas = &layout.gas;
        let parts = gas.elements.len() / crate::gas::PART + gas.bodies.len();
        let too_large = |words: usize| GpuError::TooLarge {
            bytes: 4 * words as u64,
            limit,
        };
        let adjacency = pack_adjacency(&layout.first, &layout.links).map_err(too_large)?;
        // The springs' constants, then the bodies' wind scales.
        let springs = layout.springs.iter();
        let scales = layout.wind.scales.iter();
        let constants: Vec<[f64; 4]> = springs
            .map(|s| [s.rest, s.stiffness, s.damping, 0.0])
            .chain(scales.map(|&scale| [scale, 0.0, 0.0, 0.0]))
            .collect();
        let mut params = layout.params;
        let (faces, at) = pack_faces(layout).map_err(too_large)?;
        (params.element_first_at, params.wind_first_at) = at;
        // Binding k + 1 holds buffers[k] (`kernels.wgsl`): eight storage
        // buffers, WebGPU's least limit.
        let buffers = [
            ("position", reals(&layout.position), READ_WRITE),
            ("velocity", reals(&layout.velocity), READ_WRITE),
            ("forces", reals(&vec![[0.0; 4]; count + parts]), READ_WRITE),
            ("adjacency", bytes(&adjacency), READ),
            ("constants", reals(&constants), READ),
            ("faces", bytes(&faces), READ),
            ("status", bytes(&[0u32, u32::MAX]), READ_WRITE),
            ("scratch", reals(&vec![[0.0; 4]; 4 * count]), READ_WRITE),
        ];
        let mut made = Vec::with_capacity(buffers.len());
        for (label, contents, _) in &buffers {
            made.push(storage(gpu, label, contents, limit)?);
        }
        let uniform = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("params"),
            contents: &params.bytes(precision),
            usage: wgpu::BufferUsages::UNIFORM,
        });
        let stage_bytes = (STAGE_VALUES * precision.size()) as u64;
        let stride = stage_bytes
            .next_multiple_of(device.limits().min_uniform_buffer_offset_alignment.into());
        let stage = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("stage"),
            size: stride * slots,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let readback = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: 8 * precision.size() as u64 * count as u64 + 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut entries = vec![entry(0, wgpu::BufferBindingType::Uniform, false)];
        for (k, (_, _, ty)) in buffers.iter().enumerate() {
            entries.push(entry(k as u32 + 1, *ty, false));
        }
        let state_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprung state"),
            entries: &entries,
        });
        let stage_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprung stage"),
            entries: &[entry(0, wgpu::BufferBindingType::Uniform, true)],
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
                    size: wgpu::BufferSize::new(stage_bytes),
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
            source: wgpu::ShaderSource::Wgsl(
                format!("{}\n{}", precision.prelude(), include_str!("kernels.wgsl")).into(),
            ),
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
        let status = made.remove(6);
        let velocity = made.remove(1);
        let position = made.remove(0);
        made.push(uniform);
        Ok(Kernels {
            position,
            velocity,
            status,
            readback,
            stage,
            precision,
            stride,
            slots,
            state_group,
            stage_group,
            pipelines,
            others: made,
        })
    }
}
