//! `scanline-racer render`: draw a glTF scene headless, write a PNG, report statistics.

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};

use super::error::CliError;
use super::picture::PictureArgs;
use super::values;
use crate::asset::{LoadedScene, load};
use crate::render::order::view_lists::{DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS};
use crate::render::{
    BucketMapping, DEFAULT_BUCKETS, DepthKey, LodMode, Method, RenderOptions, Renderer, Stats, TextureMode,
};

/// Texture interpolation names on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum TextureArg {
    /// Perspective-correct at every pixel.
    Perspective,
    /// Exact every 16 pixels, linear between.
    Subdivided,
    /// Linear in screen space.
    Affine,
}

/// Bucket mapping names on the command line.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum MappingArg {
    /// Equal depth ranges.
    Linear,
    /// Equal 1/z ranges.
    Reciprocal,
}

/// Arguments of `render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// The glTF 2.0 scene (.gltf or .glb).
    pub scene: PathBuf,
    /// Camera node by index (in scene traversal order) or by node or camera name; default: the first camera
    /// node, or a camera that frames the scene's bounds when there is none.
    #[arg(long)]
    pub camera: Option<String>,
    /// Frame width in pixels (1 to 16384).
    #[arg(long, default_value_t = 640, value_parser = values::side(values::MAX_SIDE))]
    pub width: usize,
    /// Frame height in pixels (1 to 16384).
    #[arg(long, default_value_t = 480, value_parser = values::side(values::MAX_SIDE))]
    pub height: usize,
    /// Visibility method: zbuffer, sort, bucket-far, bucket-near.
    #[arg(long, default_value = "zbuffer")]
    pub method: Method,
    /// Ordering-table buckets (bucket-far, bucket-near), 1 to 1048576.
    #[arg(long, default_value_t = DEFAULT_BUCKETS, value_parser = values::count(values::MAX_BUCKETS))]
    pub buckets: usize,
    /// Representative depth for sort and buckets: avg, min, max.
    #[arg(long, default_value = "max")]
    pub key: DepthKey,
    /// Depth-to-bucket mapping.
    #[arg(long, value_enum, default_value_t = MappingArg::Linear)]
    pub mapping: MappingArg,
    /// Texture-coordinate interpolation.
    #[arg(long, value_enum, default_value_t = TextureArg::Perspective)]
    pub texture: TextureArg,
    /// Texture filter, mip levels and anti-aliasing.
    #[command(flatten)]
    pub picture: PictureArgs,
    /// Level of detail for LOD sets: auto (by projected size), or close, mid or long for every set.
    #[arg(long, default_value = "auto")]
    pub lod: LodMode,
    /// LOD bias: projected sizes are multiplied by 2^BIAS before choosing (positive keeps finer models);
    /// -16 to 16. Default: 0, or the --quality preset's.
    #[arg(long, allow_negative_numbers = true, value_parser = values::parse_lod_bias)]
    pub lod_bias: Option<f32>,
    /// Worker threads for the fill, 0 to 256 (0, the default: the cores available); frames are identical
    /// for every count.
    #[arg(long, default_value_t = 0, value_parser = values::threads())]
    pub threads: usize,
    /// Background colour as R,G,B (0-255 each).
    #[arg(long, default_value = "135,206,235", value_parser = values::parse_rgb)]
    pub background: u32,
    /// Output image, PNG or JPEG by its extension (.png, .jpg, .jpeg); default: the scene's file name with
    /// .png, in the current directory.
    #[arg(long, value_parser = values::image_path())]
    pub out: Option<PathBuf>,
    /// Draw the frame N times and report the median time (1 to 100000).
    #[arg(long, default_value_t = 1, value_parser = values::count(values::MAX_REPEAT))]
    pub repeat: usize,
    /// Print statistics: `json` prints one JSON object on stdout.
    #[arg(long)]
    pub stats: Option<StatsFormat>,
}

/// Statistics formats.
#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum StatsFormat {
    /// One JSON object on stdout.
    Json,
}

impl RenderArgs {
    /// The renderer options these arguments ask for (clap has checked every range).
    #[must_use]
    pub fn options(&self) -> RenderOptions {
        let options = self.picture.apply(RenderOptions {
            method: self.method,
            buckets: self.buckets,
            key: self.key,
            mapping: match self.mapping {
                MappingArg::Linear => BucketMapping::Linear,
                MappingArg::Reciprocal => BucketMapping::Reciprocal,
            },
            texture_mode: match self.texture {
                TextureArg::Perspective => TextureMode::Perspective,
                TextureArg::Subdivided => TextureMode::Subdivided,
                TextureArg::Affine => TextureMode::Affine,
            },
            threads: self.threads,
            background: Some(self.background),
            lod: self.lod,
            ..RenderOptions::default()
        });
        // A bias given beside a preset wins over the preset's.
        RenderOptions { lod_bias: self.lod_bias.unwrap_or(options.lod_bias), ..options }
    }
}

/// The camera `--camera` selects, with its display name.
pub fn pick_camera(
    scene: &LoadedScene,
    sel: Option<&str>,
    file: &Path,
    aspect: f32,
) -> Result<(crate::render::Camera, String), CliError> {
    match sel {
        Some(sel) => match scene.find_camera(sel) {
            Some(c) => Ok((c.camera, c.name.clone())),
            None => {
                let names: Vec<String> = scene.cameras.iter().take(8).map(|c| format!("'{}'", c.name)).collect();
                Err(CliError::NoSuchCamera {
                    file: file.display().to_string(),
                    wanted: sel.to_string(),
                    count: scene.cameras.len(),
                    names: if names.is_empty() { String::new() } else { format!(": {}", names.join(", ")) },
                })
            }
        },
        None => Ok(match scene.cameras.first() {
            Some(c) => (c.camera, c.name.clone()),
            None => (scene.framing_camera(aspect), "framing".to_string()),
        }),
    }
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Runs `render`.
pub fn render_command(args: &RenderArgs) -> Result<(), CliError> {
    args.picture.fixed_for("render")?;
    let options = args.options();
    let out = args.out.clone().unwrap_or_else(|| {
        let stem = args.scene.file_stem().map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
        PathBuf::from(format!("{stem}.png"))
    });
    crate::userfile::check_output(&out).map_err(|source| CliError::Output { flag: "--out", source })?;
    let t_load = Instant::now();
    let mut scene = load(&args.scene)?;
    let ms_load = t_load.elapsed().as_secs_f64() * 1e3;
    // The scene, its buffers and its images are read; none of them may be what the frame is written over.
    let mut inputs = crate::userfile::Inputs::new();
    inputs.add(&args.scene, "the glTF scene");
    inputs.add_all(scene.files.iter().skip(1), "a file the glTF scene names");
    super::error::not_an_input("--out", &out, &inputs)?;
    if options.method == Method::ViewLists {
        scene.prepare_view_lists(DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS);
    }
    let aspect = args.width as f32 / args.height as f32;
    let (camera, camera_name) = pick_camera(&scene, args.camera.as_deref(), &args.scene, aspect)?;
    let mut frame = vec![0u32; args.width * args.height];
    let mut renderer = Renderer::new();
    let mut times = Vec::with_capacity(args.repeat);
    let mut stats = Stats::default();
    for _ in 0..args.repeat {
        let t = Instant::now();
        stats = renderer.render(&mut frame, args.width, args.height, &camera, &scene.draw_list(), &options)?;
        times.push(t.elapsed().as_secs_f64() * 1e3);
    }
    let ms_min = times.iter().copied().fold(f64::INFINITY, f64::min);
    let ms_median = median(&mut times);
    crate::shell::image_file::write_image(&out, &frame, args.width, args.height)?;
    if scene.skipped_primitives > 0 {
        eprintln!("note: {} point/line primitive(s) skipped (only triangles are drawn)", scene.skipped_primitives);
    }
    match args.stats {
        Some(StatsFormat::Json) => {
            let times = Timings { ms_load, ms_median, ms_min };
            let json = stats_json(args, &options, &out, &camera_name, &stats, times);
            println!("{json}");
        }
        None => eprintln!(
            "wrote {} ({}x{}, {}, {} of {} polygons drawn, {:.2} ms median over {} frame(s))",
            out.display(),
            args.width,
            args.height,
            options.method,
            stats.polygons_drawn,
            stats.polygons_in,
            ms_median,
            args.repeat
        ),
    }
    Ok(())
}

/// How long the load and the frames took, in milliseconds.
struct Timings {
    ms_load: f64,
    ms_median: f64,
    ms_min: f64,
}

/// `--stats json`: the settings, the timings and every counter of the last frame's [`Stats`].
fn stats_json(
    args: &RenderArgs,
    options: &RenderOptions,
    out: &Path,
    camera_name: &str,
    stats: &Stats,
    times: Timings,
) -> serde_json::Value {
    let threads = match options.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => n,
    };
    serde_json::json!({
        "scene": args.scene.display().to_string(),
        "out": out.display().to_string(),
        "camera": camera_name,
        "method": options.method.name(),
        "buckets": options.buckets,
        "key": format!("{:?}", options.key).to_lowercase(),
        "texture": format!("{:?}", options.texture_mode).to_lowercase(),
        "filter": options.filter.name(),
        "mip": options.mip.name(),
        "threads": threads,
        "lod": match options.lod {
            LodMode::Auto => "auto",
            LodMode::Force(level) => level.name(),
        },
        "lod_bias": options.lod_bias,
        "mip_bias": options.mip_bias,
        "lod_close": stats.lod_close,
        "lod_mid": stats.lod_mid,
        "lod_long": stats.lod_long,
        "polygons_saved_by_lod": stats.polygons_saved_by_lod,
        "width": args.width,
        "height": args.height,
        "frames": args.repeat,
        "ms_load": times.ms_load,
        "ms_median": times.ms_median,
        "ms_min": times.ms_min,
        "ms_transform": stats.ms_transform,
        "ms_clip": stats.ms_clip,
        "ms_order": stats.ms_order,
        "ms_fill": stats.ms_fill,
        "objects_in": stats.objects_in,
        "objects_culled": stats.objects_culled,
        "polygons_in": stats.polygons_in,
        "polygons_in_culled_objects": stats.polygons_in_culled_objects,
        "polygons_outside": stats.polygons_outside,
        "polygons_clipped": stats.polygons_clipped,
        "polygons_backface": stats.polygons_backface,
        "polygons_degenerate": stats.polygons_degenerate,
        "polygons_invalid": stats.polygons_invalid,
        "polygons_split": stats.polygons_split,
        "polygons_drawn": stats.polygons_drawn,
        "pixels_shaded": stats.pixels_shaded,
        "pixels_written": stats.pixels_written,
        "pixels_rejected": stats.pixels_rejected,
    })
}
