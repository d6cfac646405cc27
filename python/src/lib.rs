//! `sprung._native`: the engine inside the Python package `sprung`.
//!
//! The Python layer (`python/sprung/*.py`) gives the API its shape
//! (`sprung.run`, `Diagnostics`, the exceptions); this module holds the
//! worlds and does the work, with the GIL released while it steps.

mod batch;
mod body;
mod errors;
mod input;
mod load;
mod output;
mod overrides;
mod pictures;
mod run;
mod sim;
mod world;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    sprung::parallel::configure_from_env();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The most levels of lists and dicts a `set=` value may nest.
    m.add("MAX_VALUE_DEPTH", sprung_io::scene::MAX_VALUE_DEPTH)?;
    m.add_class::<world::World>()?;
    m.add_class::<body::Body>()?;
    m.add_class::<batch::Batch>()?;
    m.add_function(wrap_pyfunction!(load::load, m)?)?;
    m.add_function(wrap_pyfunction!(load::loads, m)?)?;
    m.add_function(wrap_pyfunction!(input::read_scene, m)?)?;
    m.add_function(wrap_pyfunction!(output::write_output, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(pictures::animate, m)?)?;
    m.add_function(wrap_pyfunction!(pictures::plot, m)?)?;
    m.add_function(wrap_pyfunction!(pictures::columns, m)?)?;
    m.add_function(wrap_pyfunction!(integrators, m)?)?;
    m.add_function(wrap_pyfunction!(overrides::effective_scene, m)?)?;
    m.add_function(wrap_pyfunction!(overrides::parse_value, m)?)?;
    Ok(())
}

/// The integrators' names, as `World.integrator` and scene files take them.
#[pyfunction]
fn integrators() -> Vec<&'static str> {
    sprung::IntegratorKind::ALL
        .iter()
        .map(|k| k.name())
        .collect()
}
