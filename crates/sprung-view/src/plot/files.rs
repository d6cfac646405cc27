//! Reading runs' folders and writing their plots (each file atomically).

use std::io;
use std::path::{Component, Path, PathBuf};

use sprung_io::export::AtomicFile;

use super::{
    compare_png, energy_png, gas_png, probes_png, DiagnosticsTable, PlotError, PlotOptions,
};

/// The name of a run's diagnostics file in its folder.
pub const DIAGNOSTICS: &str = "diagnostics.csv";

/// The folder of a run given as its folder or as its `diagnostics.csv`.
fn run_dir(path: &Path) -> &Path {
    if path.is_file() {
        match path.parent() {
            Some(parent) if !parent.as_os_str().is_empty() => parent,
            _ => Path::new("."),
        }
    } else {
        path
    }
}

/// Read the diagnostics of the run in `path` (its folder, or its
/// `diagnostics.csv` itself); in a folder without one, the rows of a run
/// killed before it finished (`diagnostics.csv.partial`, up to its last
/// whole line).
pub fn read_run(path: &Path) -> Result<DiagnosticsTable, PlotError> {
    if path.is_file() {
        return DiagnosticsTable::read(path);
    }
    if !path.exists() {
        return Err(PlotError::Read {
            path: path.to_path_buf(),
            source: io::Error::new(io::ErrorKind::NotFound, "no such file or folder"),
        });
    }
    let file = path.join(DIAGNOSTICS);
    if !file.exists() {
        // A run killed before it finished leaves its rows under this name.
        let unfinished = path.join(format!("{DIAGNOSTICS}.partial"));
        if unfinished.is_file() {
            return DiagnosticsTable::read_unfinished(&unfinished);
        }
        return Err(PlotError::NoDiagnostics {
            dir: path.to_path_buf(),
        });
    }
    DiagnosticsTable::read(&file)
}

/// The name plots give the run in `path` (a folder or its
/// `diagnostics.csv`): the folder's name.
pub fn run_name(path: &Path) -> String {
    let dir = run_dir(path);
    let name = |p: &Path| p.file_name().map(|n| n.to_string_lossy().into_owned());
    name(dir)
        .or_else(|| dir.canonicalize().ok().as_deref().and_then(name))
        .unwrap_or_else(|| "run".into())
}

/// Plot the run in `path` (its folder or its `diagnostics.csv`) into `out`
/// (default: `plots/` in the run's folder): `energy.png`, and `gas.png`
/// and `probes.png` when the run has gas bodies and probes (a stale one
/// from an earlier run is removed). Returns the files written.
pub fn plot_run(
    path: &Path,
    out: Option<&Path>,
    options: &PlotOptions,
) -> Result<Vec<PathBuf>, PlotError> {
    options.check()?;
    let table = read_run(path)?;
    let run = run_name(path);
    let out = out.map_or_else(|| run_dir(path).join("plots"), Path::to_path_buf);
    let plots = [
        ("energy.png", Some(energy_png(&table, &run, options)?)),
        ("gas.png", gas_png(&table, &run, options)?),
        ("probes.png", probes_png(&table, &run, options)?),
    ];
    create_dir(&out)?;
    let mut written = Vec::new();
    for (name, bytes) in plots {
        let file = out.join(name);
        match bytes {
            Some(bytes) => {
                write(&file, &bytes)?;
                written.push(file);
            }
            None if file.is_file() => {
                std::fs::remove_file(&file)
                    .map_err(|source| PlotError::Write { path: file, source })?;
            }
            None => {}
        }
    }
    Ok(written)
}

/// The folder a comparison of `runs` goes to by default: `plots/` in the
/// deepest folder that holds them all (as the paths are written), and
/// not in a run itself: a single run's comparison goes to `plots/` beside
/// it, not among its own plots.
pub fn compare_out_dir(runs: &[PathBuf]) -> PathBuf {
    let common = common_ancestor(runs);
    let holding = if runs.iter().any(|r| run_dir(r) == common) {
        match common.parent() {
            Some(parent) if !parent.as_os_str().is_empty() && common.file_name().is_some() => {
                parent.to_path_buf()
            }
            // `run`, `.`, `..`: the folder above, as written.
            _ => common.join(".."),
        }
    } else {
        common
    };
    holding.join("plots")
}

fn common_ancestor(runs: &[PathBuf]) -> PathBuf {
    let dirs: Vec<Vec<Component>> = runs
        .iter()
        .map(|r| run_dir(r).components().collect())
        .collect();
    let mut common = PathBuf::new();
    if let Some(first) = dirs.first() {
        for (index, part) in first.iter().enumerate() {
            if dirs.iter().all(|d| d.get(index) == Some(part)) {
                common.push(part);
            } else {
                break;
            }
        }
    }
    if common.as_os_str().is_empty() {
        common.push(".");
    }
    common
}

/// Plot the column `column` (e.g. `total`) of `runs` (folders or their
/// `diagnostics.csv`) on one chart, labelled by folder name (by path when
/// two names clash), into `out` (default [`compare_out_dir`]):
/// `compare.png` for `total`, `compare-COLUMN.png` for another column.
/// The output folder itself is skipped when it is among `runs` (as a shell
/// glob `DIR/*` gives it on a second plot). Returns the file written.
pub fn plot_compare(
    runs: &[PathBuf],
    column: &str,
    out: Option<&Path>,
    options: &PlotOptions,
) -> Result<PathBuf, PlotError> {
    options.check()?;
    let out = out.map_or_else(|| compare_out_dir(runs), Path::to_path_buf);
    let runs: Vec<&PathBuf> = runs.iter().filter(|r| !same_place(r, &out)).collect();
    let names: Vec<String> = runs.iter().map(|r| run_name(r)).collect();
    let mut tables = Vec::new();
    for (run, name) in runs.iter().zip(&names) {
        let clash = names.iter().filter(|n| *n == name).count() > 1;
        let label = if clash {
            run_dir(run).display().to_string()
        } else {
            name.clone()
        };
        tables.push((label, read_run(run)?));
    }
    let runs: Vec<PathBuf> = runs.into_iter().cloned().collect();
    let name = run_name(&common_ancestor(&runs));
    let bytes = compare_png(&name, &tables, column, options)?;
    create_dir(&out)?;
    let file = out.join(if column == "total" {
        "compare.png".to_string()
    } else {
        let safe: String = column
            .chars()
            .map(|c| {
                if c.is_ascii_alphanumeric() || "._-".contains(c) {
                    c
                } else {
                    '_'
                }
            })
            .collect();
        format!("compare-{safe}.png")
    });
    write(&file, &bytes)?;
    Ok(file)
}

/// Whether `a` and `b` name the same folder.
fn same_place(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    }
}

fn create_dir(dir: &Path) -> Result<(), PlotError> {
    std::fs::create_dir_all(dir).map_err(|source| PlotError::Write {
        path: dir.to_path_buf(),
        source,
    })
}

fn write(file: &Path, bytes: &[u8]) -> Result<(), PlotError> {
    AtomicFile::write(file, bytes).map_err(|source| PlotError::Write {
        path: file.to_path_buf(),
        source,
    })
}
