//! Spring colours by strain `ε = (d - L0) / L0`: green at rest, blending
//! linearly to red as the spring stretches and to blue as it is
//! compressed, saturating at `±saturation`.

use sprung::Real;

/// An sRGB colour, 8 bits per channel.
pub type Rgb = [u8; 3];

/// The colour of a spring at rest.
pub const REST: Rgb = [34, 160, 72];
/// The colour of a spring stretched by `saturation` or more.
pub const STRETCHED: Rgb = [214, 39, 40];
/// The colour of a spring compressed by `saturation` or more.
pub const COMPRESSED: Rgb = [31, 90, 220];
/// The colour of a spring whose rest length is unknown (frames written
/// before they carried `rest_length`).
pub const UNKNOWN: Rgb = [110, 110, 118];

/// The default strain at which colours saturate: 0.1 (10 %).
pub const DEFAULT_SATURATION: Real = 0.1;

/// Maps a spring's strain to its colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrainColours {
    /// The strain (no unit: 0.1 is 10 %) at which the colour is fully red
    /// (stretched) or fully blue (compressed); positive and finite.
    pub saturation: Real,
}

impl Default for StrainColours {
    fn default() -> Self {
        StrainColours {
            saturation: DEFAULT_SATURATION,
        }
    }
}

impl StrainColours {
    /// Colours saturating at `saturation` (no unit, e.g. 0.1 for 10 %);
    /// `None` unless it is positive and finite.
    pub fn new(saturation: Real) -> Option<Self> {
        (saturation.is_finite() && saturation > 0.0).then_some(StrainColours { saturation })
    }

    /// The strain `(length - rest_length) / rest_length` of a spring of
    /// current `length` (m) and `rest_length` (m); NaN when the rest length
    /// is unknown (NaN) or not positive.
    pub fn strain(length: Real, rest_length: Real) -> Real {
        if rest_length > 0.0 {
            (length - rest_length) / rest_length
        } else {
            Real::NAN
        }
    }

    /// The colour of strain `strain` (no unit): [`REST`] at 0, a linear
    /// blend towards [`STRETCHED`] (positive) or [`COMPRESSED`] (negative)
    /// reaching it at `±saturation`; [`UNKNOWN`] for NaN.
    pub fn colour(&self, strain: Real) -> Rgb {
        if strain.is_nan() {
            return UNKNOWN;
        }
        let t = (strain / self.saturation).clamp(-1.0, 1.0);
        if t >= 0.0 {
            blend(REST, STRETCHED, t)
        } else {
            blend(REST, COMPRESSED, -t)
        }
    }
}

/// `a + t (b - a)` per channel, `t` in [0, 1], rounded.
pub fn blend(a: Rgb, b: Rgb, t: Real) -> Rgb {
    let mix = |x: u8, y: u8| (Real::from(x) + t * (Real::from(y) - Real::from(x))).round() as u8;
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2])]
}
