//! The software renderer: from a camera and a draw list to pixels in a caller-owned frame buffer.
//!
//! The renderer knows nothing of windows, input, UI or the game. [`Renderer::render`] takes `&mut [u32]`
//! pixels (`0x00RRGGBB`, rows from the top), a [`Camera`] and a [`DrawList`], and returns [`Stats`].
//! Stages, each in a file named after it: object culling ([`cull`]), transform and near-plane / guard-band
//! clipping ([`clip`]), snapping to [`fixed::Fx28_4`] and back-face culling, splitting of non-monotone
//! polygons ([`monotone`]), visibility ordering ([`ordering_table`], or a sort, or a z-buffer), the scanline
//! walk ([`scanline`]) and span shading ([`span`], [`texture`]). The pipeline itself is in [`pipeline`].

pub mod bands;
pub mod camera;
pub mod clip;
mod cpu;
pub mod cull;
pub mod fixed;
pub mod lod;
pub mod mesh;
pub mod monotone;
pub mod ordering_table;
pub mod overlay;
pub mod pipeline;
mod project;
pub mod scanline;
#[cfg(target_arch = "x86_64")]
mod small_avx2;
mod small_triangle;
pub mod span;
#[cfg(target_arch = "x86_64")]
mod span_avx2;
pub mod span_lanes;
pub mod stats;
#[cfg(test)]
mod test_rng;
pub mod texture;
mod transform;
#[cfg(target_arch = "x86_64")]
mod transform_avx2;
pub mod view_lists;

use std::fmt;
use std::str::FromStr;

pub use camera::{Camera, Projection};
pub use lod::{Level, LodMode, LodSet};
pub use mesh::{AlphaMode, Material, Mesh, MeshBuilder, MeshError, Vertex};
pub use ordering_table::BucketMapping;
pub use pipeline::{RenderError, Renderer};
pub use span::TextureMode;
pub use stats::Stats;
pub use texture::{Filter, Sampler, Texture, Wrap};
pub use view_lists::ViewLists;

/// How visibility is resolved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Method {
    /// Per-pixel depth test (`1/w`): the accuracy reference, and the default: the bench measured it exact at
    /// 1.0-1.1x the time of the painter's methods on the game's frames (see the README).
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

impl FromStr for Method {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Method::ALL.into_iter().find(|m| m.name() == s).ok_or_else(|| {
            format!("unknown method '{s}' (expected zbuffer, sort, bucket-far, bucket-near or view-lists)")
        })
    }
}

/// The representative depth of a polygon for ordering.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum DepthKey {
    /// Mean of the vertices' depths (seed claim 2).
    Avg,
    /// Nearest vertex (seed claim 3).
    Min,
    /// Farthest vertex: the default, measured best on the game's frames (fewest pixels differing from the
    /// z-buffer for `sort` and both bucket methods; a big road polygon sorts by its far end, so the cars
    /// standing on it are drawn after it).
    #[default]
    Max,
}

impl FromStr for DepthKey {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "avg" => Ok(DepthKey::Avg),
            "min" => Ok(DepthKey::Min),
            "max" => Ok(DepthKey::Max),
            _ => Err(format!("unknown key '{s}' (expected avg, min or max)")),
        }
    }
}

/// Default number of ordering-table buckets; see the README for why.
pub const DEFAULT_BUCKETS: usize = 1024;

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
    /// Worker threads for the fill (0 = the cores available). Frames are identical for every count.
    pub threads: usize,
    /// Colour the frame is cleared to first, `0x00RRGGBB`; `None` draws over what is there.
    pub background: Option<u32>,
    /// Level-of-detail choice for instances of LOD sets.
    pub lod: LodMode,
    /// Multiplies projected sizes by `2^lod_bias` before choosing a level: positive keeps finer models longer.
    pub lod_bias: f32,
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
            threads: 0,
            background: Some(SKY_BLUE),
            lod: LodMode::Auto,
            lod_bias: 0.0,
        }
    }
}

/// The default background, sky blue (135, 206, 235).
pub const SKY_BLUE: u32 = 0x0087_ceeb;

/// One placed mesh, or one placed LOD set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`DrawList::meshes`] (ignored when `lod` names a set).
    pub mesh: usize,
    /// Model space to world space.
    pub model: glam::Mat4,
    /// Index into [`DrawList::lod_sets`]: the model is chosen per frame from that set.
    pub lod: Option<usize>,
    /// Drawn see-through: a screen door (every other pixel, in a checkerboard), so what is behind shows
    /// between its pixels in every visibility method, with no blending and no sorting of its own (as the
    /// Saturn drew its shadows and ghosts).
    pub see_through: bool,
}

impl Instance {
    /// A single mesh placed by `model`.
    #[must_use]
    pub fn new(mesh: usize, model: glam::Mat4) -> Self {
        Self { mesh, model, lod: None, see_through: false }
    }

    /// A LOD set placed by `model`.
    #[must_use]
    pub fn of_lod_set(set: usize, model: glam::Mat4) -> Self {
        Self { mesh: 0, model, lod: Some(set), see_through: false }
    }

    /// The same instance drawn see-through (see [`Instance::see_through`]).
    #[must_use]
    pub fn see_through(self) -> Self {
        Self { see_through: true, ..self }
    }
}

/// What to draw: meshes, the textures their materials refer to, and where to put them.
#[derive(Clone, Copy, Debug)]
pub struct DrawList<'a> {
    /// Meshes.
    pub meshes: &'a [Mesh],
    /// Textures, indexed by [`Material::texture`].
    pub textures: &'a [Texture],
    /// Instances, drawn in this order (it is the submission order the ordering table keeps within a bucket).
    pub instances: &'a [Instance],
    /// Sets of close/mid/long meshes that instances may refer to.
    pub lod_sets: &'a [LodSet],
    /// Drawing orders made in advance for the meshes (used by [`Method::ViewLists`]; `None` elsewhere).
    pub view_lists: Option<&'a ViewLists>,
}
