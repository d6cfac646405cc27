//! PNG encoding of an RGB buffer, with fixed settings so that the same
//! pixels always give the same bytes.

use super::PlotError;

/// Encode `rgb` (8-bit RGB, row by row, `width` × `height` pixels) as PNG.
pub(crate) fn png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, PlotError> {
    let fail = |e: png::EncodingError| PlotError::Draw(format!("PNG encoding: {e}"));
    let mut bytes = Vec::new();
    let mut encoder = png::Encoder::new(&mut bytes, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Balanced);
    let mut writer = encoder.write_header().map_err(fail)?;
    writer.write_image_data(rgb).map_err(fail)?;
    writer.finish().map_err(fail)?;
    Ok(bytes)
}

/// Average `factor` × `factor` blocks of `rgb` (`width` × `height` pixels):
/// drawing at a multiple of the size and shrinking smooths the edges of
/// lines (the drawing library does not anti-alias them).
pub(crate) fn shrink(rgb: &[u8], width: usize, height: usize, factor: usize) -> Vec<u8> {
    let (w, h) = (width / factor, height / factor);
    let mut out = vec![0u8; w * h * 3];
    let area = (factor * factor) as u32;
    for y in 0..h {
        for x in 0..w {
            for c in 0..3 {
                let mut sum = 0u32;
                for dy in 0..factor {
                    let row = (y * factor + dy) * width;
                    for dx in 0..factor {
                        sum += u32::from(rgb[(row + x * factor + dx) * 3 + c]);
                    }
                }
                out[(y * w + x) * 3 + c] = ((sum + area / 2) / area) as u8;
            }
        }
    }
    out
}
