//! The animated GIF: one frame per picture, each with its own 256-colour
//! palette (NeuQuant quantisation, deterministic), looping forever.

use std::io::Write;
use std::path::{Path, PathBuf};

use sprung::Real;
use sprung_io::export::AtomicFile;

use super::image::Image;
use super::RenderError;

/// NeuQuant sampling factor (1 best, 30 fastest): 10 is the usual balance.
const QUANTISER_SPEED: i32 = 10;

/// The shortest frame delay viewers honour (1/100 s); shorter ones are
/// shown at 1/10 s by most browsers.
pub const MIN_DELAY_CENTISECONDS: u16 = 2;

/// An animated GIF being written to its file (complete or not at all), or
/// to memory ([`GifWriter::in_memory`]).
pub struct GifWriter<W: Write = AtomicFile> {
    encoder: gif::Encoder<W>,
    path: PathBuf,
    width: u16,
    height: u16,
    frames: usize,
}

impl<W: Write> std::fmt::Debug for GifWriter<W> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GifWriter")
            .field("path", &self.path)
            .field("frames", &self.frames)
            .finish()
    }
}

/// The GIF delay (1/100 s) for `seconds` (s) between pictures: rounded,
/// at least [`MIN_DELAY_CENTISECONDS`].
pub fn delay_centiseconds(seconds: Real) -> u16 {
    let cs = (seconds * 100.0).round();
    if cs.is_finite() {
        cs.clamp(Real::from(MIN_DELAY_CENTISECONDS), Real::from(u16::MAX)) as u16
    } else {
        MIN_DELAY_CENTISECONDS
    }
}

impl GifWriter {
    /// Start the GIF `path` for pictures of `width` × `height` pixels
    /// (each at most 65535).
    pub fn create(path: &Path, width: u32, height: u32) -> Result<Self, RenderError> {
        let file = AtomicFile::create(path).map_err(|e| RenderError::io(path, e))?;
        GifWriter::start(file, path, width, height)
    }

    /// Finish the file and move it into place; returns its path.
    pub fn finish(self) -> Result<PathBuf, RenderError> {
        let path = self.path;
        let file = self
            .encoder
            .into_inner()
            .map_err(|e| RenderError::Encode(format!("{}: {e}", path.display())))?;
        file.commit().map_err(|e| RenderError::io(&path, e))?;
        Ok(path)
    }
}

impl GifWriter<Vec<u8>> {
    /// A GIF of `width` × `height` pixels gathered in memory.
    pub fn in_memory(width: u32, height: u32) -> Result<Self, RenderError> {
        GifWriter::start(Vec::new(), Path::new("the GIF"), width, height)
    }

    /// The finished GIF's bytes.
    pub fn into_bytes(self) -> Result<Vec<u8>, RenderError> {
        self.encoder
            .into_inner()
            .map_err(|e| RenderError::Encode(format!("the GIF: {e}")))
    }
}

impl<W: Write> GifWriter<W> {
    /// Start a GIF into `sink`, named `path` in messages.
    fn start(sink: W, path: &Path, width: u32, height: u32) -> Result<Self, RenderError> {
        let (Ok(w), Ok(h)) = (u16::try_from(width), u16::try_from(height)) else {
            return Err(RenderError::BadSize(format!(
                "{width}×{height} is too large for a GIF (65535 at most)"
            )));
        };
        let fail = |e: gif::EncodingError| RenderError::Encode(format!("{}: {e}", path.display()));
        let mut encoder = gif::Encoder::new(sink, w, h, &[]).map_err(fail)?;
        encoder.set_repeat(gif::Repeat::Infinite).map_err(fail)?;
        Ok(GifWriter {
            encoder,
            path: path.to_path_buf(),
            width: w,
            height: h,
            frames: 0,
        })
    }

    /// Add `image` (of the size given at creation) shown for `delay`
    /// hundredths of a second.
    pub fn push(&mut self, image: &Image, delay: u16) -> Result<(), RenderError> {
        if image.width() != u32::from(self.width) || image.height() != u32::from(self.height) {
            return Err(RenderError::BadSize(format!(
                "a {}×{} picture in a {}×{} GIF",
                image.width(),
                image.height(),
                self.width,
                self.height
            )));
        }
        let mut frame =
            gif::Frame::from_rgb_speed(self.width, self.height, image.rgb(), QUANTISER_SPEED);
        frame.delay = delay;
        self.encoder
            .write_frame(&frame)
            .map_err(|e| RenderError::Encode(format!("{}: {e}", self.path.display())))?;
        self.frames += 1;
        Ok(())
    }
}
