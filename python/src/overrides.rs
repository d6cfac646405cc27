//! `set=`: a dict of dotted scene keys, the command line's `--set`, with
//! Python values turned into TOML values.

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use sprung_io::toml::{Table, Value};
use sprung_io::Override;

use crate::errors::bad_value;

/// The overrides of `set` (pairs of a dotted key and a Python value).
pub fn overrides(set: Option<Vec<(String, Bound<'_, PyAny>)>>) -> PyResult<Vec<Override>> {
    set.unwrap_or_default()
        .into_iter()
        .map(|(key, value)| {
            let value = to_toml(&value).map_err(|e| bad_value(format!("set: `{key}`: {e}")))?;
            Ok(Override::new(key, value))
        })
        .collect()
}

/// A Python value as TOML: bool, int, float, str, a list or tuple of
/// them, a dict of them (numpy scalars and arrays through their Python
/// forms).
fn to_toml(value: &Bound<'_, PyAny>) -> Result<Value, String> {
    if value.is_instance_of::<PyBool>() {
        return value
            .extract::<bool>()
            .map(Value::Boolean)
            .map_err(|e| e.to_string());
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(Value::Integer)
            .map_err(|_| format!("{value}: an integer beyond 64 bits"));
    }
    if value.is_instance_of::<PyFloat>() {
        return value
            .extract::<f64>()
            .map(Value::Float)
            .map_err(|e| e.to_string());
    }
    if let Ok(text) = value.cast::<PyString>() {
        return Ok(Value::String(text.to_string()));
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = Table::new();
        for (key, item) in dict.iter() {
            table.insert(
                key.str().map_err(|e| e.to_string())?.to_string(),
                to_toml(&item)?,
            );
        }
        return Ok(Value::Table(table));
    }
    if value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = value.extract().map_err(|e: PyErr| e.to_string())?;
        return items
            .iter()
            .map(to_toml)
            .collect::<Result<_, _>>()
            .map(Value::Array);
    }
    // numpy scalars and arrays: their own Python form (`item`, `tolist`).
    for method in ["tolist", "item"] {
        if let Ok(plain) = value.call_method0(method) {
            if !plain.is(value) {
                return to_toml(&plain);
            }
        }
    }
    Err(format!(
        "{}: a value of type {} has no TOML form (give a number, bool, str, list or dict)",
        value.repr().map(|r| r.to_string()).unwrap_or_default(),
        value
            .get_type()
            .name()
            .map(|n| n.to_string())
            .unwrap_or_default()
    ))
}

/// The effective scene of `text` (the scene file `path`, or text whose
/// meshes are found from `path`'s folder) with `set` applied, as TOML
/// text whose mesh paths are absolute: what a run of a sweep builds and
/// keeps as its `scene.toml`, wherever it runs.
#[pyfunction]
#[pyo3(signature = (text, path, set=None))]
pub fn effective_scene(
    py: Python<'_>,
    text: &str,
    path: std::path::PathBuf,
    set: Option<Vec<(String, Bound<'_, PyAny>)>>,
) -> PyResult<String> {
    let overrides = overrides(set)?;
    let scene_error = |e: sprung_io::SceneError| crate::errors::scene_error(py, &e);
    let mut table =
        sprung_io::scene::overridden_table(text, &path, &overrides).map_err(scene_error)?;
    let folder = path.parent().unwrap_or(std::path::Path::new(""));
    let folder = std::path::absolute(folder).unwrap_or_else(|_| folder.to_path_buf());
    let bodies = table.get_mut("body").and_then(Value::as_array_mut);
    for body in bodies.into_iter().flatten() {
        if let Some(Value::String(mesh)) = body.get_mut("mesh") {
            *mesh = folder.join(&*mesh).display().to_string();
        }
    }
    sprung_io::scene::scene_toml(&table, &path).map_err(scene_error)
}
