//! [`GpuWorld`]: a world's explicit step on the GPU, its state kept there
//! between steps.

use sprung::{IntegratorKind, Real, Substeps, Vec3, World};
use wgpu::util::DeviceExt;

use crate::layout::{grid, Layout, Params};
use crate::{support, Gpu, GpuError};

/// Steps encoded into one submission (a long run is cut so that no
/// command buffer grows without bound).
const STEPS_PER_SUBMIT: u64 = 64;

/// The kernels of `kernels.wgsl`, each a pipeline.
#[derive(Debug)]
struct Pipelines {
    forces: wgpu::ComputePipeline,
    symplectic: wgpu::ComputePipeline,
    verlet_start: wgpu::ComputePipeline,
    verlet: wgpu::ComputePipeline,
    rk4_begin: wgpu::ComputePipeline,
    rk4_stages: [wgpu::ComputePipeline; 3],
    rk4_end: wgpu::ComputePipeline,
    tick: wgpu::ComputePipeline,
}

/// The GPU's buffers of a world.
#[derive(Debug)]
struct Buffers {
    position: wgpu::Buffer,
    velocity: wgpu::Buffer,
    status: wgpu::Buffer,
    /// Positions, velocities and status copied here to be read.
    readback: wgpu::Buffer,
}

/// A world whose explicit step runs on the GPU ([`support::check`] says
/// which worlds), in f32, its state held there between steps.
#[derive(Debug)]
pub struct GpuWorld {
    gpu: Gpu,
    kind: IntegratorKind,
    /// The step (s) and the substeps of each.
    dt: Real,
    substeps: u32,
    count: usize,
    groups: (u32, u32),
    buffers: Buffers,
    bind_group: wgpu::BindGroup,
    pipelines: Pipelines,
    /// Verlet's first step (its bootstrap) is still to come.
    first: bool,
    /// Steps run since the last [`GpuWorld::read_into`].
    pending: u64,
    /// Steps read back so far.
    read: u64,
    /// The world's step count when it was put on the GPU.
    start_step: u64,
    /// The world's stable time step then (s), for a blow-up's message.
    stable_dt: Real,
}

fn storage(gpu: &Gpu, label: &str, contents: &[u8], limit: u64) -> Result<wgpu::Buffer, GpuError> {
    let bytes = contents.len() as u64;
    if bytes > limit {
        return Err(GpuError::TooLarge { bytes, limit });
    }
    Ok(gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents,
            usage: wgpu::BufferUsages::STORAGE
                | wgpu::BufferUsages::COPY_SRC
                | wgpu::BufferUsages::COPY_DST,
        }))
}

/// At least one element: a binding may not be empty.
fn nonempty<T: Copy + bytemuck::Zeroable>(mut items: Vec<T>) -> Vec<T> {
    if items.is_empty() {
        items.push(T::zeroed());
    }
    items
}

fn entry(binding: u32, ty: wgpu::BufferBindingType) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

impl GpuWorld {
    /// `world` on a new [`Gpu`], to be stepped by `dt` (s).
    pub fn new(world: &World, dt: Real) -> Result<GpuWorld, GpuError> {
        GpuWorld::on(Gpu::new()?, world, dt)
    }

    /// `world` on `gpu`, to be stepped by `dt` (s): refused if the GPU
    /// step lacks something it uses ([`support::check`]) or `dt` is not a
    /// positive, finite step.
    pub fn on(gpu: Gpu, world: &World, dt: Real) -> Result<GpuWorld, GpuError> {
        support::check(world)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(sprung::StepError::InvalidTimeStep { dt }.into());
        }
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let memory = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let made = GpuWorld::make(gpu.clone(), world, dt);
        let errors = [memory.pop(), scope.pop()].map(pollster::block_on);
        if let Some(error) = errors.into_iter().flatten().next() {
            return Err(GpuError::Device(error.to_string()));
        }
        made
    }

    /// [`GpuWorld::on`] for a world it has checked.
    fn make(gpu: Gpu, world: &World, dt: Real) -> Result<GpuWorld, GpuError> {
        let substeps = match world.settings.substeps {
            Substeps::Fixed(n) => n.max(1),
            Substeps::Auto => 1,
        };
        let layout = Layout::of(world, dt / Real::from(substeps));
        let count = world.particles.len();
        let limit = gpu.max_binding();
        let position = storage(
            &gpu,
            "position",
            bytemuck::cast_slice(&nonempty(layout.position)),
            limit,
        )?;
        let velocity = storage(
            &gpu,
            "velocity",
            bytemuck::cast_slice(&nonempty(layout.velocity)),
            limit,
        )?;
        let force = storage(
            &gpu,
            "force",
            bytemuck::cast_slice(&vec![[0f32; 4]; count.max(1)]),
            limit,
        )?;
        let first = storage(&gpu, "first", bytemuck::cast_slice(&layout.first), limit)?;
        let links = storage(
            &gpu,
            "links",
            bytemuck::cast_slice(&nonempty(layout.links)),
            limit,
        )?;
        let springs = storage(
            &gpu,
            "springs",
            bytemuck::cast_slice(&nonempty(layout.springs)),
            limit,
        )?;
        let scratch = storage(
            &gpu,
            "scratch",
            bytemuck::cast_slice(&vec![[0f32; 4]; 4 * count.max(1)]),
            limit,
        )?;
        let status = storage(
            &gpu,
            "status",
            bytemuck::cast_slice(&[0u32, u32::MAX]),
            limit,
        )?;
        let params: [Params; 1] = [layout.params];
        let uniform = gpu
            .device
            .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("params"),
                contents: bytemuck::cast_slice(&params),
                usage: wgpu::BufferUsages::UNIFORM,
            });
        let readback = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("readback"),
            size: 32 * count.max(1) as u64 + 8,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        use wgpu::BufferBindingType::{Storage, Uniform};
        let read_write = Storage { read_only: false };
        let read = Storage { read_only: true };
        let entries = [
            entry(0, Uniform),
            entry(1, read_write),
            entry(2, read_write),
            entry(3, read_write),
            entry(4, read),
            entry(5, read),
            entry(6, read_write),
            entry(7, read_write),
            entry(8, read),
        ];
        let device = &gpu.device;
        let bind_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sprung step"),
            entries: &entries,
        });
        let buffers = [
            &uniform, &position, &velocity, &force, &first, &links, &scratch, &status, &springs,
        ];
        let bound: Vec<wgpu::BindGroupEntry> = buffers
            .iter()
            .enumerate()
            .map(|(binding, buffer)| wgpu::BindGroupEntry {
                binding: binding as u32,
                resource: buffer.as_entire_binding(),
            })
            .collect();
        let bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("sprung step"),
            layout: &bind_layout,
            entries: &bound,
        });
        let pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("sprung step"),
            bind_group_layouts: &[Some(&bind_layout)],
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
        Ok(GpuWorld {
            kind: world.integrator(),
            dt,
            substeps,
            count,
            groups: grid(count as u32),
            buffers: Buffers {
                position,
                velocity,
                status,
                readback,
            },
            bind_group,
            pipelines,
            first: true,
            pending: 0,
            read: 0,
            start_step: world.steps(),
            stable_dt: world.stable_time_step(),
            gpu,
        })
    }

    /// The GPU it runs on.
    pub fn gpu(&self) -> &Gpu {
        &self.gpu
    }

    /// Steps run and not yet read back.
    pub fn pending(&self) -> u64 {
        self.pending
    }

    /// Run `steps` steps of the world's `dt` on the GPU (queued: they are
    /// done by the time [`GpuWorld::read_into`] returns).
    pub fn step(&mut self, steps: u64) {
        let mut left = steps;
        while left > 0 {
            let batch = left.min(STEPS_PER_SUBMIT);
            let mut encoder = self
                .gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("steps"),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, &self.bind_group, &[]);
                for _ in 0..batch {
                    self.encode_step(&mut pass);
                }
            }
            self.gpu.queue.submit([encoder.finish()]);
            left -= batch;
        }
        self.pending += steps;
    }

    /// One step's kernels, each over every particle, then the count.
    fn encode_step(&mut self, pass: &mut wgpu::ComputePass) {
        let (x, y) = self.groups;
        let p = &self.pipelines;
        let mut run = |pipeline: &wgpu::ComputePipeline| {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(x, y, 1);
        };
        for _ in 0..self.substeps {
            match self.kind {
                IntegratorKind::Verlet => {
                    run(&p.forces);
                    if self.first {
                        run(&p.verlet_start);
                    }
                    run(&p.verlet);
                }
                IntegratorKind::Rk4 => {
                    run(&p.rk4_begin);
                    for stage in &p.rk4_stages {
                        run(&p.forces);
                        run(stage);
                    }
                    run(&p.forces);
                    run(&p.rk4_end);
                }
                _ => {
                    run(&p.forces);
                    run(&p.symplectic);
                }
            }
            self.first = false;
        }
        pass.set_pipeline(&p.tick);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// Wait until the steps run so far are done, reading nothing back (a
    /// bench's clock).
    pub fn wait(&self) -> Result<(), GpuError> {
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(e.to_string()))?;
        match self.gpu.failure() {
            Some(failure) => Err(GpuError::Device(failure)),
            None => Ok(()),
        }
    }

    /// Wait for the steps run so far, then write the positions and
    /// velocities into `world` (the one this was made from, f32 widened to
    /// f64) and advance its clock by them ([`World::took_steps`]). If a
    /// step blew up, the GPU stopped at its end: the world gets that state
    /// and its clock stops there, and the engine's guard says which
    /// particle and why ([`GpuError::Step`] holding
    /// [`StepError::BlowUp`](sprung::StepError::BlowUp)), as a step on
    /// the CPU would. Nothing more can be stepped then.
    pub fn read_into(&mut self, world: &mut World) -> Result<(), GpuError> {
        if let Some(failure) = self.gpu.failure() {
            return Err(GpuError::Device(failure));
        }
        let n = self.count as u64;
        let b = &self.buffers;
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.copy_buffer_to_buffer(&b.position, 0, &b.readback, 0, 16 * n);
        encoder.copy_buffer_to_buffer(&b.velocity, 0, &b.readback, 16 * n, 16 * n);
        encoder.copy_buffer_to_buffer(&b.status, 0, &b.readback, 32 * n, 8);
        self.gpu.queue.submit([encoder.finish()]);
        let slice = b.readback.slice(..32 * n + 8);
        let (sender, receiver) = std::sync::mpsc::channel();
        slice.map_async(wgpu::MapMode::Read, move |result| {
            let _ = sender.send(result);
        });
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| GpuError::Device(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| GpuError::Device(e.to_string()))?
            .map_err(|e| GpuError::Device(e.to_string()))?;
        let read = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Device(e.to_string()))
            .map(|data| {
                let floats: &[[f32; 4]] = bytemuck::cast_slice(&data[..32 * n as usize]);
                let status: &[u32] = bytemuck::cast_slice(&data[32 * n as usize..]);
                let widen = |p: &[f32; 4]| Vec3::new(p[0].into(), p[1].into(), p[2].into());
                let (position, velocity) = floats.split_at(self.count);
                for (to, from) in world.particles.position.iter_mut().zip(position) {
                    *to = widen(from);
                }
                for (to, from) in world.particles.velocity.iter_mut().zip(velocity) {
                    *to = widen(from);
                }
                (status[0], status[1])
            });
        b.readback.unmap();
        let (taken, blew_up) = read?;
        // Steps taken since the last read: all those run, or up to the
        // one that blew up.
        let steps = u64::from(taken) - self.read;
        self.read = u64::from(taken);
        self.pending = 0;
        world.took_steps(self.dt, steps)?;
        if blew_up != u32::MAX {
            // Past a limit in f32, within it in f64.
            return Err(GpuError::BlowUp {
                step: self.start_step + u64::from(blew_up),
                stable_dt: self.stable_dt,
            });
        }
        Ok(())
    }
}
