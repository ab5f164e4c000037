//! The picture flags `render`, `replay` and `play` share: texture filter, mip levels and anti-aliasing,
//! written once so the three commands name, document and default them alike.

use clap::Args;

use crate::render::{Antialias, Filter, MipMode, RenderOptions};

/// `--filter`, `--mip` and `--aa`: each, when not given, the renderer's own default (for `play`'s race,
/// not `--scene` or `--demo`, the settings file's choice, which Settings saves).
///
/// A flag given to `play` is for that run: the settings file keeps its own choice unless it is changed in
/// Settings.
#[derive(Clone, Copy, Debug, Default, Args)]
pub struct PictureArgs {
    /// Texture filtering: nearest, bilinear, or trilinear (bilinear in the two mip levels around the level of
    /// detail, blended; bilinear with --mip off). Default: nearest (play's race: the settings file's, else nearest).
    #[arg(long)]
    pub filter: Option<Filter>,
    /// Where mip levels are chosen: off (level 0 only), polygon (once per polygon), span (at each span's
    /// middle pixel) or pixel (at every pixel). Default: polygon (play's race: the settings file's, else polygon).
    #[arg(long)]
    pub mip: Option<MipMode>,
    /// Anti-aliasing: off, 4x, 8x or 16x coverage samples per pixel, or ssaa (2x2 supersampling). Default:
    /// off (play's race: the settings file's, else off).
    #[arg(long)]
    pub aa: Option<Antialias>,
}

impl PictureArgs {
    /// `options` with the choices given on the command line (the others as `options` has them).
    #[must_use]
    pub fn apply(&self, options: RenderOptions) -> RenderOptions {
        RenderOptions {
            filter: self.filter.unwrap_or(options.filter),
            mip: self.mip.unwrap_or(options.mip),
            antialias: self.aa.unwrap_or(options.antialias),
            ..options
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_defaults_named_in_the_help_are_the_renderer_s() {
        let d = RenderOptions::default();
        assert_eq!((d.filter.name(), d.mip.name(), d.antialias.name()), ("nearest", "polygon", "off"));
        let given = PictureArgs { aa: Some(Antialias::Samples4), ..PictureArgs::default() };
        let base = RenderOptions { filter: Filter::Trilinear, ..d };
        let got = given.apply(base);
        assert_eq!((got.filter, got.mip, got.antialias), (Filter::Trilinear, d.mip, Antialias::Samples4));
    }
}
