//! Span drawing: per pixel, the visibility test, texture and colour, alpha mask, and the write.
//!
//! Part of the fill, the `d_*` half of the renderer (as Quake split it): it knows spans, textures and the
//! buffers of one row, nothing of polygons, cameras or meshes.

use super::row::{Row, SpanCounts, Visibility};
use super::scanline::Span;
use super::span_lanes::{self, Source};
use super::texel::Tex;
use crate::render::core::anisotropic::{self, Probes};
use crate::render::core::door::Door;
use crate::render::core::mip::TexGradients;
use crate::render::core::options::{MipMode, SUBDIVISION, TextureMode};
use crate::render::core::polygon::{FastPathRule, pack_rgb};
use crate::render::core::texture::{Filter, Sampler, Texture, unpack};
use crate::render::core::vertex::{ATTRS, slot};

/// Everything a span needs to shade its pixels.
#[derive(Clone, Copy, Debug)]
pub struct Shading<'a> {
    /// The texture, if any.
    pub texture: Option<&'a Texture>,
    /// Its wrap modes.
    pub sampler: Sampler,
    /// Nearest, bilinear, trilinear or anisotropic.
    pub filter: Filter,
    /// Where the mip level is chosen (as [`MipMode::with_filter`] gives it: per pixel for an anisotropic
    /// filter with mip-maps on).
    pub mip: MipMode,
    /// The polygon's level of detail `λ`, chosen at set-up ([`MipMode::Polygon`]; 0 otherwise).
    pub lod: f32,
    /// The polygon's `1/w`, `s/w`, `t/w` planes ([`MipMode::Span`] and [`MipMode::Pixel`] measure `λ` by them).
    pub gradients: TexGradients,
    /// Interpolation of texture coordinates and colours.
    pub mode: TextureMode,
    /// Alpha cutoff for `alphaMode` MASK.
    pub alpha_cutoff: Option<f32>,
    /// The visibility rule.
    pub visibility: Visibility,
    /// The polygon's colour when all its vertices share one (enables the fast paths below).
    pub constant_color: Option<[f32; 4]>,
    /// The screen door: the pixels it hides are left alone (nothing is written or marked on them).
    pub door: Door,
}

/// Texture coordinate and colour at one pixel: `[u, v, r, g, b, a]`.
pub(crate) type Surface = [f32; 6];

/// The surface values at pixel offset `k` of a span whose attributes start at `a0` and change by `da` a
/// pixel, divided by `1/w` when `perspective`.
#[inline]
pub(crate) fn exact_at(a0: &[f32; ATTRS], da: &[f32; ATTRS], k: f32, perspective: bool) -> Surface {
    let at = |i: usize| a0[i] + k * da[i];
    let w = if perspective { 1.0 / at(slot::Q) } else { 1.0 };
    let r = slot::RGBA;
    [at(slot::S) * w, at(slot::T) * w, at(r) * w, at(r + 1) * w, at(r + 2) * w, at(r + 3) * w]
}

/// `1/w`, `s/w`, `t/w` at pixel offset `k` of a span whose attributes start at `a0` and change by `da`.
#[inline]
pub(crate) fn qst_at(a0: &[f32; ATTRS], da: &[f32; ATTRS], k: f32) -> [f32; 3] {
    [a0[slot::Q] + k * da[slot::Q], a0[slot::S] + k * da[slot::S], a0[slot::T] + k * da[slot::T]]
}

impl Shading<'_> {
    /// The level of detail `λ` for a pixel whose `1/w`, `s/w`, `t/w` are `qst`: 0 with mip-maps off, the
    /// polygon's with [`MipMode::Polygon`], else the texel footprint there (a span's caller asks once, at
    /// its middle pixel, for [`MipMode::Span`]). The `lod` `shade_surface` takes.
    #[inline]
    #[must_use]
    pub fn lod_at(&self, qst: [f32; 3]) -> f32 {
        match (self.mip, self.texture) {
            (MipMode::Off, _) | (_, None) => 0.0,
            (MipMode::Polygon, _) => self.lod,
            (MipMode::Span | MipMode::Pixel, Some(t)) => self.gradients.lod_at(qst, (t.width(), t.height())),
        }
    }

    /// How the texture is sampled at a pixel whose `1/w`, `s/w`, `t/w` are `qst`: by the anisotropic
    /// filter's probes, measured there, for levels chosen per pixel; by `area`'s footprint extent measured
    /// there; else at [`lod_at`](Self::lod_at). The
    /// `footprint` `shade_surface` takes.
    #[inline]
    #[must_use]
    pub(crate) fn footprint_at(&self, qst: [f32; 3]) -> Footprint {
        match (self.filter, self.mip, self.texture) {
            (Filter::Anisotropic(max), MipMode::Pixel, Some(t)) => {
                let w = 1.0 / qst[0];
                Footprint::Probes(anisotropic::probes(&self.gradients, w, (qst[1] * w, qst[2] * w), t, max))
            }
            (Filter::Area, _, Some(t)) => Footprint::Area(self.gradients.extent_at(qst, (t.width(), t.height()))),
            _ => Footprint::Lod(self.lod_at(qst)),
        }
    }
}

/// How a pixel's texture is sampled: at a level of detail by the filter, by anisotropic probes, or by
/// `area`'s box of a measured extent.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Footprint {
    /// The level of detail `λ` ([`Shading::lod_at`]).
    Lod(f32),
    /// The anisotropic filter's probes.
    Probes(Probes),
    /// The `area` filter's footprint extent in level-0 texels, across and down.
    Area([f32; 2]),
}

/// The colour of a pixel with surface values `s` (texture coordinate and colour, perspective already
/// divided out) sampled as `footprint` says ([`Shading::footprint_at`]), packed `0x00RRGGBB`; `None` where the
/// alpha cutoff rejects it. Shared by the general span and the anti-aliased fill, which shade a pixel the
/// same way.
#[inline]
pub(crate) fn shade_surface(sh: &Shading<'_>, s: &Surface, footprint: &Footprint) -> Option<u32> {
    let texel = match (sh.texture, footprint) {
        (None, _) => [1.0; 4],
        (Some(t), Footprint::Probes(p)) => unpack(p.sample(t, (s[0], s[1]), sh.sampler)),
        (Some(t), Footprint::Area(e)) => unpack(t.area(s[0], s[1], *e, sh.sampler)),
        (Some(t), &Footprint::Lod(lod)) => t.sample(sh.filter, lod, s[0], s[1], sh.sampler),
    };
    // A polygon of one colour uses it as is (interpolating it would only add rounding).
    let col = sh.constant_color.unwrap_or([s[2], s[3], s[4], s[5]]);
    let c = [texel[0] * col[0], texel[1] * col[1], texel[2] * col[2], texel[3] * col[3]];
    if let Some(cutoff) = sh.alpha_cutoff {
        // NaN alpha fails the test too: nothing is drawn from a broken colour.
        if c[3].partial_cmp(&cutoff).is_none_or(std::cmp::Ordering::is_lt) {
            return None;
        }
    }
    Some(pack_rgb(c))
}

/// How a polygon's spans are drawn, chosen once per polygon from its [`Shading`].
#[derive(Clone, Copy)]
pub struct Prepared<'a> {
    /// The fast path's colour source and alpha mask (the polygon's alpha and the cutoff), if one applies.
    fast: Option<(Source<'a>, Option<(f32, f32)>)>,
}

impl Prepared<'_> {
    /// The fast path's colour source and alpha mask, if one applies (spans then need only the first four
    /// attributes, depth, `1/w`, `u/w`, `v/w`, or only depth for a flat colour).
    pub(crate) fn fast(&self) -> Option<(Source<'_>, Option<(f32, f32)>)> {
        self.fast
    }
}

impl<'a> Shading<'a> {
    /// Chooses the fast path (if any) for spans with this shading.
    #[must_use]
    pub fn prepare(&self) -> Prepared<'a> {
        debug_assert_eq!(self.mip, self.mip.with_filter(self.filter), "an anisotropic filter's levels are per pixel");
        let rule = FastPathRule { filter: self.filter, mode: self.mode, mip: self.mip };
        let fast = rule.applies(
            self.texture.is_some(),
            self.constant_color.is_some(),
            self.alpha_cutoff.is_some(),
            !self.door.is_none(),
        );
        // The rule gives a textured polygon a fast path with one level for it, its level's texture (texture
        // coordinates are normalised, so the same ones address every level), or with the level chosen per
        // pixel, the whole chain and the polygon's gradients.
        // With levels per span, the chain and gradients too: `draw_prepared` picks each span's level (and
        // the anti-aliased fill, whose pixels are not spans, measures at each pixel).
        let tex = |t: &'a Texture| match self.mip {
            // `area` measures its footprint at every pixel of its polygon's level.
            MipMode::Pixel | MipMode::Span => Tex::per_pixel(t, self.sampler, self.filter, self.gradients),
            _ if self.filter == Filter::Area => Tex::per_pixel(t, self.sampler, self.filter, self.gradients),
            _ => Tex::polygon(t, self.sampler, self.filter, self.lod_at([1.0, 0.0, 0.0])),
        };
        // Which fast path, for a polygon the rule gives one.
        let source = match (self.texture.map(tex), self.constant_color) {
            _ if !fast => None,
            (None, Some(c)) => Some(Source::Flat(pack_rgb(c))),
            (Some(t), Some([1.0, 1.0, 1.0, _])) => Some(Source::Texel(t)),
            (Some(t), Some(c)) => {
                // `as u32` saturates (NaN and negatives to 0); colours above 1 are clamped to 1 as packing would.
                let fx16 = |c: f32| ((c.min(1.0) * 65536.0 + 0.5) as u32).min(65536);
                Some(Source::Tinted(t, [fx16(c[0]), fx16(c[1]), fx16(c[2])]))
            }
            (_, None) => None,
        };
        debug_assert_eq!(source.is_some(), fast);
        let alpha = self.alpha_cutoff.zip(self.constant_color).map(|(cutoff, c)| (c[3], cutoff));
        Prepared { fast: source.map(|s| (s, alpha)) }
    }
}

/// Draws one span into a row and returns the pixel counts.
pub fn draw_span(span: &Span, sh: &Shading<'_>, row: &mut Row<'_>) -> SpanCounts {
    draw_prepared(span, sh, &sh.prepare(), row)
}

/// Draws one span with the path chosen by [`Shading::prepare`] (`prepared` must come from `sh`).
pub fn draw_prepared(span: &Span, sh: &Shading<'_>, prepared: &Prepared<'_>, row: &mut Row<'_>) -> SpanCounts {
    match prepared.fast {
        Some((source, alpha)) if sh.mip == MipMode::Span => {
            // The span's level, measured at its middle pixel as the general span measures it.
            let lod = sh.lod_at(qst_at(&span.a0, &span.da, ((span.x1 - span.x0) / 2) as f32));
            span_lanes::draw(span, source.at_lod(lod), alpha, sh.visibility, row)
        }
        Some((source, alpha)) => span_lanes::draw(span, source, alpha, sh.visibility, row),
        None => draw_general(span, sh, row),
    }
}

/// The general span: any texture mode, filter, vertex colours, alpha mask and screen door.
fn draw_general(span: &Span, sh: &Shading<'_>, row: &mut Row<'_>) -> SpanCounts {
    let mut counts = SpanCounts::default();
    let n = span.x1 - span.x0;
    let (a0, da) = (&span.a0, &span.da);
    // Subdivided mode: exact values at both ends of each segment, linear between them.
    let mut seg_start = i32::MIN;
    let mut seg_base: Surface = [0.0; 6];
    let mut seg_step: Surface = [0.0; 6];
    // λ for the whole span, unless the footprint is measured at every pixel.
    let span_footprint = sh.footprint_at(qst_at(a0, da, (n / 2) as f32));
    let per_pixel = (sh.mip == MipMode::Pixel || sh.filter == Filter::Area) && sh.texture.is_some();
    for k in 0..n {
        let x = (span.x0 + k) as usize;
        if sh.door.hides(span.x0 + k, span.y) {
            continue;
        }
        let kf = k as f32;
        let depth = a0[slot::DEPTH] + kf * da[slot::DEPTH];
        match sh.visibility {
            Visibility::Overwrite => {}
            Visibility::DepthTest => {
                // Strictly nearer wins, so on equal depth the polygon drawn first stays (like GL_LESS).
                if depth.partial_cmp(&row.depth[x]) != Some(std::cmp::Ordering::Greater) {
                    counts.rejected += 1;
                    continue;
                }
            }
            Visibility::Coverage => {
                if row.coverage[x >> 6] & (1u64 << (x & 63)) != 0 {
                    counts.rejected += 1;
                    continue;
                }
            }
        }
        let s = match sh.mode {
            TextureMode::Perspective => exact_at(a0, da, kf, true),
            TextureMode::Affine => exact_at(a0, da, kf, false),
            TextureMode::Subdivided => {
                if k >= seg_start.saturating_add(SUBDIVISION) || seg_start == i32::MIN {
                    seg_start = k - k % SUBDIVISION;
                    let last = (seg_start + SUBDIVISION - 1).min(n - 1);
                    seg_base = exact_at(a0, da, seg_start as f32, true);
                    let end = exact_at(a0, da, last as f32, true);
                    let len = (last - seg_start).max(1) as f32;
                    for i in 0..6 {
                        seg_step[i] = (end[i] - seg_base[i]) / len;
                    }
                }
                let t = (k - seg_start) as f32;
                let mut s = [0.0; 6];
                for i in 0..6 {
                    s[i] = seg_base[i] + t * seg_step[i];
                }
                s
            }
        };
        counts.shaded += 1;
        let footprint = if per_pixel { sh.footprint_at(qst_at(a0, da, kf)) } else { span_footprint };
        let Some(c) = shade_surface(sh, &s, &footprint) else { continue };
        row.color[x] = c;
        counts.written += 1;
        match sh.visibility {
            Visibility::Overwrite => {}
            Visibility::DepthTest => row.depth[x] = depth,
            Visibility::Coverage => row.coverage[x >> 6] |= 1u64 << (x & 63),
        }
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn prepare_gives_a_fast_path_exactly_to_flat_polygons_and_perspective_textures() {
        let texture = Texture::from_rgba8(2, 2, &[255; 16]).unwrap();
        for mip in MipMode::ALL {
            // A textured polygon takes a fast path under every filter and mip choice.
            assert_eq!(fast_paths(&texture, mip), 16, "{mip}");
        }
    }

    /// How many of the 128 combinations of filter, mode, texture, cutoff, colour and screen door take a fast
    /// path under `mip`, checking that the rule and `prepare` agree on each.
    fn fast_paths(texture: &Texture, mip: MipMode) -> usize {
        let mut fast = 0;
        for bits in 0..128u32 {
            let bit = |k: u32| bits >> k & 1 == 1;
            let rule = FastPathRule {
                filter: if bit(0) { Filter::Bilinear } else { Filter::Nearest },
                mode: if bit(1) { TextureMode::Subdivided } else { TextureMode::Perspective },
                mip,
            };
            let sh = Shading {
                texture: bit(2).then_some(texture),
                sampler: Sampler::default(),
                filter: rule.filter,
                mip: rule.mip,
                lod: 0.0,
                gradients: TexGradients::default(),
                mode: rule.mode,
                alpha_cutoff: bit(3).then_some(0.5),
                visibility: Visibility::DepthTest,
                constant_color: bit(4).then_some(if bit(5) { [1.0; 4] } else { [0.5, 0.2, 0.1, 0.7] }),
                door: if bit(6) { Door::CHECKERBOARD } else { Door::NONE },
            };
            let expected = sh.prepare().fast().is_some();
            assert_eq!(rule.applies(bit(2), bit(4), bit(3), bit(6)), expected, "combination {bits:07b}");
            // Set-up makes small triangles for a fast path with one nearest level for the polygon only.
            let one_level = matches!(mip, MipMode::Off | MipMode::Polygon);
            let small = expected && !(bit(2) && (!one_level || bit(0)));
            assert_eq!(rule.small_triangles(bit(2), bit(4), bit(3), bit(6)), small, "combination {bits:07b}");
            fast += usize::from(expected);
        }
        // Flat without a cutoff under any filter and mode, white or not (8); textured with perspective
        // sampling, nearest or bilinear, with or without a cutoff, white or tinted (8).
        fast
    }

    #[test]
    fn levels_chosen_per_span_or_pixel_draw_what_the_general_span_draws() {
        use crate::render::core::test_rng::Lcg;
        let mut rng = Lcg(3);
        // 64x16 down to 1x1: seven levels, each texel random.
        let texture = Texture::new(64, 16, (0..64 * 16).map(|_| rng.next() | 0xff00_0000).collect()).unwrap();
        let mut unit = |scale: f32| (rng.unit() - 0.5) * scale;
        for case in 0..1200 {
            let filter =
                [Filter::Nearest, Filter::Bilinear, Filter::Trilinear, Filter::Anisotropic(8), Filter::Area][case % 5];
            // `area`'s planes magnified (footprints of a few tenths of a texel), so its weights are sharpened.
            let k = if filter == Filter::Area { 0.004 } else { 1.0 };
            let gradients = TexGradients {
                dx: [unit(0.01 * k), unit(0.5 * k), unit(0.5 * k)],
                dy: [unit(0.01 * k), unit(0.5 * k), unit(0.5 * k)],
            };
            // Levels per span for every other case (an anisotropic filter's are always per pixel; `area`
            // measures its footprint at every pixel of the polygon's level).
            let mip = match filter {
                Filter::Area => MipMode::Polygon,
                Filter::Anisotropic(_) => MipMode::Pixel,
                _ if case % 3 == 0 => MipMode::Pixel,
                _ => MipMode::Span,
            };
            let sh = Shading {
                texture: Some(&texture),
                sampler: Sampler::default(),
                filter,
                mip,
                lod: 0.0,
                gradients,
                mode: TextureMode::Perspective,
                alpha_cutoff: None,
                visibility: Visibility::DepthTest,
                constant_color: Some([1.0; 4]),
                door: Door::NONE,
            };
            let prepared = sh.prepare();
            assert!(prepared.fast().is_some(), "a white texture with levels per span or pixel has a fast path");
            let mut a0 = [0.0; ATTRS];
            let mut da = [0.0; ATTRS];
            (a0[slot::DEPTH], da[slot::DEPTH]) = (unit(2.0), unit(0.1));
            (a0[slot::Q], da[slot::Q]) = (0.2 + unit(0.3).abs(), gradients.dx[0]);
            (a0[slot::S], da[slot::S]) = (unit(8.0), gradients.dx[1]);
            (a0[slot::T], da[slot::T]) = (unit(8.0), gradients.dx[2]);
            let span = Span { y: 0, x0: 3, x1: 3 + 1 + (case % 40) as i32, a0, da };
            let depth: Vec<f32> = (0..48).map(|_| unit(2.0)).collect();
            let draw = |general: bool| {
                let (mut color, mut depth) = (vec![0u32; 48], depth.clone());
                let row = &mut Row { color: &mut color, depth: &mut depth, coverage: &mut [] };
                let counts =
                    if general { draw_general(&span, &sh, row) } else { draw_prepared(&span, &sh, &prepared, row) };
                (color, depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>(), counts)
            };
            assert_eq!(draw(false), draw(true), "case {case}: {} {} {gradients:?}", sh.filter, sh.mip);
        }
    }

    #[test]
    fn packing_rounds_and_clamps() {
        assert_eq!(pack_rgb([1.0, 0.5, 0.0, 1.0]), 0x00ff_8000);
        assert_eq!(pack_rgb([2.0, -1.0, f32::NAN, 1.0]), 0x00ff_0000);
        // Against one channel at a time, around every level's rounding boundary and at the extremes.
        let one = |v: f32| (v * 255.0 + 0.5).clamp(0.0, 255.0) as u32;
        let mut values = vec![f32::NAN, f32::INFINITY, f32::NEG_INFINITY, f32::MAX, -0.0, 0.0, 1.0, 2.0, -1e30];
        for level in 0..=256 {
            let b = (level as f32 - 0.5) / 255.0;
            values.extend([b, f32::from_bits(b.to_bits() + 1), f32::from_bits(b.to_bits().wrapping_sub(1))]);
        }
        // And a dense sweep over -0.1..1.1.
        values.extend((0..200_000).map(|i| -0.1 + i as f32 * (1.2 / 200_000.0)));
        for &v in &values {
            for (i, shift) in [16, 8, 0].into_iter().enumerate() {
                let mut c = [0.25; 4];
                c[i] = v;
                assert_eq!((pack_rgb(c) >> shift) & 0xff, one(v), "{v:e} in channel {i}");
            }
        }
    }
}
