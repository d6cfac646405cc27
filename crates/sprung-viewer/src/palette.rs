//! Colours: bodies, strain, background and the panel.

use macroquad::color::Color;

/// Behind everything.
pub const BACKGROUND: Color = rgb(0x16, 0x1a, 0x21);
/// The solid side of a floor or wall.
pub const GROUND: Color = rgb(0x25, 0x2b, 0x35);
/// Grid lines and the edge of the ground.
pub const GRID: Color = rgb(0x3a, 0x44, 0x53);
/// The surface line of a floor in 2D.
pub const GROUND_EDGE: Color = rgb(0x8a, 0x9b, 0xb0);
/// Pinned particles.
pub const PINNED: Color = rgb(0xf2, 0xc0, 0x4b);
/// The grabbed particle and the hand's spring.
pub const HAND: Color = rgb(0x5e, 0xe0, 0xff);
/// Rigid rods: light steel, drawn thicker than springs.
pub const ROD: Color = rgb(0xe6, 0xe9, 0xee);
/// Panel text.
pub const TEXT: Color = rgb(0xdc, 0xe3, 0xec);
/// Quieter panel text.
pub const DIM: Color = rgb(0x8b, 0x97, 0xa8);
/// Warnings and errors.
pub const ERROR: Color = rgb(0xff, 0x6b, 0x6b);
/// Panel background.
pub const PANEL: Color = Color::new(0.09, 0.105, 0.13, 0.92);
/// Controls at rest.
pub const CONTROL: Color = rgb(0x2c, 0x34, 0x41);
/// Controls under the cursor.
pub const CONTROL_HOT: Color = rgb(0x3b, 0x46, 0x58);
/// The filled part of sliders, active toggles.
pub const ACCENT: Color = rgb(0x3d, 0x8b, 0xd9);

const BODIES: [Color; 6] = [
    rgb(0xf0, 0x7f, 0x5e),
    rgb(0x4f, 0xc1, 0xa6),
    rgb(0x6d, 0x9e, 0xeb),
    rgb(0xe8, 0xb6, 0x4c),
    rgb(0xb0, 0x84, 0xe0),
    rgb(0xe0, 0x6f, 0xa8),
];

const fn rgb(r: u8, g: u8, b: u8) -> Color {
    Color::new(r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0)
}

/// The colour of body number `index`.
pub fn body(index: usize) -> Color {
    BODIES[index % BODIES.len()]
}

/// A spring's colour from its strain `(l - l0) / l0`: blue compressed,
/// pale grey at rest, red stretched, full at ±`full`.
pub fn strain(strain: f32, full: f32) -> Color {
    let neutral = rgb(0xd8, 0xdd, 0xe4);
    let t = (strain / full).clamp(-1.0, 1.0);
    let end = if t < 0.0 {
        rgb(0x3a, 0x7b, 0xff)
    } else {
        rgb(0xff, 0x3b, 0x30)
    };
    mix(neutral, end, t.abs())
}

/// `a` to `b` by `t` in [0, 1].
pub fn mix(a: Color, b: Color, t: f32) -> Color {
    Color::new(
        a.r + (b.r - a.r) * t,
        a.g + (b.g - a.g) * t,
        a.b + (b.b - a.b) * t,
        a.a + (b.a - a.a) * t,
    )
}

/// `c` with its brightness times `factor` and alpha `alpha`.
pub fn shade(c: Color, factor: f32, alpha: f32) -> Color {
    Color::new(c.r * factor, c.g * factor, c.b * factor, alpha)
}

/// A muscle's colour from its phase (rad): a hue around the colour wheel,
/// so muscles that beat together share a colour.
pub fn muscle(phase: f64) -> Color {
    let turn = (phase.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU) as f32;
    let channel = |offset: f32| {
        let distance = ((turn - offset + 0.5).rem_euclid(1.0) - 0.5).abs();
        0.2 + 0.75 * (1.0 - 3.0 * distance).clamp(0.0, 1.0)
    };
    Color::new(channel(0.0), channel(1.0 / 3.0), channel(2.0 / 3.0), 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strain_runs_blue_to_grey_to_red() {
        let compressed = strain(-0.1, 0.05);
        let stretched = strain(0.05, 0.05);
        assert!(compressed.b > compressed.r);
        assert!(stretched.r > stretched.b);
        assert!((strain(0.0, 0.05).r - strain(0.0, 0.05).b).abs() < 0.1);
    }
}
