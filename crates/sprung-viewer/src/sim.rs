//! The running simulation: the world, the user's settings (time step,
//! integrator, stiffness, damping, gas and wind) and real-time stepping on a
//! budget of wall-clock time per frame.

use sprung::forces::Wind;
use sprung::{IntegratorKind, Real, Vec3, World};
use sprung_io::Scene;

use crate::gpu::GpuRun;

/// Longest frame the simulation catches up on (s): after a stall (a window
/// drag, a hidden tab) it goes on instead of racing to catch up.
const MAX_FRAME: Real = 0.1;

/// The user's settings, kept across a reset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Time step (s).
    pub dt: Real,
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Factor on every spring's stiffness from the scene.
    pub stiffness_scale: Real,
    /// Factor on every spring's damping from the scene; where the scene has
    /// no damping at all, the damping itself (N·s/m).
    pub damping: Real,
    /// Factor on every gas's nRT from the scene.
    pub nrt_scale: Real,
    /// Wind speed (m/s), along the scene's wind direction.
    pub wind_speed: Real,
    /// Simulated seconds per wall-clock second wanted (1: real time).
    pub speed: Real,
}

/// A gas's nRT (J) and its schedule's keyframes `(t, nRT)` in the scene.
type GasBase = Option<(Real, Vec<(Real, Real)>)>;

/// The scene's own values that the settings scale.
#[derive(Debug, Clone)]
struct Base {
    stiffness: Vec<Real>,
    damping: Vec<Real>,
    nrt: Vec<GasBase>,
    wind: Option<Vec3>,
}

/// A world being simulated, with its settings and timing.
#[derive(Debug)]
pub struct Sim {
    /// The world.
    pub world: World,
    /// The current settings.
    pub settings: Settings,
    /// The scene's own settings (for "reset settings" and the sliders' ranges).
    pub defaults: Settings,
    /// Not stepping.
    pub paused: bool,
    /// Why the run stopped (a blow-up), shown until a reset.
    pub failure: Option<String>,
    /// Simulated time over the time wanted (wall-clock time × speed), over
    /// the last frames: 1 keeps up, less is slow motion.
    pub rate: Real,
    /// Steps taken in the last frame.
    pub steps_last_frame: u32,
    /// The last frame ran out of its wall-clock budget.
    pub behind: bool,
    /// The GPU step, with `--device gpu` (or the scene's `device`).
    pub gpu: Option<GpuRun>,
    base: Base,
    debt: Real,
    simulated: Real,
    wanted: Real,
}

impl Sim {
    /// Start `scene` with its own settings.
    pub fn new(scene: Scene) -> Self {
        let base = Base::of(&scene.world);
        let defaults = Settings {
            dt: scene.dt,
            integrator: scene.world.integrator(),
            stiffness_scale: 1.0,
            damping: if base.damping.iter().any(|&c| c > 0.0) {
                1.0
            } else {
                0.0
            },
            nrt_scale: 1.0,
            wind_speed: base.wind.map_or(0.0, Vec3::length),
            speed: 1.0,
        };
        Sim {
            world: scene.world,
            settings: defaults,
            defaults,
            paused: false,
            failure: None,
            rate: 1.0,
            steps_last_frame: 0,
            behind: false,
            gpu: None,
            base,
            debt: 0.0,
            simulated: 0.0,
            wanted: 0.0,
        }
    }

    /// Start `scene` again with `settings` (a reset keeps the user's).
    pub fn with_settings(scene: Scene, settings: Settings) -> Self {
        let mut sim = Sim::new(scene);
        sim.settings = settings;
        sim.apply();
        sim
    }

    /// The scene has springs with damping, so the damping setting is a factor.
    pub fn damping_is_factor(&self) -> bool {
        self.base.damping.iter().any(|&c| c > 0.0)
    }

    /// The scene has a wind.
    pub fn has_wind(&self) -> bool {
        self.base.wind.is_some()
    }

    /// The scene has a gas.
    pub fn has_gas(&self) -> bool {
        self.base.nrt.iter().any(Option::is_some)
    }

    /// Write the settings into the world.
    pub fn apply(&mut self) {
        if let Some(gpu) = &mut self.gpu {
            gpu.invalidate();
        }
        let s = self.settings;
        self.world.set_integrator(s.integrator);
        let factor = self.damping_is_factor();
        let springs = &mut self.world.springs;
        let count = springs
            .len()
            .min(self.base.stiffness.len())
            .min(self.base.damping.len());
        for k in 0..count {
            if springs.is_broken(k) {
                continue; // a broken spring stays broken
            }
            springs.stiffness[k] = self.base.stiffness[k] * s.stiffness_scale;
            let c0 = self.base.damping[k];
            springs.damping[k] = if factor { c0 * s.damping } else { s.damping };
        }
        for (body, base) in self.world.bodies.iter_mut().zip(&self.base.nrt) {
            if let (Some(gas), Some((nrt, keyframes))) = (body.gas.as_mut(), base) {
                gas.nrt = nrt * s.nrt_scale;
                for (k, k0) in gas.keyframes.iter_mut().zip(keyframes) {
                    k.1 = k0.1 * s.nrt_scale;
                }
            }
        }
        if let (Some(wind), Some(w0)) = (self.world.forces.get_mut::<Wind>(), self.base.wind) {
            wind.field.velocity = w0.normalize_or_zero() * s.wind_speed;
        }
    }

    /// Advance by one frame of `wall` seconds, taking steps until the
    /// simulated time catches up (times `speed`) or `budget` seconds of
    /// wall-clock time (read with `clock`) are spent; what is left over is
    /// dropped, so the run goes on in slow motion.
    pub fn advance(&mut self, wall: Real, budget: Real, clock: &mut dyn FnMut() -> Real) {
        self.steps_last_frame = 0;
        self.behind = false;
        if self.paused || self.failure.is_some() || wall.is_nan() || wall <= 0.0 {
            return;
        }
        let dt = self.settings.dt;
        let wanted = wall.min(MAX_FRAME) * self.settings.speed;
        self.debt += wanted;
        let start = clock();
        let mut simulated = 0.0;
        // Steps go to the engine's threads a batch at a time (one hand-over
        // to the pool per batch rather than per step). A batch doubles while
        // it takes under a tenth of the budget, and holds no more steps than
        // the rest of the budget allows at the last batch's pace: the budget
        // is overrun by about a step, as when the steps were taken one by
        // one, unless the steps get dearer within the frame.
        // In a browser the GPU takes all the steps owed at once (they land
        // at the next frame); the engine takes its batches.
        let mut batch = 1usize;
        while self.debt >= dt {
            let owed = (self.debt / dt) as usize;
            let before = clock();
            let (taken, ok) = self.step_batch(batch.min(owed.max(1)), owed.max(1), false);
            for _ in 0..taken {
                self.debt -= dt;
                simulated += dt;
            }
            self.steps_last_frame += u32::try_from(taken).unwrap_or(u32::MAX);
            if !ok {
                break;
            }
            if taken == 0 {
                // The GPU's last steps have not landed: the time owed from
                // before this frame is dropped (slow motion), this frame's
                // kept for the next.
                self.behind = self.debt > wanted;
                self.debt = self.debt.min(wanted);
                break;
            }
            let now = clock();
            if now - start > budget {
                self.behind = self.debt >= dt;
                self.debt = 0.0;
                break;
            }
            if now - before < 0.1 * budget {
                batch = batch.saturating_mul(2);
            }
            let per_step = (now - before) / taken as Real;
            if per_step > 0.0 {
                let affordable = ((budget - (now - start)) / per_step).ceil().max(1.0);
                batch = batch.min(affordable as usize);
            }
        }
        // Smoothed over about 20 frames, as sums, so that a time step longer
        // than a frame (a step every few frames) still reads as real time.
        self.simulated += 0.05 * (simulated - self.simulated);
        self.wanted += 0.05 * (wanted - self.wanted);
        self.rate = (self.simulated / self.wanted).min(1.0);
    }

    /// One step of the current `dt`; false (and `failure` set) on a blow-up.
    /// In a browser the engine takes it: a GPU step would land only at the
    /// next frame, which a paused run does not take.
    pub fn step_once(&mut self) -> bool {
        let engine = self.gpu.as_ref().is_some_and(GpuRun::takes_a_frame);
        self.step_batch(1, 1, engine).1
    }

    /// Up to `steps` steps of the current `dt` (`at_once` where the GPU
    /// takes a frame's steps together), on the GPU unless `engine`, else
    /// on a thread of the engine's pool; the steps taken, and false (and
    /// `failure` set) on a blow-up.
    fn step_batch(&mut self, steps: usize, at_once: usize, engine: bool) -> (usize, bool) {
        let (world, dt) = (&mut self.world, self.settings.dt);
        let gpu = self.gpu.as_mut().filter(|_| !engine);
        let stepped = gpu.and_then(|gpu| {
            let steps = if gpu.takes_a_frame() { at_once } else { steps };
            gpu.step(world, dt, steps)
        });
        if let Some(stepped) = stepped {
            return match stepped {
                Ok(taken) => (taken, true),
                Err(failure) => {
                    self.failure = Some(failure);
                    (steps, false)
                }
            };
        }
        let (taken, failure) = sprung::parallel::in_pool(|| {
            for taken in 0..steps {
                if let Err(e) = world.step(dt) {
                    return (taken, Some(e.to_string()));
                }
            }
            (steps, None)
        });
        let ok = failure.is_none();
        if failure.is_some() {
            self.failure = failure;
        }
        (taken, ok)
    }

    /// Wall-clock time the simulation still owes (s); for the collider path.
    pub fn pending(&self, wall: Real) -> Real {
        if self.paused || self.failure.is_some() {
            0.0
        } else {
            self.debt + wall.min(MAX_FRAME) * self.settings.speed
        }
    }
}

impl Base {
    fn of(world: &World) -> Self {
        Base {
            stiffness: world.springs.stiffness.clone(),
            damping: world.springs.damping.clone(),
            nrt: world
                .bodies
                .iter()
                .map(|b| b.gas.as_ref().map(|g| (g.nrt, g.keyframes.clone())))
                .collect(),
            wind: world.forces.get::<Wind>().map(|w| w.field.velocity),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::demos::Source;

    fn sim(name: &str) -> Sim {
        let index = crate::demos::find(name).unwrap_or(0);
        match Source::Demo(index).load() {
            Ok(scene) => Sim::new(scene),
            Err(e) => panic!("{e}"),
        }
    }

    #[test]
    fn a_fast_machine_keeps_real_time() {
        let mut sim = sim("rope");
        let mut now = 0.0;
        let mut clock = || {
            now += 1e-6;
            now
        };
        for _ in 0..10 {
            sim.advance(1.0 / 60.0, 0.01, &mut clock);
        }
        // 10 frames of 1/60 s at dt = 1e-3: 166 steps, give or take the remainder.
        assert!((sim.world.time() - 10.0 / 60.0).abs() <= 1e-3 + 1e-12);
        assert!(!sim.behind);
    }

    #[test]
    fn a_slow_machine_goes_into_slow_motion() {
        let mut sim = sim("rope");
        let mut now = 0.0;
        // Every clock read costs a millisecond: the 10 ms budget allows ~10 steps.
        let mut clock = || {
            now += 1e-3;
            now
        };
        sim.advance(1.0 / 60.0, 0.01, &mut clock);
        assert!(sim.behind);
        assert!(sim.steps_last_frame < 16, "{}", sim.steps_last_frame);
        assert!(sim.world.time() < 1.0 / 60.0);
    }

    #[test]
    fn settings_scale_the_scene_and_survive_a_reset() {
        let mut sim = sim("flag");
        let k0 = sim.world.springs.stiffness[0];
        sim.settings.stiffness_scale = 2.0;
        sim.settings.wind_speed = 4.0;
        sim.apply();
        assert_eq!(sim.world.springs.stiffness[0], 2.0 * k0);
        let wind = sim.world.forces.get::<Wind>().map(|w| w.field.velocity);
        assert_eq!(wind, Some(Vec3::new(4.0, 0.0, 0.0)));
        let scene = Source::Demo(crate::demos::find("flag").unwrap_or(0)).load();
        let reset = Sim::with_settings(scene.unwrap_or_else(|e| panic!("{e}")), sim.settings);
        assert_eq!(reset.world.springs.stiffness[0], 2.0 * k0);
    }

    #[test]
    fn gas_scale_and_absolute_damping() {
        let mut sim = sim("ball3d");
        sim.settings.nrt_scale = 0.5;
        sim.apply();
        assert_eq!(sim.world.bodies[0].gas.as_ref().map(|g| g.nrt), Some(250.0));
        let mut chain = self::sim("chain");
        assert!(!chain.damping_is_factor());
        chain.settings.damping = 0.3;
        chain.apply();
        assert!(chain.world.springs.damping.iter().all(|&c| c == 0.3));
    }

    #[test]
    fn a_blow_up_stops_the_run_with_its_message() {
        let mut sim = sim("oscillator");
        sim.settings.dt = 1.0; // far above the stable step of 1/π s
        sim.settings.integrator = IntegratorKind::Euler;
        sim.apply();
        let mut now = 0.0;
        for _ in 0..200 {
            sim.advance(0.1, 1.0, &mut || {
                now += 1e-6;
                now
            });
        }
        let failure = sim.failure.clone().unwrap_or_default();
        assert!(failure.contains("blew up"), "{failure}");
    }

    /// With `--device gpu`, the steps go to the GPU while the world is one
    /// it can run: a hand (a mouse spring) sends them to the engine, and
    /// letting go (the particle thrown) back to the GPU, with the world as
    /// the engine left it (skipped without an adapter unless
    /// `SPRUNG_GPU_TESTS=require`).
    #[cfg(not(target_arch = "wasm32"))]
    #[test]
    fn a_hand_sends_the_steps_to_the_engine_and_back_to_the_gpu() {
        use sprung::forces::MouseSpring;
        let gpu = match GpuRun::new(sprung_gpu::Precision::F32) {
            Ok(gpu) => gpu,
            Err(e) if std::env::var("SPRUNG_GPU_TESTS").as_deref() != Ok("require") => {
                eprintln!("skipped: {e}");
                return;
            }
            Err(e) => panic!("{e}"),
        };
        let mut sim = sim("cloth");
        sim.gpu = Some(gpu);
        let steps_on_gpu = |sim: &Sim| sim.gpu.as_ref().map_or(0, |g| g.steps);
        assert_eq!(sim.step_batch(10, 10, false), (10, true));
        assert_eq!(steps_on_gpu(&sim), 10);
        let hand = MouseSpring {
            particle: 5,
            target: sim.world.particles.position[5] + Vec3::Y,
            stiffness: 10.0,
            damping: 0.1,
        };
        sim.world.forces.push(Box::new(hand));
        assert_eq!(sim.step_batch(10, 10, false), (10, true));
        assert_eq!(steps_on_gpu(&sim), 10, "the engine took them");
        sim.world.forces.remove::<MouseSpring>();
        sim.world.particles.velocity[5] = Vec3::new(0.0, 3.0, 0.0); // thrown
        assert_eq!(sim.step_batch(10, 10, false), (10, true));
        assert_eq!(steps_on_gpu(&sim), 20);
        assert_eq!(sim.world.steps(), 30);
        // The throw went to the GPU with the state: the particle rose.
        let thrown = sim.world.particles.velocity[5].y;
        assert!(thrown > 1.0, "{thrown}");
    }
}
