//! The plot of `sprung study stability`: for each integrator, the
//! wall-clock cost per simulated second against its largest stable time
//! step, on log-log axes, one labelled point per integrator.

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axis::Axis;
use super::figure::{axis_title, Look, GREY, GRID, SUPERSAMPLE};
use super::figures::colour;
use super::{encode, font, PlotError, PlotOptions};

/// One integrator on the stability plot.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityPoint {
    /// The integrator's name, written beside its point.
    pub label: String,
    /// The largest stable time step found (s); must be positive.
    pub dt: f64,
    /// Wall-clock time per simulated second at that step (s/s); must be
    /// positive.
    pub cost: f64,
    /// Stable at every step tried, up to the cap: its limit is at least
    /// `dt` (drawn hollow, labelled "≥").
    pub capped: bool,
}

/// PNG of `points` (cost per simulated second against largest stable time
/// step, both log₁₀), titled `title`, with the lines of `note` under the
/// title. Points whose `dt` or `cost` is not positive and finite are left
/// out; each point's colour follows its place in `points`.
pub fn stability_png(
    title: &str,
    points: &[StabilityPoint],
    note: &str,
    options: &PlotOptions,
) -> Result<Vec<u8>, PlotError> {
    options.check()?;
    font::register()?;
    let (width, height) = (options.width, options.height);
    let (big_w, big_h) = (width * SUPERSAMPLE, height * SUPERSAMPLE);
    let mut buffer = vec![255u8; big_w as usize * big_h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (big_w, big_h)).into_drawing_area();
        // Each keeps its colour by its place in `points`.
        let usable: Vec<(usize, &StabilityPoint)> = points
            .iter()
            .enumerate()
            .filter(|(_, p)| p.dt.is_finite() && p.dt > 0.0 && p.cost.is_finite() && p.cost > 0.0)
            .collect();
        draw(&root, title, &usable, note).map_err(|e| PlotError::Draw(e.to_string()))?;
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
    root: &DrawingArea<DB, Shift>,
    title: &str,
    points: &[(usize, &StabilityPoint)],
    note: &str,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let (w, h) = root.dim_in_pixel();
    let (w, h) = (w as i32, h as i32);
    let look = Look::new(w, h);
    let px = |v: f64| look.px(v);
    // The title, and under it the note's lines, joined with " · " as far
    // as the width allows.
    let mut subtitle: Vec<String> = Vec::new();
    for part in note.lines().filter(|l| !l.trim().is_empty()) {
        let joined = subtitle.last().map(|last| format!("{last}  ·  {part}"));
        match joined {
            Some(j) if root.estimate_text_size(&j, &look.note)?.0 as i32 <= w - px(40.0) => {
                *subtitle.last_mut().expect("a line") = j;
            }
            _ => subtitle.push(part.to_string()),
        }
    }
    let title_h = px(40.0) + px(17.0) * subtitle.len() as i32;
    root.draw_text(title, &look.title, (w / 2, px(22.0)))?;
    let centred = look.note.pos(Pos::new(HPos::Center, VPos::Center));
    for (index, line) in subtitle.iter().enumerate() {
        root.draw_text(line, &centred, (w / 2, px(44.0) + px(17.0) * index as i32))?;
    }

    let range = |values: Vec<f64>| {
        values
            .into_iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    };
    // Nothing to show: a decade around 1.
    let range = |values: Vec<f64>| match range(values) {
        (lo, hi) if lo <= hi => (lo, hi),
        _ => (1.0, 1.0),
    };
    let (x_lo, x_hi) = range(points.iter().map(|(_, p)| p.dt).collect());
    let (y_lo, y_hi) = range(points.iter().map(|(_, p)| p.cost).collect());
    // A factor 4 of room either side, so that points and labels stay
    // inside the frame.
    let x_axis = Axis::log(x_lo / 4.0, x_hi * 4.0, 8);
    let y_axis = Axis::log(y_lo / 4.0, y_hi * 4.0, 8);
    let mut y_labels_w = px(30.0);
    for label in y_axis.labels() {
        y_labels_w = y_labels_w.max(root.estimate_text_size(label, &look.tick)?.0 as i32);
    }
    let tick_h = root.estimate_text_size("0123456789", &look.tick)?.1 as i32;
    let area = root.split_vertically(title_h).1;
    let mut chart = ChartBuilder::on(&area)
        .margin_top(px(10.0))
        .margin_right(px(24.0))
        .margin_left(px(8.0))
        .x_label_area_size(tick_h + px(40.0))
        .y_label_area_size(y_labels_w + px(36.0))
        .build_cartesian_2d(x_axis.clone(), y_axis.clone())?;
    let x_format = |v: &f64| x_axis.label(*v);
    let y_format = |v: &f64| y_axis.label(*v);
    chart
        .configure_mesh()
        .x_label_formatter(&x_format)
        .y_label_formatter(&y_format)
        .bold_line_style(GRID)
        .axis_style(GREY)
        .label_style(look.tick.clone())
        .axis_desc_style(look.axis_title.clone())
        .set_all_tick_mark_size(px(5.0))
        .x_desc(axis_title("largest stable time step", "s", &x_axis))
        .y_desc(axis_title(
            "wall-clock time per simulated second",
            "s/s",
            &y_axis,
        ))
        .draw()?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    chart
        .plotting_area()
        .strip_coord_spec()
        .draw(&Rectangle::new(
            [(0, 0), (xs.end - xs.start - 1, ys.end - ys.start - 1)],
            ShapeStyle::from(&GREY).stroke_width(px(1.0) as u32),
        ))?;

    // Points, then labels beside them, each moved down or up by a line
    // until it overlaps no label placed before it.
    let radius = px(6.0);
    let line_h = px(20.0);
    let mut placed: Vec<(i32, i32, i32, i32)> = Vec::new();
    for &(index, point) in points {
        let centre = chart.backend_coord(&(point.dt.log10(), point.cost.log10()));
        let color = colour(index);
        let style = if point.capped {
            ShapeStyle::from(&color).stroke_width(px(2.0) as u32)
        } else {
            ShapeStyle::from(&color).filled()
        };
        root.draw(&Circle::new(centre, radius, style))?;
        let label = if point.capped {
            format!("{} (≥)", point.label)
        } else {
            point.label.clone()
        };
        let tw = root.estimate_text_size(&label, &look.legend)?.0 as i32;
        let right = centre.0 + radius + px(6.0);
        let left = centre.0 - radius - px(6.0) - tw;
        // Right of the point, else left of it, then a line lower or higher.
        let sides: Vec<i32> = [right, left]
            .into_iter()
            .filter(|&x| x >= xs.start + px(4.0) && x + tw <= xs.end - px(4.0))
            .collect();
        let sides = if sides.is_empty() { vec![right] } else { sides };
        let candidates = [0, 1, -1, 2, -2, 3, -3]
            .into_iter()
            .flat_map(|shift| sides.iter().map(move |&x| (x, centre.1 + shift * line_h)));
        let mut spot = (sides[0], centre.1);
        for (x, y) in candidates {
            let clash = placed.iter().any(|&(ax, ay, bx, by)| {
                x < bx && ax < x + tw && y - line_h / 2 < by && ay < y + line_h / 2
            });
            if !clash {
                spot = (x, y);
                break;
            }
        }
        let (x, y) = spot;
        placed.push((x, y - line_h / 2, x + tw, y + line_h / 2));
        root.draw_text(&label, &look.legend.color(&color), (x, y))?;
    }

    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(label: &str, dt: f64, cost: f64, capped: bool) -> StabilityPoint {
        StabilityPoint {
            label: label.into(),
            dt,
            cost,
            capped,
        }
    }

    #[test]
    fn draws_a_png_of_the_asked_size() {
        let points = [
            point("euler", 1e-4, 2e-2, false),
            point("rk4", 0.4, 1e-5, false),
            point("implicit_euler", 2.0, 1e-6, true),
            point("projective", 2.0, 1.2e-6, true),
            point("none", f64::NAN, f64::NAN, false),
        ];
        let options = PlotOptions {
            width: 640,
            height: 400,
            ..PlotOptions::default()
        };
        let png =
            stability_png("oscillator", &points, "a note\nsecond line", &options).expect("drawn");
        assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
        let be = |i: usize| u32::from_be_bytes([png[i], png[i + 1], png[i + 2], png[i + 3]]);
        assert_eq!((be(16), be(20)), (640, 400));
        // The same points give the same bytes.
        assert_eq!(
            png,
            stability_png("oscillator", &points, "a note\nsecond line", &options).expect("drawn")
        );
    }

    #[test]
    fn nothing_to_draw_still_gives_a_plot() {
        let png = stability_png("empty", &[], "", &PlotOptions::default()).expect("drawn");
        assert!(!png.is_empty());
    }
}
