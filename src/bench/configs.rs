//! The configurations the bench draws: the visibility methods and their settings, texture mapping and
//! filtering, mip-maps, anti-aliasing, levels of detail and frame sizes, each a point on the charts.

use crate::render::{
    Antialias, DepthKey, Filter, Level, LodMode, Method, MipMode, Quality, RenderOptions, TextureMode,
};

/// One point of the chart: a named set of options at a frame size.
#[derive(Clone, Debug)]
pub struct Config {
    /// Which sweep it belongs to (`visibility`, `texture`, `lod`, `resolution`).
    pub group: &'static str,
    /// A short label for the chart.
    pub label: String,
    /// The renderer's options.
    pub options: RenderOptions,
    /// Frame width and height.
    pub size: (usize, usize),
    /// For `view-lists`: the icosahedron subdivision level of the stored directions.
    pub view_level: Option<u32>,
}

/// The configurations of the sweep at `main` size, plus the resolution sweep, each starting from the
/// picture of the preset `base` (the renderer's default for `low`).
#[must_use]
pub fn configs(
    main: (usize, usize),
    bucket_counts: &[usize],
    resolutions: &[(usize, usize)],
    base: Quality,
) -> Vec<Config> {
    let base = base.apply(RenderOptions::default());
    let mut v = vec![];
    visibility(&mut v, base, main, bucket_counts);
    texture_and_lod(&mut v, base, main);
    mips_and_antialiasing(&mut v, base, main);
    let mut add = |group, label: String, options: RenderOptions, size| {
        v.push(Config { group, label, options, size, view_level: None })
    };
    // The default at every size, beside the fastest method (`bucket-near`) at the same size.
    for &size in resolutions.iter().filter(|&&s| s != main) {
        add("resolution", format!("{} {}x{}", base.method, size.0, size.1), base, size);
        add(
            "resolution",
            format!("bucket-near {}x{}", size.0, size.1),
            RenderOptions { method: Method::BucketNear, ..base },
            size,
        );
    }
    // Every preset is a point whatever the base: the ones the sweep does not draw already are added.
    for q in Quality::ALL {
        let options = q.apply(RenderOptions::default());
        if !v.iter().any(|c| c.size == main && c.view_level.is_none() && c.options == options) {
            v.push(Config { group: "quality", label: format!("preset {q}"), options, size: main, view_level: None });
        }
    }
    v
}

/// The visibility methods: the z-buffer, the sort and the ordering table by key and bucket count, and the
/// stored view lists by direction count.
fn visibility(v: &mut Vec<Config>, base: RenderOptions, main: (usize, usize), bucket_counts: &[usize]) {
    let mut add = |group, label: String, options: RenderOptions, size| {
        v.push(Config { group, label, options, size, view_level: None })
    };
    add("visibility", "zbuffer".into(), RenderOptions { method: Method::ZBuffer, ..base }, main);
    for key in [DepthKey::Avg, DepthKey::Min, DepthKey::Max] {
        add("visibility", format!("sort {}", key_name(key)), RenderOptions { method: Method::Sort, key, ..base }, main);
    }
    for method in [Method::BucketFar, Method::BucketNear] {
        for &buckets in bucket_counts {
            add(
                "visibility",
                format!("{method} {buckets} {}", key_name(base.key)),
                RenderOptions { method, buckets, ..base },
                main,
            );
        }
        for key in [DepthKey::Avg, DepthKey::Min, DepthKey::Max].into_iter().filter(|&k| k != base.key) {
            add(
                "visibility",
                format!("{method} {} {}", base.buckets, key_name(key)),
                RenderOptions { method, key, ..base },
                main,
            );
        }
    }
    for level in 0..=2u32 {
        let dirs = crate::render::order::view_lists::directions(level).len();
        v.push(Config {
            group: "visibility",
            label: format!("view-lists {dirs} dirs"),
            options: RenderOptions { method: Method::ViewLists, ..base },
            size: main,
            view_level: Some(level),
        });
    }
}

/// Texture mapping and filtering without mip-maps, and the levels of detail.
fn texture_and_lod(v: &mut Vec<Config>, base: RenderOptions, main: (usize, usize)) {
    let mut add = |group, label: String, options: RenderOptions, size| {
        v.push(Config { group, label, options, size, view_level: None })
    };
    for mode in [TextureMode::Affine, TextureMode::Subdivided, TextureMode::Perspective] {
        for filter in [Filter::Nearest, Filter::Bilinear] {
            add(
                "texture",
                format!("{} {}", mode_name(mode), filter.name()),
                RenderOptions { texture_mode: mode, filter, ..base },
                main,
            );
        }
    }
    add("lod", "lod close".into(), RenderOptions { lod: LodMode::Force(Level::Close), ..base }, main);
    for bias in [-1.0f32, 1.0] {
        add("lod", format!("lod auto {bias:+}"), RenderOptions { lod_bias: bias, ..base }, main);
    }
    add("lod", "lod long".into(), RenderOptions { lod: LodMode::Force(Level::Long), ..base }, main);
    add("lod", "lod auto fade".into(), RenderOptions { lod_fade: true, ..base }, main);
}

/// The mip-map choices, and anti-aliasing alone and with other mip choices than the default's.
fn mips_and_antialiasing(v: &mut Vec<Config>, base: RenderOptions, main: (usize, usize)) {
    let mut add = |group, label: String, options: RenderOptions, size| {
        v.push(Config { group, label, options, size, view_level: None })
    };
    let mips = [
        (Filter::Nearest, MipMode::Off),
        (Filter::Nearest, MipMode::Polygon),
        (Filter::Nearest, MipMode::Span),
        (Filter::Nearest, MipMode::Pixel),
        (Filter::Bilinear, MipMode::Pixel),
        (Filter::MinBilinear, MipMode::Polygon),
        (Filter::Area, MipMode::Polygon),
        (Filter::Trilinear, MipMode::Polygon),
        (Filter::Trilinear, MipMode::Span),
        (Filter::Trilinear, MipMode::Pixel),
        (Filter::Anisotropic(4), MipMode::Pixel),
        (Filter::Anisotropic(16), MipMode::Pixel),
    ];
    // Every choice but the default's (the visibility sweep's `zbuffer` is that point).
    for (filter, mip) in mips.into_iter().filter(|&m| m != (base.filter, base.mip)) {
        add("mip", format!("{} mip {mip}", filter.name()), RenderOptions { filter, mip, ..base }, main);
    }
    for (method, antialias) in [
        (Method::ZBuffer, Antialias::Samples4),
        (Method::ZBuffer, Antialias::Samples8),
        (Method::ZBuffer, Antialias::Samples16),
        (Method::BucketNear, Antialias::Samples4),
        (Method::BucketNear, Antialias::Samples16),
        (Method::BucketFar, Antialias::Samples4),
        (Method::ZBuffer, Antialias::Supersample2x2),
        (Method::ZBuffer, Antialias::RotatedGrid),
    ] {
        add("antialias", format!("{method} aa {antialias}"), RenderOptions { method, antialias, ..base }, main);
    }
    // Anti-aliasing with other mip-map choices than the default's.
    for (antialias, filter, mip) in [
        (Antialias::Samples4, Filter::Nearest, MipMode::Off),
        (Antialias::Samples4, Filter::Nearest, MipMode::Pixel),
        (Antialias::Samples4, Filter::Trilinear, MipMode::Pixel),
        (Antialias::Samples8, Filter::Nearest, MipMode::Pixel),
        (Antialias::Supersample2x2, Filter::Nearest, MipMode::Off),
        (Antialias::Supersample2x2, Filter::Nearest, MipMode::Pixel),
        (Antialias::Supersample2x2, Filter::Trilinear, MipMode::Pixel),
        (Antialias::Supersample2x2, Filter::Anisotropic(16), MipMode::Pixel),
    ] {
        add(
            "antialias",
            format!("aa {antialias} {} mip {mip}", filter.name()),
            RenderOptions { antialias, filter, mip, ..base },
            main,
        );
    }
}

/// The preset a configuration draws, if it is one: the z-buffer at the sweep's `main` size, every other
/// setting the renderer's default, and the picture of a preset.
#[must_use]
pub fn preset_of(config: &Config, main: (usize, usize)) -> Option<Quality> {
    let q = Quality::of(&config.options)?;
    let options = RenderOptions { threads: 0, ..config.options };
    (config.size == main && config.view_level.is_none() && options == q.apply(RenderOptions::default())).then_some(q)
}

pub(crate) fn key_name(k: DepthKey) -> &'static str {
    match k {
        DepthKey::Avg => "avg",
        DepthKey::Min => "min",
        DepthKey::Max => "max",
    }
}

pub(crate) fn mode_name(m: TextureMode) -> &'static str {
    match m {
        TextureMode::Perspective => "perspective",
        TextureMode::Subdivided => "subdivided",
        TextureMode::Affine => "affine",
    }
}
