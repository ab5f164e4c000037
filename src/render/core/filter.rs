//! The texture filters a frame may draw with, and the filter a polygon is drawn with (`min-bilinear` and
//! `area` decided by the polygon's level of detail); how each one samples is [`super::texture`]'s.

/// Texture filtering used for every texture in a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Filter {
    /// The texel that contains the sample point (the default: exact, cheap, the retro look).
    #[default]
    Nearest,
    /// Weighted mean of the four nearest texel centres.
    Bilinear,
    /// Nearest texels on a polygon whose texture is magnified, bilinear ones on a polygon whose texture is
    /// minified (its level of detail above 0: more texels than samples), as OpenGL's `NEAREST`
    /// magnification with `LINEAR_MIPMAP_NEAREST` minification, decided once per polygon. Magnified
    /// texels stay the sharp squares the reference integrates, where bilinear ones would blur them; minified
    /// ones are reconstructed between the level's texel centres, where the nearest one would snap to a
    /// texel that the pixel's footprint only partly covers. Its level is chosen per polygon. A minified
    /// cut-out (alpha-masked) polygon keeps nearest texels ([`Filter::for_surface`]).
    MinBilinear,
    /// `min-bilinear` whose magnified texels are box-filtered over the pixel's footprint instead of
    /// taken nearest: across each texel edge the two texels are weighed by how much of the footprint each
    /// covers (the footprint's extent in texels measured at every pixel), so a texel stays a sharp square
    /// inside and its edge is the integral the reference converges to, where nearest steps at the sample.
    /// Minified polygons are drawn bilinear, as `min-bilinear` draws them (cut-outs too).
    Area,
    /// Bilinear in the two mip levels around the level of detail, blended by its fraction (bilinear in
    /// level 0 when mip-maps are off).
    Trilinear,
    /// Up to this many trilinear probes along the long axis of the pixel's footprint, at the level its
    /// short axis asks for ([`anisotropic`](super::anisotropic); one of
    /// [`ANISOTROPY`](super::anisotropic::ANISOTROPY)). It measures the footprint and chooses the level
    /// at every pixel, whatever the mip choice says.
    Anisotropic(u8),
}

impl Filter {
    /// Every filter, in the order the command line lists them.
    pub const ALL: [Filter; 9] = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::MinBilinear,
        Filter::Area,
        Filter::Trilinear,
        Filter::Anisotropic(2),
        Filter::Anisotropic(4),
        Filter::Anisotropic(8),
        Filter::Anisotropic(16),
    ];

    /// The command-line name (`anisoN` for up to `N` probes; a count outside
    /// [`ANISOTROPY`](super::anisotropic::ANISOTROPY) is named `aniso`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Filter::Nearest => "nearest",
            Filter::Bilinear => "bilinear",
            Filter::MinBilinear => "min-bilinear",
            Filter::Area => "area",
            Filter::Trilinear => "trilinear",
            Filter::Anisotropic(2) => "aniso2",
            Filter::Anisotropic(4) => "aniso4",
            Filter::Anisotropic(8) => "aniso8",
            Filter::Anisotropic(16) => "aniso16",
            Filter::Anisotropic(_) => "aniso",
        }
    }

    /// The filter a polygon whose level of detail is `lod` (before any mip bias) is drawn with:
    /// [`Filter::MinBilinear`] resolved to bilinear when `lod` is above 0 and to nearest otherwise,
    /// [`Filter::Area`] to bilinear when `lod` is above 0 and to itself otherwise, every other filter itself.
    #[must_use]
    pub fn for_polygon(self, lod: f32) -> Filter {
        match self {
            Filter::MinBilinear | Filter::Area if lod > 0.0 => Filter::Bilinear,
            Filter::MinBilinear => Filter::Nearest,
            f => f,
        }
    }

    /// The filter a polygon whose level of detail is `lod` is drawn with, when it is a cut-out (alpha-masked)
    /// if `cut_out`: [`Self::for_polygon`], except that `min-bilinear` keeps nearest texels on a minified
    /// cut-out (`area` keeps bilinear ones: with nearest its FLIP and shimmer were worse on every course, by
    /// 0.0002-0.0006 and 0.06-0.36, for 0.94x the time on the mountain and none saved elsewhere).
    ///
    /// Why: a cut-out's bilinear texels are blended before its alpha is tested, and its spans are short
    /// (a tree's card, a rail), so the four texels a pixel cost most there and buy least. On the mountain,
    /// whose trees are cut-outs, `ultra` with `min-bilinear`, LOD bias 1.5 and mip bias -1 took 3.70x the
    /// default's time with them bilinear and 3.20x with them nearest, at FLIP 0.0147 and 0.0148
    /// (docs/performance.md, "Bilinear where the texture is minified").
    #[must_use]
    pub fn for_surface(self, lod: f32, cut_out: bool) -> Filter {
        match self.for_polygon(lod) {
            Filter::Bilinear if cut_out && self == Filter::MinBilinear => Filter::Nearest,
            f => f,
        }
    }

    /// The most probes a pixel takes: 1, or `N` for `anisoN`.
    #[must_use]
    pub fn max_probes(self) -> u8 {
        match self {
            Filter::Anisotropic(n) => n.clamp(1, 16),
            _ => 1,
        }
    }
}

impl std::fmt::Display for Filter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::texture::{AREA_MIN_EXTENT, Sampler, Texture, area_weight};

    #[test]
    fn an_area_weight_is_bilinear_at_one_texel_and_the_box_s_share_below() {
        for a in 0..256 {
            // A footprint of a texel or more: the bilinear weight itself.
            assert_eq!(area_weight(a, 1.0), a);
            assert_eq!(area_weight(a, 7.0), a);
            assert_eq!(area_weight(a, f32::INFINITY), a);
            // Shorter: the share of a box `e` texels long centred at the sample that lies past the edge
            // at 128, rounded.
            for e in [0.5f32, 0.25, 0.1, AREA_MIN_EXTENT] {
                let past = ((f64::from(a) / 256.0 - 0.5) / f64::from(e) + 0.5).clamp(0.0, 1.0) * 256.0;
                assert!((f64::from(area_weight(a, e)) - past).abs() <= 0.5 + 1e-3, "{a} at {e}");
            }
            // No footprint to speak of (NaN, zero): the sharpest box, the nearest texel away from the edge.
            for e in [f32::NAN, 0.0, -1.0] {
                assert_eq!(area_weight(a, e), area_weight(a, AREA_MIN_EXTENT));
            }
        }
        assert_eq!(
            (area_weight(0, 0.5), area_weight(64, 0.5), area_weight(192, 0.5), area_weight(255, 0.5)),
            (0, 0, 256, 256)
        );
        assert_eq!(area_weight(128, 0.01), 128);
    }

    #[test]
    fn an_area_texel_is_the_box_integral_of_the_nearest_texels() {
        // Four texels across, black and white in turn; one row (a row repeats: no blend down).
        let Ok(t) = Texture::new(4, 1, vec![0xff00_0000, 0xffff_ffff, 0xff00_0000, 0xffff_ffff]) else {
            panic!("texture")
        };
        let sampler = Sampler::default();
        for e in [0.2f32, 0.5, 0.9] {
            for i in 0..400 {
                let x = 0.5 + f64::from(i) * (3.0 / 400.0); // texel coordinates, between the first and last centre
                // The white share of `[x - e/2, x + e/2]`: white on `[1, 2)` and `[3, 4)`.
                let lo = x - f64::from(e) / 2.0;
                let hi = lo + f64::from(e);
                let white: f64 =
                    [(1.0, 2.0), (3.0, 4.0)].iter().map(|&(a, b): &(f64, f64)| (hi.min(b) - lo.max(a)).max(0.0)).sum();
                let want = white / f64::from(e) * 255.0;
                let got = f64::from(t.area((x / 4.0) as f32, 0.5, [e, e], sampler) & 0xff);
                // The sample's position is floored to 1/256 of a texel, an error the box's `1/e` scales;
                // then the weight's and the blend's rounding.
                let within = 255.0 / (256.0 * f64::from(e)) + 1.5;
                assert!((got - want).abs() <= within, "x {x} extent {e}: {got} against {want}");
            }
        }
    }

    #[test]
    fn names_round_trip_and_min_bilinear_resolves_by_the_polygon_s_level() {
        for f in Filter::ALL {
            assert_eq!(f.name().parse::<Filter>(), Ok(f));
        }
        let err = "linear".parse::<Filter>().map(|_| ()).unwrap_err().to_string();
        assert!(err.contains("min-bilinear"), "{err}");
        // Above 0 (minified) bilinear; at 0, and for NaN, nearest; the other filters are themselves.
        for (lod, want) in [(1.0 / 16.0, Filter::Bilinear), (7.5, Filter::Bilinear), (0.0, Filter::Nearest)] {
            assert_eq!(Filter::MinBilinear.for_polygon(lod), want, "{lod}");
        }
        assert_eq!(Filter::MinBilinear.for_polygon(f32::NAN), Filter::Nearest);
        // `area` likewise minified, and itself (measured at each pixel) otherwise.
        assert_eq!(Filter::Area.for_polygon(1.0 / 16.0), Filter::Bilinear);
        assert_eq!(Filter::Area.for_polygon(0.0), Filter::Area);
        assert_eq!(Filter::Area.for_polygon(f32::NAN), Filter::Area);
        // A minified cut-out keeps nearest texels under `min-bilinear`; nothing else changes for a cut-out.
        for f in Filter::ALL {
            for lod in [0.0, 1.0 / 16.0, 3.0, f32::NAN] {
                let want = match (f, f.for_polygon(lod)) {
                    (Filter::MinBilinear, Filter::Bilinear) => Filter::Nearest,
                    (_, g) => g,
                };
                assert_eq!(f.for_surface(lod, true), want, "{f} at {lod}");
                assert_eq!(f.for_surface(lod, false), f.for_polygon(lod), "{f} at {lod}");
            }
        }
        assert_eq!(Filter::MinBilinear.for_surface(3.0, true), Filter::Nearest);
        assert_eq!(Filter::Area.for_surface(3.0, true), Filter::Bilinear);
        for f in Filter::ALL.into_iter().filter(|&f| !matches!(f, Filter::MinBilinear | Filter::Area)) {
            assert_eq!(f.for_polygon(3.0), f);
            assert_eq!(f.for_polygon(0.0), f);
        }
    }
}
