//! [`GpuWorld`]: a world's explicit step on the GPU, its state kept there
//! between steps.

use sprung::forces::Wind;
use sprung::{Gas, IntegratorKind, Real, Substeps, Vec3, World};

use std::sync::{Arc, Mutex};

use crate::gas;
use crate::kernels::{Kernels, STAGE_VALUES};
use crate::layout::{grid, Layout};
use crate::precision::Precision;
use crate::wind::WindLayout;
use crate::{support, Gpu, GpuError};

/// Steps encoded into one submission (a long run is cut so that no
/// command buffer grows without bound).
const STEPS_PER_SUBMIT: u64 = 64;

/// Stage slots (force evaluations) the stage buffer holds: a submission
/// takes as many steps as fit.
const SLOTS: u64 = 1024;

/// A world whose explicit step runs on the GPU ([`support::check`] says
/// which worlds), in f32 or f64 ([`Precision`]), its state held there
/// between steps.
#[derive(Debug)]
pub struct GpuWorld {
    gpu: Gpu,
    kind: IntegratorKind,
    /// The step (s), the substeps of each and the substep (s).
    dt: Real,
    substeps: u32,
    h: Real,
    /// The time of the next substep's start (s).
    time: Real,
    count: usize,
    /// Workgroups over the particles, and over the gas elements.
    groups: (u32, u32),
    gas_groups: (u32, u32),
    /// The gas bodies' schedules (one a gas slot).
    gases: Vec<Gas>,
    /// The wind, for its field's time-dependent parts.
    wind: Option<Wind>,
    kernels: Kernels,
    /// The stage slots of the submission being encoded.
    stages: Vec<u8>,
    /// Verlet's first step (its bootstrap) is still to come.
    first: bool,
    /// Steps run since the last read-back was asked for.
    pending: u64,
    /// The read-back asked for and not yet taken.
    reading: Option<Reading>,
    /// Steps read back so far.
    read: u64,
    /// The world's step count when it was put on the GPU.
    start_step: u64,
    /// The world's stable time step then (s), for a blow-up's message.
    stable_dt: Real,
}

/// A read-back on its way: whether (and how) the mapping ended.
#[derive(Debug)]
struct Reading {
    mapped: Arc<Mutex<Option<Result<(), String>>>>,
}

/// The times of one substep's force evaluations, as fractions of it.
fn evaluations(kind: IntegratorKind) -> &'static [Real] {
    match kind {
        IntegratorKind::Rk4 => &[0.0, 0.5, 0.5, 1.0],
        _ => &[0.0],
    }
}

impl GpuWorld {
    /// `world` on a new [`Gpu`], to be stepped by `dt` (s).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn new(world: &World, dt: Real) -> Result<GpuWorld, GpuError> {
        GpuWorld::on(Gpu::new()?, world, dt)
    }

    /// `world` on `gpu` in f32, to be stepped by `dt` (s): refused if the
    /// GPU step lacks something it uses ([`support::check`]) or `dt` is
    /// not a positive, finite step.
    pub fn on(gpu: Gpu, world: &World, dt: Real) -> Result<GpuWorld, GpuError> {
        GpuWorld::in_precision(gpu, world, dt, Precision::F32)
    }

    /// `world` on `gpu` in `precision`, as [`GpuWorld::on`]; f64 is
    /// refused where the adapter lacks it ([`Gpu::has_f64`]).
    pub fn in_precision(
        gpu: Gpu,
        world: &World,
        dt: Real,
        precision: Precision,
    ) -> Result<GpuWorld, GpuError> {
        support::check(world)?;
        if precision == Precision::F64 && !gpu.has_f64() {
            return Err(GpuError::NoF64(gpu.name()));
        }
        if !(dt.is_finite() && dt > 0.0) {
            return Err(sprung::StepError::InvalidTimeStep { dt }.into());
        }
        let substeps = match world.settings.substeps {
            Substeps::Fixed(n) => n.max(1),
            Substeps::Auto => 1,
        };
        let h = dt / Real::from(substeps);
        let layout = Layout::of(world, h);
        let per_step = evaluations(world.integrator()).len() as u64 * u64::from(substeps);
        // In a browser nothing can be waited for: an error there reaches
        // the device's handler, and the first read-back reports it.
        #[cfg(not(target_arch = "wasm32"))]
        let scope = gpu.device.push_error_scope(wgpu::ErrorFilter::Validation);
        #[cfg(not(target_arch = "wasm32"))]
        let memory = gpu.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
        let made = Kernels::new(&gpu, &layout, SLOTS.max(per_step), precision);
        #[cfg(not(target_arch = "wasm32"))]
        {
            let errors = [memory.pop(), scope.pop()].map(pollster::block_on);
            if let Some(error) = errors.into_iter().flatten().next() {
                return Err(GpuError::Device(error.to_string()));
            }
        }
        let count = world.particles.len();
        Ok(GpuWorld {
            kind: world.integrator(),
            dt,
            substeps,
            h,
            time: world.time(),
            count,
            groups: grid(count as u32),
            gas_groups: grid(layout.params.elements),
            gases: layout.gas.gas,
            wind: layout.wind.wind,
            kernels: made?,
            stages: Vec::new(),
            first: true,
            pending: 0,
            reading: None,
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

    /// Steps run and not yet read back (nor asked for).
    pub fn pending(&self) -> u64 {
        self.pending
    }

    /// Run `steps` steps of the world's `dt` on the GPU (queued: they are
    /// done by the time a read-back of them arrives, or
    /// [`GpuWorld::wait`] returns).
    pub fn step(&mut self, steps: u64) {
        let per_step = evaluations(self.kind).len() as u64 * u64::from(self.substeps);
        let most = (self.kernels.slots / per_step).clamp(1, STEPS_PER_SUBMIT);
        let mut left = steps;
        while left > 0 {
            let batch = left.min(most);
            self.fill_stages(batch);
            let queue = &self.gpu.queue;
            queue.write_buffer(&self.kernels.stage, 0, &self.stages);
            let mut encoder = self
                .gpu
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
            {
                let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("steps"),
                    timestamp_writes: None,
                });
                pass.set_bind_group(0, &self.kernels.state_group, &[]);
                // Every pipeline's layout has the stage; the evaluations
                // move it to their slots.
                pass.set_bind_group(1, &self.kernels.stage_group, &[0]);
                let mut slot = 0;
                for _ in 0..batch {
                    self.encode_step(&mut pass, &mut slot);
                }
            }
            self.gpu.queue.submit([encoder.finish()]);
            left -= batch;
        }
        self.pending += steps;
    }

    /// The stage slots of the next `batch` steps: each force evaluation's
    /// time and nRT, the clock moved on.
    fn fill_stages(&mut self, batch: u64) {
        let stride = self.kernels.stride as usize;
        self.stages.clear();
        for _ in 0..batch * u64::from(self.substeps) {
            for &offset in evaluations(self.kind) {
                let time = self.time + offset * self.h;
                let start = self.stages.len();
                // The slot: the time, the wind, then each gas's nRT, padded
                // to the stride (written in place: no allocation a slot).
                let mut values = [0.0; STAGE_VALUES];
                values[0] = time;
                values[4..16].copy_from_slice(&WindLayout::stage(self.wind.as_ref(), time));
                for (value, nrt) in values[16..].iter_mut().zip(gas::nrt_at(&self.gases, time)) {
                    *value = nrt;
                }
                self.kernels.precision.extend(&mut self.stages, &values);
                self.stages.resize(start + stride, 0);
            }
            self.time += self.h;
        }
    }

    /// One step's kernels, each over every particle, then the count;
    /// `slot` is the next stage slot.
    fn encode_step(&mut self, pass: &mut wgpu::ComputePass, slot: &mut u64) {
        let (x, y) = self.groups;
        let p = &self.kernels.pipelines;
        let run = |pass: &mut wgpu::ComputePass, pipeline: &wgpu::ComputePipeline| {
            pass.set_pipeline(pipeline);
            pass.dispatch_workgroups(x, y, 1);
        };
        let gas_bodies = self.gases.len() as u32;
        let (stage_group, stride, gas_groups) = (
            &self.kernels.stage_group,
            self.kernels.stride,
            self.gas_groups,
        );
        // The forces at the trial state, with the slot's time and nRT.
        let forces = |pass: &mut wgpu::ComputePass, slot: &mut u64| {
            pass.set_bind_group(1, stage_group, &[(*slot * stride) as u32]);
            *slot += 1;
            if gas_bodies > 0 {
                pass.set_pipeline(&p.volume_parts);
                pass.dispatch_workgroups(gas_groups.0, gas_groups.1, 1);
                pass.set_pipeline(&p.pressures);
                pass.dispatch_workgroups(gas_bodies.div_ceil(64), 1, 1);
            }
            run(pass, &p.forces);
        };
        for _ in 0..self.substeps {
            match self.kind {
                IntegratorKind::Verlet => {
                    forces(pass, slot);
                    if self.first {
                        run(pass, &p.verlet_start);
                    }
                    run(pass, &p.verlet);
                }
                IntegratorKind::Rk4 => {
                    run(pass, &p.rk4_begin);
                    for stage in &p.rk4_stages {
                        forces(pass, slot);
                        run(pass, stage);
                    }
                    forces(pass, slot);
                    run(pass, &p.rk4_end);
                }
                _ => {
                    forces(pass, slot);
                    run(pass, &p.symplectic);
                }
            }
            self.first = false;
        }
        pass.set_pipeline(&p.tick);
        pass.dispatch_workgroups(1, 1, 1);
    }

    /// Wait until the steps run so far are done, reading nothing back (a
    /// bench's clock).
    #[cfg(not(target_arch = "wasm32"))]
    pub fn wait(&self) -> Result<(), GpuError> {
        self.poll()?;
        match self.gpu.failure() {
            Some(failure) => Err(GpuError::Device(failure)),
            None => Ok(()),
        }
    }

    #[cfg(not(target_arch = "wasm32"))]
    fn poll(&self) -> Result<(), GpuError> {
        self.gpu
            .device
            .poll(wgpu::PollType::wait_indefinitely())
            .map(|_| ())
            .map_err(|e| GpuError::Device(e.to_string()))
    }

    /// Wait for the steps run so far, then write the positions and
    /// velocities into `world` (the one this was made from, widened to
    /// f64) and advance its clock by them ([`World::took_steps`]). If a
    /// step blew up, the GPU stopped at its end: the world gets that state
    /// and its clock stops there, and the engine's guard says which
    /// particle and why ([`GpuError::Step`] holding
    /// [`StepError::BlowUp`](sprung::StepError::BlowUp)), as a step on
    /// the CPU would. Nothing more can be stepped then.
    #[cfg(not(target_arch = "wasm32"))]
    pub fn read_into(&mut self, world: &mut World) -> Result<(), GpuError> {
        // A read asked for earlier holds fewer steps: take it first.
        if self.reading.is_some() {
            self.poll()?;
            self.finish_read(world)?;
        }
        self.request_read();
        self.poll()?;
        self.finish_read(world)
    }

    /// Ask for the state after the steps run so far, without waiting (in a
    /// browser, where nothing may block): [`GpuWorld::read_ready`] says
    /// when [`GpuWorld::finish_read`] can take it. Steps may be run
    /// meanwhile; a second ask before the first is taken does nothing.
    pub fn request_read(&mut self) {
        if self.reading.is_some() {
            return;
        }
        let b = &self.kernels;
        let state = self.state_bytes();
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
        encoder.copy_buffer_to_buffer(&b.position, 0, &b.readback, 0, state);
        encoder.copy_buffer_to_buffer(&b.velocity, 0, &b.readback, state, state);
        encoder.copy_buffer_to_buffer(&b.status, 0, &b.readback, 2 * state, 8);
        self.gpu.queue.submit([encoder.finish()]);
        let mapped = Arc::new(Mutex::new(None));
        let done = Arc::clone(&mapped);
        b.readback
            .slice(..2 * state + 8)
            .map_async(wgpu::MapMode::Read, move |result| {
                if let Ok(mut slot) = done.lock() {
                    *slot = Some(result.map_err(|e| e.to_string()));
                }
            });
        self.reading = Some(Reading { mapped });
        self.pending = 0;
    }

    /// Bytes of the positions (or the velocities) on the GPU.
    fn state_bytes(&self) -> u64 {
        (4 * self.kernels.precision.size() * self.count) as u64
    }

    /// The floating-point type it runs in.
    pub fn precision(&self) -> Precision {
        self.kernels.precision
    }

    /// Whether a read-back was asked for and not yet taken.
    pub fn is_reading(&self) -> bool {
        self.reading.is_some()
    }

    /// Whether the read-back asked for has arrived (or failed).
    pub fn read_ready(&self) -> bool {
        self.reading
            .as_ref()
            .is_some_and(|reading| reading.mapped.lock().map_or(true, |slot| slot.is_some()))
    }

    /// Take the read-back asked for into `world`, as
    /// [`GpuWorld::read_into`] does; an error if none was asked for or it
    /// has not arrived.
    pub fn finish_read(&mut self, world: &mut World) -> Result<(), GpuError> {
        if let Some(failure) = self.gpu.failure() {
            return Err(GpuError::Device(failure));
        }
        if !self.read_ready() {
            return Err(GpuError::Device("the read-back has not arrived".into()));
        }
        let Some(reading) = self.reading.take() else {
            return Err(GpuError::Device("no read-back was asked for".into()));
        };
        let mapped = reading.mapped.lock().ok().and_then(|mut slot| slot.take());
        if let Some(Err(error)) = mapped {
            return Err(GpuError::Device(error));
        }
        let b = &self.kernels;
        let state = self.state_bytes() as usize;
        let slice = b.readback.slice(..2 * state as u64 + 8);
        let read = slice
            .get_mapped_range()
            .map_err(|e| GpuError::Device(e.to_string()))
            .map(|data| {
                let values = b.precision.read(&data[..2 * state]);
                let status: &[u32] = bytemuck::cast_slice(&data[2 * state..]);
                let (position, velocity) = values.split_at(4 * self.count);
                let vector = |p: &[f64]| Vec3::new(p[0], p[1], p[2]);
                for (to, from) in world
                    .particles
                    .position
                    .iter_mut()
                    .zip(position.chunks_exact(4))
                {
                    *to = vector(from);
                }
                for (to, from) in world
                    .particles
                    .velocity
                    .iter_mut()
                    .zip(velocity.chunks_exact(4))
                {
                    *to = vector(from);
                }
                (status[0], status[1])
            });
        b.readback.unmap();
        let (taken, blew_up) = read?;
        // Steps taken up to the read: all those run before it, or up to
        // the one that blew up.
        let steps = u64::from(taken) - self.read;
        self.read = u64::from(taken);
        world.took_steps(self.dt, steps)?;
        if blew_up != u32::MAX {
            // Past a limit on the GPU, perhaps within it in the engine's
            // own f64 (f32's rounding).
            return Err(GpuError::BlowUp {
                step: self.start_step + u64::from(blew_up),
                stable_dt: self.stable_dt,
            });
        }
        Ok(())
    }
}
