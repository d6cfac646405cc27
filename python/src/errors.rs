//! Rust errors as the package's typed Python exceptions (defined in
//! `sprung/_errors.py`): the same message the command line prints, and
//! the fields a program needs.

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use pyo3::BoundObject;
use sprung::StepError;
use sprung_io::SceneError;

/// An instance of `sprung._errors.CLASS(message)` with `fields` set, as a
/// `PyErr`; if the class cannot be had, the error that says why.
pub fn typed(
    py: Python<'_>,
    class: &str,
    message: String,
    fields: &[(&str, Bound<'_, PyAny>)],
) -> PyErr {
    let made = || -> PyResult<PyErr> {
        let kwargs = PyDict::new(py);
        for (name, value) in fields {
            kwargs.set_item(name, value)?;
        }
        let class = py.import("sprung._errors")?.getattr(class)?;
        Ok(PyErr::from_value(
            class.call((message.clone(),), Some(&kwargs))?,
        ))
    };
    made().unwrap_or_else(|e| e)
}

/// A Python value from anything that converts.
pub fn value<'py>(py: Python<'py>, v: impl IntoPyObject<'py>) -> Bound<'py, PyAny> {
    match v.into_pyobject(py) {
        Ok(v) => v.into_any().into_bound(),
        Err(_) => py.None().into_bound(py),
    }
}

/// `sprung.SceneError` (or `sprung.MeshError`, where the scene failed on
/// one of its meshes).
pub fn scene_error(py: Python<'_>, error: &SceneError) -> PyErr {
    let path = error.file.display().to_string();
    match &error.mesh {
        Some(mesh) => typed(
            py,
            "MeshError",
            error.to_string(),
            &[
                ("path", value(py, mesh.file.display().to_string())),
                ("line", value(py, mesh.line)),
                ("field", value(py, error.key.clone())),
                ("scene", value(py, path)),
                ("scene_line", value(py, error.line)),
            ],
        ),
        None => typed(
            py,
            "SceneError",
            error.to_string(),
            &[
                ("path", value(py, path)),
                ("line", value(py, error.line)),
                ("field", value(py, error.key.clone())),
            ],
        ),
    }
}

/// `sprung.BlowUp` for a state that ran away, `sprung.StepError` for the
/// other ways a step fails; both `RuntimeError`s.
pub fn step_error(py: Python<'_>, error: &StepError) -> PyErr {
    match error {
        StepError::BlowUp {
            step,
            time,
            particle,
            body,
            dt,
            stable_dt,
            ..
        } => typed(
            py,
            "BlowUp",
            error.to_string(),
            &[
                ("step", value(py, step)),
                ("time", value(py, time)),
                ("stable_dt", value(py, stable_dt)),
                ("dt", value(py, dt)),
                ("particle", value(py, particle)),
                ("body", value(py, body.clone())),
            ],
        ),
        StepError::NotFinite {
            step,
            time,
            quantity,
            dt,
            stable_dt,
            ..
        } => typed(
            py,
            "BlowUp",
            error.to_string(),
            &[
                ("step", value(py, step)),
                ("time", value(py, time)),
                ("stable_dt", value(py, stable_dt)),
                ("dt", value(py, dt)),
                ("quantity", value(py, quantity.clone())),
            ],
        ),
        StepError::Solver { step, time, .. }
        | StepError::TooManyContacts { step, time, .. }
        | StepError::CcdOverBudget { step, time, .. }
        | StepError::RodOff { step, time, .. } => typed(
            py,
            "StepError",
            error.to_string(),
            &[("step", value(py, step)), ("time", value(py, time))],
        ),
        StepError::InvalidTimeStep { .. } | StepError::InvalidSettings(_) => {
            typed(py, "StepError", error.to_string(), &[])
        }
    }
}

/// A `ValueError` with `message`.
pub fn bad_value(message: impl Into<String>) -> PyErr {
    PyValueError::new_err(message.into())
}

/// A `RuntimeError` with `message`.
pub fn failed(message: impl Into<String>) -> PyErr {
    PyRuntimeError::new_err(message.into())
}
