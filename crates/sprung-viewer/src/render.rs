//! What the two renderers share: what to draw, whether a world is 2D, and
//! the overlays drawn on top in screen space (the hand, the strain legend,
//! messages).

use macroquad::color::Color;
use macroquad::math::{vec2, Rect, Vec2};
use macroquad::shapes::{draw_circle, draw_circle_lines, draw_line, draw_rectangle};
use macroquad::text::{draw_text, measure_text};
use sprung::forces::Wind;
use sprung::{Shape, World};

use crate::palette;

/// What to draw.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Look {
    /// Shade faces (fill loops in 2D).
    pub faces: bool,
    /// Draw the springs of bodies that have faces too (bodies without faces
    /// always show theirs).
    pub springs: bool,
    /// The collider that follows the cursor, if any (drawn see-through).
    pub poke: Option<usize>,
    /// Strain drawn in full colour (a round number near the largest strains).
    pub full_strain: f32,
}

/// Size of panel and overlay text (pixels).
pub const FONT: f32 = 18.0;

/// A world that stays in the xy-plane: every particle at z = 0 and at rest
/// along z, gravity and wind in the plane, floors facing along the plane.
pub fn is_flat(world: &World) -> bool {
    let particles = &world.particles;
    let in_plane = particles.position.iter().all(|p| p.z == 0.0)
        && particles.velocity.iter().all(|v| v.z == 0.0);
    let wind = world
        .forces
        .get::<Wind>()
        .is_none_or(|w| w.field.is_uniform() && w.field.velocity.z == 0.0);
    let colliders = world.colliders.iter().all(|c| match c.shape {
        Shape::Plane { normal, .. } => normal.z == 0.0,
        Shape::Sphere { centre, .. } => centre.z == 0.0,
    });
    in_plane && world.gravity().z == 0.0 && wind && colliders
}

/// The strain to draw in full colour: a round number (1, 2 or 5 × 10ⁿ,
/// from 0.1 % to 500 %) near the 90th percentile of the springs' |strain|, so that
/// the colours spread over the springs; it moves up at once and down only
/// when the strains have fallen well below it, so that it does not flicker.
pub fn full_strain(world: &World, current: f32, scratch: &mut Vec<f32>) -> f32 {
    let s = &world.springs;
    let x = &world.particles.position;
    scratch.clear();
    scratch.extend((0..s.len()).map(|k| {
        let length = (x[s.second()[k] as usize] - x[s.first()[k] as usize]).length();
        ((length / s.rest_length[k] - 1.0).abs()) as f32
    }));
    if scratch.is_empty() {
        return current;
    }
    let n = scratch.len() * 9 / 10;
    let (_, &mut p90, _) = scratch.select_nth_unstable_by(n, f32::total_cmp);
    if p90 > current || p90 < 0.3 * current {
        round_up(p90.clamp(0.001, 5.0))
    } else {
        current
    }
}

/// The smallest of 1, 2 or 5 × 10ⁿ at or above `value` (> 0).
fn round_up(value: f32) -> f32 {
    let decade = 10f32.powf(value.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&v| v >= value * 0.999)
        .unwrap_or(10.0 * decade)
}

/// The user's hand: a line from the grabbed particle to the cursor.
pub fn hand(particle: Vec2, cursor: Vec2) {
    draw_line(
        particle.x,
        particle.y,
        cursor.x,
        cursor.y,
        2.0,
        palette::HAND,
    );
    draw_circle_lines(particle.x, particle.y, 8.0, 2.5, palette::HAND);
    draw_circle(cursor.x, cursor.y, 3.5, palette::HAND);
}

/// A ring around the particle the cursor would grab.
pub fn hover(particle: Vec2) {
    draw_circle_lines(
        particle.x,
        particle.y,
        9.0,
        1.5,
        Color::new(1.0, 1.0, 1.0, 0.6),
    );
}

/// The strain colour scale (full colour at ±`full`), `width` pixels wide
/// at `(x, y)`.
pub fn legend(x: f32, y: f32, width: f32, full: f32) {
    let steps = 40;
    let w = width / steps as f32;
    for i in 0..steps {
        let t = 2.0 * (i as f32 + 0.5) / steps as f32 - 1.0;
        draw_rectangle(x + i as f32 * w, y, w + 0.5, 8.0, palette::strain(t, 1.0));
    }
    let label = |words: &str, at: f32| {
        text(
            words,
            at - 0.5 * text_width(words, 14.0),
            y + 22.0,
            14.0,
            palette::DIM,
        );
    };
    let full = percent(full);
    label(&format!("-{full}"), x + 8.0);
    label("strain", x + 0.5 * width);
    label(&format!("+{full}"), x + width - 8.0);
}

/// `fraction` as a percentage with as few digits as it needs.
fn percent(fraction: f32) -> String {
    let p = 100.0 * fraction;
    if p >= 1.0 {
        format!("{p:.0}%")
    } else {
        format!("{p:.1}%")
    }
}

/// Text at whole pixels (the pixel font blurs between them).
pub fn text(words: &str, x: f32, y: f32, size: f32, colour: Color) {
    draw_text(words, x.round(), y.round(), size.round(), colour);
}

/// Width of `words` in pixels at `size`.
pub fn text_width(words: &str, size: f32) -> f32 {
    measure_text(words, None, size.round() as u16, 1.0).width
}

/// A box in the middle of `viewport` with a title and wrapped text.
pub fn message(viewport: Rect, title: &str, body: &str, colour: Color) {
    let width = (viewport.w - 80.0).clamp(200.0, 720.0);
    let lines = wrap(body, width - 40.0, FONT);
    let height = 70.0 + lines.len() as f32 * (FONT + 4.0);
    let corner = viewport.center() - vec2(width, height) / 2.0;
    draw_rectangle(corner.x, corner.y, width, height, palette::PANEL);
    draw_rectangle(corner.x, corner.y, 4.0, height, colour);
    text(title, corner.x + 20.0, corner.y + 32.0, FONT + 6.0, colour);
    for (i, line) in lines.iter().enumerate() {
        let y = corner.y + 62.0 + i as f32 * (FONT + 4.0);
        text(line, corner.x + 20.0, y, FONT, palette::TEXT);
    }
}

/// Break `text` into lines no wider than `width` pixels.
pub fn wrap(text: &str, width: f32, font: f32) -> Vec<String> {
    let mut lines = Vec::new();
    for paragraph in text.lines() {
        let mut line = String::new();
        for word in paragraph.split(' ') {
            let candidate = if line.is_empty() {
                word.to_string()
            } else {
                format!("{line} {word}")
            };
            if !line.is_empty() && text_width(&candidate, font) > width {
                lines.push(std::mem::replace(&mut line, word.to_string()));
            } else {
                line = candidate;
            }
        }
        lines.push(line);
    }
    lines
}
