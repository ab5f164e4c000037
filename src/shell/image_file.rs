//! Writing frames as image files, in the format the file's extension names: PNG (`.png`) or JPEG
//! (`.jpg`, `.jpeg`, quality 90).
//!
//! Why the extension decides: a file called `x.jpg` that holds PNG bytes is mislabelled for every other
//! program, and a name with an extension no writer here knows (`.gif`, none at all) is refused before any
//! work ([`ImageFormat::of`]), naming the extensions accepted.

use std::path::{Path, PathBuf};

use crate::userfile::UserFileError;

/// The extensions an image output may have, as messages list them.
pub const ACCEPTED: &str = ".png, .jpg or .jpeg";

/// JPEG quality (1-100): high enough that a frame's edges and text stay clean.
const JPEG_QUALITY: u8 = 90;

/// An image file format the program writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// Lossless PNG, 8-bit RGB.
    Png,
    /// JPEG, 8-bit RGB at quality 90.
    Jpeg,
}

/// A path whose extension names no image format the program writes.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{}: {} (an image is written as {ACCEPTED})", path.display(), match extension {
    Some(e) => format!("unknown image extension '.{e}'"),
    None => "no file extension to choose the image format by".to_string(),
})]
pub struct UnknownImageFormat {
    /// The path as named.
    pub path: PathBuf,
    /// Its extension, if it has one.
    pub extension: Option<String>,
}

impl ImageFormat {
    /// The format `path`'s extension names (any letter case).
    pub fn of(path: &Path) -> Result<Self, UnknownImageFormat> {
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
        match ext.as_deref() {
            Some("png") => Ok(ImageFormat::Png),
            Some("jpg" | "jpeg") => Ok(ImageFormat::Jpeg),
            _ => Err(UnknownImageFormat { path: path.to_path_buf(), extension: ext }),
        }
    }
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum ImageFileError {
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
    /// A side longer than the format can have.
    #[error("cannot write '{path}': {side} pixels is too long a side for this image format")]
    TooLarge {
        /// The output path.
        path: PathBuf,
        /// The side.
        side: usize,
    },
    /// The path's extension names no format.
    #[error("cannot write {0}")]
    Format(#[from] UnknownImageFormat),
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

/// Writes `width * height` pixels of `0x00RRGGBB` to `path` in the format its extension names, replacing
/// it atomically.
pub fn write_image(path: &Path, pixels: &[u32], width: usize, height: usize) -> Result<(), ImageFileError> {
    let format = ImageFormat::of(path)?;
    let n = width.checked_mul(height).filter(|&n| n <= pixels.len()).ok_or_else(|| ImageFileError::SizeMismatch {
        path: path.to_path_buf(),
        width,
        height,
        pixels: pixels.len(),
    })?;
    let mut rgb = Vec::with_capacity(n * 3);
    for &p in &pixels[..n] {
        rgb.extend_from_slice(&[(p >> 16) as u8, (p >> 8) as u8, p as u8]);
    }
    let side =
        |side: usize| u32::try_from(side).map_err(|_| ImageFileError::TooLarge { path: path.to_path_buf(), side });
    let (w, h) = (side(width)?, side(height)?);
    let mut bytes = Vec::new();
    let encoded = match format {
        ImageFormat::Png => image::write_buffer_with_format(
            &mut std::io::Cursor::new(&mut bytes),
            &rgb,
            w,
            h,
            image::ColorType::Rgb8,
            image::ImageFormat::Png,
        ),
        ImageFormat::Jpeg => {
            if width > usize::from(u16::MAX) || height > usize::from(u16::MAX) {
                return Err(ImageFileError::TooLarge { path: path.to_path_buf(), side: width.max(height) });
            }
            let mut encoder = image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, JPEG_QUALITY);
            encoder.encode(&rgb, w, h, image::ExtendedColorType::Rgb8)
        }
    };
    encoded.map_err(|source| ImageFileError::Encode { path: path.to_path_buf(), source })?;
    // Encoded in memory, then put in place whole: a failed write never leaves a truncated old file.
    Ok(crate::userfile::replace_atomically(path, &bytes)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_extension_chooses_the_format_and_an_unknown_one_is_named() {
        let d = std::env::temp_dir().join(format!("image-file-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let pixels: Vec<u32> = (0..64 * 48u32).map(|i| i.wrapping_mul(2_654_435_761) & 0xff_ffff).collect();
        for (name, magic) in
            [("a.png", &b"\x89PNG"[..]), ("b.JPG", &[0xff, 0xd8, 0xff][..]), ("c.jpeg", &[0xff, 0xd8][..])]
        {
            write_image(&d.join(name), &pixels, 64, 48).unwrap();
            let bytes = std::fs::read(d.join(name)).unwrap();
            assert!(bytes.starts_with(magic), "{name}");
            let back = image::load_from_memory(&bytes).unwrap();
            assert_eq!((back.width(), back.height()), (64, 48), "{name}");
        }
        let e = write_image(&d.join("x.gif"), &pixels, 64, 48).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "cannot write {}: unknown image extension '.gif' (an image is written as .png, .jpg or .jpeg)",
                d.join("x.gif").display()
            )
        );
        assert!(!d.join("x.gif").exists());
        let e = ImageFormat::of(Path::new("frame")).unwrap_err();
        assert_eq!(
            e.to_string(),
            "frame: no file extension to choose the image format by (an image is written as .png, .jpg or .jpeg)"
        );
    }
}
