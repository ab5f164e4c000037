//! `scanline-racer bench`: the speed-against-accuracy sweep over a demo replay; writes a CSV and the charts.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use super::error::CliError;
use super::values;
use crate::bench::chart::Panel;
use crate::bench::{Row, chart, collect_frames, collect_sequence, configs, csv, lod_pops_per_min, run};
use crate::render::order::view_lists::DEFAULT_MAX_POLYGONS;
use crate::render::{DEFAULT_BUCKETS, DrawList, Method, ViewLists};
use crate::shell::image_file::write_image;
use crate::shell::race_scene::Assets;
use crate::shell::race_scene::RaceScene;

/// Arguments of `bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Folder for `bench.csv` and the charts (`bench`, `visibility` and `stability`, SVG and PNG).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// The trace to replay (default: the shipped demo race).
    #[arg(long)]
    pub trace: Option<PathBuf>,
    /// Chase-camera frames taken from the trace (half of them also add the far-chase, bumper and trackside
    /// views), 1 to 1000.
    #[arg(long, default_value_t = 8, value_parser = values::count(1000))]
    pub frames: usize,
    /// Consecutive chase-camera frames (every second tick from tick 3000) for the temporal-stability
    /// measure, 1 to 1000.
    #[arg(long, default_value_t = 20, value_parser = values::count(1000))]
    pub sequence: usize,
    /// Times each frame is drawn per configuration; the best counts (1 to 1000).
    #[arg(long, default_value_t = 3, value_parser = values::count(1000))]
    pub repeats: usize,
    /// Renderer threads for every configuration, 0 (the cores available) to 256 (1 by default: per-core
    /// speed, the steadiest figure).
    #[arg(long, default_value_t = 1, value_parser = values::threads())]
    pub threads: usize,
    /// Frame width of the main sweep (1 to 8192).
    #[arg(long, default_value_t = 640, value_parser = values::side(values::MAX_BENCH_SIDE))]
    pub width: usize,
    /// Frame height of the main sweep (1 to 8192).
    #[arg(long, default_value_t = 480, value_parser = values::side(values::MAX_BENCH_SIDE))]
    pub height: usize,
    /// A small sweep for tests: 2 frames, a sequence of 4, 1 repeat, 160x120, three bucket counts, two
    /// resolutions.
    #[arg(long)]
    pub quick: bool,
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

/// Runs `bench`.
pub fn bench_command(args: &BenchArgs) -> Result<(), CliError> {
    // Before the sweep (minutes long): an output folder that cannot be written fails now, not after it.
    super::error::output_folder("--out", &args.out, "the CSV and the charts")?;
    let assets = args.assets.find();
    let trace = trace_to_measure(args.trace.as_deref(), &assets)?;
    let scene = args.assets.scene_for_trace(&trace)?;
    outputs_not_inputs(&args.out, &trace, &scene)?;
    let (frames, sequence, repeats, main, buckets, resolutions): (usize, usize, usize, _, Vec<usize>, Vec<_>) =
        if args.quick {
            (2, 4, 1, (160, 120), vec![8, DEFAULT_BUCKETS, 65536], vec![(160, 120), (320, 240)])
        } else {
            (
                args.frames,
                args.sequence,
                args.repeats,
                (args.width, args.height),
                vec![8, 32, 128, 512, 1024, 4096, 16384, 65536],
                vec![(320, 240), (640, 480), (1280, 720), (1920, 1080)],
            )
        };
    let frames = collect_frames(&scene, &trace, frames)?;
    if frames.is_empty() {
        return Err(CliError::NoRacingFrames { trace: trace.clone() });
    }
    let sequence = collect_sequence(&scene, &trace, sequence)?;
    let configs = configs(main, &buckets, &resolutions);
    let mut err = std::io::stderr();
    let terminal = std::io::IsTerminal::is_terminal(&err);
    eprintln!(
        "bench: {} configurations x {} frames x {repeats} repeats and {} sequence frames, {} thread(s), main size {}x{}",
        configs.len(),
        frames.len(),
        sequence.len(),
        args.threads,
        main.0,
        main.1
    );
    let levels: Vec<(u32, ViewLists)> = configs
        .iter()
        .filter_map(|c| c.view_level)
        .map(|l| (l, ViewLists::build(&scene.scene().meshes, l, DEFAULT_MAX_POLYGONS)))
        .collect();
    let mut rows = run(
        &frames,
        &sequence,
        |f, c| {
            let lists = c.view_level.and_then(|l| levels.iter().find(|(k, _)| *k == l)).map(|(_, v)| v);
            DrawList { view_lists: lists, ..scene.draw_list(&f.instances) }
        },
        &configs,
        repeats,
        args.threads,
        |done, total, label| {
            if terminal {
                let filled = done * 30 / total.max(1);
                let _ = write!(err, "\r[{}{}] {done}/{total} {label:<28}", "#".repeat(filled), " ".repeat(30 - filled));
                let _ = err.flush();
            }
        },
    )?;
    if terminal {
        eprintln!();
    }
    let settings: Vec<_> = configs.iter().map(|c| (c.options, c.size)).collect();
    for (r, pops) in rows.iter_mut().zip(lod_pops_per_min(&scene, &trace, &settings)?) {
        r.lod_pops_per_min = pops;
    }
    let trace_name = trace.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let title =
        format!("{} frames and a run of {} of {trace_name}, {} thread(s)", frames.len(), sequence.len(), args.threads);
    write_outputs(args, &rows, &title)?;
    print_summary(&rows);
    eprintln!(
        "wrote {}/bench.csv, bench.svg, bench.png, visibility.svg, visibility.png, stability.svg and stability.png",
        args.out.display()
    );
    Ok(())
}

/// The trace `bench` measures: the one named, else the demo race of the assets folder (the built-in assets
/// hold none).
fn trace_to_measure(named: Option<&std::path::Path>, assets: &Assets) -> Result<std::path::PathBuf, CliError> {
    match (named, assets) {
        (Some(t), _) => Ok(t.to_path_buf()),
        (None, Assets::Folder(dir)) => Ok(dir.join("replays/demo-race.trace")),
        (None, Assets::BuiltIn) => Err(CliError::NoTrace),
    }
}

/// Refuses an output folder in which a file the bench writes is the trace or one of the assets.
fn outputs_not_inputs(out: &std::path::Path, trace: &std::path::Path, scene: &RaceScene) -> Result<(), CliError> {
    let mut inputs = crate::userfile::Inputs::new();
    inputs.add(trace, "the trace");
    inputs.add_all(&scene.scene().files, super::error::ASSET_FILE);
    for name in OUTPUTS {
        super::error::not_an_input("--out", &out.join(name), &inputs)?;
    }
    Ok(())
}

/// The files `bench` writes into `--out`.
const OUTPUTS: [&str; 7] =
    ["bench.csv", "bench.svg", "bench.png", "visibility.svg", "visibility.png", "stability.svg", "stability.png"];

/// Writes the CSV and, for each panel, the chart as SVG and PNG into `--out`; `title` heads the charts.
fn write_outputs(args: &BenchArgs, rows: &[Row], title: &str) -> Result<(), CliError> {
    let write = |name: &str, bytes: &[u8]| {
        let p = args.out.join(name);
        crate::userfile::replace_atomically(&p, bytes).map_err(CliError::Write)
    };
    write("bench.csv", csv(rows, args.threads).as_bytes())?;
    for (name, panel, what) in [
        ("bench", Panel::Accuracy, "error against the reference"),
        ("visibility", Panel::Visibility, "visibility error alone"),
        ("stability", Panel::Stability, "shimmer over consecutive frames"),
    ] {
        let title = format!("{title}: {what}");
        let chart_error = |source| CliError::Chart { name: name.to_string(), source };
        write(&format!("{name}.svg"), chart::svg(rows, &title, panel).map_err(chart_error)?.as_bytes())?;
        let px = chart::pixels(rows, &title, panel).map_err(chart_error)?;
        write_image(&args.out.join(format!("{name}.png")), &px, chart::SIZE.0 as usize, chart::SIZE.1 as usize)?;
    }
    Ok(())
}

/// Prints the Pareto fronts, the z-buffer, the LOD settings and the default configuration as a table.
fn print_summary(rows: &[Row]) {
    println!(
        "{:<28} {:>10} {:>8} {:>8} {:>9} {:>9} {:>8} {:>7} {:>8}  front",
        "configuration", "size", "ms", "x zbuf", "FLIP", "vis err%", "shimmer", "shim%", "pops/min"
    );
    let default = crate::render::RenderOptions::default();
    for r in rows {
        let is_default = r.config.group == "visibility" && r.config.options == default;
        if r.pareto
            || r.vis_pareto
            || r.stability_pareto
            || r.config.group == "lod"
            || is_default
            || r.config.options.method == Method::ZBuffer && r.config.group == "visibility"
        {
            let fronts: Vec<&str> =
                [(r.pareto, "accuracy"), (r.vis_pareto, "visibility"), (r.stability_pareto, "stability")]
                    .into_iter()
                    .filter_map(|(on, name)| on.then_some(name))
                    .collect();
            println!(
                "{:<28} {:>10} {:>8.2} {:>8.2} {:>9.5} {:>9.3} {:>8.2} {:>7.2} {:>8.1}  {}{}",
                r.config.label,
                format!("{}x{}", r.config.size.0, r.config.size.1),
                r.ms,
                r.ms / r.zbuffer_ms.max(1e-9),
                r.flip_mean,
                r.vis_wrong_pct,
                r.shimmer_rms,
                r.shimmer_pct,
                r.lod_pops_per_min,
                fronts.join(","),
                if is_default { " (default)" } else { "" }
            );
        }
    }
}
