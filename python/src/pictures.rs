//! Pictures for notebooks: a World drawn now (`_repr_png_`), a run as an
//! animated GIF (`sprung.animate`), the energy and gas plots
//! (`sprung.plot`); all by the renderer and plots of `sprung render` and
//! `sprung plot`.

use std::path::Path;
use std::sync::Arc;

use numpy::PyArray1;
use pyo3::prelude::*;
use sprung::Real;
use sprung_view::plot::{energy_png, gas_png, DiagnosticsTable, PlotError, PlotOptions};
use sprung_view::render::{
    render_in_memory, steps_between_pictures, Model, RenderSettings, Snapshot, DEFAULT_FOV_DEGREES,
};

use crate::errors::{bad_value, failed};
use crate::sim::Sim;
use crate::world::World;

/// Render settings of `width` × `height` pixels with the scene's camera.
fn settings(sim: &Sim, width: u32, height: u32) -> RenderSettings {
    let mut settings = RenderSettings::new(width, height);
    let camera = sim.scene.camera;
    settings.camera.eye = camera.eye;
    settings.camera.target = camera.target;
    settings.camera.fov_degrees = camera.fov.unwrap_or(DEFAULT_FOV_DEGREES);
    settings
}

/// A PNG of `world` now: its snapshot taken under the World's lock, the
/// drawing done without it and without the GIL.
pub fn picture(py: Python<'_>, world: &World, width: u32, height: u32) -> PyResult<Vec<u8>> {
    let (snapshot, settings) = {
        let sim = world.sim();
        let model = Arc::new(Model::of_world(&sim.scene.world));
        (
            Snapshot::of_world(&sim.scene.world, &model),
            settings(&sim, width, height),
        )
    };
    py.detach(|| {
        let (pictures, _) = render_in_memory(std::slice::from_ref(&snapshot), &settings)?;
        pictures[0].encode_png()
    })
    .map_err(|e| bad_value(e.to_string()))
}

/// Run `world` for `time` (s) or `steps` and return an animated GIF of
/// it: `fps` pictures per second of playback, each a `1/fps` s of
/// simulated time apart (real time). (`sprung.animate` hands it a copy.)
#[pyfunction]
#[pyo3(signature = (world, time=None, steps=None, fps=25.0, width=480, height=360))]
pub fn animate(
    py: Python<'_>,
    world: &Bound<'_, World>,
    time: Option<f64>,
    steps: Option<u64>,
    fps: f64,
    width: u32,
    height: u32,
) -> PyResult<Vec<u8>> {
    if !(fps.is_finite() && fps > 0.0) {
        return Err(bad_value(format!(
            "fps = {fps}: must be positive (pictures per second)"
        )));
    }
    let mut world = world
        .try_borrow_mut()
        .map_err(|_| failed("the World is in use (stepped or read by another thread)"))?;
    let sim = world.sim_mut();
    let steps = sim.planned_steps(steps, time)?;
    let every = steps_between_pictures(sim.scene.dt, fps as Real);
    let pictures = steps / every + 2;
    // The pictures are kept until the GIF is made: at most about 1 GB.
    let bytes = pictures as f64 * f64::from(width) * f64::from(height) * 3.0;
    if pictures > 10_000 || bytes > 1e9 {
        return Err(bad_value(format!(
            "{pictures} pictures of {width}×{height}: at most 10000 and 1 GB of pictures in a GIF (lower fps or the size, or animate a shorter time)"
        )));
    }
    let mut settings = settings(sim, width, height);
    settings.gif = true;
    settings.fps = Some(fps);
    let model = Arc::new(Model::of_world(&sim.scene.world));
    let mut snapshots = vec![Snapshot::of_world(&sim.scene.world, &model)];
    let mut taken = 0;
    while taken < steps {
        let chunk = every.min(steps - taken);
        crate::world::step_sim(py, sim, chunk)?;
        taken += chunk;
        snapshots.push(Snapshot::of_world(&sim.scene.world, &model));
    }
    let (_, gif) = py
        .detach(|| render_in_memory(&snapshots, &settings))
        .map_err(|e| bad_value(e.to_string()))?;
    gif.ok_or_else(|| failed("no GIF was made"))
}

/// The PNG plots of a diagnostics table's CSV `text` (named `name`):
/// `energy`, and `gas` where a body has gas, as `sprung plot` draws them.
#[pyfunction]
#[pyo3(signature = (text, name="run", width=1000, height=600))]
pub fn plot(
    py: Python<'_>,
    text: &str,
    name: &str,
    width: u32,
    height: u32,
) -> PyResult<Vec<(String, Vec<u8>)>> {
    let options = PlotOptions {
        width,
        height,
        ..PlotOptions::default()
    };
    py.detach(|| {
        let table = DiagnosticsTable::parse(text, Path::new(name))?;
        let mut pngs = vec![("energy".to_string(), energy_png(&table, name, &options)?)];
        if let Some(gas) = gas_png(&table, name, &options)? {
            pngs.push(("gas".to_string(), gas));
        }
        Ok::<_, PlotError>(pngs)
    })
    .map_err(|e| bad_value(e.to_string()))
}

/// The columns of a diagnostics CSV `text`, read by `sprung plot`'s
/// reader: each name with its values (NaN for an empty cell), `step` as
/// whole numbers, the text columns (`solver_preconditioner`) as a list of
/// strings.
#[pyfunction]
pub fn columns<'py>(py: Python<'py>, text: &str) -> PyResult<Vec<(String, Bound<'py, PyAny>)>> {
    let table = DiagnosticsTable::parse(text, Path::new("diagnostics.csv"))
        .map_err(|e| bad_value(e.to_string()))?;
    table
        .names()
        .iter()
        .map(|name| {
            if let Some(words) = table.text_column(name) {
                let list = pyo3::types::PyList::new(py, words)?;
                return Ok((name.clone(), list.into_any()));
            }
            let cells = table.column(name).unwrap_or_default();
            let array = if name == "step" {
                let steps: Vec<i64> = cells.iter().map(|c| c.unwrap_or(0.0) as i64).collect();
                PyArray1::from_vec(py, steps).into_any()
            } else {
                let values: Vec<f64> = cells.iter().map(|c| c.unwrap_or(f64::NAN)).collect();
                PyArray1::from_vec(py, values).into_any()
            };
            Ok((name.clone(), array))
        })
        .collect()
}
