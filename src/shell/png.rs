//! Writing frames as PNG files.

use std::path::Path;

/// Why a PNG could not be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write '{path}': {reason}")]
pub struct PngError {
    /// The output path.
    pub path: String,
    /// The error.
    pub reason: String,
}

/// Writes `width * height` pixels of `0x00RRGGBB` as an 8-bit RGB PNG, replacing `path` atomically.
pub fn write_png(path: &Path, pixels: &[u32], width: usize, height: usize) -> Result<(), PngError> {
    let err = |reason: String| PngError { path: path.display().to_string(), reason };
    let n =
        width.checked_mul(height).filter(|&n| n <= pixels.len()).ok_or_else(|| err("frame size mismatch".into()))?;
    let mut rgb = Vec::with_capacity(n * 3);
    for &p in &pixels[..n] {
        rgb.extend_from_slice(&[(p >> 16) as u8, (p >> 8) as u8, p as u8]);
    }
    let w = u32::try_from(width).map_err(|e| err(e.to_string()))?;
    let h = u32::try_from(height).map_err(|e| err(e.to_string()))?;
    let mut png = Vec::new();
    image::write_buffer_with_format(
        &mut std::io::Cursor::new(&mut png),
        &rgb,
        w,
        h,
        image::ColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| err(e.to_string()))?;
    // Encoded in memory, then put in place whole: a failed write never leaves a truncated old file.
    crate::userfile::replace_atomically(path, &png).map_err(|e| err(e.to_string()))
}
