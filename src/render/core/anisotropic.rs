//! Anisotropic texture filtering: several probes along the long axis of a pixel's texel footprint, each
//! the mean of the texels under its box, at the level its short axis asks for.
//!
//! A pixel's footprint in the texture is the parallelogram spanned by `(du/dx, dv/dx)` and `(du/dy, dv/dy)`
//! (in texels of level 0). An isotropic filter ([`mip`](super::mip)) takes one sample at the level of the
//! longer side: on the road seen at a grazing angle, where one side is many times the other, that level
//! blurs across the short side what only the long side needed. Anisotropic filtering (as GPUs do it, after
//! `EXT_texture_filter_anisotropic`) takes `N = min(⌈Pmax / Pmin⌉, max)` probes instead, spaced evenly
//! along the long side (at offsets `(i + ½) / N − ½` of it from the pixel's texture coordinate), and
//! averages them.
//!
//! **The probe is a box, not a tent.** A GPU's probe is trilinear: a tent two texels wide at a level
//! chosen by the footprint's size, which blurs. The measure here is the integral of the texture over the
//! pixel (the converged reference: nearest samples on a fine grid), so each probe is the mean of the
//! texture over its own box: the bounding box in texture space of its share of the footprint (`1/N` of
//! the long side by the short side), `eu` by `ev` texels. The probe reads level `L = ⌈log2 max(eu, ev)⌉`
//! (0 when the box is at most a texel, the last level when it is larger than the texture), where the box is
//! at most one texel on each axis, so it meets at most 2x2 texels; each is weighted by the share of the box
//! it covers (in 1/256, blended as bilinear filtering blends). Level `L`'s texels are means of level 0's
//! ([`mip`](super::mip)'s box chain), so this is the box integral up to where the box falls on the coarser
//! grid. Magnified (a pixel smaller than a texel), a probe is the texel under it except within half a pixel
//! of a texel's edge, where the two texels mix by their areas: sharp where nearest is sharp, smooth where
//! nearest steps.
//!
//! **Rules.** `Pmax` and `Pmin` are the lengths of the two sides (the larger and the smaller). `⌈·⌉` of the
//! ratio forgives 1/64 (a ratio of 2.01 takes two probes, not three), and no pixel takes more probes than
//! there are texels along its long side (`⌈Pmax⌉`). A footprint with no area, or a broken one (NaN,
//! infinite), takes one probe of no size at level 0: the nearest texel. The mean of the probes is taken
//! per channel in the stored 8-bit values and rounded to nearest (`(sum + N/2) / N`), as the mip chain
//! averages texels.

use crate::render::core::mip::TexGradients;
use crate::render::core::texture::{Sampler, Texture, blend, floor_i32};

/// The maximum probe counts `--filter anisoN` offers (as GPUs offer 2x to 16x).
pub const ANISOTROPY: [u8; 4] = [2, 4, 8, 16];

/// The probes one pixel takes: how many, from which level, how large, and how far apart.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Probes {
    /// The mip level every probe reads.
    pub level: usize,
    /// Half the box's width and height in texels of that level (each at most ½).
    pub radius: [f32; 2],
    /// How many probes (1 for an isotropic footprint, at most the filter's maximum).
    pub count: u32,
    /// The step from one probe to the next in `(u, v)`: the long side divided by `count`.
    pub step: [f32; 2],
}

impl Probes {
    /// One probe of no size at level 0: the nearest texel (for a footprint that cannot be measured).
    const POINT: Probes = Probes { level: 0, radius: [0.0; 2], count: 1, step: [0.0; 2] };

    /// The texture coordinate of probe `i` around the pixel's `(u, v)`.
    #[inline]
    #[must_use]
    pub fn at(&self, i: u32, (u, v): (f32, f32)) -> (f32, f32) {
        let t = i as f32 - (self.count - 1) as f32 * 0.5;
        (u + t * self.step[0], v + t * self.step[1])
    }

    /// The filtered texel (packed `0xAARRGGBB`) of `chain` (level 0 of a mip chain) at the pixel's `(u, v)`.
    #[inline]
    #[must_use]
    pub fn sample(&self, chain: &Texture, uv: (f32, f32), sampler: Sampler) -> u32 {
        let level = chain.level(self.level);
        self.average(uv, |u, v| box_sample(level, (u, v), self.radius, sampler))
    }

    /// The mean of the probes' packed texels, each channel rounded to nearest; `texel` samples one probe at
    /// `(u, v)`. One probe is its texel as is.
    #[inline]
    pub fn average(&self, (u, v): (f32, f32), mut texel: impl FnMut(f32, f32) -> u32) -> u32 {
        if self.count <= 1 {
            return texel(u, v);
        }
        // Two channels a word: 16 probes of 255 fit in 16 bits.
        const M: u32 = 0x00ff_00ff;
        let (mut even, mut odd) = (0u32, 0u32);
        for i in 0..self.count {
            let (pu, pv) = self.at(i, (u, v));
            let t = texel(pu, pv);
            even += t & M;
            odd += (t >> 8) & M;
        }
        mean_of_sums(even, odd, self.count)
    }
}

/// The per-channel means (rounded to nearest) of `n` texels whose channels are summed two a word: `even`
/// holds blue and red, `odd` green and alpha.
#[inline]
pub(crate) fn mean_of_sums(even: u32, odd: u32, n: u32) -> u32 {
    let mean = |sum: u32, shift: u32| (((sum >> shift) & 0xffff) + n / 2) / n;
    mean(even, 0) | mean(odd, 0) << 8 | mean(even, 16) << 16 | mean(odd, 16) << 24
}

/// The mean of `texture` over the box of half-size `radius` texels (each at most ½) centred on `(u, v)`:
/// the (at most) 2x2 texels it meets, each weighted by its share of the box in 1/256.
#[inline]
#[must_use]
pub fn box_sample(texture: &Texture, (u, v): (f32, f32), radius: [f32; 2], sampler: Sampler) -> u32 {
    let (x, ax) = box_axis(u * texture.width() as f32, radius[0]);
    let (y, ay) = box_axis(v * texture.height() as f32, radius[1]);
    let row = |y: i32| {
        let left = texture.texel(x, y, sampler);
        if ax == 0 { left } else { blend(left, texture.texel(x.wrapping_add(1), y, sampler), ax) }
    };
    let top = row(y);
    if ay == 0 { top } else { blend(top, row(y.wrapping_add(1)), ay) }
}

/// On one axis, the first texel a box from `c - r` to `c + r` (in texels) meets and the share (in 1/256)
/// of the box on the texel after it.
#[inline]
fn box_axis(c: f32, r: f32) -> (i32, u32) {
    let first = floor_i32(c - r);
    let over = c + r - (first as f32 + 1.0);
    // Past the edge by `over` of the box's `2r`; `as u32` saturates (NaN and negatives to 0).
    let share = if over > 0.0 { ((over / (2.0 * r)).min(1.0) * 256.0 + 0.5) as u32 } else { 0 };
    (first, share)
}

/// The probes at a pixel whose `w` (`1/(1/w)`), `u` and `v` are given, for a polygon with gradients `g`
/// and the mip chain `chain`, taking at most `max` probes (clamped to `1..=16`).
#[inline]
#[must_use]
pub fn probes(g: &TexGradients, w: f32, (u, v): (f32, f32), chain: &Texture, max: u8) -> Probes {
    let (tw, th) = (chain.width() as f32, chain.height() as f32);
    // The footprint's sides in texels of level 0 (u = s/q, so du = (ds - u dq) / q; likewise v).
    let side = |d: &[f32; 3]| ((d[1] - u * d[0]) * w * tw, (d[2] - v * d[0]) * w * th);
    let (x, y) = (side(&g.dx), side(&g.dy));
    let (x2, y2) = (x.0 * x.0 + x.1 * x.1, y.0 * y.0 + y.1 * y.1);
    let (long, short, major2, minor2) = if x2 >= y2 { (x, y, x2, y2) } else { (y, x, y2, x2) };
    if !(major2.is_finite() && minor2.is_finite()) {
        return Probes::POINT;
    }
    // `as u32` saturates (an infinite ratio, a side of no length, takes the most); never more probes than
    // texels along the long side (a magnified footprint takes one).
    let most = u32::from(max.clamp(1, 16)).min(major2.sqrt().ceil() as u32).max(1);
    let ratio = (major2 / minor2).sqrt();
    let count = if ratio.is_nan() { 1 } else { ((ratio - 1.0 / 64.0).ceil() as u32).clamp(1, most) };
    let n = count as f32;
    // Each probe's box: its share of the long side plus the short side, on each axis.
    let extent = [long.0.abs() / n + short.0.abs(), long.1.abs() / n + short.1.abs()];
    let level = level_for(extent[0].max(extent[1])).min(chain.last_level());
    let scale = 1.0 / (1u32 << level) as f32;
    let radius = extent.map(|e| (e * scale * 0.5).min(0.5));
    Probes { level, radius, count, step: [long.0 / (tw * n), long.1 / (th * n)] }
}

/// `⌈log2 e⌉` for a box `e` texels wide (0 for at most one texel), exact at powers of two: the first level
/// where it is at most one texel.
#[inline]
fn level_for(e: f32) -> usize {
    if e.is_nan() || e <= 1.0 {
        return 0;
    }
    let bits = e.to_bits();
    let exponent = ((bits >> 23) & 0xff) as usize;
    // `e > 1`: exponent >= 127; a mantissa beyond the power of two takes the next level. Infinity gives 129.
    exponent - 127 + usize::from(bits & 0x007f_ffff != 0)
}

#[cfg(test)]
#[path = "anisotropic_tests.rs"]
mod tests;
