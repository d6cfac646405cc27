//! `sprung.Body`: one body of a World, read live.

use numpy::PyArray1;
use pyo3::prelude::*;

use crate::errors::bad_value;
use crate::sim::Sim;
use crate::world::{busy, World};

/// One body of a World, read live: each property is the body's value at
/// the World's current state. It keeps its World alive.
#[pyclass(module = "sprung._native")]
pub struct Body {
    world: Py<World>,
    index: usize,
}

impl Body {
    /// Body `index` of `world`.
    pub fn new(world: Py<World>, index: usize) -> Self {
        Body { world, index }
    }

    /// `f` of the World, its simulation and this body, read under the
    /// World's borrow.
    fn with<R>(
        &self,
        py: Python<'_>,
        f: impl FnOnce(&World, &Sim, &sprung::Body) -> R,
    ) -> PyResult<R> {
        let world = self.world.try_borrow(py).map_err(busy)?;
        let sim = world.sim();
        Ok(f(&world, &sim, &sim.scene.world.bodies[self.index]))
    }
}

#[pymethods]
impl Body {
    /// The body's name.
    #[getter]
    fn name(&self, py: Python<'_>) -> PyResult<String> {
        self.with(py, |_, _, body| body.name.clone())
    }

    /// Its particles' indices in the World's arrays: int64 `(k,)`.
    #[getter]
    fn indices<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<i64>>> {
        let range = self.with(py, |_, _, body| body.particles.clone())?;
        Ok(PyArray1::from_vec(py, range.map(|i| i as i64).collect()))
    }

    /// Enclosed volume (m³; area, m², in 2D), `None` for a body that is not closed.
    #[getter]
    fn volume(&self, py: Python<'_>) -> PyResult<Option<f64>> {
        self.with(py, |_, sim, _| sim.scene.world.volume(self.index))
    }

    /// Gas pressure (Pa; N/m in 2D), `None` for a body without gas.
    #[getter]
    fn pressure(&self, py: Python<'_>) -> PyResult<Option<f64>> {
        self.with(py, |_, sim, _| sim.scene.world.pressure(self.index))
    }

    /// Centre of mass (m): float64 `(3,)`, `(2,)` in 2D.
    #[getter]
    fn centroid<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (c, columns) = self.with(py, |world, sim, _| {
            let c = sim.scene.world.centroid(self.index).unwrap_or_default();
            (c, world.columns())
        })?;
        Ok(PyArray1::from_vec(py, c.to_array()[..columns].to_vec()))
    }

    /// The gas's `nRT` (J) now, for a body with gas (else `None`).
    /// Setting it holds `nRT` at that value from now on (the scene's ramp,
    /// schedule and leak are dropped): a controller inflating and
    /// deflating the body between steps.
    #[getter]
    fn nrt(&self, py: Python<'_>) -> PyResult<Option<f64>> {
        self.with(py, |_, sim, body| {
            let t = sim.scene.world.time();
            body.gas.as_ref().map(|gas| gas.nrt_at(t))
        })
    }

    #[setter]
    fn set_nrt(&self, py: Python<'_>, nrt: f64) -> PyResult<()> {
        if !(nrt.is_finite() && nrt >= 0.0) {
            return Err(bad_value(format!(
                "nrt = {nrt}: must be a finite amount of gas, 0 or more (J)"
            )));
        }
        let mut world = self.world.try_borrow_mut(py).map_err(busy)?;
        let body = &mut world.sim_mut().scene.world.bodies[self.index];
        let Some(gas) = body.gas.as_mut() else {
            return Err(bad_value(format!(
                "body {:?} has no gas: only a gas body's nrt can be set",
                body.name
            )));
        };
        *gas = sprung::Gas {
            volume_model: gas.volume_model,
            ..sprung::Gas::new(nrt, 0.0)
        };
        Ok(())
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        self.with(py, |_, _, body| {
            format!(
                "<sprung.Body {:?}: {} particles>",
                body.name,
                body.particles.len()
            )
        })
    }
}
