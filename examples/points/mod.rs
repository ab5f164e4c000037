//! The picture points the quality examples take on their command lines (`examples/presets`,
//! `examples/error_map`): a preset (`ultra`), a preset and a texture filter (`ultra/aniso4`), or the
//! anti-aliasing, filter and mip choice over the default (`ssaa/aniso8/pixel`) or over a preset
//! (`medium/4x/area/polygon`, the preset's models, fades and mip bias kept); any of them may end in
//! `:BIAS`, a LOD bias (`ultra/nearest:2`), and then in `@BIAS`, a mip bias (`rgss/nearest/pixel:1@-1`).

use scanline_racer::render::{Antialias, Filter, MipMode, Quality, RenderOptions};

/// The renderer's options for `point`; panics on a point it cannot read (these are measuring tools).
pub fn options(point: &str) -> RenderOptions {
    let (point, mip_bias) = point.split_once('@').map_or((point, None), |(p, x)| (p, Some(x.parse::<f32>().unwrap())));
    let (body, bias) = point.split_once(':').map_or((point, None), |(b, x)| (b, Some(x.parse::<f32>().unwrap())));
    let parts: Vec<&str> = body.split('/').collect();
    let options = match parts[..] {
        [preset] => preset.parse::<Quality>().unwrap().apply(RenderOptions::default()),
        [preset, filter] => RenderOptions {
            filter: filter.parse::<Filter>().unwrap(),
            ..preset.parse::<Quality>().unwrap().apply(RenderOptions::default())
        },
        [aa, filter, mip] => RenderOptions {
            antialias: aa.parse::<Antialias>().unwrap(),
            filter: filter.parse::<Filter>().unwrap(),
            mip: mip.parse::<MipMode>().unwrap(),
            ..RenderOptions::default()
        },
        [preset, aa, filter, mip] => RenderOptions {
            antialias: aa.parse::<Antialias>().unwrap(),
            filter: filter.parse::<Filter>().unwrap(),
            mip: mip.parse::<MipMode>().unwrap(),
            ..preset.parse::<Quality>().unwrap().apply(RenderOptions::default())
        },
        _ => panic!(
            "a point is preset, preset/filter, aa/filter/mip or preset/aa/filter/mip (each may end in :BIAS), got {point}"
        ),
    };
    RenderOptions {
        lod_bias: bias.unwrap_or(options.lod_bias),
        mip_bias: mip_bias.unwrap_or(options.mip_bias),
        ..options
    }
}
