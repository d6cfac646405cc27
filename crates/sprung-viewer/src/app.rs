//! The viewer's state and its frame: input, stepping on a time budget,
//! drawing, the panel, and the probe for tests.

use macroquad::math::{Rect, Vec2, Vec3};
use macroquad::time::{get_frame_time, get_time};
use macroquad::window::{clear_background, screen_dpi_scale, screen_height, screen_width};
use sprung::{IntegratorKind, Shape};

use crate::camera::{to_f32, Bounds, View};
use crate::demos::Source;
use crate::gpu::GpuRun;
use crate::hand::Hand;
use crate::render::{self, Look};
use crate::render3d::Renderer3d;
use crate::sim::{Settings, Sim};
use crate::ui::Ui;
use crate::{palette, probe, render2d};
use sprung_io::demos::DEMOS;
use sprung_io::Device;

/// Width of the control panel (pixels).
pub const PANEL_WIDTH: f32 = 300.0;

/// Wall-clock time the simulation may take per frame (s), leaving the rest
/// of a 60 Hz frame for drawing.
const STEP_BUDGET: f64 = 0.010;

/// The viewer.
pub struct App {
    /// Where the scene comes from.
    pub source: Source,
    /// Where the steps run, from the command line (else the scene's).
    device: Option<Device>,
    /// The running scene, if it loaded.
    pub sim: Option<Sim>,
    /// Why the scene did not load.
    pub error: Option<String>,
    /// The camera.
    pub view: View,
    /// The scene stays in the xy-plane.
    pub flat: bool,
    /// The particles' box when the scene was loaded.
    pub bounds: Bounds,
    /// Follow bodies that leave the view, until the user moves it.
    pub auto_fit: bool,
    /// The grab and the poking sphere.
    pub hand: Hand,
    /// What to draw.
    pub look: Look,
    /// Show the list of demos in the panel.
    pub scene_list: bool,
    /// Show the panel.
    pub panel: bool,
    /// Smoothed frame time (s).
    pub frame_time: f32,
    /// Frames drawn.
    pub frames: u32,
    /// Smoothed wall-clock time spent stepping per frame (s).
    pub physics_time: f64,
    /// Wall-clock time spent stepping (s) and steps taken, since the start.
    pub physics_total: (f64, u64),
    pub(crate) ui: Ui,
    renderer: Renderer3d,
    pub(crate) hover: Option<usize>,
    pub(crate) cursor_world: Vec3,
    pub(crate) last_mouse: Vec2,
    strains: Vec<f32>,
}

impl App {
    /// A viewer on `source`, its steps where `device` says (else where the
    /// scene's `device` does); a scene that does not load is shown as an
    /// error.
    pub fn new(source: Source, device: Option<Device>) -> App {
        let mut app = App {
            device,
            source: source.clone(),
            sim: None,
            error: None,
            view: View::framing(true, Bounds::of([]), Rect::new(0.0, 0.0, 1.0, 1.0)),
            flat: true,
            bounds: Bounds::of([]),
            auto_fit: true,
            hand: Hand::default(),
            look: Look {
                faces: true,
                springs: false,
                poke: None,
                full_strain: 0.05,
            },
            scene_list: false,
            // A narrow window (a phone) shows the world; H brings the panel.
            panel: screen_width() >= 900.0,
            frame_time: 1.0 / 60.0,
            frames: 0,
            physics_time: 0.0,
            physics_total: (0.0, 0),
            ui: Ui::default(),
            renderer: Renderer3d::default(),
            hover: None,
            cursor_world: Vec3::ZERO,
            last_mouse: Vec2::ZERO,
            strains: Vec::new(),
        };
        app.open(source, None);
        app
    }

    /// Load `source`, with `settings` (a reset) or the scene's own.
    pub fn open(&mut self, source: Source, settings: Option<Settings>) {
        let poke = self.hand.poke.is_some();
        self.hand = Hand::default();
        self.source = source;
        match self.source.load() {
            Ok(scene) => {
                let device = self.device.unwrap_or(scene.device);
                let mut sim = match settings {
                    Some(settings) => Sim::with_settings(scene, settings),
                    None => Sim::new(scene),
                };
                if device.is_gpu() {
                    let precision = match device {
                        Device::GpuF64 => sprung_gpu::Precision::F64,
                        _ => sprung_gpu::Precision::F32,
                    };
                    match GpuRun::new(precision) {
                        Ok(gpu) => sim.gpu = Some(gpu),
                        Err(message) => {
                            report(&message);
                            sim.failure = Some(message);
                        }
                    }
                }
                let reframe = settings.is_none() || self.sim.is_none();
                self.flat = render::is_flat(&sim.world);
                self.bounds = scene_bounds(&sim);
                self.sim = Some(sim);
                self.error = None;
                if reframe {
                    self.frame_view();
                }
                if poke {
                    self.toggle_poke();
                }
            }
            Err(message) => {
                report(&message);
                self.sim = None;
                self.error = Some(message);
            }
        }
    }

    /// Frame the scene as it was loaded, and follow it again.
    pub fn frame_view(&mut self) {
        self.view = View::framing(self.flat, self.bounds, self.viewport());
        self.auto_fit = true;
    }

    /// Start again from the scene's initial state, keeping the settings.
    pub fn reset(&mut self) {
        let settings = self.sim.as_ref().map(|s| s.settings);
        self.open(self.source.clone(), settings);
    }

    /// The demo `step` places after (or before) the one shown.
    pub fn next_scene(&mut self, step: i32) {
        let count = DEMOS.len() as i32;
        let current = self.source.demo().map_or(-1, |i| i as i32);
        let next = (current + step).rem_euclid(count) as usize;
        self.open(Source::Demo(next), None);
    }

    /// The part of the window the world is drawn in.
    pub fn viewport(&self) -> Rect {
        let left = if self.panel { PANEL_WIDTH } else { 0.0 };
        Rect::new(left, 0.0, (screen_width() - left).max(1.0), screen_height())
    }

    /// Turn the poking sphere on or off.
    pub fn toggle_poke(&mut self) {
        if let Some(sim) = self.sim.as_mut() {
            let radius = 0.12 * self.bounds.radius();
            self.hand
                .toggle_poke(&mut sim.world, self.cursor_world, radius);
        }
        self.look.poke = self.hand.poke;
    }

    /// One frame: take requests and input, step, draw.
    pub fn frame(&mut self) {
        let wall = get_frame_time().clamp(0.0, 1.0);
        self.frame_time += 0.05 * (wall - self.frame_time);
        if let Some(index) = probe::lock().request.take() {
            self.open(Source::Demo(index), None);
        }
        let device = probe::lock().device_request.take();
        if let Some(device) = device {
            self.device = Some(device);
            self.reset();
        }
        let upload = probe::lock().scene_request.take();
        if let Some((upload, reload)) = upload {
            let settings = reload
                .then(|| self.sim.as_ref().map(|s| s.settings))
                .flatten();
            self.open(Source::Upload(std::sync::Arc::new(upload)), settings);
        }
        let viewport = self.viewport();
        let panel = Rect::new(0.0, 0.0, PANEL_WIDTH, screen_height());
        let over_ui = self.panel && self.ui.wants_mouse(panel);
        self.keys();
        self.mouse(viewport, over_ui);
        if let Some(sim) = self.sim.as_mut() {
            if self.hand.poke.is_some() && !over_ui {
                let span = sim.pending(wall as f64);
                self.hand
                    .move_poke(&mut sim.world, self.cursor_world, span, wall as f64);
            }
            let before = get_time();
            sim.advance(wall as f64, STEP_BUDGET, &mut get_time);
            let spent = get_time() - before;
            self.physics_time += 0.05 * (spent - self.physics_time);
            self.physics_total.0 += spent;
            self.physics_total.1 += u64::from(sim.steps_last_frame);
            if self.auto_fit {
                let now = Bounds::of(sim.world.particles.position.iter().map(|&p| to_f32(p)));
                self.view.follow(now, viewport);
            }
        }
        self.draw(viewport);
        if self.panel {
            crate::panel::draw(self, panel);
        }
        self.frames += 1;
        self.publish(viewport);
    }

    fn draw(&mut self, viewport: Rect) {
        clear_background(palette::BACKGROUND);
        let Some(sim) = self.sim.as_ref() else {
            render2d::veil(viewport);
            // On the web the page shows it, in its one message box.
            if !cfg!(target_arch = "wasm32") {
                let text = self.error.as_deref().unwrap_or("");
                render::message(
                    viewport,
                    "This scene cannot be loaded",
                    &format!("{text}\n\n{LOAD_HINT}"),
                    palette::ERROR,
                );
            }
            return;
        };
        let world = &sim.world;
        self.look.full_strain =
            render::full_strain(world, self.look.full_strain, &mut self.strains);
        if self.flat {
            render2d::draw(world, &self.view, viewport, &self.look);
        } else if let Some(camera) = self.view.camera(viewport, screen_dpi_scale()) {
            self.renderer.draw(world, &camera, self.bounds, &self.look);
        }
        let screen = |i: usize| {
            let p = to_f32(world.particles.position[i]);
            self.view.project(p, viewport).map(|(s, _)| s)
        };
        if let Some(grab) = self.hand.grab {
            let target = self.view.project(grab.target, viewport).map(|(s, _)| s);
            if let (Some(particle), Some(target)) = (screen(grab.particle), target) {
                render::hand(particle, target);
            }
        } else if let Some(particle) = self.hover.and_then(screen) {
            render::hover(particle);
        }
        crate::hud::draw(self, viewport);
        if let (Some(failure), false) = (&sim.failure, cfg!(target_arch = "wasm32")) {
            render::message(
                viewport,
                "The simulation blew up",
                &format!("{failure}\n\n{BLOW_UP_HINT}"),
                palette::ERROR,
            );
        }
    }

    fn publish(&self, viewport: Rect) {
        let mut probe = probe::lock();
        probe.frames = self.frames;
        probe.fps = 1.0 / self.frame_time.max(1e-6);
        probe.grabbed = self.hand.grab.map(|g| g.particle);
        probe.cursor = to_f64_array(self.cursor_world);
        probe.demo = self.source.demo();
        probe.error = self.error.is_some();
        probe.message = match &self.error {
            Some(error) => format!("{error}\n{LOAD_HINT}"),
            None => String::new(),
        };
        probe.positions.clear();
        probe.screen.clear();
        if let Some(sim) = &self.sim {
            probe.error |= sim.failure.is_some();
            if let Some(failure) = &sim.failure {
                probe.message = format!("{failure}\n{BLOW_UP_HINT}");
            }
            probe.time = sim.world.time();
            probe.gpu_steps = sim.gpu.as_ref().map_or(0.0, |gpu| gpu.steps as f64);
            if let Some(notice) = sim.gpu.as_ref().and_then(|gpu| gpu.notice.as_ref()) {
                if !probe.message.is_empty() {
                    probe.message.push('\n');
                }
                probe.message.push_str(notice);
            }
            for &p in &sim.world.particles.position {
                probe.positions.push(p.to_array());
                let screen = self.view.project(to_f32(p), viewport);
                probe
                    .screen
                    .push(screen.map_or([f32::NAN; 2], |(s, _)| s.to_array()));
            }
        }
    }
}

fn to_f64_array(p: Vec3) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

/// The particles' box, with the nearest point of each floor, so that the
/// first view shows where the bodies will land.
fn scene_bounds(sim: &Sim) -> Bounds {
    let world = &sim.world;
    let points: Vec<Vec3> = world
        .particles
        .position
        .iter()
        .map(|&p| to_f32(p))
        .collect();
    let centre = Bounds::of(points.iter().copied()).centre();
    let floors = world.colliders.iter().filter_map(|c| match c.shape {
        Shape::Plane { point, normal } => {
            let (point, normal) = (to_f32(point), to_f32(normal));
            Some(centre - normal * (centre - point).dot(normal))
        }
        Shape::Sphere { .. } => None,
    });
    Bounds::of(points.iter().copied().chain(floors))
}

/// Switch to the integrator `step` places along [`IntegratorKind::ALL`].
pub fn cycle_integrator(sim: &mut Sim, step: i32) {
    let all = IntegratorKind::ALL;
    let current = all
        .iter()
        .position(|&k| k == sim.settings.integrator)
        .unwrap_or(0) as i32;
    let next = (current + step).rem_euclid(all.len() as i32) as usize;
    sim.settings.integrator = all[next];
    sim.apply();
}

/// Multiply the time step by `factor`, within 1e-6 s and 0.05 s.
pub fn scale_dt(sim: &mut Sim, factor: f64) {
    sim.settings.dt = (sim.settings.dt * factor).clamp(1e-6, 0.05);
}

/// Say why a scene did not load where the user will see it: the terminal
/// natively, the browser's console on the web.
/// What to do about a scene that did not load (R reads it again from
/// where it came: the file, or on the web its address or picked file).
const LOAD_HINT: &str =
    "Pick a demo in the panel (or press Tab); fix the file and press R to load it again.";

/// What to do after a blow-up.
const BLOW_UP_HINT: &str =
    "Press R to start again; a smaller time step ([) or a stabler integrator (I) may hold.";

fn report(message: &str) {
    #[cfg(not(target_arch = "wasm32"))]
    eprintln!("sprung-viewer: cannot load the scene: {message}");
    #[cfg(target_arch = "wasm32")]
    macroquad::logging::error!("sprung-viewer: cannot load the scene: {}", message);
}
