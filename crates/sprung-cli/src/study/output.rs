//! What `sprung study stability` writes: the table on stdout,
//! `stability.csv` and `stability.png` (each file complete or absent).

use std::fmt::Write as _;
use std::path::Path;

use sprung::Real;
use sprung_io::export::AtomicFile;
use sprung_view::plot::{stability_png, PlotOptions, StabilityPoint};

use super::search::{Limit, BRACKET};
use super::{Row, Setting};
use crate::error::CliError;

/// The CSV's file name in the output folder.
pub const CSV: &str = "stability.csv";
/// The plot's file name in the output folder.
pub const PNG: &str = "stability.png";

/// The CSV header: the integrator, the largest stable dt (s), whether it
/// is the cap, the scene's stable estimate (s), the cost (wall-clock s per
/// simulated s), steps per wall-clock second, and whether the energy
/// criterion applied.
pub const HEADER: &str = "integrator,largest_stable_dt,capped,stable_estimate,cost_per_simulated_second,steps_per_second,energy_criterion";

/// The lines that say what was studied and how stability was judged.
pub fn describe(setting: &Setting) -> String {
    let estimate = if setting.estimate.is_finite() {
        format!("stable estimate {:.3e} s", setting.estimate)
    } else {
        "no stable estimate (nothing stiff)".to_string()
    };
    let criterion = if setting.energy_criterion() {
        format!(
            "energy criterion on: a trial is unstable if it blows up or its total energy rises above its start by more than {} × S, S = {:.4e} J (the sum of the sizes of the energy terms at the start) or, if larger, the largest change of the gravity and gas terms over the trial",
            setting.margin, setting.scale
        )
    } else {
        format!(
            "energy criterion off (driving forces: {}): a trial is unstable only if it blows up",
            setting.driving.join("; ")
        )
    };
    format!(
        "{}: {} particle{}, trial runs of {} s, {estimate}\n{criterion}",
        setting.path.display(),
        setting.particles,
        if setting.particles == 1 { "" } else { "s" },
        setting.time
    )
}

/// The table printed on stdout.
pub fn table(setting: &Setting, rows: &[Row]) -> String {
    let mut text = describe(setting);
    let _ = write!(
        text,
        "\n{:<16} {:>19} {:>11} {:>15} {:>11}  note",
        "integrator", "largest stable dt", "/ estimate", "cost (s/sim s)", "steps/s"
    );
    for row in rows {
        let ratio = |dt: Real| {
            if setting.estimate.is_finite() {
                significant(dt / setting.estimate)
            } else {
                "-".to_string()
            }
        };
        let (dt, over, note) = match &row.limit {
            Limit::Bracketed {
                stable,
                unstable,
                why,
                unconverged,
            } => (
                format!("{stable:.3e} s"),
                ratio(*stable),
                format!(
                    "unstable at {unstable:.3e} s: {why}{}",
                    unconverged_note(*unconverged)
                ),
            ),
            Limit::Capped {
                stable,
                unconverged,
            } => (
                format!("≥ {stable:.3e} s"),
                ratio(*stable),
                format!(
                    "stable at every step tried, up to {stable} s (the trial time){}",
                    unconverged_note(*unconverged)
                ),
            ),
            Limit::NoneFound { why, .. } => ("none found".into(), "-".into(), why.clone()),
        };
        let (cost, steps) = match &row.cost {
            Some(c) => (
                format!("{:.3e}", c.per_simulated_second),
                format!("{:.3e}", c.steps_per_second),
            ),
            None => ("-".into(), "-".into()),
        };
        let note = match (&row.cost, row.limit.stable()) {
            (None, Some(_)) => format!("{note}; the timed run failed"),
            _ => note,
        };
        let _ = write!(
            text,
            "\n{:<16} {:>19} {:>11} {:>15} {:>11}  {note}",
            row.kind.name(),
            dt,
            over,
            cost,
            steps
        );
    }
    let _ = write!(
        text,
        "\n(bisection on log dt to within {:.0} %; cost: wall-clock seconds per simulated second at the largest stable dt)",
        (BRACKET - 1.0) * 100.0
    );
    text
}

/// `value` to 4 significant digits: plain from 0.01 to 10⁴, else with
/// an exponent.
fn significant(value: Real) -> String {
    if (0.01..1e4).contains(&value.abs()) {
        let decimals = (3 - value.abs().log10().floor() as i32).max(0) as usize;
        format!("{value:.decimals$}")
    } else {
        format!("{value:.3e}")
    }
}

fn unconverged_note(steps: u64) -> String {
    if steps > 0 {
        format!(" (the solver stopped above its tolerance in {steps} steps)")
    } else {
        String::new()
    }
}

/// The CSV: [`HEADER`], then a row per integrator; empty cells where
/// there is no value, numbers in full precision.
pub fn csv(setting: &Setting, rows: &[Row]) -> String {
    let number = |v: Option<Real>| {
        v.filter(|v| v.is_finite())
            .map_or(String::new(), |v| format!("{v:e}"))
    };
    let mut text = format!("{HEADER}\n");
    for row in rows {
        let _ = writeln!(
            text,
            "{},{},{},{},{},{},{}",
            row.kind.name(),
            number(row.limit.stable()),
            matches!(row.limit, Limit::Capped { .. }),
            number(Some(setting.estimate)),
            number(row.cost.map(|c| c.per_simulated_second)),
            number(row.cost.map(|c| c.steps_per_second)),
            setting.energy_criterion()
        );
    }
    text
}

/// The plot: cost against largest stable dt, one point per integrator.
pub fn png(setting: &Setting, rows: &[Row]) -> Result<Vec<u8>, CliError> {
    // Every integrator, so that each keeps its colour; those without a
    // value (NaN) are left off the plot.
    let points: Vec<StabilityPoint> = rows
        .iter()
        .map(|row| StabilityPoint {
            label: row.kind.name().to_string(),
            dt: row.limit.stable().unwrap_or(Real::NAN),
            cost: row.cost.map_or(Real::NAN, |c| c.per_simulated_second),
            capped: matches!(row.limit, Limit::Capped { .. }),
        })
        .collect();
    let mut note = vec![format!("trial runs of {} s", setting.time)];
    note.push(if setting.energy_criterion() {
        format!("energy criterion on, margin {}", setting.margin)
    } else {
        "energy criterion off (driving forces)".to_string()
    });
    if points.iter().any(|p| p.capped) {
        note.push("hollow (≥): stable at every step tried".into());
    }
    let missing: Vec<&str> = rows
        .iter()
        .filter(|r| r.limit.stable().is_none() || r.cost.is_none())
        .map(|r| r.kind.name())
        .collect();
    if !missing.is_empty() {
        note.push(format!("not plotted: {}", missing.join(", ")));
    }
    let stem = setting
        .path
        .file_stem()
        .map_or("scene".into(), |s| s.to_string_lossy().into_owned());
    stability_png(
        &format!("{stem}: largest stable time step and cost of the integrators"),
        &points,
        &note.join("\n"),
        &PlotOptions::default(),
    )
    .map_err(|e| CliError::Io(e.to_string()))
}

/// Write `stability.csv` and `stability.png` into `out` (created if
/// needed); the plot is drawn before anything is written.
pub fn write(out: &Path, setting: &Setting, rows: &[Row]) -> Result<(), CliError> {
    let png = png(setting, rows)?;
    let csv = csv(setting, rows);
    std::fs::create_dir_all(out)
        .map_err(|e| CliError::Io(format!("cannot create {}: {e}", out.display())))?;
    for (name, bytes) in [(CSV, csv.as_bytes()), (PNG, &png[..])] {
        let file = out.join(name);
        AtomicFile::write(&file, bytes)
            .map_err(|e| CliError::Io(format!("cannot write {}: {e}", file.display())))?;
    }
    Ok(())
}
