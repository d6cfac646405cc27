//! `sprung plot`: PNG plots of runs' `diagnostics.csv` (energies, gas
//! bodies, probes), and one column of several runs on one chart.

use std::path::PathBuf;

use clap::Args;
use sprung_view::plot::{self, Dimension, PlotError, PlotOptions, Scale};

use crate::error::CliError;
use crate::values;

/// Arguments of `sprung plot`.
#[derive(Debug, Args)]
#[command(
    after_help = "Writes OUT/energy.png, OUT/gas.png (runs with gas bodies) and OUT/probes.png \
                  (runs with --probe) for each DIR; with --compare, OUT/compare.png \
                  (default OUT: plots/ in the folder holding the compared runs).\n\
                  Example: sprung demo oscillator && sprung plot --compare out/demo/oscillator/*"
)]
pub struct PlotArgs {
    /// Run folders (or their diagnostics.csv) to plot, each into DIR/plots.
    #[arg(value_name = "DIR", required_unless_present = "compare")]
    dirs: Vec<PathBuf>,
    /// Runs to compare on one chart (by default their total energy relative
    /// to its start), e.g. --compare out/a,out/b or --compare out/demo/oscillator/*.
    #[arg(long, value_name = "DIR", value_delimiter = ',', num_args = 1..)]
    compare: Vec<PathBuf>,
    /// The column compared with --compare.
    #[arg(long, default_value = "total", requires = "compare")]
    column: String,
    /// Vertical scale of the compared values: auto (log when they span more
    /// than a factor 100), linear or log.
    #[arg(long, default_value = "auto")]
    scale: Scale,
    /// Output folder (default: DIR/plots).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Image width (px), 200 to 4000.
    #[arg(long, default_value_t = 1000, value_parser = values::plot_side)]
    width: u32,
    /// Image height (px), 200 to 4000.
    #[arg(long, default_value_t = 600, value_parser = values::plot_side)]
    height: u32,
    /// Units of a 2D (m², N/m) or 3D (m³, Pa) run; default: 2D when every z is zero.
    #[arg(long, value_name = "2|3")]
    dimension: Option<Dimension>,
    /// Print nothing but errors and warnings.
    #[arg(long)]
    quiet: bool,
}

/// Run `sprung plot`.
pub fn run(args: &PlotArgs) -> Result<(), CliError> {
    if args.out.is_some() && args.dirs.len() > 1 {
        return Err(CliError::Input(
            "--out takes one DIR: with several, each one's plots go to DIR/plots".into(),
        ));
    }
    let options = PlotOptions {
        width: args.width,
        height: args.height,
        dimension: args.dimension,
        scale: args.scale,
    };
    options.check().map_err(error)?;
    let mut written = Vec::new();
    for dir in &args.dirs {
        written.extend(plot::plot_run(dir, args.out.as_deref(), &options).map_err(error)?);
    }
    if !args.compare.is_empty() {
        written.push(
            plot::plot_compare(&args.compare, &args.column, args.out.as_deref(), &options)
                .map_err(error)?,
        );
    }
    if !args.quiet {
        for file in written {
            println!("{}", file.display());
        }
    }
    Ok(())
}

/// Bad input (exit status 1) or a file that cannot be written.
fn error(e: PlotError) -> CliError {
    match e {
        PlotError::Write { .. } => CliError::Io(e.to_string()),
        _ => CliError::Input(e.to_string()),
    }
}
