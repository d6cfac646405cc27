//! `set=`: a dict of dotted scene keys, the command line's `--set`, with
//! Python values turned into TOML values.

use std::path::Path;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use sprung_io::scene::MAX_VALUE_DEPTH;
use sprung_io::toml::{Table, Value};
use sprung_io::{Override, SceneError};

use crate::errors::{bad_value, scene_error};

/// The overrides of `set` (pairs of a dotted key and a Python value) for
/// the scene `path`: a value with no TOML form, or one that nests lists
/// and dicts deeper than [`MAX_VALUE_DEPTH`], is refused as
/// `sprung.SceneError` naming its key (and the limit).
pub fn overrides(
    py: Python<'_>,
    set: Option<Vec<(String, Bound<'_, PyAny>)>>,
    path: &Path,
) -> PyResult<Vec<Override>> {
    set.unwrap_or_default()
        .into_iter()
        .map(|(key, value)| {
            let value = to_toml(&value, 0).map_err(|message| {
                let error =
                    SceneError::new(path, None, format!("set: `{key}`: {message}")).with_key(&key);
                scene_error(py, &error)
            })?;
            Ok(Override::new(key, value))
        })
        .collect()
}

/// A Python value as TOML, `depth` levels of lists and dicts down: bool,
/// int, float, str, a list or tuple of them, a dict of them, and numpy
/// scalars and arrays through their Python forms (`tolist`, `item`).
/// Refused where lists and dicts nest deeper than [`MAX_VALUE_DEPTH`]
/// levels (a list that holds itself too): no value recurses without bound.
fn to_toml(value: &Bound<'_, PyAny>, depth: usize) -> Result<Value, String> {
    if let Some(plain) = plain_toml(value, depth)? {
        return Ok(plain);
    }
    // numpy scalars and arrays: their own Python form, converted at the
    // same depth (not again: a form that is not plain has no TOML form).
    for method in ["tolist", "item"] {
        if let Ok(plain) = value.call_method0(method) {
            if let Some(plain) = plain_toml(&plain, depth)? {
                return Ok(plain);
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

/// A Python bool, int, float, str, list, tuple or dict as TOML, its items
/// through [`to_toml`] one level down; `None` for a value of another type.
fn plain_toml(value: &Bound<'_, PyAny>, depth: usize) -> Result<Option<Value>, String> {
    if value.is_instance_of::<PyBool>() {
        return value
            .extract::<bool>()
            .map(|b| Some(Value::Boolean(b)))
            .map_err(|e| e.to_string());
    }
    if value.is_instance_of::<PyInt>() {
        return value
            .extract::<i64>()
            .map(|n| Some(Value::Integer(n)))
            .map_err(|_| format!("{value}: an integer beyond 64 bits"));
    }
    if value.is_instance_of::<PyFloat>() {
        return value
            .extract::<f64>()
            .map(|x| Some(Value::Float(x)))
            .map_err(|e| e.to_string());
    }
    if let Ok(text) = value.cast::<PyString>() {
        return Ok(Some(Value::String(text.to_string())));
    }
    let is_dict = value.is_instance_of::<PyDict>();
    if !(is_dict || value.is_instance_of::<PyList>() || value.is_instance_of::<PyTuple>()) {
        return Ok(None);
    }
    if depth >= MAX_VALUE_DEPTH {
        return Err(too_deep());
    }
    if let Ok(dict) = value.cast::<PyDict>() {
        let mut table = Table::new();
        for (key, item) in dict.iter() {
            table.insert(
                key.str().map_err(|e| e.to_string())?.to_string(),
                to_toml(&item, depth + 1)?,
            );
        }
        return Ok(Some(Value::Table(table)));
    }
    let items: Vec<Bound<'_, PyAny>> = value.extract().map_err(|e: PyErr| e.to_string())?;
    items
        .iter()
        .map(|item| to_toml(item, depth + 1))
        .collect::<Result<_, _>>()
        .map(|items| Some(Value::Array(items)))
}

/// The error of a value that nests lists and dicts too deep.
fn too_deep() -> String {
    format!(
        "the value nests lists or dicts more than {MAX_VALUE_DEPTH} deep, the most a value may \
         (a list or dict that holds itself nests without end)"
    )
}

/// The effective scene of `text` (the scene file `path`, or text whose
/// meshes are found from `path`'s folder) with `set` applied, as TOML
/// text whose mesh paths are absolute: what a run of a sweep builds and
/// keeps as its `scene.toml`, wherever it runs.
///
/// `steps` or `time` (s), and `every`, when given, are written into its
/// `[sim]` table (`steps`, or `duration`, in place of the other), so the
/// text alone runs as the sweep ran it.
#[pyfunction]
#[pyo3(signature = (text, path, set=None, steps=None, time=None, every=None))]
pub fn effective_scene(
    py: Python<'_>,
    text: &str,
    path: std::path::PathBuf,
    set: Option<Vec<(String, Bound<'_, PyAny>)>>,
    steps: Option<u64>,
    time: Option<f64>,
    every: Option<u64>,
) -> PyResult<String> {
    let overrides = overrides(py, set, &path)?;
    let refuse = |e: SceneError| scene_error(py, &e);
    let mut table = sprung_io::scene::overridden_table(text, &path, &overrides).map_err(refuse)?;
    if steps.is_some() || time.is_some() || every.is_some() {
        let sim = table
            .entry("sim")
            .or_insert_with(|| Value::Table(Table::new()));
        if let Value::Table(sim) = sim {
            let count = |n: u64| Value::Integer(i64::try_from(n).unwrap_or(i64::MAX));
            if let Some(steps) = steps {
                sim.remove("duration");
                sim.insert("steps".into(), count(steps));
            } else if let Some(time) = time {
                sim.remove("steps");
                sim.insert("duration".into(), Value::Float(time));
            }
            if let Some(every) = every {
                sim.insert("every".into(), count(every));
            }
        }
    }
    let folder = path.parent().unwrap_or(Path::new(""));
    let folder = std::path::absolute(folder).unwrap_or_else(|_| folder.to_path_buf());
    let bodies = table.get_mut("body").and_then(Value::as_array_mut);
    for body in bodies.into_iter().flatten() {
        if let Some(Value::String(mesh)) = body.get_mut("mesh") {
            *mesh = folder.join(&*mesh).display().to_string();
        }
    }
    sprung_io::scene::scene_toml(&table, &path).map_err(refuse)
}

/// A command line's VALUE as `--set KEY=VALUE` reads it (a TOML value, or
/// a bare word as a string), as a Python value.
#[pyfunction]
pub fn parse_value<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    let parsed: Override = format!("value={text}")
        .parse()
        .map_err(|e: sprung_io::OverrideError| bad_value(e.message))?;
    from_toml(py, &parsed.value)
}

/// A TOML value as a Python one.
fn from_toml<'py>(py: Python<'py>, value: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        Value::String(text) => text.into_pyobject(py)?.into_any(),
        Value::Integer(n) => n.into_pyobject(py)?.into_any(),
        Value::Float(x) => x.into_pyobject(py)?.into_any(),
        Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(from_toml(py, item)?)?;
            }
            list.into_any()
        }
        Value::Table(table) => {
            let dict = PyDict::new(py);
            for (key, item) in table {
                dict.set_item(key, from_toml(py, item)?)?;
            }
            dict.into_any()
        }
    })
}
