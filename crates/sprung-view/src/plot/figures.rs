//! What each plot shows: energies, gas bodies, probed particles, and the
//! comparison of several runs.

use plotters::style::RGBColor;

use super::figure::{Figure, Panel, Series, YScale};
use super::{DiagnosticsTable, Dimension, Scale};

/// Line colours for bodies, probes and runs (the "tab10" palette of
/// matplotlib, easy to tell apart and kind to colour-blind readers).
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The colours of the standard energy terms (other terms, of a user's
/// forces, take the palette's); `total` comes last, in black.
const ENERGY_COLOURS: [(&str, RGBColor); 6] = [
    ("kinetic", RGBColor(214, 39, 40)),
    ("spring", RGBColor(31, 119, 180)),
    ("gravity", RGBColor(44, 160, 44)),
    ("gas", RGBColor(255, 127, 14)),
    ("contact", RGBColor(148, 103, 189)),
    ("gravitation", RGBColor(140, 86, 75)),
];

const LINE: f64 = 1.6;
const THICK: f64 = 2.4;

pub(super) fn colour(index: usize) -> RGBColor {
    PALETTE[index % PALETTE.len()]
}

fn series(
    table: &DiagnosticsTable,
    column: &str,
    label: String,
    color: RGBColor,
    width: f64,
) -> Series {
    let values = table.column(column).unwrap_or(&[]);
    Series {
        label,
        color,
        width,
        points: table
            .time()
            .iter()
            .copied()
            .zip(values.iter().copied())
            .collect(),
    }
}

/// Each energy term (J) of the table ([`DiagnosticsTable::energy_terms`])
/// that is not zero throughout, and the total.
pub(crate) fn energy(table: &DiagnosticsTable, run: &str) -> Figure {
    let mut lines = Vec::new();
    let mut zero = Vec::new();
    let mut others = 0;
    for term in table.energy_terms() {
        if table.is_zero(&term) {
            zero.push(term);
            continue;
        }
        let known = ENERGY_COLOURS.iter().find(|(name, _)| *name == term);
        let color = known.map_or_else(
            || {
                others += 1;
                colour(others + 5)
            },
            |&(_, color)| color,
        );
        lines.push(series(table, &term, term.clone(), color, LINE));
    }
    lines.push(series(
        table,
        "total",
        "total".into(),
        RGBColor(0, 0, 0),
        THICK,
    ));
    Figure {
        title: format!("{run}: energy"),
        panels: vec![Panel {
            quantity: "energy".into(),
            unit: "J".into(),
            scale: YScale::Linear,
            min_span: 0.0,
            series: lines,
            note: (!zero.is_empty()).then(|| format!("zero throughout:\n{}", zero.join(", "))),
        }],
    }
}

/// Volume (area in 2D) of every closed body and pressure of every body
/// with gas; `None` without gas bodies.
pub(crate) fn gas(table: &DiagnosticsTable, run: &str, dimension: Dimension) -> Option<Figure> {
    let bodies = table.bodies();
    let pressure = |b: &String| format!("{b}.pressure");
    if !bodies.iter().any(|b| table.has_values(&pressure(b))) {
        return None;
    }
    let panel = |quantity: &str, title: &str, unit: &str| Panel {
        quantity: title.into(),
        unit: unit.into(),
        scale: YScale::Linear,
        min_span: 0.0,
        series: bodies
            .iter()
            .enumerate()
            .filter(|(_, b)| table.has_values(&format!("{b}.{quantity}")))
            .map(|(i, b)| {
                series(
                    table,
                    &format!("{b}.{quantity}"),
                    b.clone(),
                    colour(i),
                    LINE,
                )
            })
            .collect(),
        note: None,
    };
    let (volume, title) = match dimension {
        Dimension::Two => (panel("volume", "area", "m²"), "area and pressure"),
        Dimension::Three => (panel("volume", "volume", "m³"), "volume and pressure"),
    };
    let mut pressure = panel("pressure", "pressure", unit("pressure", dimension));
    if dimension == Dimension::Two {
        pressure.note = Some("2D pressure:\nforce per length".into());
    }
    Some(Figure {
        title: format!("{run}: {title} of the bodies"),
        panels: vec![volume, pressure],
    })
}

/// Positions of the probed particles (m), a panel per coordinate (no z
/// in 2D); `None` without probes.
pub(crate) fn probes(table: &DiagnosticsTable, run: &str, dimension: Dimension) -> Option<Figure> {
    let probes = table.probes();
    if probes.is_empty() {
        return None;
    }
    let axes: &[&str] = match dimension {
        Dimension::Two => &["x", "y"],
        Dimension::Three => &["x", "y", "z"],
    };
    // Rounding noise on a coordinate that stays put (z of a symmetric 3D
    // body, say) shows as a flat line, not as a wild one at 10⁻¹⁵ m.
    let largest = probes
        .iter()
        .flat_map(|p| axes.iter().map(move |a| format!("{p}.{a}")))
        .filter_map(|c| table.column(&c))
        .flatten()
        .flatten()
        .fold(0.0f64, |m, v| m.max(v.abs()));
    let panels = axes
        .iter()
        .map(|axis| Panel {
            quantity: (*axis).into(),
            unit: "m".into(),
            scale: YScale::Linear,
            min_span: 1e-6 * largest,
            series: probes
                .iter()
                .enumerate()
                .map(|(i, p)| {
                    series(
                        table,
                        &format!("{p}.{axis}"),
                        probe_label(p),
                        colour(i),
                        LINE,
                    )
                })
                .collect(),
            note: None,
        })
        .collect();
    Some(Figure {
        title: format!("{run}: probed particles"),
        panels,
    })
}

/// "particle 3" for the probe `p3`.
fn probe_label(prefix: &str) -> String {
    match prefix.strip_prefix('p') {
        Some(index) if !index.is_empty() && index.bytes().all(|b| b.is_ascii_digit()) => {
            format!("particle {index}")
        }
        _ => prefix.to_string(),
    }
}

/// The unit of a diagnostics column that is not an energy term
/// ([`DiagnosticsTable::is_energy`]), from its name ("" when unknown).
pub(crate) fn unit(column: &str, dimension: Dimension) -> &'static str {
    let suffix = column.rsplit_once('.').map_or(column, |(_, s)| s);
    match (suffix, dimension) {
        ("time", _) => "s",
        ("volume", Dimension::Two) => "m²",
        ("volume", Dimension::Three) => "m³",
        ("pressure", Dimension::Two) => "N/m",
        ("pressure", Dimension::Three) => "Pa",
        ("cx" | "cy" | "cz" | "x" | "y" | "z", _) => "m",
        _ => "",
    }
}

/// The column `column` of several runs (label, table) on one chart, titled
/// after `name`: each relative to its first value (when none of those is
/// zero), with the relative change below on a log scale so that small
/// drifts show beside large ones.
pub(crate) fn compare(
    name: &str,
    runs: &[(String, DiagnosticsTable)],
    column: &str,
    scale: Scale,
    dimension: Dimension,
) -> Figure {
    let first = |t: &DiagnosticsTable| {
        t.column(column)
            .and_then(|c| c.iter().flatten().next().copied())
    };
    let relative = runs.iter().all(|(_, t)| first(t).is_some_and(|v| v != 0.0));
    let symbol = if column == "total" {
        "E".to_string()
    } else {
        column.to_string()
    };
    let unit = if runs.iter().any(|(_, t)| t.is_energy(column)) {
        "J"
    } else {
        unit(column, dimension)
    };
    let mut values = Vec::new();
    let mut changes = Vec::new();
    for (index, (label, table)) in runs.iter().enumerate() {
        let start = first(table).unwrap_or(0.0);
        let mut line = series(table, column, label.clone(), colour(index), LINE);
        let mut change = line.clone();
        for ((_, v), (_, c)) in line.points.iter_mut().zip(change.points.iter_mut()) {
            let value = v.unwrap_or(f64::NAN);
            *c = Some(if relative {
                ((value - start) / start).abs()
            } else {
                (value - start).abs()
            });
            if relative {
                *v = Some(value / start);
            }
        }
        values.push(line);
        changes.push(change);
    }
    let (value_title, change_title, unit) = if relative {
        (
            format!("{symbol} / {symbol}₀"),
            format!("|{symbol} − {symbol}₀| / |{symbol}₀|"),
            "",
        )
    } else {
        (symbol.clone(), format!("|{symbol} − {symbol}₀|"), unit)
    };
    let value_scale = match scale {
        Scale::Linear => YScale::Linear,
        Scale::Log => YScale::Log,
        Scale::Auto => auto_scale(&values),
    };
    let log_note = |s: YScale| (s == YScale::Log).then(|| "log scale".to_string());
    let common = if column == "total" {
        "total energy"
    } else {
        column
    };
    Figure {
        title: format!("{name}: {common} of {} runs", runs.len()),
        panels: vec![
            Panel {
                quantity: value_title,
                unit: unit.into(),
                scale: value_scale,
                min_span: 0.0,
                series: values,
                note: log_note(value_scale),
            },
            Panel {
                quantity: change_title,
                unit: unit.into(),
                scale: YScale::Log,
                min_span: 0.0,
                series: changes,
                note: log_note(YScale::Log),
            },
        ],
    }
}

/// Log when every value is positive and they span more than a factor 100.
fn auto_scale(lines: &[Series]) -> YScale {
    let values = || lines.iter().flat_map(|s| &s.points).filter_map(|(_, y)| *y);
    let positive = values().all(|v| v > 0.0);
    let (lo, hi) = values().fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if positive && lo > 0.0 && hi / lo > 100.0 {
        YScale::Log
    } else {
        YScale::Linear
    }
}
