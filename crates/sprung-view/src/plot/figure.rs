//! Drawing a figure (a title over one or more panels that share the time
//! axis, each with a legend on its right) into an RGB buffer with
//! plotters, and encoding it as PNG.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::{Axis, HUGE};
use super::font::{self, FONT_FAMILY};
use super::{encode, PlotError};

/// Drawn at this multiple of the size, then shrunk (smooth lines).
pub(super) const SUPERSAMPLE: u32 = 2;

const INK: RGBColor = RGBColor(40, 40, 40);
pub(super) const GREY: RGBColor = RGBColor(110, 110, 110);
pub(super) const GRID: RGBColor = RGBColor(222, 222, 222);

/// A line on a panel: (x, y) points, with gaps where y is missing.
#[derive(Debug, Clone)]
pub(crate) struct Series {
    pub label: String,
    pub color: RGBColor,
    /// Line width (px at the final size).
    pub width: f64,
    pub points: Vec<(f64, Option<f64>)>,
}

/// How a panel's vertical axis maps values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum YScale {
    Linear,
    /// log₁₀; values ≤ 0 are left out.
    Log,
}

/// One chart of a figure.
#[derive(Debug, Clone)]
pub(crate) struct Panel {
    /// What the vertical axis shows, e.g. "energy".
    pub quantity: String,
    /// Its unit, e.g. "J" ("" for a ratio).
    pub unit: String,
    pub scale: YScale,
    /// The least span (in the unit) the linear axis shows: keeps rounding
    /// noise on a constant from filling the panel.
    pub min_span: f64,
    pub series: Vec<Series>,
    /// A remark under the legend (e.g. the terms left out).
    pub note: Option<String>,
}

/// A picture: a title and panels stacked over a shared time axis.
#[derive(Debug, Clone)]
pub(crate) struct Figure {
    pub title: String,
    /// Panels over a shared time axis (s).
    pub panels: Vec<Panel>,
}

impl Figure {
    /// Draw at `width` × `height` pixels and encode as PNG.
    pub(crate) fn png(&self, width: u32, height: u32) -> Result<Vec<u8>, PlotError> {
        font::register()?;
        let (big_w, big_h) = (width * SUPERSAMPLE, height * SUPERSAMPLE);
        let mut buffer = vec![255u8; big_w as usize * big_h as usize * 3];
        {
            let root = BitMapBackend::with_buffer(&mut buffer, (big_w, big_h)).into_drawing_area();
            self.draw(&root)
                .map_err(|e| PlotError::Draw(e.to_string()))?;
            root.present().map_err(|e| PlotError::Draw(e.to_string()))?;
        }
        let rgb = encode::shrink(
            &buffer,
            big_w as usize,
            big_h as usize,
            SUPERSAMPLE as usize,
        );
        encode::png(&rgb, width, height)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        root.fill(&WHITE)?;
        let (w, h) = root.dim_in_pixel();
        let (w, h) = (w as i32, h as i32);
        let look = Look::new(w, h);
        let px = |v: f64| look.px(v);

        let title_h = px(44.0);
        root.draw_text(&self.title, &look.title, (w / 2, title_h / 2 + px(2.0)))?;

        // The legend column: wide enough for the longest label or note.
        let mut legend_w = px(60.0);
        for panel in &self.panels {
            for series in &panel.series {
                let (tw, _) = root.estimate_text_size(&series.label, &look.legend)?;
                legend_w = legend_w.max(tw as i32 + px(56.0));
            }
            for line in panel.note.iter().flat_map(|n| n.lines()) {
                let (tw, _) = root.estimate_text_size(line, &look.note)?;
                legend_w = legend_w.max(tw as i32 + px(24.0));
            }
        }
        let legend_w = legend_w.min(w * 3 / 10);

        // Equal plot heights; the bottom panel also holds the time axis title.
        let n = self.panels.len().max(1) as i32;
        let tick_h = root.estimate_text_size("0123456789", &look.tick)?.1 as i32;
        let x_labels_h = tick_h + px(14.0);
        let x_title_h = px(26.0);
        let gap = px(10.0);
        let plot_h = ((h - title_h - x_title_h - px(8.0)) / n - x_labels_h - gap).max(px(20.0));
        let y_axes: Vec<Axis> = self
            .panels
            .iter()
            .map(|p| y_axis(p, (plot_h / px(36.0)).clamp(3, 12) as usize))
            .collect();
        // One width for every panel's y labels, so that the plots line up.
        let mut y_labels_w = px(30.0);
        for label in y_axes.iter().flat_map(Axis::labels) {
            y_labels_w = y_labels_w.max(root.estimate_text_size(label, &look.tick)?.0 as i32);
        }
        let y_area_w = y_labels_w + px(36.0);
        let plot_w = (w - legend_w - y_area_w - px(20.0)).max(px(40.0));
        let x_axis = {
            let (lo, hi) = x_range(&self.panels);
            Axis::linear(
                lo,
                hi,
                (plot_w / px(95.0)).clamp(3, 12) as usize,
                false,
                0.0,
            )
        };

        let breaks: Vec<i32> = (1..n).map(|i| i * (plot_h + x_labels_h + gap)).collect();
        let areas = root
            .split_vertically(title_h)
            .1
            .split_by_breakpoints::<i32, i32, _, _>([], breaks);
        let mut previous_labels: Option<Vec<&str>> = None;
        for (index, ((panel, area), y_axis)) in
            self.panels.iter().zip(&areas).zip(&y_axes).enumerate()
        {
            let last = index + 1 == self.panels.len();
            let mut chart = ChartBuilder::on(area)
                .margin_top(gap)
                .margin_right(legend_w + px(12.0))
                .margin_left(px(8.0))
                .x_label_area_size(x_labels_h + if last { x_title_h } else { 0 })
                .y_label_area_size(y_area_w)
                .build_cartesian_2d(x_axis.clone(), y_axis.clone())?;
            let x_format = |v: &f64| x_axis.label(*v);
            let y_format = |v: &f64| y_axis.label(*v);
            let mut mesh = chart.configure_mesh();
            mesh.x_label_formatter(&x_format)
                .y_label_formatter(&y_format)
                .bold_line_style(GRID)
                .axis_style(GREY)
                .label_style(look.tick.clone())
                .axis_desc_style(look.axis_title.clone())
                .set_all_tick_mark_size(px(5.0))
                .y_desc(axis_title(&panel.quantity, &panel.unit, y_axis));
            if last {
                mesh.x_desc(axis_title("time", "s", &x_axis));
            }
            mesh.draw()?;
            for series in &panel.series {
                for run in runs(series, panel.scale) {
                    let pixels: Vec<(i32, i32)> =
                        run.iter().map(|p| chart.backend_coord(p)).collect();
                    stroke(root, &pixels, &series.color, px(series.width))?;
                }
            }
            let (xs, ys) = chart.plotting_area().get_pixel_range();
            chart
                .plotting_area()
                .strip_coord_spec()
                .draw(&Rectangle::new(
                    [(0, 0), (xs.end - xs.start - 1, ys.end - ys.start - 1)],
                    ShapeStyle::from(&GREY).stroke_width(px(1.0) as u32),
                ))?;
            // The legend, unless it repeats the panel above's.
            let labels: Vec<&str> = panel.series.iter().map(|s| s.label.as_str()).collect();
            if previous_labels.as_ref() != Some(&labels) {
                let base = area.get_base_pixel();
                let corner = (xs.end - base.0 + px(18.0), ys.start - base.1 + px(12.0));
                legend(area, corner, panel, &look)?;
            }
            previous_labels = Some(labels);
        }
        Ok(())
    }
}

/// Sizes and text styles, scaled with the picture (1 unit = 1 px on a
/// 1000 × 600 plot).
pub(super) struct Look {
    unit: f64,
    pub(super) title: TextStyle<'static>,
    pub(super) tick: TextStyle<'static>,
    pub(super) axis_title: TextStyle<'static>,
    pub(super) legend: TextStyle<'static>,
    pub(super) note: TextStyle<'static>,
}

impl Look {
    /// The look of a `w` × `h` pixel drawing (at [`SUPERSAMPLE`] times the
    /// final size).
    pub(super) fn new(w: i32, h: i32) -> Look {
        let s = f64::from(SUPERSAMPLE);
        let unit = s
            * (f64::from(w) / s / 1000.0)
                .min(f64::from(h) / s / 600.0)
                .clamp(0.75, 3.0);
        let text = |size: f64, color: &'static RGBColor| {
            TextStyle::from((FONT_FAMILY, size * unit).into_font()).color(color)
        };
        let (left, centre) = (
            Pos::new(HPos::Left, VPos::Center),
            Pos::new(HPos::Center, VPos::Center),
        );
        Look {
            unit,
            title: text(21.0, &INK).pos(centre),
            tick: text(13.5, &INK),
            axis_title: text(15.0, &INK),
            legend: text(14.0, &INK).pos(left),
            note: text(12.5, &GREY).pos(left),
        }
    }

    /// `v` units in pixels (at least 1).
    pub(super) fn px(&self, v: f64) -> i32 {
        (v * self.unit).round().max(1.0) as i32
    }
}

/// The legend of `panel` from `corner` (its top left, px) of `area`: a
/// sample of each line with its label, then the note.
fn legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    corner: (i32, i32),
    panel: &Panel,
    look: &Look,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let px = |v: f64| look.px(v);
    let (x0, mut y) = corner;
    for series in &panel.series {
        let style = ShapeStyle::from(&series.color).stroke_width(px(series.width.max(2.0)) as u32);
        area.draw(&PathElement::new(vec![(x0, y), (x0 + px(28.0), y)], style))?;
        area.draw_text(&series.label, &look.legend, (x0 + px(36.0), y))?;
        y += px(22.0);
    }
    y += px(4.0);
    for line in panel.note.iter().flat_map(|n| n.lines()) {
        area.draw_text(line, &look.note, (x0, y))?;
        y += px(17.0);
    }
    Ok(())
}

/// "quantity (unit)", with the axis's power of ten: "time (×10⁻⁹ s)".
pub(super) fn axis_title(quantity: &str, unit: &str, axis: &Axis) -> String {
    match (&axis.factor, unit) {
        (None, "") => quantity.to_string(),
        (None, unit) => format!("{quantity} ({unit})"),
        (Some(f), "") => format!("{quantity} ({f})"),
        (Some(f), unit) => format!("{quantity} ({f} {unit})"),
    }
}

/// Draw the polyline `pixels` `width` pixels wide: thin lines repeated
/// under a round brush. (The library's own wide lines join segments with
/// mitres that spike at sharp turns of noisy data.)
fn stroke<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    pixels: &[(i32, i32)],
    color: &RGBColor,
    width: i32,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let mut path = pixels.to_vec();
    path.dedup();
    if let [only] = path[..] {
        path.push(only);
    }
    let radius = f64::from(width.max(1)) / 2.0;
    let reach = radius.floor() as i32;
    for dx in -reach..=reach {
        for dy in -reach..=reach {
            if f64::from(dx * dx + dy * dy) <= radius * radius + 0.25 {
                let shifted = path.iter().map(|&(x, y)| (x + dx, y + dy));
                root.draw(&PathElement::new(shifted.collect::<Vec<_>>(), color))?;
            }
        }
    }
    Ok(())
}

/// The time span of all series (s).
fn x_range(panels: &[Panel]) -> (f64, f64) {
    let xs = panels
        .iter()
        .flat_map(|p| &p.series)
        .flat_map(|s| &s.points)
        .map(|(x, _)| *x)
        .filter(|x| x.is_finite());
    min_max(xs)
}

/// The vertical axis of `panel` with about `target` ticks.
fn y_axis(panel: &Panel, target: usize) -> Axis {
    let values = panel
        .series
        .iter()
        .flat_map(|s| &s.points)
        .filter_map(|(_, y)| *y);
    match panel.scale {
        YScale::Linear => {
            let (lo, hi) = min_max(values.filter(|y| y.is_finite()));
            Axis::linear(lo, hi, target, true, panel.min_span)
        }
        YScale::Log => {
            let (lo, hi) = min_max(values.filter(|y| y.is_finite() && *y > 0.0));
            Axis::log(lo, hi, target)
        }
    }
}

/// Smallest and largest of `values`; (0, 1) when there are none.
fn min_max(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if lo <= hi {
        (lo, hi)
    } else {
        (0.0, 1.0)
    }
}

/// The unbroken stretches of `series`, in plot coordinates (log₁₀ of the
/// value on a log axis).
fn runs(series: &Series, scale: YScale) -> Vec<Vec<(f64, f64)>> {
    let mut runs = Vec::new();
    let mut current = Vec::new();
    for &(x, y) in &series.points {
        let y = match (y, scale) {
            (Some(y), YScale::Linear) if y.is_finite() => Some(y.clamp(-HUGE, HUGE)),
            (Some(y), YScale::Log) if y.is_finite() && y > 0.0 => Some(y.log10()),
            _ => None,
        };
        match y {
            Some(y) if x.is_finite() => current.push((x.clamp(-HUGE, HUGE), y)),
            _ if !current.is_empty() => runs.push(std::mem::take(&mut current)),
            _ => {}
        }
    }
    if !current.is_empty() {
        runs.push(current);
    }
    runs
}
