//! The font of the plots: DejaVu Sans 2.37, bundled in the crate
//! (`fonts/DejaVuSans.ttf`, licence in `fonts/LICENSE`) and embedded in
//! the binary, so plotting needs no system font library.

use std::sync::OnceLock;

use super::PlotError;

/// The family name the bundled font is registered under with plotters.
pub const FONT_FAMILY: &str = "sprung-dejavu-sans";

/// The bundled TrueType font (DejaVu Sans).
pub static DEJAVU_SANS: &[u8] = include_bytes!("../../fonts/DejaVuSans.ttf");

/// Register the bundled font with plotters as [`FONT_FAMILY`] (once per
/// process; later calls only report the first call's outcome).
pub fn register() -> Result<(), PlotError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FONT_FAMILY, plotters::style::FontStyle::Normal, DEJAVU_SANS)
            .is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(PlotError::Draw("the bundled font cannot be read".into()))
    }
}
