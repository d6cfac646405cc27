//! `sprung.load` and `sprung.loads`: a scene file or text, read through
//! the command line's gate, built into a World.

use std::path::{Path, PathBuf};

use pyo3::prelude::*;
use sprung_io::{Disk, Override};

use crate::errors::scene_error;
use crate::overrides::overrides;
use crate::sim::Sim;
use crate::world::World;

/// Read the scene file at `path` through the command line's gate (a
/// regular file, at most 16 MiB, UTF-8: see [`crate::input::read_scene`])
/// and build it, with `overrides`.
pub fn load_sim(py: Python<'_>, path: &Path, overrides: &[Override]) -> PyResult<Sim> {
    let text = crate::input::read_scene_text(py, path)?;
    build_sim(py, text, path, overrides)
}

/// Build the scene `text`, named `path` (its folder anchors mesh paths),
/// with `overrides`; the Sim keeps the effective text. Text longer than a
/// scene file may be, or nested too deep, is refused by the scene reader
/// before it is parsed.
pub fn build_sim(
    py: Python<'_>,
    text: String,
    path: &Path,
    overrides: &[Override],
) -> PyResult<Sim> {
    let built = py.detach(|| {
        let scene = sprung_io::parse_scene_overridden(&text, path, overrides, &Disk)?;
        let text = match overrides {
            [] => text,
            _ => sprung_io::apply_overrides(&text, path, overrides)?,
        };
        Ok((scene, text))
    });
    let (scene, text) = built.map_err(|e| scene_error(py, &e))?;
    Ok(Sim::new(scene, text))
}

/// Load the scene file at `path` (TOML) into a World, read through the
/// command line's gate (see [`load_sim`]).
#[pyfunction]
#[pyo3(signature = (path, set=None))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    set: Option<Vec<(String, Bound<'_, PyAny>)>>,
) -> PyResult<World> {
    let overrides = overrides(py, set, &path)?;
    Ok(World::new(load_sim(py, &path, &overrides)?))
}

/// Build a World from scene text; mesh paths are relative to `base_dir`
/// (default: the current folder). Text longer than a scene file may be
/// (16 MiB, or `SPRUNG_MAX_INPUT_BYTES`) is refused as a file is.
#[pyfunction]
#[pyo3(signature = (text, base_dir=None, set=None, name=None))]
pub fn loads(
    py: Python<'_>,
    text: String,
    base_dir: Option<PathBuf>,
    set: Option<Vec<(String, Bound<'_, PyAny>)>>,
    name: Option<String>,
) -> PyResult<World> {
    // Errors name the text `<string>` (or `name`) in `base_dir`.
    let path = base_dir
        .unwrap_or_default()
        .join(name.as_deref().unwrap_or("<string>"));
    let overrides = overrides(py, set, &path)?;
    Ok(World::new(build_sim(py, text, &path, &overrides)?))
}
