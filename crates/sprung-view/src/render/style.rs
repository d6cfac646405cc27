//! How pictures look: the palette, line widths, the light, strain colours.

use sprung::Real;

use super::strain::{Rgb, StrainColours};

/// The background.
pub const BACKGROUND: Rgb = [246, 246, 242];
/// Faces seen from outside (their counter-clockwise side).
pub const FRONT: Rgb = [126, 172, 224];
/// Faces seen from inside (the back of a cloth).
pub const BACK: Rgb = [232, 178, 112];
/// The faint fill of a closed 2D body.
pub const OUTLINE_FILL: Rgb = [214, 228, 243];
/// A floor (plane collider).
pub const FLOOR: Rgb = [226, 226, 220];
/// The floor's grid and its edge in 2D.
pub const FLOOR_LINE: Rgb = [196, 196, 188];
/// Sphere colliders.
pub const OBSTACLE: Rgb = [176, 176, 184];
/// The highlight of sphere colliders.
pub const OBSTACLE_LIGHT: Rgb = [226, 226, 232];
/// Pinned particles.
pub const PIN: Rgb = [30, 30, 40];
/// Particles that are on no face (ropes, rings, lattices).
pub const PARTICLE: Rgb = [52, 58, 72];
/// Opacity of springs drawn over faces (255 opaque), so the shading shows.
pub const SPRING_OVER_FACES_ALPHA: u8 = 170;
/// Face normals (`--normals`).
pub const NORMAL: Rgb = [150, 40, 170];
/// Rigid rods: dark steel, drawn thicker than springs.
pub const ROD: Rgb = [62, 66, 84];
/// The path of a traced particle (`--trace`).
pub const TRACE: Rgb = [200, 30, 120];

/// The fraction of a face's colour lit by ambient light alone.
pub const AMBIENT: Real = 0.45;

/// Drawing options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Style {
    /// Spring colours by strain.
    pub strain: StrainColours,
    /// Draw each face's normal (a short line from its centre).
    pub normals: bool,
    /// Draw every spring; by default a body with faces shows only the
    /// springs along its face edges (not its shear, bending or internal
    /// springs, which would hide the surface).
    pub all_springs: bool,
    /// Width of the springs (pixels).
    pub line_width: f32,
    /// Side of a pinned particle's square (pixels).
    pub pin_size: f32,
    /// Draw the path of this particle (index in the world) up to each
    /// picture.
    pub trace: Option<u32>,
}

impl Style {
    /// Defaults for a picture of `width` × `height` pixels: lines of 2 px
    /// at 800 × 600, thicker on larger pictures, never under 1 px.
    pub fn for_size(width: u32, height: u32) -> Self {
        let scale = (width.min(height) as f32 / 600.0).max(0.25);
        let line_width = (2.0 * scale).max(1.0);
        Style {
            strain: StrainColours::default(),
            normals: false,
            all_springs: false,
            line_width,
            pin_size: (3.0 * line_width + 2.0).round(),
            trace: None,
        }
    }
}

/// `colour` × `factor` per channel (factor in [0, 1]).
pub fn shade(colour: Rgb, factor: Real) -> Rgb {
    let f = factor.clamp(0.0, 1.0);
    colour.map(|c| (Real::from(c) * f).round() as u8)
}

/// The colour of a muscle of phase `phase` (rad): a hue around the colour
/// wheel (red at 0, green at 2π/3, blue at 4π/3), so muscles that beat
/// together share a colour.
pub fn phase_colour(phase: Real) -> Rgb {
    let turn = phase.rem_euclid(std::f64::consts::TAU) / std::f64::consts::TAU;
    let channel = |offset: Real| {
        let distance = ((turn - offset + 0.5).rem_euclid(1.0) - 0.5).abs();
        let level = (1.0 - 3.0 * distance).clamp(0.0, 1.0);
        (40.0 + 180.0 * level).round() as u8
    };
    [channel(0.0), channel(1.0 / 3.0), channel(2.0 / 3.0)]
}
