//! `sprung.World`: a loaded scene, its state as numpy arrays (copies,
//! never views), stepped with the GIL released.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard, PoisonError};

use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sprung::{IntegratorKind, Vec3};
use sprung_io::export::energy_columns;
use sprung_io::state;

use crate::body::Body;
use crate::errors::{bad_value, failed, step_error, typed, value};
use crate::load::build_sim;
use crate::sim::{Sim, SIGNAL_CHECK};

/// A simulated world: particles joined by springs, bodies, colliders.
///
/// Every array it returns is a copy of the state at the time of the call
/// (never a view), so none can outlive the World or change under a
/// program's feet; assigning an array sets the state.
#[pyclass(module = "sprung._native")]
pub struct World {
    /// The simulation, behind a lock as Python may reach it from any
    /// thread (uncontended: one holder at a time, by `&mut self` or a
    /// short read).
    sim: Mutex<Sim>,
    /// Columns of its arrays of vectors: 2 in a 2D scene, else 3.
    columns: usize,
}

impl World {
    /// A World holding `sim`.
    pub fn new(sim: Sim) -> Self {
        let columns = if sim.planar { 2 } else { 3 };
        World {
            sim: Mutex::new(sim),
            columns,
        }
    }

    /// The simulation, for reading.
    pub fn sim(&self) -> MutexGuard<'_, Sim> {
        self.sim.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The simulation, for changing.
    pub fn sim_mut(&mut self) -> &mut Sim {
        self.sim.get_mut().unwrap_or_else(PoisonError::into_inner)
    }

    /// The columns of an array of vectors: 2 in a 2D scene, else 3.
    pub(crate) fn columns(&self) -> usize {
        self.columns
    }

    /// `vectors` as a numpy `(n, 2)` or `(n, 3)` array of float64.
    fn vectors<'py>(
        &self,
        py: Python<'py>,
        vectors: &[Vec3],
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let columns = self.columns();
        let flat: Vec<f64> = vectors
            .iter()
            .flat_map(|v| v.to_array().into_iter().take(columns))
            .collect();
        PyArray1::from_vec(py, flat).reshape([vectors.len(), columns])
    }

    /// An array-like of `(n, 2)` or `(n, 3)` finite numbers as vectors,
    /// refused with a message naming `what` otherwise.
    fn read_vectors(
        &self,
        array: &PyArrayLike2<'_, f64, AllowTypeChange>,
        what: &str,
    ) -> PyResult<Vec<Vec3>> {
        let view = array.as_array();
        let (n, columns) = (self.sim().scene.world.particles.len(), self.columns());
        if view.shape() != [n, columns] {
            return Err(bad_value(format!(
                "{what}: an array of shape {:?} where this world needs ({n}, {columns})",
                view.shape()
            )));
        }
        let mut vectors = Vec::with_capacity(n);
        for (i, row) in view.outer_iter().enumerate() {
            let z = if columns == 3 { row[2] } else { 0.0 };
            let v = Vec3::new(row[0], row[1], z);
            if !v.is_finite() {
                return Err(bad_value(format!("{what}: row {i} is not finite ({v:?})")));
            }
            vectors.push(v);
        }
        Ok(vectors)
    }

    /// The index of the body called `name`, or a `KeyError` listing them.
    fn body_index(&self, name: &str) -> PyResult<usize> {
        let sim = self.sim();
        let world = &sim.scene.world;
        world.body_index(name).ok_or_else(|| {
            let names: Vec<&str> = world.bodies.iter().map(|b| b.name.as_str()).collect();
            pyo3::exceptions::PyKeyError::new_err(format!(
                "no body named {name:?} (the bodies: {})",
                names.join(", ")
            ))
        })
    }
}

/// Step `sim` `steps` times with the GIL released, looking at Python's
/// signals every [`SIGNAL_CHECK`]: Ctrl-C stops it between steps with
/// `KeyboardInterrupt`, the world usable at the step it reached.
pub(crate) fn step_sim(py: Python<'_>, sim: &mut Sim, steps: u64) -> PyResult<()> {
    let mut left = steps;
    while left > 0 {
        let (done, result) = py.detach(|| sim.step_for(left, SIGNAL_CHECK));
        left -= done;
        result.map_err(|e| step_error(py, &e))?;
        if left > 0 {
            py.check_signals()?;
        }
    }
    Ok(())
}

#[pymethods]
impl World {
    /// Advance `n` steps of `dt` (s), with the GIL released.
    #[pyo3(signature = (n=1))]
    fn step(&mut self, py: Python<'_>, n: u64) -> PyResult<()> {
        step_sim(py, self.sim_mut(), n)
    }

    /// The time step (s).
    #[getter]
    fn dt(&self) -> f64 {
        self.sim().scene.dt
    }

    #[setter]
    fn set_dt(&mut self, dt: f64) -> PyResult<()> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(bad_value(format!(
                "dt = {dt}: must be a positive, finite time (s)"
            )));
        }
        self.sim_mut().scene.dt = dt;
        Ok(())
    }

    /// Simulated time (s).
    #[getter]
    fn time(&self) -> f64 {
        self.sim().scene.world.time()
    }

    /// Steps taken since the start.
    #[getter]
    fn steps(&self) -> u64 {
        self.sim().scene.world.steps()
    }

    /// Steps the scene asks for (its `duration` or `steps`).
    #[getter]
    fn scene_steps(&self) -> u64 {
        self.sim().scene.steps
    }

    /// 2 for a 2D scene (arrays have columns x, y), else 3.
    #[getter]
    fn dimension(&self) -> usize {
        self.columns()
    }

    /// The scene file's path (`<string>` for text given to `loads`).
    #[getter]
    fn path(&self) -> PathBuf {
        self.sim().path()
    }

    /// Positions (m), a copy: float64 `(n, 3)`, `(n, 2)` in 2D.
    #[getter]
    fn positions<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, &self.sim().scene.world.particles.position)
    }

    #[setter]
    fn set_positions(&mut self, array: PyArrayLike2<'_, f64, AllowTypeChange>) -> PyResult<()> {
        let positions = self.read_vectors(&array, "positions")?;
        let world = &mut self.sim_mut().scene.world;
        world.particles.position = positions;
        world.restart_integrator();
        Ok(())
    }

    /// Velocities (m/s), a copy: float64 `(n, 3)`, `(n, 2)` in 2D.
    #[getter]
    fn velocities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        self.vectors(py, &self.sim().scene.world.particles.velocity)
    }

    #[setter]
    fn set_velocities(&mut self, array: PyArrayLike2<'_, f64, AllowTypeChange>) -> PyResult<()> {
        let velocities = self.read_vectors(&array, "velocities")?;
        let world = &mut self.sim_mut().scene.world;
        if let Some(i) = (0..velocities.len())
            .find(|&i| world.particles.is_pinned(i) && velocities[i] != Vec3::ZERO)
        {
            return Err(bad_value(format!(
                "velocities: particle {i} is pinned, and a pinned particle stays at rest (give it 0)"
            )));
        }
        world.particles.velocity = velocities;
        world.restart_integrator();
        Ok(())
    }

    /// Masses (kg), a copy: float64 `(n,)`.
    #[getter]
    fn masses<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim().scene.world.particles.mass)
    }

    /// Which particles are pinned, a copy: bool `(n,)`.
    #[getter]
    fn pinned<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<bool>> {
        let sim = self.sim();
        let particles = &sim.scene.world.particles;
        let pinned: Vec<bool> = (0..particles.len())
            .map(|i| particles.is_pinned(i))
            .collect();
        PyArray1::from_vec(py, pinned)
    }

    /// Each spring's two particles, a copy: int64 `(m, 2)`.
    #[getter]
    fn springs<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<i64>>> {
        let sim = self.sim();
        let springs = &sim.scene.world.springs;
        let ends: Vec<i64> = (0..springs.len())
            .flat_map(|k| springs.endpoints(k).map(i64::from))
            .collect();
        PyArray1::from_vec(py, ends).reshape([springs.len(), 2])
    }

    /// Each spring's rest length (m), a copy: float64 `(m,)`.
    #[getter]
    fn rest_lengths<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_slice(py, &self.sim().scene.world.springs.rest_length)
    }

    /// The bodies' names, in the scene's order.
    #[getter]
    fn bodies(&self) -> Vec<String> {
        self.sim()
            .scene
            .world
            .bodies
            .iter()
            .map(|b| b.name.clone())
            .collect()
    }

    /// The body called `name` (a `KeyError` if there is none).
    fn body(slf: Bound<'_, Self>, name: &str) -> PyResult<Body> {
        let index = slf.try_borrow().map_err(busy)?.body_index(name)?;
        Ok(Body::new(slf.unbind(), index))
    }

    /// The energies (J) by the names of `diagnostics.csv`'s columns:
    /// `kinetic`, each potential term, `total`.
    fn energies<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let world = &self.sim().scene.world;
        let dict = PyDict::new(py);
        for (name, energy) in energy_columns(world, &world.energy_names()) {
            dict.set_item(name, energy)?;
        }
        Ok(dict)
    }

    /// The integrator's name (`sprung.integrators()` lists them); setting
    /// it switches integrator between steps.
    #[getter]
    fn integrator(&self) -> &'static str {
        self.sim().scene.world.integrator().name()
    }

    #[setter]
    fn set_integrator(&mut self, name: &str) -> PyResult<()> {
        let kind: IntegratorKind = name
            .parse::<IntegratorKind>()
            .map_err(|e| bad_value(e.to_string()))?;
        self.sim_mut().scene.world.set_integrator(kind);
        Ok(())
    }

    /// The force (N) applied from outside to each particle over the coming
    /// steps, a copy: `(n, 3)` (`(n, 2)` in 2D), zeros when none is set.
    /// Assign an array to set it, `None` to take it away.
    #[getter]
    fn external_forces<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let sim = self.sim();
        let n = sim.scene.world.particles.len();
        match sim.applied() {
            Some(force) => self.vectors(py, force),
            None => self.vectors(py, &vec![Vec3::ZERO; n]),
        }
    }

    #[setter]
    fn set_external_forces(
        &mut self,
        array: Option<PyArrayLike2<'_, f64, AllowTypeChange>>,
    ) -> PyResult<()> {
        let force = match array {
            Some(array) => Some(self.read_vectors(&array, "external_forces")?),
            None => None,
        };
        self.sim_mut().set_applied(force);
        Ok(())
    }

    /// Save the state (positions, velocities, time, the integrator's
    /// history) to `path`, complete or not at all.
    fn save_state(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let sim = self.sim();
        let world = &sim.scene.world;
        let mut saved = world.save_state();
        saved.put("run.dt", vec![sim.scene.dt]);
        state::write_state(&path, world, &saved).map_err(|e| state_error(py, &path, e))
    }

    /// Put back a state `save_state` wrote from a World of the same scene
    /// (and its time step); the World is unchanged when it is refused.
    fn load_state(&mut self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        let sim = self.sim_mut();
        let world = &mut sim.scene.world;
        let saved = state::read_state(&path, world).map_err(|e| state_error(py, &path, e))?;
        let dt = saved.get("run.dt", 1).ok().map(|v| v[0]);
        state::restore(&path, world, &saved).map_err(|e| state_error(py, &path, e))?;
        if let Some(dt) = dt.filter(|dt| dt.is_finite() && *dt > 0.0) {
            sim.scene.dt = dt;
        }
        Ok(())
    }

    /// A new World of the same scene in the same state.
    fn copy(&self, py: Python<'_>) -> PyResult<World> {
        let (text, path, dt, integrator, state, applied, gases) = {
            let this = self.sim();
            let world = &this.scene.world;
            let applied = this.applied().map(<[Vec3]>::to_vec);
            // A gas's nRT set from Python is not in the scene's text.
            let gases: Vec<_> = world.bodies.iter().map(|b| b.gas.clone()).collect();
            (
                this.text.clone(),
                this.path(),
                this.scene.dt,
                world.integrator(),
                world.save_state(),
                applied,
                gases,
            )
        };
        let mut sim = build_sim(py, text, &path, &[])?;
        sim.scene.dt = dt;
        sim.scene.world.set_integrator(integrator);
        sim.scene
            .world
            .restore_state(&state)
            .map_err(|e| failed(e.to_string()))?;
        if applied.is_some() {
            sim.set_applied(applied);
        }
        for (body, gas) in sim.scene.world.bodies.iter_mut().zip(gases) {
            body.gas = gas;
        }
        Ok(World::new(sim))
    }

    fn __copy__(&self, py: Python<'_>) -> PyResult<World> {
        self.copy(py)
    }

    fn __deepcopy__(&self, py: Python<'_>, _memo: Bound<'_, PyAny>) -> PyResult<World> {
        self.copy(py)
    }

    /// A PNG picture of the world now, drawn by `sprung render`'s renderer
    /// (camera fitted, springs coloured by strain).
    #[pyo3(signature = (width=640, height=480))]
    fn picture(&self, py: Python<'_>, width: u32, height: u32) -> PyResult<Vec<u8>> {
        crate::pictures::picture(py, self, width, height)
    }

    /// The picture Jupyter shows inline.
    fn _repr_png_(&self, py: Python<'_>) -> PyResult<Vec<u8>> {
        self.picture(py, 640, 480)
    }

    fn __repr__(&self) -> String {
        let sim = self.sim();
        let world = &sim.scene.world;
        format!(
            "<sprung.World {:?}: {} bodies, {} particles, {} springs, {}D, {}, dt = {} s, t = {} s>",
            sim.path().display().to_string(),
            world.bodies.len(),
            world.particles.len(),
            world.springs.len(),
            self.columns(),
            world.integrator().name(),
            sim.scene.dt,
            world.time()
        )
    }
}

/// The error for a World that another thread holds (stepping it).
pub fn busy(_: impl std::fmt::Debug) -> PyErr {
    failed("the World is in use (stepped or read by another thread): wait for that call to end")
}

/// A state file's error as `sprung.StateError` (a `ValueError`).
fn state_error(py: Python<'_>, path: &Path, error: state::StateFileError) -> PyErr {
    typed(
        py,
        "StateError",
        error.to_string(),
        &[("path", value(py, path.display().to_string()))],
    )
}
