//! `--device gpu` in the viewer (or the scene's `device`; on the web page,
//! `?device=gpu` too): the steps on the GPU step (`sprung-gpu`,
//! docs/gpu.md) while the world is one it can run, and on the engine while
//! it is not (a hand holds a particle: the hand is a spring the GPU step
//! has no kernel for). Whatever the window changes in the world (a
//! particle thrown, a setting moved, the other integrator) is put on the
//! GPU again before its next steps.
//!
//! Natively the state is read back every frame, in that frame. In a
//! browser nothing may wait: the GPU (its WebGPU) arrives a few frames
//! after the page asks for it, the engine stepping meanwhile, and each
//! frame's steps are read back at the next frame, so the picture is a
//! frame behind the GPU. A browser without WebGPU steps on the engine, and
//! the page says so.

use std::cell::RefCell;
use std::rc::Rc;

use sprung::{Real, Vec3, World};
use sprung_gpu::{support, Gpu, GpuError, GpuWorld, Precision};

/// The GPU, once it has arrived (or why it will not).
type Arrival = Rc<RefCell<Option<Result<Gpu, String>>>>;

/// The GPU, and the world on it while it runs there.
#[derive(Debug)]
pub struct GpuRun {
    gpu: Arrival,
    on_gpu: Option<OnGpu>,
    /// The feature that last sent the steps to the engine, said once.
    lacked: Option<String>,
    /// Why the steps run on the engine although the GPU was asked for (a
    /// browser without WebGPU), for the page to show.
    pub notice: Option<String>,
    /// The floating-point type of the steps on the GPU.
    precision: Precision,
    /// Steps taken on the GPU and read back so far.
    pub steps: u64,
    /// The last steps went to the GPU (not the engine).
    pub stepping: bool,
    /// The world on the GPU is to be put there again.
    stale: bool,
}

/// A world on the GPU, with what it last read back: a world that no
/// longer matches it was changed by the window.
#[derive(Debug)]
struct OnGpu {
    world: GpuWorld,
    dt: Real,
    read: (Vec<Vec3>, Vec<Vec3>),
}

impl OnGpu {
    /// Whether `world` is as the GPU last left it (the window changed
    /// nothing since).
    fn untouched(&self, world: &World) -> bool {
        self.read.0 == world.particles.position && self.read.1 == world.particles.velocity
    }
}

/// Say `message` where the viewer's notes go (the terminal, or the
/// browser's console).
fn note(message: &str) {
    #[cfg(not(target_arch = "wasm32"))]
    eprintln!("sprung-viewer: {message}");
    #[cfg(target_arch = "wasm32")]
    macroquad::logging::info!("sprung-viewer: {}", message);
}

#[cfg(not(target_arch = "wasm32"))]
fn arrival() -> Result<Arrival, String> {
    let gpu = Gpu::new().map_err(|e| format!("the GPU step: {e}"))?;
    note(&format!("stepping on the GPU: {}", gpu.name()));
    Ok(Rc::new(RefCell::new(Some(Ok(gpu)))))
}

/// The browser's GPU, asked for once a page: each scene opened after
/// shares it.
#[cfg(target_arch = "wasm32")]
fn arrival() -> Result<Arrival, String> {
    thread_local! {
        static ASKED: RefCell<Option<Arrival>> = const { RefCell::new(None) };
    }
    Ok(ASKED.with(|asked| {
        asked
            .borrow_mut()
            .get_or_insert_with(|| {
                let cell: Arrival = Rc::new(RefCell::new(None));
                let fill = Rc::clone(&cell);
                wasm_bindgen_futures::spawn_local(async move {
                    let gpu = Gpu::in_browser().await.map_err(|e| match e {
                        GpuError::NoAdapter(_) => {
                            "this browser offers no WebGPU adapter: stepping on the CPU".into()
                        }
                        other => format!("WebGPU: {other}: stepping on the CPU"),
                    });
                    match &gpu {
                        Ok(gpu) => note(&format!("stepping on the GPU: {}", gpu.name())),
                        Err(message) => note(message),
                    }
                    *fill.borrow_mut() = Some(gpu);
                });
                cell
            })
            .clone()
    }))
}

impl GpuRun {
    /// The GPU, to step in `precision`, or why there is none (natively;
    /// in a browser it arrives later, or the page is told why not).
    pub fn new(precision: Precision) -> Result<GpuRun, String> {
        // WebGPU has no f64.
        let (precision, notice) = if cfg!(target_arch = "wasm32") && precision == Precision::F64 {
            let why = "WebGPU has no f64: stepping on the GPU in f32";
            (Precision::F32, Some(why.to_string()))
        } else {
            (precision, None)
        };
        Ok(GpuRun {
            gpu: arrival()?,
            precision,
            on_gpu: None,
            lacked: None,
            notice,
            steps: 0,
            stepping: false,
            stale: false,
        })
    }

    /// Whether the steps of a frame go to the GPU at once and arrive at
    /// the next (in a browser), rather than in batches read back at once.
    pub fn takes_a_frame(&self) -> bool {
        cfg!(target_arch = "wasm32")
    }

    /// Mark the world on the GPU stale (its springs, gas or wind were
    /// changed): it is put there again before the next steps, once the
    /// steps on their way have landed.
    pub fn invalidate(&mut self) {
        self.stale = true;
    }

    /// Take `steps` steps of `dt` (s) of `world` on the GPU: the steps
    /// taken (in a browser, those of the last frame land in `world` and
    /// this frame's are sent; none while they have not landed), or `None`
    /// where the GPU step cannot run the world as it stands or has not
    /// arrived (the engine takes them).
    pub fn step(
        &mut self,
        world: &mut World,
        dt: Real,
        steps: usize,
    ) -> Option<Result<usize, String>> {
        self.stepping = false;
        let gpu = match &*self.gpu.borrow() {
            Some(Ok(gpu)) => gpu.clone(),
            Some(Err(why)) => {
                self.notice = Some(why.clone());
                return None;
            }
            None => return None,
        };
        if let Err(GpuError::Unsupported(feature)) = support::check(world) {
            if self.lacked.as_deref() != Some(&feature) {
                note(&format!(
                    "the GPU step lacks {feature}: stepping on the CPU"
                ));
                self.lacked = Some(feature);
            }
            self.on_gpu = None;
            return None;
        }
        self.lacked = None;
        if self.on_gpu.as_ref().is_some_and(|on| on.world.is_reading()) {
            match self.land(world) {
                Some(Ok(())) => {}
                Some(Err(failure)) => return Some(Err(failure)),
                None => {
                    self.stepping = true;
                    return Some(Ok(0));
                }
            }
        }
        let current = !self.stale
            && (self.on_gpu.as_ref()).is_some_and(|on| on.dt == dt && on.untouched(world));
        if !current {
            self.stale = false;
            match GpuWorld::in_precision(gpu, world, dt, self.precision) {
                Ok(gpu_world) => {
                    self.on_gpu = Some(OnGpu {
                        world: gpu_world,
                        dt,
                        read: (
                            world.particles.position.clone(),
                            world.particles.velocity.clone(),
                        ),
                    });
                }
                Err(error) => return Some(Err(format!("the GPU step: {error}"))),
            }
        }
        let on = self.on_gpu.as_mut()?;
        self.stepping = true;
        on.world.step(steps as u64);
        on.world.request_read();
        #[cfg(not(target_arch = "wasm32"))]
        {
            if let Err(error) = on.world.wait() {
                return Some(Err(format!("the GPU step: {error}")));
            }
            if let Some(Err(failure)) = self.land(world) {
                return Some(Err(failure));
            }
        }
        Some(Ok(steps))
    }

    /// The read-back on its way into `world`, if it has arrived; one the
    /// window has overtaken (it changed the world since the last read, or
    /// since the world went on the GPU) is dropped with the world on the
    /// GPU, which is put there again.
    fn land(&mut self, world: &mut World) -> Option<Result<(), String>> {
        let on = self.on_gpu.as_mut()?;
        if !on.world.read_ready() {
            return None;
        }
        if !on.untouched(world) {
            self.on_gpu = None;
            return Some(Ok(()));
        }
        let before = world.steps();
        let read = on.world.finish_read(world);
        self.steps += world.steps() - before;
        on.read.0.clone_from(&world.particles.position);
        on.read.1.clone_from(&world.particles.velocity);
        Some(read.map_err(|error| match error {
            GpuError::Step(step) => step.to_string(),
            other => format!("the GPU step: {other}"),
        }))
    }
}
