//! How a frame is to be drawn: the visibility method and its settings, chosen per frame by the caller.

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

use crate::render::core::texture::Filter;

/// How visibility is resolved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Per-pixel depth test (`1/w`): the accuracy reference, and the default: it is exact, and on the game's
    /// frames no painter's method is faster than it by more than noise (the README's bench section).
    #[default]
    ZBuffer,
    /// Exact stable sort of polygons by key, drawn far to near.
    Sort,
    /// Ordering table chained far to near, painter's algorithm.
    BucketFar,
    /// Ordering table chained near to far, each pixel shaded at most once.
    BucketNear,
    /// Orders made in advance per view direction for rigid meshes (seed 004), objects placed with the
    /// ordering table far to near; meshes without stored lists are ordered per polygon as `bucket-far`.
    ViewLists,
}

impl Method {
    /// Every method, in the order the command line lists them.
    pub const ALL: [Method; 5] =
        [Method::ZBuffer, Method::Sort, Method::BucketFar, Method::BucketNear, Method::ViewLists];

    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::ZBuffer => "zbuffer",
            Method::Sort => "sort",
            Method::BucketFar => "bucket-far",
            Method::BucketNear => "bucket-near",
            Method::ViewLists => "view-lists",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A setting's name that is not one of its values, as the command line and settings file give them.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[error("unknown {setting} '{given}' (expected {expected})")]
pub struct UnknownName {
    /// Which setting: "method", "key", "level of detail", "filter", "mip level choice".
    pub setting: &'static str,
    /// The name given.
    pub given: String,
    /// The names it may be.
    pub expected: &'static str,
}

impl UnknownName {
    pub(crate) fn new(setting: &'static str, given: &str, expected: &'static str) -> Self {
        Self { setting, given: given.to_owned(), expected }
    }
}

impl FromStr for Method {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownName::new("method", s, "zbuffer, sort, bucket-far, bucket-near or view-lists"))
    }
}

impl FromStr for Filter {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Filter::ALL.into_iter().find(|f| f.name() == s).ok_or_else(|| {
            UnknownName::new(
                "filter",
                s,
                "nearest, bilinear, min-bilinear, area, trilinear, aniso2, aniso4, aniso8 or aniso16",
            )
        })
    }
}

/// Where a textured pixel's mip level ([`mip`](super::mip)) is chosen: each a point of the speed against
/// accuracy chart, from no mip-maps (the default: today's frames, and the fast paths) to OpenGL's level of
/// detail at every pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MipMode {
    /// Level 0 everywhere (far surfaces alias).
    Off,
    /// Once per polygon at set-up, from its area in texels over its area in pixels (as Quake chose a
    /// surface's level); the nearest filter keeps the fast paths, handed that level's texture. The default:
    /// the knee of the bench within the frame-time budget (as fast as `off`, less error and shimmer).
    #[default]
    Polygon,
    /// Once per span, from the texel footprint at its middle pixel.
    Span,
    /// At every pixel, from its texel footprint (`λ` of OpenGL).
    Pixel,
}

impl MipMode {
    /// Every mode, in the order the command line lists them.
    pub const ALL: [MipMode; 4] = [MipMode::Off, MipMode::Polygon, MipMode::Span, MipMode::Pixel];

    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            MipMode::Off => "off",
            MipMode::Polygon => "polygon",
            MipMode::Span => "span",
            MipMode::Pixel => "pixel",
        }
    }
}

impl MipMode {
    /// The choice a frame makes with `filter`: an anisotropic filter chooses its level at every pixel (the
    /// level where its probes' boxes fit a texel is part of the filter), so with it every choice is `pixel`;
    /// `min-bilinear` and `area` decide by the polygon's level of detail, so with them every choice is
    /// `polygon`.
    #[must_use]
    pub fn with_filter(self, filter: Filter) -> MipMode {
        match filter {
            Filter::Anisotropic(_) => MipMode::Pixel,
            Filter::MinBilinear | Filter::Area => MipMode::Polygon,
            _ => self,
        }
    }
}

impl fmt::Display for MipMode {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for MipMode {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        MipMode::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| UnknownName::new("mip level choice", s, "off, polygon, span or pixel"))
    }
}

/// The representative depth of a polygon for ordering.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DepthKey {
    /// Mean of the vertices' depths (seed claim 2).
    Avg,
    /// Nearest vertex (seed claim 3).
    Min,
    /// Farthest vertex: the default, best on the game's frames in the bench (fewest pixels differing from
    /// the z-buffer for `sort` and both bucket methods; a big road polygon sorts by its far end, so the cars
    /// standing on it are drawn after it).
    #[default]
    Max,
}

impl FromStr for DepthKey {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "avg" => Ok(DepthKey::Avg),
            "min" => Ok(DepthKey::Min),
            "max" => Ok(DepthKey::Max),
            _ => Err(UnknownName::new("key", s, "avg, min or max")),
        }
    }
}

/// Default number of ordering-table buckets; see the README for why.
pub const DEFAULT_BUCKETS: usize = 1024;

/// Most worker threads a frame is drawn with: more only cut the frame into bands too thin to pay for
/// their start, and thousands took a minute to start before failing.
pub const MAX_THREADS: usize = 256;

/// Settings for one frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Visibility method.
    pub method: Method,
    /// Ordering-table buckets (`bucket-far`, `bucket-near`).
    pub buckets: usize,
    /// Representative depth (`sort`, `bucket-*`).
    pub key: DepthKey,
    /// Depth-to-bucket mapping.
    pub mapping: BucketMapping,
    /// Texture-coordinate interpolation.
    pub texture_mode: TextureMode,
    /// Texture filtering.
    pub filter: Filter,
    /// Where mip levels are chosen (off: level 0 only).
    pub mip: MipMode,
    /// Worker threads for the fill (0 = the cores available), at most [`MAX_THREADS`] (more are taken as
    /// that many). Frames are identical for every count.
    pub threads: usize,
    /// Colour the frame is cleared to first, `0x00RRGGBB`; `None` draws over what is there.
    pub background: Option<u32>,
    /// Level-of-detail choice for instances of LOD sets.
    pub lod: LodMode,
    /// Multiplies projected sizes by `2^lod_bias` before choosing a level: positive keeps finer models longer.
    pub lod_bias: f32,
    /// Added to every texture's level of detail before its mip level is chosen (as OpenGL's
    /// `GL_TEXTURE_LOD_BIAS`): negative picks finer levels, positive coarser ones; a bias that is not
    /// finite counts as none. The levels are box filters of the texture, so with several samples a pixel
    /// a finer level than the one whose texels match the pixel follows the texture's integral over the
    /// pixel more closely (the presets above `low` use -0.5: the finer of the two nearest levels).
    pub mip_bias: f32,
    /// Anti-aliasing: none, coverage samples per pixel, or 2x2 supersampling.
    pub antialias: Antialias,
    /// Cross-fades a level-of-detail change over a few frames (the old and new models each drawn through
    /// one of two complementary screen doors) instead of swapping the models at once. It needs the LOD
    /// history of consecutive frames of one renderer; a single frame draws what the history says.
    pub lod_fade: bool,
    /// Moves the whole image by this many pixels of the frame (right, down) before it is sampled, so a
    /// pixel is sampled at its centre minus the offset: how the reference image puts its sub-pixel grid of
    /// samples. `[0.0, 0.0]` for every ordinary frame; an offset that is not finite counts as none.
    pub pixel_offset: [f32; 2],
    /// Lets the z-buffer's fill skip a polygon whole where a band's coarse depth (the least depth under
    /// each tile of the band, raised by the polygons that cover a tile) shows every pixel of it would fail
    /// the depth test. It never changes a pixel; off only to measure what it saves.
    pub coarse_depth: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            method: Method::default(),
            buckets: DEFAULT_BUCKETS,
            key: DepthKey::default(),
            mapping: BucketMapping::default(),
            texture_mode: TextureMode::default(),
            filter: Filter::default(),
            mip: MipMode::default(),
            threads: 0,
            background: Some(SKY_BLUE),
            lod: LodMode::Auto,
            lod_bias: 0.0,
            mip_bias: 0.0,
            antialias: Antialias::default(),
            lod_fade: false,
            pixel_offset: [0.0, 0.0],
            coarse_depth: true,
        }
    }
}

/// The default background, sky blue (135, 206, 235).
pub const SKY_BLUE: u32 = 0x0087_ceeb;

/// How texture coordinates (and colours) are interpolated across a span.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TextureMode {
    /// Exact: `u/w`, `v/w`, `1/w` interpolated and divided at every pixel (the default).
    #[default]
    Perspective,
    /// Exact every [`SUBDIVISION`] pixels, linear in between (as Quake did).
    Subdivided,
    /// Linear in screen space (as the PlayStation did): cheap, warps on polygons seen at an angle.
    Affine,
}

/// Span length between exact perspective divides in [`TextureMode::Subdivided`].
pub const SUBDIVISION: i32 = 16;

/// How a depth is mapped to a bucket.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum BucketMapping {
    /// Buckets of equal depth range between near and far.
    #[default]
    Linear,
    /// Buckets of equal `1/z` range: thin near the eye, wide far away (like a perspective z-buffer).
    Reciprocal,
}

/// One of the three models of a set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// The close-up model (about 200-300 polygons for a car).
    Close = 0,
    /// The middle-range model (about 20-30).
    Mid = 1,
    /// The long-shot model (6: a hexahedron).
    Long = 2,
}

impl Level {
    /// All levels, finest first.
    pub const ALL: [Level; 3] = [Level::Close, Level::Mid, Level::Long];

    /// The name used on the command line and in statistics.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Level::Close => "close",
            Level::Mid => "mid",
            Level::Long => "long",
        }
    }

    pub(crate) fn from_index(i: u8) -> Option<Level> {
        Level::ALL.get(usize::from(i)).copied()
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How levels are chosen for a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LodMode {
    /// By projected size, with hysteresis (the default).
    #[default]
    Auto,
    /// The same level for every set (for comparisons and the chart).
    Force(Level),
}

impl FromStr for LodMode {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(LodMode::Auto),
            "close" => Ok(LodMode::Force(Level::Close)),
            "mid" => Ok(LodMode::Force(Level::Mid)),
            "long" => Ok(LodMode::Force(Level::Long)),
            _ => Err(UnknownName::new("level of detail", s, "auto, close, mid or long")),
        }
    }
}

/// How polygon edges are anti-aliased.
///
/// Coverage samples work with every visibility method, each in its own way: the z-buffer keeps a depth and a
/// colour per sample (MSAA: one shade per pixel per polygon, coverage and depth per sample); `bucket-near`
/// keeps the seed's "already drawn" flag per sample instead of per pixel (an A-buffer without depth: each
/// sample is shaded at most once, near to far); the painter's methods overwrite the samples a polygon
/// covers. Only pixels an edge crosses keep their samples; the others stay one colour (see `fill::samples`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Antialias {
    /// One sample per pixel, at its centre (the 1990s look).
    #[default]
    Off,
    /// Four coverage samples per pixel (the Direct3D standard rotated grid).
    Samples4,
    /// Eight coverage samples per pixel (the Direct3D standard pattern).
    Samples8,
    /// Sixteen coverage samples per pixel (the Direct3D standard pattern).
    Samples16,
    /// The frame drawn at twice the width and height and box-filtered down: the quality yardstick, at
    /// four times the pixels.
    Supersample2x2,
    /// Four samples a pixel on a rotated grid (RGSS): the frame drawn at four times its height, each row's
    /// samples shifted right or left by its own fraction of a pixel, and each column of four rows averaged.
    /// Four rows and four columns of samples where 2x2 supersampling has two of each, so an edge near the
    /// horizontal or the vertical gets five levels.
    RotatedGrid,
}

impl Antialias {
    /// Every choice, in the order the command line lists them.
    pub const ALL: [Antialias; 6] = [
        Antialias::Off,
        Antialias::Samples4,
        Antialias::Samples8,
        Antialias::Samples16,
        Antialias::Supersample2x2,
        Antialias::RotatedGrid,
    ];

    /// The command-line name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Antialias::Off => "off",
            Antialias::Samples4 => "4x",
            Antialias::Samples8 => "8x",
            Antialias::Samples16 => "16x",
            Antialias::Supersample2x2 => "ssaa",
            Antialias::RotatedGrid => "rgss",
        }
    }

    /// The coverage samples per pixel, for the sample choices.
    #[must_use]
    pub fn coverage_samples(self) -> Option<usize> {
        match self {
            Antialias::Samples4 => Some(4),
            Antialias::Samples8 => Some(8),
            Antialias::Samples16 => Some(16),
            Antialias::Off | Antialias::Supersample2x2 | Antialias::RotatedGrid => None,
        }
    }
}

impl fmt::Display for Antialias {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Antialias {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Antialias::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| UnknownName::new("anti-aliasing", s, "off, 4x, 8x, 16x, ssaa or rgss"))
    }
}
