//! `scanline-racer bench`: the speed-against-accuracy sweep over a demo replay; writes a CSV and the charts.

use std::io::Write;
use std::path::PathBuf;

use clap::Args;

use super::error::CliError;
use super::values;
use crate::bench::chart::Panel;
use crate::bench::{Row, chart, collect_frames, collect_sequence, configs, csv, lod_pops_per_min, run};
use crate::render::order::view_lists::DEFAULT_MAX_POLYGONS;
use crate::render::{DEFAULT_BUCKETS, DrawList, Method, Quality, ViewLists};
use crate::shell::image_file::write_image;
use crate::shell::race_scene::Assets;
use crate::shell::race_scene::RaceScene;

/// Arguments of `bench`.
#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Folder for `bench.csv` and the charts (`bench`, `visibility` and `stability`, SVG and PNG).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// The trace to replay (default: each course's demo race, `replays/demo-*.trace` of the assets folder).
    #[arg(long, conflicts_with = "course")]
    pub trace: Option<PathBuf>,
    /// A course to measure, by its demo race (repeat for several); default: every course with one.
    #[arg(long, value_name = "NAME", value_parser = values::course_name)]
    pub course: Vec<String>,
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
    /// The preset every configuration starts from (low, medium, high or ultra; each adds its filter, mip
    /// levels and anti-aliasing to the sweep's points). Every preset is also drawn as a point of its own.
    #[arg(long, value_name = "PRESET", default_value_t = Quality::Low)]
    pub quality: Quality,
    /// The race's assets.
    #[command(flatten)]
    pub assets: super::error::AssetsArg,
}

/// Runs `bench`: the sweep on each course's demo race, one CSV with a `course` column, and each course's
/// charts.
pub fn bench_command(args: &BenchArgs) -> Result<(), CliError> {
    // Before the sweep (minutes long): an output folder that cannot be written fails now, not after it.
    super::error::output_folder("--out", &args.out, "the CSV and the charts")?;
    let assets = args.assets.find();
    let traces = traces_to_measure(args, &assets)?;
    let mut measured = vec![];
    for (course, trace) in &traces {
        let scene = args.assets.scene_for_trace(trace)?;
        outputs_not_inputs(&args.out, trace, &scene, &traces)?;
        let (rows, title) = measure(args, &scene, trace)?;
        println!("{course}:");
        print_summary(&rows);
        measured.push((course.clone(), rows, title));
    }
    write_outputs(args, &measured)?;
    let names: Vec<String> = traces.iter().map(|(c, _)| chart_names(c).join(", ")).collect();
    eprintln!("wrote {}/bench.csv, {}", args.out.display(), names.join(", "));
    Ok(())
}

/// The sweep over the frames of `trace` on `scene`: its rows, and the charts' title.
fn measure(args: &BenchArgs, scene: &RaceScene, trace: &std::path::Path) -> Result<(Vec<Row>, String), CliError> {
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
    let frames = collect_frames(scene, trace, frames)?;
    if frames.is_empty() {
        return Err(CliError::NoRacingFrames { trace: trace.to_path_buf() });
    }
    let sequence = collect_sequence(scene, trace, sequence)?;
    let configs = configs(main, &buckets, &resolutions, args.quality);
    let mut err = std::io::stderr();
    let terminal = std::io::IsTerminal::is_terminal(&err);
    eprintln!(
        "bench {}: {} configurations x {} frames x {repeats} repeats and {} sequence frames, {} thread(s), main size {}x{}",
        scene.course,
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
    for (r, pops) in rows.iter_mut().zip(lod_pops_per_min(scene, trace, &settings)?) {
        r.lod_pops_per_min = pops;
    }
    let trace_name = trace.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let title = format!(
        "{}: {} frames and a run of {} of {trace_name}, {} thread(s)",
        scene.course,
        frames.len(),
        sequence.len(),
        args.threads
    );
    Ok((rows, title))
}

/// The traces `bench` measures, with their courses: the one named (its header names the course), else the
/// demo race of each course asked for, else of every course the assets folder has one for (the built-in
/// assets hold none).
fn traces_to_measure(args: &BenchArgs, assets: &Assets) -> Result<Vec<(String, PathBuf)>, CliError> {
    if let Some(t) = &args.trace {
        let (header, _) = crate::input::trace::TraceReader::open(t).map_err(crate::input::replay::ReplayError::from)?;
        return Ok(vec![(header.course, t.clone())]);
    }
    let Assets::Folder(dir) = assets else { return Err(CliError::NoTrace) };
    let demos = demo_traces(&dir.join("replays"));
    let wanted = if args.course.is_empty() { assets.course_names() } else { args.course.clone() };
    let mut out = vec![];
    for course in wanted {
        match demos.iter().find(|(c, _)| *c == course) {
            Some((_, t)) => out.push((course, t.clone())),
            None if args.course.is_empty() => {}
            None => return Err(CliError::NoDemoTrace { course, folder: dir.join("replays") }),
        }
    }
    if out.is_empty() {
        return Err(CliError::NoTrace);
    }
    Ok(out)
}

/// The demo races in `folder` (`demo-*.trace`, in name order) with the course each header names.
fn demo_traces(folder: &std::path::Path) -> Vec<(String, PathBuf)> {
    let Ok(entries) = std::fs::read_dir(folder) else { return vec![] };
    let mut paths: Vec<PathBuf> = entries
        .flatten()
        .take(4096)
        .map(|e| e.path())
        .filter(|p| {
            let name = p.file_name().and_then(|n| n.to_str()).unwrap_or("");
            name.starts_with("demo-") && name.ends_with(".trace")
        })
        .collect();
    paths.sort();
    paths
        .into_iter()
        .filter_map(|p| crate::input::trace::TraceReader::open(&p).ok().map(|(h, _)| (h.course, p)))
        .collect()
}

/// Refuses an output folder in which a file the bench writes (for any of the `courses` measured) is the
/// trace or one of the assets of the course measured on `scene`.
fn outputs_not_inputs(
    out: &std::path::Path,
    trace: &std::path::Path,
    scene: &RaceScene,
    courses: &[(String, PathBuf)],
) -> Result<(), CliError> {
    let mut inputs = crate::userfile::Inputs::new();
    inputs.add(trace, "the trace");
    inputs.add_all(&scene.scene().files, super::error::ASSET_FILE);
    super::error::not_an_input("--out", &out.join("bench.csv"), &inputs)?;
    for (course, _) in courses {
        for name in chart_names(course) {
            super::error::not_an_input("--out", &out.join(name), &inputs)?;
        }
    }
    Ok(())
}

/// The charts `bench` writes into `--out` for `course`: `bench-COURSE`, `visibility-COURSE` and
/// `stability-COURSE`, SVG and PNG.
fn chart_names(course: &str) -> Vec<String> {
    ["bench", "visibility", "stability"]
        .iter()
        .flat_map(|c| [format!("{c}-{course}.svg"), format!("{c}-{course}.png")])
        .collect()
}

/// Writes the CSV of every course's rows and, for each course and panel, the chart as SVG and PNG into
/// `--out`; each course's title heads its charts.
fn write_outputs(args: &BenchArgs, measured: &[(String, Vec<Row>, String)]) -> Result<(), CliError> {
    let write = |name: &str, bytes: &[u8]| {
        let p = args.out.join(name);
        crate::userfile::replace_atomically(&p, bytes).map_err(CliError::Write)
    };
    let all: Vec<(&str, &[Row])> = measured.iter().map(|(c, rows, _)| (c.as_str(), rows.as_slice())).collect();
    write("bench.csv", csv(&all, args.threads).as_bytes())?;
    for (course, rows, title) in measured {
        for (name, panel, what) in [
            ("bench", Panel::Accuracy, "error against the reference"),
            ("visibility", Panel::Visibility, "visibility error alone"),
            ("stability", Panel::Stability, "shimmer over consecutive frames"),
        ] {
            let title = format!("{title}: {what}");
            let name = format!("{name}-{course}");
            let chart_error = |source| CliError::Chart { name: name.clone(), source };
            write(&format!("{name}.svg"), chart::svg(rows, &title, panel).map_err(chart_error)?.as_bytes())?;
            let px = chart::pixels(rows, &title, panel).map_err(chart_error)?;
            let (w, h) = (chart::SIZE.0 as usize, chart::SIZE.1 as usize);
            write_image(&args.out.join(format!("{name}.png")), &px, w, h)?;
        }
    }
    Ok(())
}

/// Prints the Pareto fronts, the z-buffer, the LOD settings and the default configuration as a table.
fn print_summary(rows: &[Row]) {
    println!(
        "{:<28} {:>10} {:>8} {:>8} {:>9} {:>9} {:>8} {:>7} {:>8}  front",
        "configuration", "size", "ms", "x zbuf", "FLIP", "vis err%", "shimmer", "shim%", "pops/min"
    );
    let main = rows.first().map_or((0, 0), |r| r.config.size);
    let default = crate::render::RenderOptions::default();
    for r in rows {
        let is_default = r.config.group == "visibility" && r.config.options == default;
        let preset = crate::bench::configs::preset_of(&r.config, main);
        if r.pareto
            || r.vis_pareto
            || r.stability_pareto
            || r.config.group == "lod"
            || is_default
            || preset.is_some()
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
                match (is_default, preset) {
                    (_, Some(q)) => format!(" (preset {q})"),
                    (true, None) => " (default)".to_string(),
                    (false, None) => String::new(),
                }
            );
        }
    }
}
