//! Value parsers for the command-line flags that have a range: a value out of range is bad usage, which
//! clap reports in one line with exit status 2, before any file is read.
//!
//! Why here: the ranges were checked inside each command and reported with exit status 1, contrary to the
//! documented contract (bad usage exits 2), and each command had its own copy.

use std::path::PathBuf;

use clap::builder::{RangedI64ValueParser, RangedU64ValueParser};
use thiserror::Error;

/// Largest frame or window side, in pixels, any command accepts.
pub const MAX_SIDE: u64 = 16384;
/// Largest frame side of the bench's main sweep (it draws every configuration at that size).
pub const MAX_BENCH_SIDE: u64 = 8192;
/// Most laps a race may have (as a trace header may hold).
pub const MAX_LAPS: i64 = 99;
/// Most ordering-table buckets.
pub const MAX_BUCKETS: u64 = 1 << 20;
/// Most times `render --repeat` draws the frame.
pub const MAX_REPEAT: u64 = 100_000;
/// Largest LOD bias either way.
pub const MAX_LOD_BIAS: f32 = 16.0;
/// Most renderer worker threads `--threads` may ask for (the renderer's own ceiling).
pub const MAX_THREADS: u64 = crate::render::MAX_THREADS as u64;

/// A frame or window side in pixels (1 to `max`).
#[must_use]
pub fn side(max: u64) -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::new().range(1..=max)
}

/// The same for `u32` sides (the window).
#[must_use]
pub fn window_side() -> RangedI64ValueParser<u32> {
    RangedI64ValueParser::new().range(1..=MAX_SIDE as i64)
}

/// A count of at least 1 and at most `max`.
#[must_use]
pub fn count(max: u64) -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::new().range(1..=max)
}

/// A worker thread count: 0 (the cores available) to [`MAX_THREADS`].
#[must_use]
pub fn threads() -> RangedU64ValueParser<usize> {
    RangedU64ValueParser::new().range(0..=MAX_THREADS)
}

/// The window's pixel scale, in the one range the `-`/`=` keys, Settings and the settings file share.
#[must_use]
pub fn scale() -> RangedI64ValueParser<u32> {
    use crate::shell::window::{MAX_SCALE, MIN_SCALE};
    RangedI64ValueParser::new().range(i64::from(MIN_SCALE)..=i64::from(MAX_SCALE))
}

/// A flag value that does not parse as what it should be.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum ValueError {
    /// `--background` is not three numbers 0-255.
    #[error("expected R,G,B with each 0-255")]
    Rgb,
    /// `--fps` is not a number of frames a second the window paces to.
    #[error("expected a number of frames a second from 20 to 1000")]
    Fps,
    /// `--lod-bias` is not a finite number within the bound.
    #[error("expected a number from -16 to 16")]
    LodBias,
    /// `--mip-bias` is not a finite number within the bound.
    #[error("expected a number from -4 to 4")]
    MipBias,
    /// An output file's extension names no format the flag writes.
    #[error("{} (accepted: {accepted})", match found {
        Some(e) => format!("unknown extension '.{e}'"),
        None => "no extension to choose the format by".to_string(),
    })]
    Extension {
        /// The extension given, if any.
        found: Option<String>,
        /// The extensions accepted, as the message lists them.
        accepted: &'static str,
    },
    /// `--mode` names no mode.
    #[error("expected race or time-trial")]
    Mode,
    /// `--difficulty` names no difficulty.
    #[error("expected easy, normal or hard")]
    Difficulty,
    /// `--course` is not a plain folder name.
    #[error(
        "a course is named by its folder: lower-case letters, digits, '-' and '_' (`scanline-racer courses` lists them)"
    )]
    Course,
}

/// A mode (`play --mode`): race or time-trial.
pub fn mode(s: &str) -> Result<crate::game::Mode, ValueError> {
    crate::game::Mode::from_name(s).ok_or(ValueError::Mode)
}

/// A difficulty (`play --difficulty`): easy, normal or hard.
pub fn difficulty(s: &str) -> Result<crate::game::Difficulty, ValueError> {
    crate::game::Difficulty::from_name(s).ok_or(ValueError::Difficulty)
}

/// A course's name (`play --course`): a plain folder name; whether the assets hold it is checked when they
/// are loaded, where the message can list the courses there are.
pub fn course_name(s: &str) -> Result<String, ValueError> {
    if crate::shell::course::is_course_name(s) { Ok(s.to_string()) } else { Err(ValueError::Course) }
}

/// `path` when its extension (any letter case) is one of `allowed`.
fn with_extension(path: PathBuf, allowed: &[&str], accepted: &'static str) -> Result<PathBuf, ValueError> {
    let found = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase());
    match &found {
        Some(e) if allowed.contains(&e.as_str()) => Ok(path),
        _ => Err(ValueError::Extension { found, accepted }),
    }
}

/// The extensions of an image output: PNG or JPEG.
fn image_extension(path: PathBuf) -> Result<PathBuf, ValueError> {
    let path = with_extension(path, &["png", "jpg", "jpeg"], crate::shell::image_file::ACCEPTED)?;
    debug_assert!(crate::shell::image_file::ImageFormat::of(&path).is_ok(), "the writer takes what is accepted");
    Ok(path)
}

/// A path flag's value as the system gives it (any bytes, not only UTF-8), checked by `check`.
fn output_path(
    check: fn(PathBuf) -> Result<PathBuf, ValueError>,
) -> impl clap::builder::TypedValueParser<Value = PathBuf> {
    use clap::builder::TypedValueParser;
    clap::builder::OsStringValueParser::new().try_map(move |s| check(PathBuf::from(s)))
}

/// An image output (`render --out`, `play --screenshot`): PNG or JPEG, by its extension.
#[must_use]
pub fn image_path() -> impl clap::builder::TypedValueParser<Value = PathBuf> {
    output_path(image_extension)
}

/// A GLB output (`export-frame --out`).
#[must_use]
pub fn glb_path() -> impl clap::builder::TypedValueParser<Value = PathBuf> {
    output_path(|p| with_extension(p, &["glb"], ".glb"))
}

/// A WAV output (`replay --audio`).
#[must_use]
pub fn wav_path() -> impl clap::builder::TypedValueParser<Value = PathBuf> {
    output_path(|p| with_extension(p, &["wav"], ".wav"))
}

/// Parses `R,G,B` (each 0-255) into `0x00RRGGBB`.
pub fn parse_rgb(s: &str) -> Result<u32, ValueError> {
    let parts: Vec<&str> = s.split(',').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(ValueError::Rgb);
    }
    let mut rgb = 0u32;
    for p in parts {
        let v: u8 = p.parse().map_err(|_| ValueError::Rgb)?;
        rgb = (rgb << 8) | u32::from(v);
    }
    Ok(rgb)
}

/// Parses a LOD bias: finite, from -16 to 16.
pub fn parse_lod_bias(s: &str) -> Result<f32, ValueError> {
    let v: f32 = s.trim().parse().map_err(|_| ValueError::LodBias)?;
    if v.is_finite() && v.abs() <= MAX_LOD_BIAS { Ok(v) } else { Err(ValueError::LodBias) }
}

/// The largest mip bias `--mip-bias` takes either way (four levels: a texel 16 times larger or smaller).
pub const MAX_MIP_BIAS: f32 = 4.0;

/// Parses a mip bias: finite, from -4 to 4.
pub fn parse_mip_bias(s: &str) -> Result<f32, ValueError> {
    let v: f32 = s.trim().parse().map_err(|_| ValueError::MipBias)?;
    if v.is_finite() && v.abs() <= MAX_MIP_BIAS { Ok(v) } else { Err(ValueError::MipBias) }
}

/// Parses a frame rate (`play --fps`): 20 to 1000 frames a second.
pub fn parse_fps(s: &str) -> Result<f64, ValueError> {
    let v: f64 = s.trim().parse().map_err(|_| ValueError::Fps)?;
    if crate::shell::pacing::RATES.contains(&v) { Ok(v) } else { Err(ValueError::Fps) }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_and_biases_parse_only_in_range() {
        assert_eq!(parse_rgb("1, 2,3"), Ok(0x010203));
        assert_eq!(parse_fps("30"), Ok(30.0));
        for bad in ["0", "19.9", "1001", "NaN", "inf", "fast"] {
            assert_eq!(parse_fps(bad), Err(ValueError::Fps), "{bad}");
        }
        for bad in ["256,0,0", "1,2", "1,2,3,4", "-1,0,0", "a,b,c", ""] {
            assert_eq!(parse_rgb(bad), Err(ValueError::Rgb), "{bad}");
        }
        assert_eq!(parse_lod_bias("-16"), Ok(-16.0));
        for bad in ["16.5", "NaN", "inf", "x"] {
            assert_eq!(parse_lod_bias(bad), Err(ValueError::LodBias), "{bad}");
        }
        assert_eq!(parse_mip_bias("-0.5"), Ok(-0.5));
        for bad in ["4.5", "-5", "NaN", "-inf", ""] {
            assert_eq!(parse_mip_bias(bad), Err(ValueError::MipBias), "{bad}");
        }
    }

    #[test]
    fn outputs_are_named_by_an_extension_their_writer_knows() {
        let image = |s: &str| image_extension(PathBuf::from(s));
        assert_eq!(image("a/b.PNG"), Ok(PathBuf::from("a/b.PNG")));
        assert_eq!(image("shot.jpeg"), Ok(PathBuf::from("shot.jpeg")));
        assert_eq!(image("x.gif").unwrap_err().to_string(), "unknown extension '.gif' (accepted: .png, .jpg or .jpeg)");
        assert_eq!(
            image("frame").unwrap_err().to_string(),
            "no extension to choose the format by (accepted: .png, .jpg or .jpeg)"
        );
        // Through clap, as the flags take them: a name that is not UTF-8 is a name like any other.
        use clap::builder::TypedValueParser;
        let cmd = clap::Command::new("test");
        #[cfg(unix)]
        {
            let odd = std::os::unix::ffi::OsStrExt::from_bytes(b"not \xff utf-8.png");
            assert_eq!(image_path().parse_ref(&cmd, None, odd).unwrap(), PathBuf::from(odd));
        }
        let parse = |p: &dyn Fn(&std::ffi::OsStr) -> bool, s: &str| p(std::ffi::OsStr::new(s));
        let glb = |s: &std::ffi::OsStr| glb_path().parse_ref(&cmd, None, s).is_ok();
        let wav = |s: &std::ffi::OsStr| wav_path().parse_ref(&cmd, None, s).is_ok();
        assert!(parse(&glb, "f.glb") && !parse(&glb, "f.gltf"));
        assert!(parse(&wav, "r.WAV") && !parse(&wav, "r.mp3"));
    }
}
