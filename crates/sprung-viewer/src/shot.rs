//! `--screenshot`: the frame just drawn, saved as a PNG.

use std::path::Path;

use macroquad::texture::get_screen_data;

/// Save what has been drawn this frame to `path` (PNG), opaque.
pub fn save(path: &Path) -> Result<(), String> {
    let screen = get_screen_data();
    let (width, height) = (u32::from(screen.width), u32::from(screen.height));
    let row = width as usize * 4;
    // OpenGL's rows run bottom to top; a PNG's top to bottom.
    let mut pixels: Vec<u8> = screen
        .bytes
        .chunks_exact(row)
        .rev()
        .flatten()
        .copied()
        .collect();
    for pixel in pixels.chunks_exact_mut(4) {
        pixel[3] = 255;
    }
    image::save_buffer_with_format(
        path,
        &pixels,
        width,
        height,
        image::ColorType::Rgba8,
        image::ImageFormat::Png,
    )
    .map_err(|e| format!("cannot write the screenshot {}: {e}", path.display()))
}
