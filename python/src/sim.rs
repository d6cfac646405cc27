//! A scene being simulated, as the Python `World` and `Batch` hold it:
//! plain Rust, stepped with the GIL released.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use pyo3::PyResult;
use sprung::forces::AppliedForces;
use sprung::{StepError, Vec3};
use sprung_io::Scene;

use crate::errors::bad_value;

/// How long a call steps between looks at Python's signals (Ctrl-C).
pub const SIGNAL_CHECK: Duration = Duration::from_millis(50);

/// A loaded scene with what the Python side adds to it.
#[derive(Debug)]
pub struct Sim {
    /// The world, its time step and how it is run.
    pub scene: Scene,
    /// The scene's TOML text, to build copies from.
    pub text: String,
    /// A 2D scene: no body with faces (a surface, which may leave the
    /// plane), every particle and gravity in the plane z = 0 at load;
    /// arrays have two columns.
    pub planar: bool,
}

impl Sim {
    /// A `scene` built from `text`.
    pub fn new(scene: Scene, text: String) -> Self {
        let world = &scene.world;
        let planar = world.gravity().z == 0.0
            && world.bodies.iter().all(|b| b.faces.is_empty())
            && world.particles.position.iter().all(|p| p.z == 0.0);
        Sim {
            scene,
            text,
            planar,
        }
    }

    /// The scene file's path (relative paths inside it start from its folder).
    pub fn path(&self) -> PathBuf {
        self.scene.path.clone()
    }

    /// Take up to `steps` steps, stopping early once `budget` has passed
    /// (so the caller can look at its signals); the steps taken, and the
    /// error that stopped them, if any.
    pub fn step_for(&mut self, steps: u64, budget: Duration) -> (u64, Result<(), StepError>) {
        let (particles, springs) = (
            self.scene.world.particles.len(),
            self.scene.world.springs.len(),
        );
        let large = particles >= sprung::parallel::CHUNK
            || sprung::parallel::particle_span(springs, particles) < sprung::parallel::CHUNK;
        let (world, dt) = (&mut self.scene.world, self.scene.dt);
        let mut run = move || {
            let start = Instant::now();
            for done in 0..steps {
                if let Err(error) = world.step(dt) {
                    return (done, Err(error));
                }
                // The clock is read every step of a large world (whose
                // steps are slow), every 16 of a small one.
                if (large || done % 16 == 15) && start.elapsed() > budget {
                    return (done + 1, Ok(()));
                }
            }
            (steps, Ok(()))
        };
        // A large world's loops (a chunk of particles, or springs cut
        // finer than one) start from the pool itself (see
        // `sprung::parallel::in_pool`); a small one's run here, paying
        // nothing for a hand-over.
        if large {
            sprung::parallel::in_pool(run)
        } else {
            run()
        }
    }

    /// The steps a call runs: `steps`, or `time` (s) in steps of `dt`, or
    /// the scene's own; both, none of them positive, or more than
    /// [`sprung_io::scene::MAX_STEPS`] are refused.
    pub fn planned_steps(&self, steps: Option<u64>, time: Option<f64>) -> PyResult<u64> {
        match (steps, time) {
            (Some(_), Some(_)) => Err(bad_value("give steps or time, not both")),
            (Some(0), None) => Err(bad_value("steps must be at least 1")),
            (Some(n), None) => Ok(n),
            (None, Some(t)) => self.scene.steps_in(t).ok_or_else(|| {
                bad_value(format!(
                    "time = {t}: must be a positive, finite time (s) of at most {:.0e} steps",
                    sprung_io::scene::MAX_STEPS as f64
                ))
            }),
            (None, None) => Ok(self.scene.steps),
        }
    }

    /// The force applied to each particle from outside, if set.
    pub fn applied(&self) -> Option<&[Vec3]> {
        self.scene
            .world
            .forces
            .get::<AppliedForces>()
            .map(|f| f.force.as_slice())
    }

    /// Apply `force` (N, one per particle) from now on; `None` takes it away.
    pub fn set_applied(&mut self, force: Option<Vec<Vec3>>) {
        match force {
            Some(force) => self.scene.world.forces.set(AppliedForces { force }),
            None => {
                self.scene.world.forces.remove::<AppliedForces>();
            }
        }
    }
}
