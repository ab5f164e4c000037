//! The fast paths' texels: nearest, bilinear or trilinear, from the polygon's mip level (or two) or from
//! the level chosen at each pixel; `area`, level 0's bilinear texels with weights sharpened to the
//! footprint measured at each pixel; anisotropic, the mean of box probes ([`anisotropic`]).
//!
//! Nearest takes the texel under `(u·W, v·H)`, floored; bilinear and trilinear follow the integer rule
//! of [`Texture::bilinear`] (sample at `u·W − ½` in `Fx24_8`, blends rounded in 1/256). Both are exactly
//! what the general span computes, so a white polygon's texels are the same on either path. They are the
//! reference the AVX2 chunk loop's texels match bit for bit (through `span_lanes`' per-pixel loop).

use super::row::Setup;
use crate::render::core::anisotropic;
use crate::render::core::mip::{TexGradients, nearest_level};
use crate::render::core::texture::{Filter, Sampler, Texture, blend, floor_i32, trilinear_levels};

/// A fast path's texture: one mip level (or two, trilinear) for the whole polygon, or the whole chain with
/// the level chosen at every pixel.
#[derive(Clone, Copy)]
pub(crate) struct Tex<'a> {
    /// The level the polygon is drawn with (the finer of two, trilinear), or level 0 of the chain when
    /// `per_pixel` is set.
    pub(crate) texture: &'a Texture,
    /// Trilinear with one level for the polygon: the coarser level and its weight in 1/256 (1..=255).
    pub(crate) coarser: Option<(&'a Texture, u32)>,
    /// The wrap modes.
    pub(crate) sampler: Sampler,
    /// Nearest, bilinear, trilinear, `area` (with `per_pixel`) or anisotropic (`min-bilinear` resolved by the
    /// polygon's level).
    pub(crate) filter: Filter,
    /// The polygon's `1/w`, `s/w`, `t/w` gradients when the level is chosen per pixel, or (`area`) when the
    /// footprint's extent is measured at every pixel.
    pub(crate) per_pixel: Option<TexGradients>,
}

impl<'a> Tex<'a> {
    /// The texture `chain` (level 0) filtered by `filter` at the polygon's level of detail `lod`
    /// (`min-bilinear` resolved by `lod`; `area`, which needs the gradients ([`per_pixel`](Self::per_pixel)),
    /// as `min-bilinear` without them).
    pub(crate) fn polygon(chain: &'a Texture, sampler: Sampler, filter: Filter, lod: f32) -> Self {
        let filter = match filter {
            Filter::MinBilinear | Filter::Area => Filter::MinBilinear.for_polygon(lod),
            f => f,
        };
        let last = chain.last_level();
        let (texture, coarser) = match filter {
            Filter::Trilinear | Filter::Anisotropic(_) => {
                let (k, weight) = trilinear_levels(lod, last);
                (chain.level(k), (weight > 0).then(|| (chain.level(k + 1), weight)))
            }
            _ => (chain.level(nearest_level(lod, last)), None),
        };
        Self { texture, coarser, sampler, filter, per_pixel: None }
    }

    /// The texture `chain` filtered by `filter` with the level chosen per pixel from the gradients `g` (for
    /// [`Filter::Area`], level 0 with the footprint measured per pixel from them).
    pub(crate) fn per_pixel(chain: &'a Texture, sampler: Sampler, filter: Filter, g: TexGradients) -> Self {
        Self { texture: chain, coarser: None, sampler, filter, per_pixel: Some(g) }
    }

    /// Whether a texel costs more than a nearest one from one level (a filter, or a level per pixel).
    #[inline]
    pub(crate) fn costly(&self) -> bool {
        self.per_pixel.is_some() || self.filter != Filter::Nearest
    }

    /// The texel at pixel offset `k` of the span `s` describes (its `w` and `h` are the texture's size):
    /// nearest by the same operations in the same order as the general span (so the same texel); bilinear
    /// and trilinear by the integer rules of the module doc.
    #[inline(always)]
    pub(crate) fn texel_at(&self, s: &Setup, k: f32) -> u32 {
        let Some(g) = &self.per_pixel else {
            if self.filter == Filter::Nearest {
                let (tx, ty) = s.texel_xy(k);
                return self.texture.texel(tx, ty, self.sampler);
            }
            let (u, v) = s.uv(k);
            let fine = self.texture.bilinear(u, v, self.sampler);
            return match self.coarser {
                Some((coarse, weight)) => blend(fine, coarse.bilinear(u, v, self.sampler), weight),
                None => fine,
            };
        };
        let t = self.texture;
        let qst = [s.q0 + k * s.dq, s.s0 + k * s.ds, s.t0 + k * s.dt];
        if self.filter == Filter::Area {
            // Level 0, the footprint's extent measured here (as the general span measures it).
            let w = 1.0 / qst[0];
            return t.area(qst[1] * w, qst[2] * w, g.extent_at(qst, (t.width(), t.height())), self.sampler);
        }
        if let Filter::Anisotropic(max) = self.filter {
            let w = 1.0 / qst[0];
            return self.probed(w, (qst[1] * w, qst[2] * w), g, max);
        }
        let lod = g.lod_at(qst, (t.width(), t.height()));
        let w = 1.0 / qst[0];
        self.at_lod(qst[1] * w, qst[2] * w, lod)
    }

    /// The anisotropic texel of the chain (a per-pixel [`Tex`]) at a pixel whose `w`, `u`, `v` are given,
    /// for a polygon with gradients `g`, taking at most `max` probes.
    #[inline]
    pub(crate) fn probed(&self, w: f32, uv: (f32, f32), g: &TexGradients, max: u8) -> u32 {
        anisotropic::probes(g, w, uv, self.texture, max).sample(self.texture, uv, self.sampler)
    }

    /// The texel of the chain (a per-pixel [`Tex`]) at texture coordinates `(u, v)` and level of detail `lod`.
    #[inline(always)]
    pub(crate) fn at_lod(&self, u: f32, v: f32, lod: f32) -> u32 {
        let t = self.texture;
        match self.filter {
            Filter::Nearest => {
                let level = t.level(nearest_level(lod, t.last_level()));
                level.texel(floor_i32(u * level.width() as f32), floor_i32(v * level.height() as f32), self.sampler)
            }
            Filter::Bilinear => t.level(nearest_level(lod, t.last_level())).bilinear(u, v, self.sampler),
            // A polygon's shading resolves it by the polygon's level; given a pixel's level, by that one.
            Filter::MinBilinear | Filter::Area => {
                Self { filter: Filter::MinBilinear.for_polygon(lod), ..*self }.at_lod(u, v, lod)
            }
            Filter::Trilinear | Filter::Anisotropic(_) => {
                let (k, weight) = trilinear_levels(lod, t.last_level());
                let fine = t.level(k).bilinear(u, v, self.sampler);
                if weight == 0 { fine } else { blend(fine, t.level(k + 1).bilinear(u, v, self.sampler), weight) }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::texture::unpack;

    #[test]
    fn a_blend_is_exact_at_its_ends_and_rounds_between() {
        let mut rng = Lcg(11);
        for _ in 0..20_000 {
            let (x, y, a) = (rng.next(), rng.next(), rng.below(257));
            assert_eq!(blend(x, y, 0), x);
            assert_eq!(blend(x, y, 256), y);
            let got = blend(x, y, a);
            for shift in [0, 8, 16, 24] {
                let (cx, cy) = (f64::from(x >> shift & 255), f64::from(y >> shift & 255));
                let exact = (cx * f64::from(256 - a) + cy * f64::from(a)) / 256.0;
                let c = f64::from(got >> shift & 255);
                assert!((c - exact).abs() <= 0.5, "{x:08x} {y:08x} at {a}: {c} against {exact}");
            }
        }
    }

    #[test]
    fn the_integer_filters_stay_within_two_levels_of_float_filtering() {
        let mut rng = Lcg(5);
        let texels: Vec<u32> = (0..32 * 16).map(|_| rng.next()).collect();
        let Ok(chain) = Texture::new(32, 16, texels) else { panic!("texture") };
        let sampler = Sampler::default();
        let mut worst = 0.0f32;
        for _ in 0..20_000 {
            let (u, v, lod) = ((rng.unit() - 0.25) * 3.0, (rng.unit() - 0.25) * 3.0, rng.unit() * 7.0 - 1.0);
            for filter in [Filter::Bilinear, Filter::Trilinear] {
                let fast = unpack(Tex::polygon(&chain, sampler, filter, lod).texel_uv(u, v));
                // Float filtering: bilinear in the nearest level, or the two levels around λ blended.
                let float = if filter == Filter::Bilinear {
                    chain.level(nearest_level(lod, chain.last_level())).sample_bilinear(u, v, sampler)
                } else {
                    let k = (lod.max(0.0) as usize).min(chain.last_level());
                    let f = if k < chain.last_level() { (lod - k as f32).max(0.0) } else { 0.0 };
                    let (a, b) = (
                        chain.level(k).sample_bilinear(u, v, sampler),
                        chain.level(k + 1).sample_bilinear(u, v, sampler),
                    );
                    std::array::from_fn(|c| a[c] + (b[c] - a[c]) * f)
                };
                for c in 0..4 {
                    worst = worst.max((fast[c] - float[c]).abs() * 255.0);
                }
            }
        }
        // The weights' 1/256 steps move a blend by at most 1/256 of a texel's range, and each of the three
        // (bilinear) or four (trilinear) roundings by half a level.
        assert!(worst <= 2.5, "worst difference {worst} levels");
        assert!(worst >= 0.5, "the integer filters round: some difference is expected, got {worst}");
    }

    #[test]
    fn trilinear_levels_at_known_scales() {
        assert_eq!(trilinear_levels(-1.0, 5), (0, 0));
        assert_eq!(trilinear_levels(f32::NAN, 5), (0, 0));
        assert_eq!(trilinear_levels(2.0, 5), (2, 0));
        assert_eq!(trilinear_levels(2.5, 5), (2, 128));
        assert_eq!(trilinear_levels(2.999, 5), (2, 255));
        assert_eq!(trilinear_levels(4.75, 5), (4, 192));
        assert_eq!(trilinear_levels(5.5, 5), (5, 0));
        assert_eq!(trilinear_levels(90.0, 5), (5, 0));
    }

    impl Tex<'_> {
        /// The texel at texture coordinates `(u, v)` (one pixel with `1/w` = 1), for the tests.
        fn texel_uv(&self, u: f32, v: f32) -> u32 {
            let (w, h) = (self.texture.width() as f32, self.texture.height() as f32);
            let s = Setup { d0: 0.0, dd: 0.0, q0: 1.0, dq: 0.0, s0: u, ds: 0.0, t0: v, dt: 0.0, w, h };
            self.texel_at(&s, 0.0)
        }
    }
}
