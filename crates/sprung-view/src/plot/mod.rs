//! # Plots of a run's `diagnostics.csv`
//!
//! Line charts against time, as PNG: the energy terms and their total
//! ([`energy_png`]), volume (area in 2D) and pressure of the gas bodies
//! ([`gas_png`]), the coordinates of probed particles ([`probes_png`]),
//! and one column (by default the total energy) of several runs on one
//! chart ([`compare_png`]), e.g. the integrators of `sprung demo
//! oscillator`. [`plot_run`] and [`plot_compare`] read the runs' folders
//! and write the files.
//!
//! Drawn with plotters on an RGB bitmap at twice the size and shrunk (the
//! library does not anti-alias lines), labelled with DejaVu Sans bundled
//! in the crate ([`font`]), and encoded with the `png` crate with fixed
//! settings: the same CSV always gives the same bytes. Ticks sit on round
//! numbers (1, 2 or 5 × 10ᵏ); big and small values share one power of ten,
//! shown in the axis title.

mod axis;
mod encode;
mod error;
mod figure;
mod figures;
mod files;
pub mod font;
mod stability;
mod table;

use std::str::FromStr;

pub use error::PlotError;
pub use files::{compare_out_dir, plot_compare, plot_run, read_run, run_name, DIAGNOSTICS};
pub use stability::{stability_png, StabilityPoint};
pub use table::{DiagnosticsTable, REQUIRED_COLUMNS};

/// Smallest plot width or height accepted (px).
pub const MIN_SIZE: u32 = 200;
/// Largest plot width or height accepted (px).
pub const MAX_SIZE: u32 = 4000;

/// Whether a run is planar (areas in m², 2D pressure in N/m, no z) or
/// spatial (volumes in m³, pressure in Pa).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// A 2D scene: every z coordinate is zero.
    Two,
    /// A 3D scene.
    Three,
}

impl Dimension {
    /// Guess from the table: 2D when every centroid and probe z coordinate
    /// (m) is zero in every row, 3D otherwise (and when there are none).
    pub fn detect(table: &DiagnosticsTable) -> Dimension {
        let zs: Vec<String> = table
            .bodies()
            .iter()
            .map(|b| format!("{b}.cz"))
            .chain(table.probes().iter().map(|p| format!("{p}.z")))
            .filter(|c| table.column(c).is_some())
            .collect();
        if !zs.is_empty() && zs.iter().all(|c| table.is_zero(c)) {
            Dimension::Two
        } else {
            Dimension::Three
        }
    }
}

impl FromStr for Dimension {
    type Err = sprung::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "2" | "2d" | "2D" => Ok(Dimension::Two),
            "3" | "3d" | "3D" => Ok(Dimension::Three),
            other => Err(sprung::UnknownName::new("dimension", other, ["2", "3"])),
        }
    }
}

/// The vertical scale of the values in a comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Logarithmic when every value is positive and they span more than a
    /// factor 100, else linear.
    #[default]
    Auto,
    /// Linear.
    Linear,
    /// Logarithmic (values ≤ 0 are left out).
    Log,
}

impl FromStr for Scale {
    type Err = sprung::UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(Scale::Auto),
            "linear" => Ok(Scale::Linear),
            "log" => Ok(Scale::Log),
            other => Err(sprung::UnknownName::new(
                "scale",
                other,
                ["auto", "linear", "log"],
            )),
        }
    }
}

/// How plots are drawn.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PlotOptions {
    /// Image width (px), [`MIN_SIZE`] to [`MAX_SIZE`].
    pub width: u32,
    /// Image height (px), [`MIN_SIZE`] to [`MAX_SIZE`].
    pub height: u32,
    /// 2D or 3D units; `None`: [`Dimension::detect`].
    pub dimension: Option<Dimension>,
    /// The scale of the values in a comparison.
    pub scale: Scale,
}

impl Default for PlotOptions {
    fn default() -> Self {
        PlotOptions {
            width: 1000,
            height: 600,
            dimension: None,
            scale: Scale::Auto,
        }
    }
}

impl PlotOptions {
    /// Refuse sizes outside [`MIN_SIZE`]..=[`MAX_SIZE`].
    pub fn check(&self) -> Result<(), PlotError> {
        for (name, value) in [("width", self.width), ("height", self.height)] {
            if !(MIN_SIZE..=MAX_SIZE).contains(&value) {
                return Err(PlotError::Options(format!(
                    "{name} {value} px: must be from {MIN_SIZE} to {MAX_SIZE}"
                )));
            }
        }
        Ok(())
    }

    fn dimension_of(&self, table: &DiagnosticsTable) -> Dimension {
        self.dimension.unwrap_or_else(|| Dimension::detect(table))
    }
}

/// PNG of every energy term (J) that is not zero throughout and of the
/// total, against time (s); titled after `run`.
pub fn energy_png(
    table: &DiagnosticsTable,
    run: &str,
    options: &PlotOptions,
) -> Result<Vec<u8>, PlotError> {
    options.check()?;
    figures::energy(table, run).png(options.width, options.height)
}

/// PNG of the volume (m³; area, m², in 2D) of every closed body and the
/// pressure (Pa; N/m in 2D) of every body with gas, two panels against
/// time (s); `None` when no body has gas.
pub fn gas_png(
    table: &DiagnosticsTable,
    run: &str,
    options: &PlotOptions,
) -> Result<Option<Vec<u8>>, PlotError> {
    options.check()?;
    match figures::gas(table, run, options.dimension_of(table)) {
        Some(figure) => figure.png(options.width, options.height).map(Some),
        None => Ok(None),
    }
}

/// PNG of the coordinates (m) of the probed particles against time (s),
/// a panel per coordinate (no z in 2D); `None` without probes.
pub fn probes_png(
    table: &DiagnosticsTable,
    run: &str,
    options: &PlotOptions,
) -> Result<Option<Vec<u8>>, PlotError> {
    options.check()?;
    match figures::probes(table, run, options.dimension_of(table)) {
        Some(figure) => figure.png(options.width, options.height).map(Some),
        None => Ok(None),
    }
}

/// PNG comparing the column `column` of several `runs` (label, table),
/// titled after `name`: each run relative to its first value (absolute, in
/// the column's unit, when one of those is zero) on [`PlotOptions::scale`],
/// and the size of the change from the first value on a log scale below.
/// Every table must have the column.
pub fn compare_png(
    name: &str,
    runs: &[(String, DiagnosticsTable)],
    column: &str,
    options: &PlotOptions,
) -> Result<Vec<u8>, PlotError> {
    options.check()?;
    let Some((_, first)) = runs.first() else {
        return Err(PlotError::Options(
            "nothing to compare: no runs given".into(),
        ));
    };
    for (_, table) in runs {
        if table.text_column(column).is_some() {
            return Err(PlotError::Options(format!(
                "`{column}` holds names, not numbers: it cannot be plotted"
            )));
        }
        if table.column(column).is_none() {
            return Err(PlotError::Malformed {
                path: table.path().to_path_buf(),
                line: 1,
                message: format!(
                    "no column `{column}` (the columns are {})",
                    listed(table.names())
                ),
            });
        }
    }
    let dimension = options.dimension_of(first);
    figures::compare(name, runs, column, options.scale, dimension)
        .png(options.width, options.height)
}

/// `names` joined with commas, cut short after about 200 characters.
fn listed(names: &[String]) -> String {
    let all = names.join(",");
    match all.char_indices().nth(200) {
        Some((cut, _)) => format!("{}, ...", &all[..cut]),
        None => all,
    }
}
