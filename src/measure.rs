//! The project's measures (DESIGN.md): the supersampled reference image and error metrics against it.
//!
//! - Reference image: z-buffer, perspective-correct, the close-up LOD everywhere, nearest texels of level 0
//!   (no mip-maps, no anti-aliasing: the samples themselves are the filter), 64x64 samples a pixel on a
//!   regular grid, box-filtered: a grid fine enough that doubling it changes the image by at most 0.0021
//!   FLIP mean on the bench's frames (it has converged, to the 8-bit rounding of its channels; 4x4 had
//!   not, and an isotropic texture filter never does: it blurs surfaces seen at a grazing angle).
//! - Wrong pixels: the share of pixels whose colour differs by more than 8/255 in any channel.
//! - PSNR over the three colour channels.
//! - Shimmer (temporal stability) over consecutive frames: how much more (or less) each frame changes from
//!   the one before than the reference does, as an RMS and as the share of shimmering pixels.
//! - FLIP (NVIDIA's perceptual difference, LDR), mean and 99th percentile of its per-pixel error map, at
//!   the viewing condition `nv_flip::DEFAULT_PIXELS_PER_DEGREE` (a 0.7 m wide monitor of 3840 px at 0.7 m).

use crate::render::{
    Antialias, Camera, DrawList, Filter, Level, LodMode, Method, MipMode, RenderError, RenderOptions, Renderer,
    TextureMode,
};

/// Samples per axis of a pixel in the reference image: 64 x 64 nearest samples on a regular grid.
///
/// Chosen by convergence (DESIGN.md: at most 0.003 FLIP mean and 1 shimmer unit between N and 2N): on
/// the bench's frames of every course the reference at this grid and at twice it differ by 0.0015-0.0021
/// FLIP mean (0.19-0.21 shimmer), most of it one-step rounding of the 8-bit channels (docs/performance.md,
/// "The reference"); 32 x 32 against 64 x 64 differs by 0.0023-0.0034, over the line on the street course.
pub const REFERENCE_GRID: usize = 64;

/// The finest grid [`reference_frame_at`] draws (at 16 times the frame's size, shifted 8 x 8 times): for
/// measuring the convergence of [`REFERENCE_GRID`] one and two doublings up.
pub const MAX_REFERENCE_GRID: usize = 128;

/// Renders the reference image of a view at [`REFERENCE_GRID`] samples per axis of a pixel.
pub fn reference_frame(
    camera: &Camera,
    list: &DrawList<'_>,
    width: usize,
    height: usize,
    background: u32,
) -> Result<Vec<u32>, RenderError> {
    reference_frame_at(camera, list, (width, height), background, REFERENCE_GRID)
}

/// Renders the reference image of a view with `grid` x `grid` samples a pixel (`grid` taken up to a power
/// of two, at most [`MAX_REFERENCE_GRID`]): `zbuffer`, perspective-correct, close LOD, nearest texels of
/// level 0, the samples box-filtered (each channel the rounded mean).
///
/// The samples sit on a regular grid, at `(i + 0.5) / grid` of the pixel for `i` in `0..grid`. They are
/// drawn as an image `s` times the size (`s` = `grid` up to 4, `grid / 8` above 32) drawn `p^2` times
/// (`p = grid / s`, at most 8), each time shifted by `(k + 0.5) / p - 0.5` of one of its pixels
/// ([`RenderOptions::pixel_offset`]). Those shifts are whole steps of the fill's 1/16 pixel (`Fx28_4`) for
/// every `p` up to 8, so every sample of the grid is a distinct position, not one rounded onto another.
pub fn reference_frame_at(
    camera: &Camera,
    list: &DrawList<'_>,
    (width, height): (usize, usize),
    background: u32,
    grid: usize,
) -> Result<Vec<u32>, RenderError> {
    let grid = grid.clamp(1, MAX_REFERENCE_GRID).next_power_of_two();
    let scale = grid.min(4).max(grid / 8);
    let passes = grid / scale;
    debug_assert!(passes <= 8 && passes * scale == grid);
    let (bw, bh) = (width * scale, height * scale);
    let mut big = vec![0u32; bw * bh];
    let mut sums = vec![[0u32; 3]; width * height];
    let mut renderer = Renderer::new();
    let step = |k: usize| (k as f32 + 0.5) / passes as f32 - 0.5;
    for j in 0..passes {
        for i in 0..passes {
            let options = RenderOptions {
                method: Method::ZBuffer,
                texture_mode: TextureMode::Perspective,
                lod: LodMode::Force(Level::Close),
                filter: Filter::Nearest,
                mip: MipMode::Off,
                antialias: Antialias::Off,
                background: Some(background),
                // The image moves by +offset, so a pixel is sampled at its centre minus the offset.
                pixel_offset: [-step(i), -step(j)],
                ..RenderOptions::default()
            };
            renderer.render(&mut big, bw, bh, camera, list, &options)?;
            accumulate(&big, bw, scale, &mut sums, width);
        }
    }
    let n = (grid * grid) as u32;
    let ch = |a: u32| (a + n / 2) / n;
    Ok(sums.iter().map(|[r, g, b]| (ch(*r) << 16) | (ch(*g) << 8) | ch(*b)).collect())
}

/// Adds each `scale` x `scale` block of `big` (`bw` pixels a row) to the channel sums of its pixel in
/// `sums` (`width` a row).
fn accumulate(big: &[u32], bw: usize, scale: usize, sums: &mut [[u32; 3]], width: usize) {
    if width == 0 || bw == 0 {
        return;
    }
    for (y, out) in sums.chunks_exact_mut(width).enumerate() {
        for row in big.chunks_exact(bw).skip(y * scale).take(scale) {
            for (sum, block) in out.iter_mut().zip(row.chunks_exact(scale)) {
                for &p in block {
                    sum[0] += (p >> 16) & 0xff;
                    sum[1] += (p >> 8) & 0xff;
                    sum[2] += p & 0xff;
                }
            }
        }
    }
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
    if mse == 0.0 { f64::INFINITY } else { 10.0 * libm::log10(255.0 * 255.0 / mse) }
}

/// FLIP statistics of a test image against a reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Flip {
    /// Mean FLIP error, 0 (identical) to 1.
    pub mean: f32,
    /// 99th percentile of the per-pixel error.
    pub p99: f32,
    /// The per-pixel error map, 0-1, row-major.
    pub map: Vec<f32>,
}

impl Flip {
    /// Share (0-1) of pixels whose FLIP error is above `threshold`.
    #[must_use]
    pub fn share_above(&self, threshold: f32) -> f64 {
        if self.map.is_empty() {
            return 0.0;
        }
        self.map.iter().filter(|e| **e > threshold).count() as f64 / self.map.len() as f64
    }

    /// The error map as a picture (FLIP's magma colour map), `0x00RRGGBB` pixels.
    #[must_use]
    pub fn magma(&self, width: usize, height: usize) -> Vec<u32> {
        let img = nv_flip::FlipImageFloat::with_data(width as u32, height as u32, &self.map);
        let rgb = img.apply_color_lut(&nv_flip::magma_lut()).to_vec();
        rgb.chunks_exact(3).map(|c| (u32::from(c[0]) << 16) | (u32::from(c[1]) << 8) | u32::from(c[2])).collect()
    }
}

/// FLIP of `test` against `reference` (`0x00RRGGBB`, `width` x `height`); `None` when the sizes disagree
/// with the slices or an image is empty.
#[must_use]
pub fn flip(reference: &[u32], test: &[u32], width: usize, height: usize) -> Option<Flip> {
    let n = width.checked_mul(height)?;
    if n == 0 || reference.len() != n || test.len() != n {
        return None;
    }
    let rgb =
        |img: &[u32]| -> Vec<u8> { img.iter().flat_map(|p| [(p >> 16) as u8, (p >> 8) as u8, *p as u8]).collect() };
    let r = nv_flip::FlipImageRgb8::with_data(width as u32, height as u32, &rgb(reference));
    let t = nv_flip::FlipImageRgb8::with_data(width as u32, height as u32, &rgb(test));
    let map = nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE);
    let mut pool = nv_flip::FlipPool::from_image(&map);
    Some(Flip { mean: pool.mean(), p99: pool.get_percentile(0.99, false), map: map.to_vec() })
}

/// A channel difference (0-255) above which a pixel counts as shimmering in [`Shimmer`].
pub const SHIMMER_THRESHOLD: i32 = 24;

/// Temporal stability of a sequence of frames against the reference sequence, fed one frame pair at a time.
///
/// For every pair of consecutive frames, every pixel and every colour channel (0-255), the difference is
/// `(test[k] - test[k-1]) - (reference[k] - reference[k-1])`: the frame-to-frame change the reference does
/// not have (a LOD pop, crawling edges, texels swimming). [`Shimmer::rms`] is its root mean square over all
/// of them; [`Shimmer::shimmering_pct`] the share of pixels, over all frame pairs, where it exceeds
/// [`SHIMMER_THRESHOLD`] in any channel. Frames must all have one size; a frame of another size restarts the
/// sequence.
#[derive(Clone, Debug, Default)]
pub struct Shimmer {
    previous: Option<(Vec<u32>, Vec<u32>)>,
    sum_sq: f64,
    values: u64,
    shimmering: u64,
    pixels: u64,
}

impl Shimmer {
    /// Adds the next frame of the sequence (`reference` and `test`, `0x00RRGGBB`, the same length).
    pub fn push(&mut self, reference: &[u32], test: &[u32]) {
        if reference.len() != test.len() {
            self.previous = None;
            return;
        }
        if let Some((r0, t0)) = self.previous.as_ref().filter(|(r0, _)| r0.len() == reference.len()) {
            for (((&r0, &t0), &r1), &t1) in r0.iter().zip(t0).zip(reference).zip(test) {
                let mut shimmers = false;
                for s in [0, 8, 16] {
                    let ch = |p: u32| ((p >> s) & 0xff) as i32;
                    let d = (ch(t1) - ch(t0)) - (ch(r1) - ch(r0));
                    self.sum_sq += f64::from(d * d);
                    shimmers |= d.abs() > SHIMMER_THRESHOLD;
                }
                self.shimmering += u64::from(shimmers);
            }
            self.values += 3 * reference.len() as u64;
            self.pixels += reference.len() as u64;
        }
        self.previous = Some((reference.to_vec(), test.to_vec()));
    }

    /// Root mean square of the unexplained change (0-255 scale), 0 before two frames.
    #[must_use]
    pub fn rms(&self) -> f64 {
        if self.values == 0 { 0.0 } else { libm::sqrt(self.sum_sq / self.values as f64) }
    }

    /// Share of pixels over all frame pairs whose unexplained change exceeds the threshold in a channel, in
    /// percent; 0 before two frames.
    #[must_use]
    pub fn shimmering_pct(&self) -> f64 {
        if self.pixels == 0 { 0.0 } else { self.shimmering as f64 * 100.0 / self.pixels as f64 }
    }
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
        assert!((p - 10.0 * libm::log10(65025.0f64 / ((81.0 + 64.0) / 12.0))).abs() < 1e-9);
    }

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_the_difference() {
        let (w, h) = (32, 24);
        let a: Vec<u32> = (0..w * h).map(|i| if (i / 4) % 2 == 0 { 0x204060 } else { 0xc0a080 }).collect();
        let same = flip(&a, &a, w, h).unwrap();
        assert_eq!(same.mean, 0.0);
        let mut b = a.clone();
        b[..w * 4].fill(0xff0000);
        let small = flip(&a, &b, w, h).unwrap();
        b.fill(0xff0000);
        let big = flip(&a, &b, w, h).unwrap();
        assert!(small.mean > 0.0 && big.mean > small.mean, "{} {}", small.mean, big.mean);
        assert!(big.p99 >= big.mean);
        assert_eq!(big.share_above(0.0), 1.0);
        assert_eq!(same.share_above(0.0), 0.0);
        // FLIP spreads an edge's error over its neighbourhood: more than the changed sixth, not all.
        let share = small.share_above(0.01);
        assert!(share > 1.0 / 6.0 && share < 1.0, "{share}");
        assert_eq!(big.magma(w, h).len(), w * h);
        assert!(flip(&a, &b, w, h + 1).is_none());
        assert!(flip(&[], &[], 0, 0).is_none());
    }

    fn shimmer_of(reference: &[Vec<u32>], test: &[Vec<u32>]) -> Shimmer {
        let mut s = Shimmer::default();
        for (r, t) in reference.iter().zip(test) {
            s.push(r, t);
        }
        s
    }

    #[test]
    fn shimmer_is_zero_for_the_reference_itself_and_for_the_same_change() {
        let seq: Vec<Vec<u32>> =
            (0..5u32).map(|k| (0..12u32).map(|i| (i * 37 + k * 91) % 0xffffff).collect()).collect();
        let same = shimmer_of(&seq, &seq);
        assert_eq!((same.rms(), same.shimmering_pct()), (0.0, 0.0));
        // A constant offset (a darker image that moves exactly as the reference does) does not shimmer.
        let darker: Vec<Vec<u32>> = seq.iter().map(|f| f.iter().map(|p| p & 0x7f7f7f).collect()).collect();
        let offset: Vec<Vec<u32>> = darker.iter().map(|f| f.iter().map(|p| p + 0x101010).collect()).collect();
        let moved = shimmer_of(&darker, &offset);
        assert_eq!((moved.rms(), moved.shimmering_pct()), (0.0, 0.0));
        // One frame, or none, has no pair.
        assert_eq!(shimmer_of(&seq[..1], &seq[..1]).rms(), 0.0);
        assert_eq!(Shimmer::default().shimmering_pct(), 0.0);
    }

    #[test]
    fn one_toggling_pixel_gives_the_rms_worked_out_by_hand() {
        // Two pixels, three frames; the reference stands still, the test's first pixel's blue goes 0, 255, 0.
        let reference = vec![vec![0x102030u32, 0x405060]; 3];
        let test = vec![vec![0x000000u32, 0x405060], vec![0x0000ff, 0x405060], vec![0x000000, 0x405060]];
        let s = shimmer_of(&reference, &test);
        // Differences: +255 then -255 in one channel of one pixel; 2 pairs x 2 pixels x 3 channels values.
        assert!((s.rms() - libm::sqrt(2.0 * 255.0 * 255.0 / 12.0f64)).abs() < 1e-9, "{}", s.rms());
        // That pixel shimmers in both pairs: 2 of 4 pixel pairs.
        assert_eq!(s.shimmering_pct(), 50.0);
        // A change of 24 is not shimmering, 25 is.
        let small = shimmer_of(&reference[..2], &[vec![0, 0x405060], vec![24, 0x405060]]);
        assert_eq!(small.shimmering_pct(), 0.0);
        let over = shimmer_of(&reference[..2], &[vec![0, 0x405060], vec![25 << 8, 0x405060]]);
        assert_eq!(over.shimmering_pct(), 50.0);
    }
}
