//! The texture filters a frame may draw with, and the filter a polygon is drawn with (`min-bilinear`
//! decided by the polygon's level of detail); how each one samples is [`super::texture`]'s.

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
    /// texel that the pixel's footprint only partly covers. Its level is chosen per polygon.
    MinBilinear,
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
    pub const ALL: [Filter; 8] = [
        Filter::Nearest,
        Filter::Bilinear,
        Filter::MinBilinear,
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
            Filter::Trilinear => "trilinear",
            Filter::Anisotropic(2) => "aniso2",
            Filter::Anisotropic(4) => "aniso4",
            Filter::Anisotropic(8) => "aniso8",
            Filter::Anisotropic(16) => "aniso16",
            Filter::Anisotropic(_) => "aniso",
        }
    }

    /// The filter a polygon whose level of detail is `lod` (before any mip bias) is drawn with:
    /// [`Filter::MinBilinear`] resolved to bilinear when `lod` is above 0 and to nearest otherwise, every
    /// other filter itself.
    #[must_use]
    pub fn for_polygon(self, lod: f32) -> Filter {
        match self {
            Filter::MinBilinear if lod > 0.0 => Filter::Bilinear,
            Filter::MinBilinear => Filter::Nearest,
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
        for f in Filter::ALL.into_iter().filter(|&f| f != Filter::MinBilinear) {
            assert_eq!(f.for_polygon(3.0), f);
            assert_eq!(f.for_polygon(0.0), f);
        }
    }
}
