//! The readout over the top right of the view (frame rate, real time or
//! slow motion, energies, volumes) and the help line along its bottom.

use macroquad::color::Color;
use macroquad::math::Rect;
use macroquad::shapes::draw_rectangle;

use crate::app::App;
use crate::palette;
use crate::render::{self, FONT};

const WIDTH: f32 = 270.0;
const LINE: f32 = 20.0;

/// Draw the readout and the help line of `app` over `viewport`.
pub fn draw(app: &App, viewport: Rect) {
    let Some(sim) = app.sim.as_ref() else {
        return;
    };
    let world = &sim.world;
    let mut rows: Vec<(String, String, Color)> = Vec::new();
    let mut row =
        |name: &str, value: String, colour: Color| rows.push((name.into(), value, colour));
    let fps = 1.0 / app.frame_time.max(1e-6);
    row("frame rate", format!("{fps:.0} fps"), palette::TEXT);
    let physics = 1000.0 * app.physics_time;
    row("physics", format!("{physics:.2} ms/frame"), palette::DIM);
    let (pace, colour) = if sim.paused {
        ("paused".to_string(), palette::PINNED)
    } else if sim.failure.is_some() {
        ("stopped".to_string(), palette::ERROR)
    } else if sim.rate > 0.97 {
        (speed_text(sim.settings.speed), palette::TEXT)
    } else {
        let rate = sim.rate * sim.settings.speed;
        (format!("slow motion {rate:.2}x"), palette::PINNED)
    };
    row("speed", pace, colour);
    row(
        "time",
        format!(
            "{:.3} s  ({} steps/frame)",
            world.time(),
            sim.steps_last_frame
        ),
        palette::TEXT,
    );
    if let Some(gpu) = &sim.gpu {
        let (device, colour) = if gpu.stepping {
            ("GPU", palette::TEXT)
        } else {
            ("CPU (not the GPU)", palette::PINNED)
        };
        row("steps on", device.into(), colour);
    }
    let e = world.energies();
    for (name, value) in std::iter::once(("kinetic", e.kinetic)).chain(e.terms()) {
        if value != 0.0 {
            row(name, number(value, "J"), palette::DIM);
        }
    }
    row("total energy", number(e.total(), "J"), palette::TEXT);
    for (index, body) in world.bodies.iter().enumerate().take(4) {
        if let Some(volume) = world.volume(index) {
            let (what, unit) = if body.is_planar() {
                ("area", "m²")
            } else {
                ("volume", "m³")
            };
            row(
                &format!("{what} {}", body.name),
                format!("{volume:.4} {unit}"),
                palette::body(index),
            );
        }
    }
    let height = 14.0 + rows.len() as f32 * LINE;
    let x = viewport.right() - WIDTH - 12.0;
    let y = viewport.y + 12.0;
    draw_rectangle(x, y, WIDTH, height, palette::PANEL);
    for (i, (name, value, colour)) in rows.iter().enumerate() {
        let baseline = y + 8.0 + (i as f32 + 0.8) * LINE;
        let size = FONT - 2.0;
        render::text(name, x + 12.0, baseline, size, palette::DIM);
        let width = render::text_width(value, size);
        render::text(value, x + WIDTH - 12.0 - width, baseline, size, *colour);
    }
    let help = if app.flat {
        "left-drag: grab and throw   right-drag: pan   wheel: zoom   C: frame   H: panel"
    } else {
        "left-drag: grab and throw   right-drag: orbit   shift+right-drag: pan   wheel: zoom   C: frame   H: panel"
    };
    render::text(
        help,
        viewport.x + 14.0,
        viewport.bottom() - 12.0,
        FONT - 3.0,
        palette::DIM,
    );
}

/// `value` with four decimals, or in scientific notation when large.
fn number(value: f64, unit: &str) -> String {
    if value.abs() < 1e5 {
        format!("{value:.4} {unit}")
    } else {
        format!("{value:.4e} {unit}")
    }
}

fn speed_text(speed: f64) -> String {
    if speed >= 0.999 {
        "real time".into()
    } else {
        format!("{speed:.2}x (slowed)")
    }
}
