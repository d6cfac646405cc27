//! Checkpoints of `sprung run`: the world's state with what the run had
//! written (`--save-state FILE`, `--checkpoint-every K`), and a run that
//! goes on from one (`--resume FILE`) writing the same bytes as a run that
//! never stopped.

use std::path::Path;

use sprung::World;
use sprung_io::scene::Scene;
use sprung_io::state::{self, StateFileError};

use crate::error::CliError;

/// Where a resumed run starts: the rows (and frames) the saved run had
/// recorded.
#[derive(Debug, Clone, Copy)]
pub struct Resumed {
    /// Rows of `diagnostics.csv` recorded up to the saved step, which is
    /// also the number of the next frame.
    pub rows: usize,
}

fn state_error(error: StateFileError) -> CliError {
    CliError::Input(error.to_string())
}

/// Put the state saved in `path` into `scene`'s world, which must have been
/// built from the scene the state came from, with the same `dt` and
/// recording every `every` steps as the saved run did.
pub fn resume(path: &Path, scene: &mut Scene, every: u64) -> Result<Resumed, CliError> {
    let saved = state::read_state(path, &scene.world).map_err(state_error)?;
    let refuse = |source| {
        state_error(StateFileError::Mismatch {
            path: path.to_path_buf(),
            source,
        })
    };
    let dt = saved.get("run.dt", 1).map_err(refuse)?[0];
    if dt != scene.dt {
        return Err(CliError::Input(format!(
            "{}: the state was saved by a run with dt = {dt} s, this scene has dt = {} s",
            path.display(),
            scene.dt
        )));
    }
    let saved_every = saved.get_count("run.every").map_err(refuse)?;
    if saved_every != every {
        return Err(CliError::Input(format!(
            "{}: the state was saved by a run recording every {saved_every} steps, this one records every {every} (give --every {saved_every})",
            path.display()
        )));
    }
    let rows = saved.get_count("run.rows").map_err(refuse)?;
    state::restore(path, &mut scene.world, &saved).map_err(state_error)?;
    Ok(Resumed {
        rows: usize::try_from(rows).unwrap_or(usize::MAX),
    })
}

/// Save `world`'s state after `rows` recorded rows of a run stepping by
/// `dt` (s) and recording every `every` steps to `path`, atomically.
pub fn save(path: &Path, world: &World, rows: usize, dt: f64, every: u64) -> Result<(), CliError> {
    let mut saved = world.save_state();
    saved.put("run.dt", vec![dt]);
    saved.put("run.every", vec![every as f64]);
    saved.put("run.rows", vec![rows as f64]);
    state::write_state(path, world, &saved).map_err(|e| CliError::Io(e.to_string()))
}
