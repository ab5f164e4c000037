//! Quality presets: the picture settings (texture filter, mip-level choice, anti-aliasing, level-of-detail
//! cross-fade, level-of-detail and mip biases) named as steps of one ladder, so a player, a test and a
//! script say `high` instead of six flags.
//!
//! Each step is a point of the bench's speed-against-accuracy front on every course (docs/performance.md,
//! "Quality presets"): no other setting measured is both faster and closer to the reference. The steps
//! leave everything else (visibility method, level of detail, threads) as the options had it.

use std::fmt;
use std::str::FromStr;

use super::options::{Antialias, MipMode, RenderOptions, UnknownName};
use super::texture::Filter;

/// The mip bias of the steps above the bottom one: each polygon's level is the finer of the two nearest
/// its level of detail (rounded down instead of to the nearest). Against the converged reference it took
/// 0.0003-0.0014 off the FLIP mean of `ultra` and of the mountain's `medium` and `high`, and moved the
/// city's by at most 0.0001 (docs/performance.md, "Quality presets"); `low` keeps the renderer's default.
const FINER: f32 = -0.5;

/// The top step's mip bias: a level finer than the nearest, under its bilinear texels on minified polygons
/// (with four samples a pixel a bilinear texel's blend widens each sample, and the finer level keeps the
/// detail the samples then average: FLIP 0.0150 against 0.0151 at -0.5 on the city, 0.0118 against 0.0120
/// on the circuit).
const FINEST: f32 = -1.0;

/// A named step of the picture ladder, cheapest first.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Quality {
    /// No anti-aliasing, nearest texels of the mip level chosen once per polygon, models swapped at once:
    /// the renderer's default.
    #[default]
    Low,
    /// As `low`, with `area` texels (minified textures bilinear, magnified ones box-filtered over the
    /// pixel: each texel a sharp square whose edges take the share of the pixel each side covers), finer
    /// models kept twice as far (LOD bias +1) and level-of-detail changes cross-faded.
    Medium,
    /// 2x2 supersampling (edges and texture detail both sampled four times a pixel) with `medium`'s models,
    /// mip bias and cross-fades, and nearest texels: with four samples a pixel `min-bilinear` cost as much
    /// as the rotated grid's `ultra` with nearest texels and `area` more, each for no better a picture,
    /// which would leave this step off the front.
    High,
    /// As `high` with the four samples on a rotated grid (four rows and four columns of them, where 2x2 has
    /// two of each), `min-bilinear` texels a level finer still (mip bias -1) and finer models kept farther
    /// (LOD bias 1.5): the most accurate and steadiest picture within 3.5x the bottom step's time. On a
    /// rotated grid a minified texture's four samples a pixel are too few for nearest texels, which snap to
    /// texels the pixel only partly covers; bilinear ones, interpolated, come within the reference's
    /// FLIP 0.015 on every course (docs/performance.md, "Quality presets").
    Ultra,
}

impl Quality {
    /// Every step, cheapest first.
    pub const ALL: [Quality; 4] = [Quality::Low, Quality::Medium, Quality::High, Quality::Ultra];

    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Quality::Low => "low",
            Quality::Medium => "medium",
            Quality::High => "high",
            Quality::Ultra => "ultra",
        }
    }

    /// The texture filter, mip-level choice, anti-aliasing, level-of-detail cross-fade, LOD bias and mip
    /// bias of this step, in that order.
    #[must_use]
    pub fn picture(self) -> (Filter, MipMode, Antialias, bool, f32, f32) {
        let (nearest, mixed, polygon) = (Filter::Nearest, Filter::Area, MipMode::Polygon);
        match self {
            Quality::Low => (nearest, polygon, Antialias::Off, false, 0.0, 0.0),
            Quality::Medium => (mixed, polygon, Antialias::Off, true, 1.0, FINER),
            Quality::High => (nearest, polygon, Antialias::Supersample2x2, true, 1.0, FINER),
            Quality::Ultra => (Filter::MinBilinear, polygon, Antialias::RotatedGrid, true, 1.5, FINEST),
        }
    }

    /// `options` with this step's picture settings (the rest as `options` has them).
    #[must_use]
    pub fn apply(self, options: RenderOptions) -> RenderOptions {
        let (filter, mip, antialias, lod_fade, lod_bias, mip_bias) = self.picture();
        RenderOptions { filter, mip, antialias, lod_fade, lod_bias, mip_bias, ..options }
    }

    /// The step whose picture settings `options` has, if one does.
    #[must_use]
    pub fn of(options: &RenderOptions) -> Option<Quality> {
        let o = options;
        let picture = (o.filter, o.mip, o.antialias, o.lod_fade, o.lod_bias, o.mip_bias);
        Quality::ALL.into_iter().find(|q| q.picture() == picture)
    }

    /// The next step up, if there is one.
    #[must_use]
    pub fn up(self) -> Option<Quality> {
        Quality::ALL.get(self as usize + 1).copied()
    }

    /// The next step down, if there is one.
    #[must_use]
    pub fn down(self) -> Option<Quality> {
        (self as usize).checked_sub(1).and_then(|i| Quality::ALL.get(i).copied())
    }
}

impl fmt::Display for Quality {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Quality {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Quality::ALL
            .into_iter()
            .find(|q| q.name() == s)
            .ok_or_else(|| UnknownName::new("quality", s, "low, medium, high or ultra"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_unknown_names_list_the_choices() {
        for q in Quality::ALL {
            assert_eq!(q.name().parse::<Quality>(), Ok(q));
            assert_eq!(Quality::of(&q.apply(RenderOptions::default())), Some(q));
        }
        let err = "best".parse::<Quality>().map(|_| ()).unwrap_err();
        assert_eq!(err.to_string(), "unknown quality 'best' (expected low, medium, high or ultra)");
    }

    #[test]
    fn the_bottom_step_is_the_renderer_s_default_and_steps_climb_one_at_a_time() {
        assert_eq!(Quality::of(&RenderOptions::default()), Some(Quality::Low));
        assert_eq!(Quality::Low.down(), None);
        assert_eq!(Quality::Ultra.up(), None);
        let climbed: Vec<Quality> = std::iter::successors(Some(Quality::Low), |q| q.up()).collect();
        assert_eq!(climbed, Quality::ALL);
        let kept = RenderOptions { threads: 3, lod_bias: 2.0, buckets: 64, ..RenderOptions::default() };
        let high = Quality::High.apply(kept);
        assert_eq!((high.threads, high.buckets), (3, 64));
        assert_eq!((high.lod_bias, high.antialias, high.lod_fade), (1.0, Antialias::Supersample2x2, true));
        let ultra = Quality::Ultra.apply(kept);
        assert_eq!((ultra.lod_bias, ultra.antialias, ultra.lod_fade), (1.5, Antialias::RotatedGrid, true));
        assert_eq!((ultra.filter, ultra.mip_bias), (Filter::MinBilinear, -1.0));
        // Above the bottom step, the finer of the two nearest mip levels, and the top one a level finer; the
        // bottom keeps the default's.
        let biases = Quality::ALL.map(|q| q.apply(kept).mip_bias);
        assert_eq!(biases, [0.0, -0.5, -0.5, -1.0]);
        // `medium` filters its texels (`area`: bilinear where minified, box-filtered where magnified), and
        // `ultra` (`min-bilinear`: bilinear where minified, nearest where magnified).
        let (nearest, mixed, min) = (Filter::Nearest, Filter::Area, Filter::MinBilinear);
        assert_eq!(Quality::ALL.map(|q| q.apply(kept).filter), [nearest, mixed, nearest, min]);
        let mut custom = ultra;
        custom.mip_bias = 0.0;
        assert_eq!(Quality::of(&custom), None, "a picture with another mip bias is no preset");
    }
}
