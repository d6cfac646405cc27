//! `sprung.run`: a whole run as the command line does it, its
//! diagnostics returned (and written, with `out`).

use std::path::PathBuf;

use pyo3::prelude::*;
use sprung::IntegratorKind;
use sprung_io::export::{self, AtomicFile, Diagnostics, FrameFormat};

use crate::errors::{bad_value, failed, step_error};
use crate::load::load_sim;
use crate::sim::{Sim, SIGNAL_CHECK};
use crate::world::World;

/// What `run` gives back: the CSV text of `diagnostics.csv`, and the
/// blow-up that stopped the run early, if one did (as a Python exception
/// carrying the rows so far).
type Ran = (String, Option<PyErr>);

/// Run a scene (a path or a World) as `sprung run` does and return the
/// text of its `diagnostics.csv`; with `out`, also write it there.
#[pyfunction]
#[pyo3(signature = (scene, steps=None, time=None, every=None, integrator=None, out=None, format=None))]
#[allow(clippy::too_many_arguments)]
pub fn run(
    py: Python<'_>,
    scene: Bound<'_, PyAny>,
    steps: Option<u64>,
    time: Option<f64>,
    every: Option<u64>,
    integrator: Option<String>,
    out: Option<PathBuf>,
    format: Option<String>,
) -> PyResult<Ran> {
    let format: Option<FrameFormat> = format
        .map(|name| {
            name.parse::<FrameFormat>()
                .map_err(|e| bad_value(e.to_string()))
        })
        .transpose()?;
    if format.is_some() && out.is_none() {
        return Err(bad_value(
            "format: frames are written into out=: give a folder",
        ));
    }
    let outputs = Outputs { out, format };
    let integrator: Option<IntegratorKind> = integrator
        .map(|name| {
            name.parse::<IntegratorKind>()
                .map_err(|e| bad_value(e.to_string()))
        })
        .transpose()?;
    if let Ok(world) = scene.cast::<World>() {
        let mut world = world.try_borrow_mut().map_err(crate::world::busy)?;
        run_sim(
            py,
            world.sim_mut(),
            (steps, time, every),
            integrator,
            &outputs,
        )
    } else {
        let path: PathBuf = scene
            .extract()
            .map_err(|_| bad_value("scene: give a scene file's path or a sprung.World"))?;
        let mut sim = load_sim(py, &path, &[])?;
        run_sim(py, &mut sim, (steps, time, every), integrator, &outputs)
    }
}

/// `run` on a loaded scene.
fn run_sim(
    py: Python<'_>,
    sim: &mut Sim,
    (steps, time, every): (Option<u64>, Option<f64>, Option<u64>),
    integrator: Option<IntegratorKind>,
    outputs: &Outputs,
) -> PyResult<Ran> {
    let out = &outputs.out;
    if let Some(kind) = integrator {
        sim.scene.world.set_integrator(kind);
    }
    let steps = sim.planned_steps(steps, time)?;
    if every == Some(0) {
        return Err(bad_value("every must be at least 1"));
    }
    let every = sim.scene.record_every(every);
    sim.scene
        .world
        .contact_pairs_now(sim.scene.dt)
        .map_err(|e| bad_value(e.to_string()))?;
    if let Some(out) = out {
        let folder = match outputs.format {
            Some(_) => out.join("frames"),
            None => out.clone(),
        };
        std::fs::create_dir_all(&folder)
            .map_err(|e| failed(format!("cannot create {}: {e}", folder.display())))?;
    }
    let mut table = Diagnostics::in_memory(&sim.scene.world, &[]);
    let record = |table: &mut Diagnostics, sim: &Sim| {
        // Frame n goes with row n, as `sprung run --format` writes them.
        let index = table.rows();
        table
            .record(&sim.scene.world)
            .map_err(|e| failed(e.to_string()))?;
        outputs.frame(index, &sim.scene.world)
    };
    record(&mut table, sim)?;
    // The rows of `sprung run`: the start, every `every` steps, the end.
    let first = sim.scene.world.steps() + 1;
    let last = (first - 1)
        .checked_add(steps)
        .filter(|&last| last <= sprung_io::scene::MAX_STEPS)
        .ok_or_else(|| {
            bad_value(format!(
                "steps = {steps}: the World would pass the {:.0e} steps a run may take",
                sprung_io::scene::MAX_STEPS as f64
            ))
        })?;
    let mut blow_up = None;
    let mut step = first;
    while step <= last {
        let record_at = (step.div_ceil(every) * every).min(last);
        let (done, result) = py.detach(|| sim.step_for(record_at + 1 - step, SIGNAL_CHECK));
        step += done;
        if let Err(error) = result {
            blow_up = Some(step_error(py, &error));
            break;
        }
        if step - 1 == record_at {
            record(&mut table, sim)?;
        }
        if let Err(interrupt) = py.check_signals() {
            // Stopped between steps: the rows so far are kept, as the
            // command line keeps them.
            write(out.as_deref(), table.text())?;
            outputs.series(&sim.scene.world, table.times())?;
            return Err(interrupt);
        }
    }
    let text = table.text().to_string();
    write(out.as_deref(), &text)?;
    outputs.series(&sim.scene.world, table.times())?;
    Ok((text, blow_up))
}

/// Write `text` to `out/diagnostics.csv`, complete or not at all, when
/// `out` is given.
fn write(out: Option<&std::path::Path>, text: &str) -> PyResult<()> {
    if let Some(out) = out {
        let path = out.join("diagnostics.csv");
        AtomicFile::write(&path, text.as_bytes())
            .map_err(|e| failed(format!("cannot write {}: {e}", path.display())))?;
    }
    Ok(())
}

/// Where a run's files go: `out/diagnostics.csv`, and frames in
/// `out/frames/` when a format is given.
struct Outputs {
    out: Option<PathBuf>,
    format: Option<FrameFormat>,
}

impl Outputs {
    /// Write frame `index` of `world`, when frames are asked for.
    fn frame(&self, index: usize, world: &sprung::World) -> PyResult<()> {
        if let (Some(out), Some(format)) = (&self.out, self.format) {
            let folder = out.join("frames");
            export::write_frame(&folder, index, world, format).map_err(|e| {
                failed(format!("cannot write a frame in {}: {e}", folder.display()))
            })?;
        }
        Ok(())
    }

    /// Write the frames' series file (ParaView's list of frames and
    /// their times), when frames are asked for.
    fn series(&self, world: &sprung::World, times: &[f64]) -> PyResult<()> {
        if let (Some(out), Some(format)) = (&self.out, self.format) {
            let folder = out.join("frames");
            export::write_series(&folder, format, world, times)
                .map_err(|e| failed(format!("cannot write {}: {e}", folder.display())))?;
        }
        Ok(())
    }
}
