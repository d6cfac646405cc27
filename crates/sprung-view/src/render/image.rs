//! A finished picture: 8-bit sRGB pixels, row after row from the top left,
//! and its PNG encoding.

use super::RenderError;

/// An opaque RGB picture.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Image {
    width: u32,
    height: u32,
    rgb: Vec<u8>,
}

impl Image {
    /// A picture of `width` × `height` pixels from `rgb` (3 bytes per pixel,
    /// rows from the top); `None` when the length does not match.
    pub fn from_rgb(width: u32, height: u32, rgb: Vec<u8>) -> Option<Self> {
        let expected = (width as usize)
            .checked_mul(height as usize)?
            .checked_mul(3)?;
        (rgb.len() == expected).then_some(Image { width, height, rgb })
    }

    /// A picture from a canvas, whose pixel count is right by construction.
    pub(super) fn from_canvas(width: u32, height: u32, rgb: Vec<u8>) -> Self {
        debug_assert_eq!(rgb.len(), 3 * width as usize * height as usize);
        Image { width, height, rgb }
    }

    /// Width (pixels).
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height (pixels).
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The pixels: 3 bytes (red, green, blue) each, rows from the top.
    pub fn rgb(&self) -> &[u8] {
        &self.rgb
    }

    /// The colour of pixel (`x`, `y`), `x` from the left and `y` from the
    /// top (pixels); `None` outside the picture.
    pub fn pixel(&self, x: u32, y: u32) -> Option<[u8; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let i = 3 * (y as usize * self.width as usize + x as usize);
        Some([self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]])
    }

    /// The picture as a PNG file (8-bit RGB, no time stamp or other
    /// metadata, so equal pictures give equal bytes).
    pub fn encode_png(&self) -> Result<Vec<u8>, RenderError> {
        let mut bytes = Vec::new();
        let fail = |e: png::EncodingError| RenderError::Encode(format!("PNG: {e}"));
        let mut encoder = png::Encoder::new(&mut bytes, self.width, self.height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_compression(png::Compression::Balanced);
        let mut writer = encoder.write_header().map_err(fail)?;
        writer.write_image_data(&self.rgb).map_err(fail)?;
        writer.finish().map_err(fail)?;
        Ok(bytes)
    }
}
