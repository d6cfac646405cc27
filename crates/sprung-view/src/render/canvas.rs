//! A thin layer over tiny-skia: anti-aliased polygons, lines, squares and
//! discs in pixel coordinates, and the pixels out as an [`Image`].

use tiny_skia::{
    Color, FillRule, GradientStop, LineCap, Paint, PathBuilder, Pixmap, Point, RadialGradient,
    Rect, SpreadMode, Stroke, Transform,
};

use super::image::Image;
use super::strain::Rgb;
use super::RenderError;

/// A picture being drawn.
pub struct Canvas {
    pixmap: Pixmap,
}

fn paint(colour: Rgb) -> Paint<'static> {
    paint_alpha(colour, 255)
}

fn paint_alpha(colour: Rgb, alpha: u8) -> Paint<'static> {
    let mut paint = Paint::default();
    paint.set_color(Color::from_rgba8(colour[0], colour[1], colour[2], alpha));
    paint.anti_alias = true;
    paint
}

impl Canvas {
    /// A `width` × `height` canvas filled with `background`.
    pub fn new(width: u32, height: u32, background: Rgb) -> Result<Self, RenderError> {
        let mut pixmap = Pixmap::new(width, height).ok_or_else(|| {
            RenderError::BadSize(format!("cannot make a {width}×{height} picture"))
        })?;
        pixmap.fill(Color::from_rgba8(
            background[0],
            background[1],
            background[2],
            255,
        ));
        Ok(Canvas { pixmap })
    }

    /// Fill the closed polygon through `points` (pixels). With `seal`, also
    /// stroke its edge with a hairline of the same colour so that abutting
    /// polygons leave no anti-aliasing seams between them.
    pub fn polygon(&mut self, points: &[(f32, f32)], colour: Rgb, seal: bool) {
        let Some(path) = closed_path(points) else {
            return;
        };
        let paint = paint(colour);
        self.pixmap.fill_path(
            &path,
            &paint,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        if seal {
            let stroke = Stroke {
                width: 0.8,
                ..Stroke::default()
            };
            self.pixmap
                .stroke_path(&path, &paint, &stroke, Transform::identity(), None);
        }
    }

    /// A line from `a` to `b` (pixels), `width` pixels wide, round caps.
    pub fn line(&mut self, a: (f32, f32), b: (f32, f32), colour: Rgb, width: f32) {
        self.line_alpha(a, b, colour, width, 255);
    }

    /// A line as [`Self::line`] with opacity `alpha` (255 opaque).
    pub fn line_alpha(&mut self, a: (f32, f32), b: (f32, f32), colour: Rgb, width: f32, alpha: u8) {
        if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
            return;
        }
        let mut builder = PathBuilder::new();
        builder.move_to(a.0, a.1);
        builder.line_to(b.0, b.1);
        let Some(path) = builder.finish() else {
            return;
        };
        let stroke = Stroke {
            width,
            line_cap: LineCap::Round,
            ..Stroke::default()
        };
        self.pixmap.stroke_path(
            &path,
            &paint_alpha(colour, alpha),
            &stroke,
            Transform::identity(),
            None,
        );
    }

    /// A filled square of side `size` centred on `centre` (pixels).
    pub fn square(&mut self, centre: (f32, f32), size: f32, colour: Rgb) {
        let half = 0.5 * size;
        if let Some(rect) = Rect::from_xywh(centre.0 - half, centre.1 - half, size, size) {
            self.pixmap
                .fill_rect(rect, &paint(colour), Transform::identity(), None);
        }
    }

    /// A disc of `radius` about `centre` (pixels), no edge.
    pub fn dot(&mut self, centre: (f32, f32), radius: f32, colour: Rgb) {
        if !(radius.is_finite() && radius > 0.0 && centre.0.is_finite() && centre.1.is_finite()) {
            return;
        }
        if let Some(path) = PathBuilder::from_circle(centre.0, centre.1, radius) {
            self.pixmap.fill_path(
                &path,
                &paint(colour),
                FillRule::Winding,
                Transform::identity(),
                None,
            );
        }
    }

    /// A ball: a disc of `radius` about `centre` (pixels) shaded from
    /// `light` (a highlight up and to the left) to `fill`, edged with `edge`
    /// (1 px).
    pub fn ball(&mut self, centre: (f32, f32), radius: f32, light: Rgb, fill: Rgb, edge: Rgb) {
        if !(radius.is_finite() && radius > 0.0 && centre.0.is_finite() && centre.1.is_finite()) {
            return;
        }
        let Some(path) = PathBuilder::from_circle(centre.0, centre.1, radius) else {
            return;
        };
        let colour = |c: Rgb| Color::from_rgba8(c[0], c[1], c[2], 255);
        let highlight = Point::from_xy(centre.0 - 0.35 * radius, centre.1 - 0.4 * radius);
        let shader = RadialGradient::new(
            highlight,
            0.0,
            Point::from_xy(centre.0, centre.1),
            radius,
            vec![
                GradientStop::new(0.0, colour(light)),
                GradientStop::new(1.0, colour(fill)),
            ],
            SpreadMode::Pad,
            Transform::identity(),
        );
        let mut shaded = paint(fill);
        if let Some(shader) = shader {
            shaded.shader = shader;
        }
        self.pixmap.fill_path(
            &path,
            &shaded,
            FillRule::Winding,
            Transform::identity(),
            None,
        );
        let stroke = Stroke {
            width: 1.0,
            ..Stroke::default()
        };
        self.pixmap
            .stroke_path(&path, &paint(edge), &stroke, Transform::identity(), None);
    }

    /// The finished picture.
    pub fn into_image(self) -> Image {
        let (width, height) = (self.pixmap.width(), self.pixmap.height());
        // Every pixel is opaque (the background was filled first), so the
        // premultiplied RGBA is plain RGBA.
        let rgb = self
            .pixmap
            .data()
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        Image::from_canvas(width, height, rgb)
    }
}

fn closed_path(points: &[(f32, f32)]) -> Option<tiny_skia::Path> {
    if points.len() < 3 || !points.iter().all(|p| p.0.is_finite() && p.1.is_finite()) {
        return None;
    }
    let mut builder = PathBuilder::new();
    builder.move_to(points[0].0, points[0].1);
    for p in &points[1..] {
        builder.line_to(p.0, p.1);
    }
    builder.close();
    builder.finish()
}
