//! The project's measures (DESIGN.md): the supersampled reference image and error metrics against it.
//!
//! - Reference image: z-buffer, perspective-correct, the close-up LOD everywhere, 4x4 supersampled and
//!   box-filtered.
//! - Wrong pixels: the share of pixels whose colour differs by more than 8/255 in any channel.
//! - PSNR over the three colour channels.

use crate::render::{Camera, DrawList, Level, LodMode, Method, RenderError, RenderOptions, Renderer, TextureMode};

/// Supersampling factor per axis of the reference image.
pub const REFERENCE_SUPERSAMPLING: usize = 4;

/// Renders the reference image of a view: `zbuffer`, perspective-correct, close LOD, 4x4 box-filtered.
pub fn reference_frame(
    camera: &Camera,
    list: &DrawList<'_>,
    width: usize,
    height: usize,
    background: u32,
) -> Result<Vec<u32>, RenderError> {
    let s = REFERENCE_SUPERSAMPLING;
    let (bw, bh) = (width * s, height * s);
    let mut big = vec![0u32; bw * bh];
    let options = RenderOptions {
        method: Method::ZBuffer,
        texture_mode: TextureMode::Perspective,
        lod: LodMode::Force(Level::Close),
        background: Some(background),
        ..RenderOptions::default()
    };
    Renderer::new().render(&mut big, bw, bh, camera, list, &options)?;
    let mut out = vec![0u32; width * height];
    let n = (s * s) as u32;
    for y in 0..height {
        for x in 0..width {
            let mut acc = [0u32; 3];
            for yy in 0..s {
                let row = &big[(y * s + yy) * bw + x * s..(y * s + yy) * bw + x * s + s];
                for &p in row {
                    acc[0] += (p >> 16) & 0xff;
                    acc[1] += (p >> 8) & 0xff;
                    acc[2] += p & 0xff;
                }
            }
            let ch = |a: u32| (a + n / 2) / n;
            out[y * width + x] = (ch(acc[0]) << 16) | (ch(acc[1]) << 8) | ch(acc[2]);
        }
    }
    Ok(out)
}

/// Share (0-1) of pixels whose colour differs by more than 8/255 in any channel; 0 for empty or unequal
/// lengths beyond the shorter one.
#[must_use]
pub fn wrong_pixels(a: &[u32], b: &[u32]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return 0.0;
    }
    let wrong = a.iter().zip(b).filter(|(p, q)| channel_diff(**p, **q) > 8).count();
    wrong as f64 / n as f64
}

/// Largest per-channel difference between two `0x00RRGGBB` pixels.
#[must_use]
pub fn channel_diff(a: u32, b: u32) -> u32 {
    (0..3).map(|s| ((a >> (8 * s)) & 0xff).abs_diff((b >> (8 * s)) & 0xff)).max().unwrap_or(0)
}

/// Peak signal-to-noise ratio in dB over the RGB channels (infinite for identical images).
#[must_use]
pub fn psnr(a: &[u32], b: &[u32]) -> f64 {
    let n = a.len().min(b.len());
    if n == 0 {
        return f64::INFINITY;
    }
    let mut se = 0.0f64;
    for (p, q) in a.iter().zip(b) {
        for s in [0, 8, 16] {
            let d = f64::from((p >> s) & 0xff) - f64::from((q >> s) & 0xff);
            se += d * d;
        }
    }
    let mse = se / (3 * n) as f64;
    if mse == 0.0 { f64::INFINITY } else { 10.0 * (255.0 * 255.0 / mse).log10() }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn metrics() {
        let a = [0x000000u32, 0x101010, 0xffffff, 0x808080];
        let b = [0x000000u32, 0x101019, 0xfffff7, 0x808080];
        assert_eq!(wrong_pixels(&a, &b), 0.25);
        assert!(psnr(&a, &a).is_infinite());
        let p = psnr(&a, &b);
        assert!((p - 10.0 * (65025.0f64 / ((81.0 + 64.0) / 12.0)).log10()).abs() < 1e-9);
    }
}
