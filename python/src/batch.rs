//! `sprung.Batch`: many worlds stepped at once on Rust threads, each
//! exactly as if stepped alone.

use pyo3::prelude::*;
use rayon::prelude::*;
use sprung::parallel::Pool;

use crate::errors::{bad_value, step_error};
use crate::sim::SIGNAL_CHECK;
use crate::world::World;

/// Worlds stepped together in parallel, with the GIL released. Each world
/// takes exactly the steps it would take alone (the engine's results do
/// not depend on its threads), so a Batch gives the same bits as a loop
/// over its worlds, on any number of threads.
#[pyclass(module = "sprung._native")]
pub struct Batch {
    worlds: Vec<Py<World>>,
    pool: Pool,
}

#[pymethods]
impl Batch {
    /// A batch of `worlds` (each a distinct World) run on `threads`
    /// threads (default: every core, or `SPRUNG_THREADS`).
    #[new]
    #[pyo3(signature = (worlds, threads=None))]
    fn new(worlds: Vec<Py<World>>, threads: Option<usize>) -> PyResult<Self> {
        for (i, a) in worlds.iter().enumerate() {
            if let Some(j) = worlds[..i].iter().position(|b| b.is(a)) {
                return Err(bad_value(format!(
                    "worlds {j} and {i} are the same World: a Batch steps each world once a step (use World.copy())"
                )));
            }
        }
        let threads = threads.unwrap_or_else(sprung::parallel::threads);
        let pool = Pool::new(threads).map_err(|e| bad_value(e.to_string()))?;
        Ok(Batch { worlds, pool })
    }

    /// The worlds, in the order given.
    #[getter]
    fn worlds(&self, py: Python<'_>) -> Vec<Py<World>> {
        self.worlds.iter().map(|w| w.clone_ref(py)).collect()
    }

    /// The threads the batch runs on.
    #[getter]
    fn threads(&self) -> usize {
        self.pool.threads()
    }

    fn __len__(&self) -> usize {
        self.worlds.len()
    }

    /// Advance every world `n` steps, in parallel, with the GIL released.
    /// Ctrl-C stops between steps (every world at a whole step, perhaps
    /// not all at the same one). A world that blows up stops there, the
    /// others finish, and `sprung.BlowUp` names the first such world
    /// (`.world`, its index).
    #[pyo3(signature = (n=1))]
    fn step(&self, py: Python<'_>, n: u64) -> PyResult<()> {
        let mut borrowed: Vec<PyRefMut<'_, World>> = self
            .worlds
            .iter()
            .map(|w| w.bind(py).try_borrow_mut())
            .collect::<Result<_, _>>()?;
        let mut left = vec![n; borrowed.len()];
        let mut failed: Vec<Option<sprung::StepError>> = Vec::new();
        failed.resize_with(borrowed.len(), || None);
        loop {
            let mut sims: Vec<_> = borrowed
                .iter_mut()
                .zip(left.iter_mut())
                .zip(failed.iter_mut())
                .filter(|((_, left), failed)| **left > 0 && failed.is_none())
                .map(|((world, left), failed)| (world.sim_mut(), left, failed))
                .collect();
            if sims.is_empty() {
                break;
            }
            py.detach(|| {
                self.pool.install(|| {
                    sims.par_iter_mut().for_each(|(sim, left, failed)| {
                        let (done, result) = sim.step_for(**left, SIGNAL_CHECK);
                        **left -= done;
                        if let Err(error) = result {
                            **failed = Some(error);
                        }
                    })
                })
            });
            py.check_signals()?;
        }
        if let Some((index, error)) = failed
            .iter()
            .enumerate()
            .find_map(|(i, e)| e.as_ref().map(|e| (i, e)))
        {
            let error = step_error(py, error);
            error.value(py).setattr("world", index)?;
            return Err(error);
        }
        Ok(())
    }
}
