//! Textures and their sampling: wrap modes, nearest, bilinear, `area` and trilinear filtering, any size,
//! each texture with its chain of mip levels (made as [`super::mip`] says).
//!
//! Texels are stored as packed `0xAARRGGBB` and used exactly as stored (no colour-space conversion), as the
//! `render` command promises. Texture coordinates follow glTF: `(0, 0)` is the top-left corner of the image,
//! `u` grows to the right and `v` downwards, and texel `i` spans `[i, i + 1) / size`.
//!
//! The renderer's bilinear filter works in integers on packed texels ([`Texture::bilinear`]): the sample
//! lies at `u·W − ½` (texel centres at half-integers) in `Fx24_8` (256 steps a texel), floored; the integer
//! part names the left of the two texels and the low 8 bits the weight `a` of the right one, likewise along
//! `v`. Two texels blend per channel, alpha included, as `(x·(256 − a) + y·a + 128) >> 8` ([`blend`]): two
//! channels at a time in one 32-bit word (each product fits 16 bits), exact at `a = 0`, never outside
//! `0..=255`. Trilinear blends the bilinear texels of the two levels around `λ` by its fraction in 1/256,
//! truncated ([`trilinear_levels`]). `area` takes the bilinear rule's four texels with the weights sharpened
//! to a box footprint ([`area_weight`]). Every span path, fast or general, filters this way, so they agree.

use thiserror::Error;

use super::mip;

/// How texture coordinates outside `[0, 1)` are folded back in (glTF sampler `wrapS` / `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Wrap {
    /// Tile the image (glTF 10497, the default).
    #[default]
    Repeat,
    /// Clamp to the edge texel (glTF 33071).
    ClampToEdge,
    /// Tile with every other copy mirrored (glTF 33648).
    MirroredRepeat,
}

pub use super::filter::Filter;

/// The wrap modes of one texture reference.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sampler {
    /// Wrap mode along `u`.
    pub wrap_s: Wrap,
    /// Wrap mode along `v`.
    pub wrap_t: Wrap,
}

/// Why a texture could not be made.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum TextureError {
    /// Width or height is zero.
    #[error("texture has a zero dimension ({width}x{height})")]
    Empty {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
    },
    /// The texel buffer does not hold `width * height` texels.
    #[error("texture of {width}x{height} needs {expected} texels, got {actual}")]
    WrongLength {
        /// Width in texels.
        width: u32,
        /// Height in texels.
        height: u32,
        /// `width * height`.
        expected: usize,
        /// Texels supplied.
        actual: usize,
    },
}

/// An image the renderer samples from, with its mip chain.
///
/// The chain is made when the texture is (a third as many texels again, one pass per level), so that no
/// frame waits for it and every frame reads the same levels; [`Texture::patch`] keeps it up to date.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Texture {
    width: u32,
    height: u32,
    texels: Vec<u32>,
    /// Levels 1, 2, ... down to 1x1, each with no chain of its own (empty for a 1x1 texture).
    levels: Vec<Texture>,
}

impl Texture {
    /// Makes a texture from packed `0xAARRGGBB` texels in rows from the top.
    pub fn new(width: u32, height: u32, texels: Vec<u32>) -> Result<Self, TextureError> {
        if width == 0 || height == 0 {
            return Err(TextureError::Empty { width, height });
        }
        let expected = width as usize * height as usize;
        if texels.len() != expected {
            return Err(TextureError::WrongLength { width, height, expected, actual: texels.len() });
        }
        let mut levels = Vec::new();
        let (mut w, mut h) = (width, height);
        while w > 1 || h > 1 {
            let src = levels.last().map_or(&texels, |l: &Texture| &l.texels);
            let (nw, nh, next) = mip::reduce(src, (w, h));
            levels.push(Self { width: nw, height: nh, texels: next, levels: Vec::new() });
            (w, h) = (nw, nh);
        }
        Ok(Self { width, height, texels, levels })
    }

    /// Mip level `k` (0 is the texture itself; past the last, the last, 1x1).
    #[inline]
    #[must_use]
    pub fn level(&self, k: usize) -> &Texture {
        match k.checked_sub(1) {
            None => self,
            Some(i) => self.levels.get(i).or(self.levels.last()).unwrap_or(self),
        }
    }

    /// The index of the last (1x1) mip level.
    #[inline]
    #[must_use]
    pub fn last_level(&self) -> usize {
        self.levels.len()
    }

    /// Makes a texture from 8-bit RGBA bytes in rows from the top.
    pub fn from_rgba8(width: u32, height: u32, rgba: &[u8]) -> Result<Self, TextureError> {
        let texels = rgba.chunks_exact(4).map(|p| u32::from_be_bytes([p[3], p[0], p[1], p[2]])).collect();
        Self::new(width, height, texels)
    }

    /// Width in texels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in texels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// The packed texels, row by row from the top.
    #[must_use]
    pub fn texels(&self) -> &[u32] {
        &self.texels
    }

    /// Overwrites a `w` x `h` block of texels at `(x, y)` (a partial update) and remakes the texels of the
    /// mip levels it reaches; `false` if it does not fit.
    pub fn patch(&mut self, x: u32, y: u32, w: u32, h: u32, texels: &[u32]) -> bool {
        let fits = x.checked_add(w).is_some_and(|r| r <= self.width)
            && y.checked_add(h).is_some_and(|b| b <= self.height)
            && texels.len() == w as usize * h as usize;
        if !fits {
            return false;
        }
        for row in 0..h as usize {
            let dst = (y as usize + row) * self.width as usize + x as usize;
            self.texels[dst..dst + w as usize].copy_from_slice(&texels[row * w as usize..(row + 1) * w as usize]);
        }
        // Each level's changed rectangle gives the next level's: the blocks meeting it.
        let mut rect = (x, y, x + w, y + h);
        for k in 0..self.levels.len() {
            let (done, rest) = self.levels.split_at_mut(k);
            let above = done.last().map_or((&self.texels, self.width, self.height), |l| (&l.texels, l.width, l.height));
            if let Some(level) = rest.first_mut() {
                rect = mip::refresh(above.0, (above.1, above.2), &mut level.texels, rect);
            }
        }
        true
    }

    /// The packed texel at integer coordinates, wrapped by `sampler`.
    #[inline(always)]
    #[must_use]
    pub fn texel(&self, x: i32, y: i32, sampler: Sampler) -> u32 {
        let x = wrap(x, self.width, sampler.wrap_s);
        let y = wrap(y, self.height, sampler.wrap_t);
        // `wrap` returns an index in `0..size`, so this never goes out of bounds.
        self.texels[y as usize * self.width as usize + x as usize]
    }

    /// Nearest-texel sample at `(u, v)` as RGBA in `0..=1`.
    #[inline]
    #[must_use]
    pub fn sample_nearest(&self, u: f32, v: f32, sampler: Sampler) -> [f32; 4] {
        // `as i32` saturates and maps NaN to 0, so hostile coordinates still pick a real texel.
        let x = floor_i32(u * self.width as f32);
        let y = floor_i32(v * self.height as f32);
        unpack(self.texel(x, y, sampler))
    }

    /// Bilinear sample at `(u, v)` as RGBA in `0..=1`, in floats (smoother than [`Texture::bilinear`]'s
    /// 1/256 steps, for the overlay's magnified glyphs); each of the four texels is wrapped on its own.
    #[must_use]
    pub fn sample_bilinear(&self, u: f32, v: f32, sampler: Sampler) -> [f32; 4] {
        let (texels, weights) = self.bilinear_footprint(u, v, sampler);
        blend_footprint(texels, weights)
    }

    /// The four packed texels [`Texture::sample_bilinear`] blends at `(u, v)` (top left, top right, bottom
    /// left, bottom right, each wrapped on its own) and its weights across and down: a caller that finds
    /// them all clear (the space around a glyph) can skip the blend, whose result it knows.
    #[inline]
    #[must_use]
    pub fn bilinear_footprint(&self, u: f32, v: f32, sampler: Sampler) -> ([u32; 4], [f32; 2]) {
        let fx = u * self.width as f32 - 0.5;
        let fy = v * self.height as f32 - 0.5;
        let x0f = fx.floor();
        let y0f = fy.floor();
        let (ax, ay) = (sanitize_frac(fx - x0f), sanitize_frac(fy - y0f));
        let (x0, y0) = (x0f as i32, y0f as i32);
        let (x1, y1) = (x0.wrapping_add(1), y0.wrapping_add(1));
        let t = [
            self.texel(x0, y0, sampler),
            self.texel(x1, y0, sampler),
            self.texel(x0, y1, sampler),
            self.texel(x1, y1, sampler),
        ];
        (t, [ax, ay])
    }

    /// A sample at `(u, v)` by `filter` at level of detail `lod` (`λ`, see [`mip`]) as RGBA in `0..=1`:
    /// nearest or bilinear in the level nearest `λ` (`min-bilinear` as `λ` decides), trilinear between the
    /// two around it. At `λ <= 0`
    /// (magnification, or mip-maps off) every filter samples level 0 exactly as without mip-maps.
    #[inline]
    #[must_use]
    pub fn sample(&self, filter: Filter, lod: f32, u: f32, v: f32, sampler: Sampler) -> [f32; 4] {
        let last = self.last_level();
        match filter {
            Filter::Nearest => self.level(mip::nearest_level(lod, last)).sample_nearest(u, v, sampler),
            Filter::Bilinear => unpack(self.level(mip::nearest_level(lod, last)).bilinear(u, v, sampler)),
            // A polygon's shading resolves it by the polygon's level; given a level here, by that one.
            Filter::MinBilinear => self.sample(filter.for_polygon(lod), lod, u, v, sampler),
            // Without a footprint (measured per pixel by the spans), as `min-bilinear`.
            Filter::Area => self.sample(Filter::MinBilinear, lod, u, v, sampler),
            Filter::Trilinear | Filter::Anisotropic(_) => {
                let (k, weight) = trilinear_levels(lod, last);
                let fine = self.level(k).bilinear(u, v, sampler);
                // At a whole level (or beyond the last, or magnified) the finer level alone, bit for bit.
                if weight == 0 {
                    return unpack(fine);
                }
                unpack(blend(fine, self.level(k + 1).bilinear(u, v, sampler), weight))
            }
        }
    }

    /// The `area` texel at `(u, v)` for a footprint `extent` texels across and down ([`area_weight`]), packed:
    /// the bilinear rule's four texels with their weights sharpened to the footprint's share of each.
    #[inline(always)]
    #[must_use]
    pub fn area(&self, u: f32, v: f32, extent: [f32; 2], sampler: Sampler) -> u32 {
        self.blend_2x2(u, v, sampler, |ax, ay| (area_weight(ax, extent[0]), area_weight(ay, extent[1])))
    }

    /// The bilinear texel at `(u, v)`, packed, by the integer rule of the module doc; each of the four
    /// texels is wrapped on its own.
    #[inline(always)]
    #[must_use]
    pub fn bilinear(&self, u: f32, v: f32, sampler: Sampler) -> u32 {
        self.blend_2x2(u, v, sampler, |ax, ay| (ax, ay))
    }

    /// The four texels around `(u, v)` by the bilinear rule, blended by its weights across and down as
    /// `weights` gives them from the bilinear ones (itself for bilinear, sharpened for `area`).
    #[inline(always)]
    fn blend_2x2(&self, u: f32, v: f32, sampler: Sampler, weights: impl Fn(u32, u32) -> (u32, u32)) -> u32 {
        let (px, py) = (fx24_8(u, self.width), fx24_8(v, self.height));
        let (x, y) = (px >> 8, py >> 8);
        let (ax, ay) = weights((px & 255) as u32, (py & 255) as u32);
        let (x1, y1) = (x.wrapping_add(1), y.wrapping_add(1));
        let top = blend(self.texel(x, y, sampler), self.texel(x1, y, sampler), ax);
        let bottom = blend(self.texel(x, y1, sampler), self.texel(x1, y1, sampler), ax);
        blend(top, bottom, ay)
    }
}

/// The finer of the two levels trilinear filtering blends at level of detail `lod` (`lod` as a whole
/// number, at most `last`), and the coarser one's weight in 1/256: the fraction truncated, 0 at or past the
/// last level and for magnification (`lod <= 0`, or NaN).
#[inline(always)]
#[must_use]
pub fn trilinear_levels(lod: f32, last: usize) -> (usize, u32) {
    // `as` saturates, sending NaN and negatives to 0.
    let k = (lod as usize).min(last);
    let weight = if k < last { ((lod - k as f32) * 256.0) as u32 } else { 0 };
    (k, weight.min(255))
}

/// Texels `x` and `y` blended per channel with weight `a` (0..=256) on `y`, rounded to nearest.
#[inline(always)]
#[must_use]
pub fn blend(x: u32, y: u32, a: u32) -> u32 {
    const M: u32 = 0x00ff_00ff;
    let b = 256 - a;
    let rb = (((x & M) * b + (y & M) * a + 0x0080_0080) >> 8) & M;
    let ag = (((x >> 8) & M) * b + ((y >> 8) & M) * a + 0x0080_0080) & !M;
    rb | ag
}

/// The sample position `u·size − ½` in `Fx24_8` (256 steps a texel), floored (saturating, NaN to 0).
#[inline(always)]
#[must_use]
pub fn fx24_8(u: f32, size: u32) -> i32 {
    floor_i32(u * (size as f32 * 256.0) - 128.0)
}

/// The `area` filter's weight (in 1/256, `0..=256`) of the second of two texels whose centres a sample lies
/// `a`/256 of the way between, for a box footprint `extent` texels long: the share of the box beyond the
/// texel edge halfway between the centres, `(a − 128) / extent + 128`, rounded and clamped. `extent` is
/// clamped to `1/64..=1` (NaN to 1/64): at 1 the weight is `a`, the bilinear one; shorter boxes sharpen it
/// towards the nearest texel's 0 or 256.
#[inline(always)]
#[must_use]
pub fn area_weight(a: u32, extent: f32) -> u32 {
    // `max` then `min`, as the vector loops do: `f32::max` gives 1/64 for NaN, where `clamp` would keep NaN.
    #[allow(clippy::manual_clamp)]
    let e = extent.max(AREA_MIN_EXTENT).min(1.0);
    // Finite (e >= 1/64, |a - 128| <= 128), so the clamp (the loops' `max` then `min`) and `as` are exact.
    ((a as f32 - 128.0) / e + 128.5).clamp(0.0, 256.0) as u32
}

/// The shortest footprint the `area` filter weighs by, in texels (a magnification of 64).
pub const AREA_MIN_EXTENT: f32 = 1.0 / 64.0;

fn sanitize_frac(f: f32) -> f32 {
    if f.is_finite() { f.clamp(0.0, 1.0) } else { 0.0 }
}

/// The bilinear blend in floats of a footprint from [`Texture::bilinear_footprint`], as RGBA in `0..=1`.
#[inline]
#[must_use]
pub fn blend_footprint(texels: [u32; 4], [ax, ay]: [f32; 2]) -> [f32; 4] {
    let [t00, t10, t01, t11] = texels.map(unpack);
    let mut out = [0.0; 4];
    for c in 0..4 {
        let top = t00[c] + (t10[c] - t00[c]) * ax;
        let bottom = t01[c] + (t11[c] - t01[c]) * ax;
        out[c] = top + (bottom - top) * ay;
    }
    out
}

/// `x.floor() as i32` without a call to libm's `floorf` (the x86-64 baseline has no rounding instruction,
/// so `floor` is a call, and the texel loops would make one per pixel): the same result for every input,
/// NaN giving 0 and out-of-range values saturating as `as` does.
#[inline(always)]
#[must_use]
pub fn floor_i32(x: f32) -> i32 {
    let i = x as i32;
    i.saturating_sub(i32::from(x < i as f32))
}

/// Folds an integer texel coordinate into `0..size` by the wrap mode.
#[inline(always)]
#[must_use]
pub fn wrap(i: i32, size: u32, mode: Wrap) -> u32 {
    if mode == Wrap::Repeat && size.is_power_of_two() {
        // Two's complement makes the mask a Euclidean remainder for negative coordinates too.
        return (i as u32) & (size - 1);
    }
    let n = size as i64;
    let i = i64::from(i);
    let r = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m >= n { 2 * n - 1 - m } else { m }
        }
    };
    r as u32
}

/// Splits a packed `0xAARRGGBB` texel into RGBA in `0..=1`.
#[inline]
#[must_use]
pub fn unpack(t: u32) -> [f32; 4] {
    const S: f32 = 1.0 / 255.0;
    [((t >> 16) & 0xff) as f32 * S, ((t >> 8) & 0xff) as f32 * S, (t & 0xff) as f32 * S, (t >> 24) as f32 * S]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fast_floor_and_power_of_two_wrap_match_the_slow_forms() {
        let mut xs = vec![0.0f32, -0.0, 0.5, -0.5, 1.0, -1.0, 1e-40, -1e-40, 2.5e9, -2.5e9, f32::NAN, f32::INFINITY];
        xs.extend([f32::NEG_INFINITY, 16_777_217.0, -16_777_217.0, 2_147_483_520.0, -2_147_483_648.0]);
        let mut seed = 0x1234_5678u32;
        for _ in 0..100_000 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            xs.push(f32::from_bits(seed));
            xs.push((seed as i32 as f32) / 977.0);
        }
        for &x in &xs {
            assert_eq!(floor_i32(x), x.floor() as i32, "{x}");
        }
        for size in [1u32, 2, 8, 64, 256, 3, 100] {
            for i in [-1_000_000i32, -257, -256, -1, 0, 1, 255, 256, 1_000_000, i32::MIN, i32::MAX] {
                let slow = i64::from(i).rem_euclid(i64::from(size)) as u32;
                assert_eq!(wrap(i, size, Wrap::Repeat), slow, "{i} mod {size}");
            }
        }
    }

    #[test]
    fn wrap_modes() {
        let w: Vec<u32> = (-5..7).map(|i| wrap(i, 3, Wrap::Repeat)).collect();
        assert_eq!(w, [1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        let c: Vec<u32> = (-2..5).map(|i| wrap(i, 3, Wrap::ClampToEdge)).collect();
        assert_eq!(c, [0, 0, 0, 1, 2, 2, 2]);
        let m: Vec<u32> = (-4..8).map(|i| wrap(i, 3, Wrap::MirroredRepeat)).collect();
        assert_eq!(m, [2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1]);
        assert!(wrap(i32::MAX, 7, Wrap::MirroredRepeat) < 7);
        assert!(wrap(i32::MIN, 7, Wrap::Repeat) < 7);
    }

    #[test]
    fn sampling_any_size_and_hostile_coordinates() {
        let t = Texture::new(3, 2, vec![0xff00_0000, 0xffff_0000, 0xff00_ff00, 0xff00_00ff, 0xffff_ffff, 0x0000_0000])
            .unwrap();
        let s = Sampler::default();
        assert_eq!(t.sample_nearest(0.5, 0.25, s), unpack(0xffff_0000));
        assert_eq!(t.sample_nearest(0.9, 0.75, s), unpack(0));
        assert_eq!(t.sample_nearest(1.5, -0.25, s), unpack(0xffff_ffff));
        for v in [f32::NAN, f32::INFINITY, -f32::INFINITY, 1e30, -1e30] {
            let _ = t.sample_nearest(v, v, s);
            let _ = t.sample_bilinear(v, 0.3, s);
        }
        // Bilinear at a texel centre returns that texel exactly.
        let b = t.sample_bilinear(0.5 / 3.0, 0.25, s);
        assert_eq!(b, unpack(0xff00_0000));
        assert!(Texture::new(0, 4, vec![]).is_err());
        assert!(Texture::new(2, 2, vec![0; 3]).is_err());
    }

    fn noise_texture(w: u32, h: u32, mut seed: u32) -> Texture {
        let texels = (0..w * h)
            .map(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                seed
            })
            .collect();
        Texture::new(w, h, texels).unwrap()
    }

    #[test]
    fn every_texture_has_its_chain_down_to_one_texel_and_patches_keep_it() {
        let mut t = noise_texture(12, 5, 7);
        let sizes: Vec<_> = (0..=t.last_level()).map(|k| (t.level(k).width(), t.level(k).height())).collect();
        assert_eq!(sizes, [(12, 5), (6, 2), (3, 1), (1, 1)]);
        for k in 0..t.last_level() {
            let (a, b) = (t.level(k), t.level(k + 1));
            assert_eq!(mip::reduce(a.texels(), (a.width(), a.height())).2, b.texels(), "level {}", k + 1);
        }
        assert_eq!(t.level(99), t.level(3));
        assert!(t.patch(10, 3, 2, 2, &[0xffff_ffff; 4]));
        let fresh = Texture::new(12, 5, t.texels().to_vec()).unwrap();
        assert_eq!(t, fresh, "a patched chain equals the chain made afresh");
        assert_eq!(Texture::new(1, 1, vec![5]).unwrap().last_level(), 0);
    }

    #[test]
    fn trilinear_at_a_whole_level_is_bilinear_there_and_halfway_blends_half() {
        let t = noise_texture(16, 16, 3);
        let s = Sampler::default();
        for (u, v) in [(0.3, 0.7), (0.01, 0.99), (0.5, 0.5), (0.123, 0.456)] {
            for k in 0..=t.last_level() {
                let b = unpack(t.level(k).bilinear(u, v, s));
                assert_eq!(t.sample(Filter::Trilinear, k as f32, u, v, s), b, "level {k}");
                assert_eq!(t.sample(Filter::Bilinear, k as f32, u, v, s), b, "level {k}");
            }
            // Magnified or mip-maps off (λ = 0): exactly bilinear and nearest in level 0.
            assert_eq!(t.sample(Filter::Trilinear, -3.0, u, v, s), unpack(t.bilinear(u, v, s)));
            assert_eq!(t.sample(Filter::Nearest, 0.0, u, v, s), t.sample_nearest(u, v, s));
            let (a, b) = (unpack(t.level(1).bilinear(u, v, s)), unpack(t.level(2).bilinear(u, v, s)));
            let half = t.sample(Filter::Trilinear, 1.5, u, v, s);
            for c in 0..4 {
                // Halfway rounds to the nearest level, so within half a level of the mean.
                assert!(
                    (half[c] - (a[c] + b[c]) / 2.0).abs() <= 0.5 / 255.0 + 1e-6,
                    "channel {c}: {half:?} {a:?} {b:?}"
                );
            }
            // Nearest and bilinear take the level nearest λ.
            assert_eq!(t.sample(Filter::Nearest, 1.6, u, v, s), t.level(2).sample_nearest(u, v, s));
            assert_eq!(t.sample(Filter::Bilinear, 1.4, u, v, s), unpack(t.level(1).bilinear(u, v, s)));
        }
    }
}
