//! The software renderer: from a camera and a draw list to pixels in a caller-owned frame buffer.
//!
//! The renderer knows nothing of windows, input, UI or the game. [`Renderer::render`] takes `&mut [u32]`
//! pixels (`0x00RRGGBB`, rows from the top), a [`Camera`] and a [`DrawList`], and returns [`Stats`].
//! Its folders are the pipeline, and records flow down them, never back:
//!
//! | layer | what | seeds |
//! |---|---|---|
//! | [`core`] | records and number formats: options, draw list, camera, mesh, texture, [`core::fixed::Fx28_4`], the screen vertex, the polygon, the small triangle, set-up batches, bands | |
//! | `simd` | the one CPU-feature seam: whether vector loops may run, and their shared helpers | |
//! | [`geometry`] | level of detail, culling, vertex transform, clipping, polygon and small-triangle set-up, monotone split | 003 (LOD) |
//! | [`order`] | the ordering table, orders made in advance per view, sort | 000, 004 |
//! | [`fill`] | bands and binning, the scanline walk, spans and their pixel loops, small triangles | 001, 002 |
//! | [`renderer`] | one frame: geometry, order, fill | |
//! | [`overlay`] | 2D triangles for the UI, drawn with the scanline walk | |
//!
//! Sub-pixel and fill rules are written in [`fill::scanline`] and `geometry::small_setup`.

pub mod core;
pub mod fill;
pub mod geometry;
pub mod order;
pub mod overlay;
pub mod renderer;
mod simd;
mod supersample;

pub use self::core::camera::{Camera, Projection};
pub use self::core::draw_list::{DrawList, Instance, LodSet, MeshLists, ViewLists};
pub use self::core::error::RenderError;
pub use self::core::mesh::{AlphaMode, Material, Mesh, MeshBuilder, MeshError, Vertex};
pub use self::core::options::{
    Antialias, BucketMapping, DEFAULT_BUCKETS, DepthKey, Level, LodMode, MAX_THREADS, Method, MipMode, RenderOptions,
    SKY_BLUE, TextureMode, UnknownName,
};
pub use self::core::quality::Quality;
pub use self::core::stats::Stats;
pub use self::core::texture::{Filter, Sampler, Texture, Wrap};
pub use self::renderer::Renderer;
