//! Writing frames as PNG files.

use std::path::{Path, PathBuf};

use crate::userfile::UserFileError;

/// Why a PNG could not be written.
#[derive(Debug, thiserror::Error)]
pub enum PngError {
    /// The frame holds fewer pixels than its width times its height.
    #[error("cannot write '{path}': frame size mismatch ({width}x{height} from {pixels} pixels)")]
    SizeMismatch {
        /// The output path.
        path: PathBuf,
        /// Frame width.
        width: usize,
        /// Frame height.
        height: usize,
        /// Pixels in the frame.
        pixels: usize,
    },
    /// A side longer than a PNG can have.
    #[error("cannot write '{path}': {side} pixels is too long a side for a PNG")]
    TooLarge {
        /// The output path.
        path: PathBuf,
        /// The side.
        side: usize,
    },
    /// The encoder failed.
    #[error("cannot write '{path}': {source}")]
    Encode {
        /// The output path.
        path: PathBuf,
        /// What the encoder reported.
        source: image::ImageError,
    },
    /// The file could not be replaced.
    #[error("cannot write {0}")]
    Write(#[from] UserFileError),
}

/// Writes `width * height` pixels of `0x00RRGGBB` as an 8-bit RGB PNG, replacing `path` atomically.
pub fn write_png(path: &Path, pixels: &[u32], width: usize, height: usize) -> Result<(), PngError> {
    let n = width.checked_mul(height).filter(|&n| n <= pixels.len()).ok_or_else(|| PngError::SizeMismatch {
        path: path.to_path_buf(),
        width,
        height,
        pixels: pixels.len(),
    })?;
    let mut rgb = Vec::with_capacity(n * 3);
    for &p in &pixels[..n] {
        rgb.extend_from_slice(&[(p >> 16) as u8, (p >> 8) as u8, p as u8]);
    }
    let side = |side: usize| u32::try_from(side).map_err(|_| PngError::TooLarge { path: path.to_path_buf(), side });
    let (w, h) = (side(width)?, side(height)?);
    let mut png = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut png),
        &rgb,
        w,
        h,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|source| PngError::Encode { path: path.to_path_buf(), source })?;
    // Encoded in memory, then put in place whole: a failed write never leaves a truncated old file.
    Ok(crate::userfile::replace_atomically(path, &png)?)
}
