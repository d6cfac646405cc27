//! # sprung-view: pictures of sprung runs
//!
//! Software rendering of a world or a finished run's frames to PNG and
//! animated GIF ([`render`]), and plots of a run's `diagnostics.csv`
//! ([`plot`]). Nothing here needs a GPU, a window or a system font.

pub mod plot;
pub mod render;
