//! The picture flags `render`, `replay` and `play` share: texture filter, mip levels and anti-aliasing,
//! written once so the three commands name, document and default them alike.

use clap::Args;

use crate::render::{Antialias, Filter, MipMode, RenderOptions};

/// `--filter`, `--mip` and `--aa`, each defaulting to the renderer's own default.
#[derive(Clone, Copy, Debug, Args)]
pub struct PictureArgs {
    /// Texture filtering: nearest, bilinear, or trilinear (bilinear in the two mip levels around the level of
    /// detail, blended; bilinear with --mip off).
    #[arg(long, default_value_t = RenderOptions::default().filter)]
    pub filter: Filter,
    /// Where mip levels are chosen: off (level 0 only), polygon (once per polygon), span (at each span's
    /// middle pixel) or pixel (at every pixel).
    #[arg(long, default_value_t = RenderOptions::default().mip)]
    pub mip: MipMode,
    /// Anti-aliasing: off, 4x, 8x or 16x coverage samples per pixel, or ssaa (2x2 supersampling).
    #[arg(long, default_value_t = RenderOptions::default().antialias)]
    pub aa: Antialias,
}

impl Default for PictureArgs {
    fn default() -> Self {
        let d = RenderOptions::default();
        Self { filter: d.filter, mip: d.mip, aa: d.antialias }
    }
}

impl PictureArgs {
    /// `options` with these choices.
    #[must_use]
    pub fn apply(&self, options: RenderOptions) -> RenderOptions {
        RenderOptions { filter: self.filter, mip: self.mip, antialias: self.aa, ..options }
    }
}
