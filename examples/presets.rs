//! Measures the quality presets as `bench` measures its points (the same frames, reference, interleaved
//! z-buffer timing and stability sequence, through `bench::run`), without the rest of the sweep: a table
//! per course of each preset's time against the default, FLIP mean against the reference, shimmer over
//! the stability sequence, and polygons drawn.
//!
//! `cargo run --release --example presets -- [course,...] [threads] [width] [height] [aa/filter/mip,...]`
//! (defaults: every course, 1 thread, 640x480, as `bench`; the last argument adds points beside the
//! presets, each named by its `--aa`, `--filter` and `--mip` values, as `ssaa/aniso8/pixel`, or by a
//! preset and a filter, as `ultra/aniso4`; either may end in `:BIAS`, a LOD bias, as `ultra/nearest:2`, and
//! then in `@BIAS`, a mip bias, as `ultra:2@-1`). A few minutes a course: most of it is the reference frames.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod points;

use scanline_racer::bench::{Config, collect_frames, collect_sequence, run};
use scanline_racer::render::{Quality, RenderOptions};
use scanline_racer::shell::race_scene::RaceScene;

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let chosen: Vec<&str> = args.first().map_or(COURSES.iter().map(|c| c.0).collect(), |a| a.split(',').collect());
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (threads, w, h) = (arg(1, 1), arg(2, 640), arg(3, 480));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let config = |label: String, options| Config { group: "quality", label, options, size: (w, h), view_level: None };
    let mut configs: Vec<Config> =
        Quality::ALL.iter().map(|q| config(q.name().to_string(), q.apply(RenderOptions::default()))).collect();
    for point in args.get(4).map(|a| a.split(',').collect::<Vec<_>>()).unwrap_or_default() {
        let options = points::options(point);
        configs.push(config(point.to_string(), options));
    }
    for (course, trace) in COURSES.iter().filter(|c| chosen.contains(&c.0)) {
        let scene = RaceScene::load(&root.join("assets"), course).unwrap();
        let path = root.join("assets/replays").join(trace);
        let frames = collect_frames(&scene, &path, 8).unwrap();
        let sequence = collect_sequence(&scene, &path, 20).unwrap();
        let rows =
            run(&frames, &sequence, |f, _| scene.draw_list(&f.instances), &configs, 3, threads, |_, _, _| {}).unwrap();
        println!("\n{course}, {w}x{h}, {threads} thread(s)\n");
        println!("| preset | x zbuffer | FLIP mean | shimmer RMS | shimmering % | polygons drawn |");
        println!("|---|---|---|---|---|---|");
        for r in &rows {
            println!(
                "| {} | {:.2} | {:.4} | {:.2} | {:.2} | {:.0} |",
                r.config.label,
                r.ms / r.zbuffer_ms.max(1e-9),
                r.flip_mean,
                r.shimmer_rms,
                r.shimmer_pct,
                r.polygons_drawn
            );
        }
    }
}
