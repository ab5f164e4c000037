//! The picture flags `render`, `replay` and `play` share: the quality preset, texture filter, mip levels
//! and anti-aliasing, written once so the three commands name, document and default them alike.

use clap::Args;

use crate::render::{Antialias, Filter, MipMode, RenderOptions};
use crate::shell::auto_quality::QualityChoice;

/// `--quality`, `--filter`, `--mip` and `--aa`: each, when not given, the renderer's own default (for
/// `play`'s race, not `--scene` or `--demo`, the settings file's choice, which Settings saves). A preset
/// sets the other three; any of them given beside it wins.
///
/// A flag given to `play` is for that run: the settings file keeps its own choice unless it is changed in
/// Settings.
#[derive(Clone, Copy, Debug, Default, Args)]
pub struct PictureArgs {
    /// Picture quality: a preset (low, medium, high, ultra: each sets --filter, --mip and --aa), or, in the
    /// window, auto (the best preset that keeps frames within 70% of the refresh period). Default: low
    /// (play's race: the settings file's, else auto).
    #[arg(long, value_name = "PRESET")]
    pub quality: Option<QualityChoice>,
    /// Texture filtering: nearest, bilinear, min-bilinear (nearest on a polygon whose texture is magnified,
    /// bilinear on one whose texture is minified, unless it is a cut-out; levels per polygon), area (min-bilinear with a magnified
    /// texture's texels weighed by how much of the pixel covers each, measured at every pixel), trilinear (bilinear in the two mip
    /// levels around the level of detail, blended; bilinear with --mip off), or aniso2, aniso4, aniso8, aniso16 (up to N box probes along
    /// the footprint's long axis, levels chosen at every pixel whatever --mip says). Default: nearest (play's race: the settings
    /// file's, else nearest).
    #[arg(long)]
    pub filter: Option<Filter>,
    /// Where mip levels are chosen: off (level 0 only), polygon (once per polygon), span (at each span's
    /// middle pixel) or pixel (at every pixel). Default: polygon (play's race: the settings file's, else polygon).
    #[arg(long)]
    pub mip: Option<MipMode>,
    /// Anti-aliasing: off, 4x, 8x or 16x coverage samples per pixel, ssaa (2x2 supersampling) or rgss (four
    /// samples on a rotated grid, the frame drawn four rows a pixel). Default:
    /// off (play's race: the settings file's, else off).
    #[arg(long)]
    pub aa: Option<Antialias>,
    /// Cross-fade level-of-detail changes over six frames (the old and new models through complementary
    /// screen doors) instead of swapping models at once. Default: off (the presets above low turn it on).
    #[arg(long)]
    pub lod_fade: bool,
    /// Mip bias: added to each texture's level of detail before its mip level is chosen (negative: finer
    /// levels, sharper; positive: coarser, blurrier); -4 to 4. Default: 0, or the --quality preset's
    /// (-0.5 above low: the finer of the two nearest levels).
    #[arg(long, allow_negative_numbers = true, value_parser = super::values::parse_mip_bias)]
    pub mip_bias: Option<f32>,
}

impl PictureArgs {
    /// `options` with the choices given on the command line (the others as `options` has them).
    #[must_use]
    pub fn apply(&self, options: RenderOptions) -> RenderOptions {
        let options = match self.quality {
            Some(QualityChoice::Fixed(q)) => q.apply(options),
            Some(QualityChoice::Auto) | None => options,
        };
        RenderOptions {
            filter: self.filter.unwrap_or(options.filter),
            mip: self.mip.unwrap_or(options.mip),
            antialias: self.aa.unwrap_or(options.antialias),
            lod_fade: self.lod_fade || options.lod_fade,
            mip_bias: self.mip_bias.unwrap_or(options.mip_bias),
            ..options
        }
    }

    /// Whether this run's picture is `auto` (`Some(true)`), fixed by a flag (`Some(false)`: a preset, or
    /// any of `--filter`, `--mip`, `--aa`, `--lod-fade`, `--mip-bias` without `--quality auto`), or left to
    /// the settings (`None`).
    #[must_use]
    pub fn auto(&self) -> Option<bool> {
        match self.quality {
            Some(QualityChoice::Auto) => Some(true),
            Some(QualityChoice::Fixed(_)) => Some(false),
            None if self.filter.is_some()
                || self.mip.is_some()
                || self.aa.is_some()
                || self.lod_fade
                || self.mip_bias.is_some() =>
            {
                Some(false)
            }
            None => None,
        }
    }

    /// Refuses `--quality auto` for `command`, which draws without a window (its frames must not depend
    /// on how fast the machine is).
    pub fn fixed_for(&self, command: &'static str) -> Result<(), super::error::CliError> {
        match self.quality {
            Some(QualityChoice::Auto) => Err(super::error::CliError::AutoQualityWithoutWindow { command }),
            _ => Ok(()),
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
        assert_eq!(given.auto(), Some(false));
        assert_eq!(PictureArgs::default().auto(), None);
    }

    #[test]
    fn a_preset_sets_the_picture_and_a_flag_beside_it_wins() {
        use crate::render::Quality;
        let high = PictureArgs { quality: Some(QualityChoice::Fixed(Quality::High)), ..PictureArgs::default() };
        assert_eq!(Quality::of(&high.apply(RenderOptions::default())), Some(Quality::High));
        let with_filter = PictureArgs { filter: Some(Filter::Bilinear), ..high };
        let got = with_filter.apply(RenderOptions::default());
        assert_eq!((got.filter, got.antialias), (Filter::Bilinear, Antialias::Supersample2x2));
        let auto = PictureArgs { quality: Some(QualityChoice::Auto), ..PictureArgs::default() };
        assert_eq!(auto.apply(RenderOptions::default()), RenderOptions::default());
        assert_eq!(auto.auto(), Some(true));
        assert_eq!(
            auto.fixed_for("render").map_err(|e| e.to_string()),
            Err("render: --quality auto needs the window (it follows the frame time); name a preset: low, medium, high or ultra".into())
        );
        assert!(high.fixed_for("render").is_ok());
    }
}
