//! Profiles the renderer's stages on every course: frames of each course's demo race drawn as the game
//! draws them (every object of the scene, culled ones included), each timed as the median of 20 renders in
//! the best of several rounds, with the median time of each stage in that round and the time outside them.
//!
//! `cargo run --release --example profile -- [threads,...] [width] [height] [rounds] [course,...]`
//! (defaults: `1,2`, 1280x720, 3 rounds, every course). Prints a Markdown table per thread count (the means
//! over the frames of each course) and, with `-v` anywhere, a line per frame; `--no-coarse-depth` anywhere
//! draws without the z-buffer's coarse depth (`RenderOptions::coarse_depth`), to see what it saves. The fill's cost per pixel
//! is the fill's wall time over the pixels it shaded: on one thread, the cost of a pixel on one core.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use scanline_racer::input::replay::Replay;
use scanline_racer::render::{RenderOptions, Renderer, Stats};
use scanline_racer::shell::race_scene::{RaceScene, View, camera_for};

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

/// The ticks drawn on every course (each demo race lasts longer than the last).
const TICKS: [u64; 8] = [1200, 2400, 3600, 4800, 6000, 7200, 8400, 9600];

/// One frame's figures: total, transform, clip, order, fill (ms), pixels shaded, polygons drawn.
#[derive(Clone, Copy, Default)]
struct Figures([f64; 7]);

fn main() {
    let verbose = std::env::args().any(|a| a == "-v");
    let coarse_depth = !std::env::args().any(|a| a == "--no-coarse-depth");
    let args: Vec<String> = std::env::args().skip(1).filter(|a| a != "-v" && a != "--no-coarse-depth").collect();
    let threads: Vec<usize> =
        args.first().map_or(vec![1, 2], |a| a.split(',').map(|t| t.parse().expect("thread count")).collect());
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (w, h, rounds) = (arg(1, 1280), arg(2, 720), arg(3, 3));
    let chosen: Vec<&str> = args.get(4).map_or(COURSES.iter().map(|c| c.0).collect(), |a| a.split(',').collect());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    for &t in &threads {
        println!("\n{w}x{h}, {t} thread(s), {rounds} rounds of 20 renders per frame, ticks {TICKS:?}\n");
        println!(
            "| course | polygons | pixels shaded | total ms | transform | clip + set-up | order | fill | outside | outside % | fill ns/pixel |"
        );
        println!("|---|---|---|---|---|---|---|---|---|---|---|");
        for (course, trace) in COURSES.iter().filter(|c| chosen.contains(&c.0)) {
            let scene = RaceScene::load(&root.join("assets"), course).unwrap();
            let mut replay = Replay::open(&root.join("assets/replays").join(trace), scene.track.clone()).unwrap();
            let mut sum = Figures::default();
            for tick in TICKS {
                while replay.world.tick < tick && replay.advance().unwrap() {}
                let camera = camera_for(&replay.world, View::ChaseNear);
                let instances = scene.instances(&replay.world, None);
                let list = scene.draw_list(&instances);
                let o = RenderOptions { threads: t, coarse_depth, ..RenderOptions::default() };
                let f = measure(rounds, || r.render(&mut frame, w, h, &camera, &list, &o).unwrap());
                if std::env::var_os("PROFILE_COUNTS").is_some() {
                    let s = r.render(&mut frame, w, h, &camera, &list, &o).unwrap();
                    println!(
                        "  {course} {tick}: objects {} culled {}, polygons in {} in culled {} outside {} backface {} degenerate {} drawn {}, lod {}/{}/{}",
                        s.objects_in,
                        s.objects_culled,
                        s.polygons_in,
                        s.polygons_in_culled_objects,
                        s.polygons_outside,
                        s.polygons_backface,
                        s.polygons_degenerate,
                        s.polygons_drawn,
                        s.lod_close,
                        s.lod_mid,
                        s.lod_long
                    );
                }
                if verbose {
                    let [tot, tr, cl, or, fi, px, polys] = f.0;
                    println!(
                        "  {course} tick {tick}: {tot:.3} ms (transform {tr:.3}, clip {cl:.3}, order {or:.3}, fill {fi:.3}, outside {:.3}), {px} pixels, {polys} polygons",
                        tot - tr - cl - or - fi
                    );
                }
                for (s, v) in sum.0.iter_mut().zip(f.0) {
                    *s += v / TICKS.len() as f64;
                }
            }
            let [tot, tr, cl, or, fi, px, polys] = sum.0;
            let outside = tot - tr - cl - or - fi;
            println!(
                "| {course} | {polys:.0} | {px:.0} | {tot:.3} | {tr:.3} | {cl:.3} | {or:.3} | {fi:.3} | {outside:.3} | {:.1} | {:.2} |",
                outside / tot * 100.0,
                fi * 1e6 / px
            );
        }
    }
}

/// The best round's figures: in each round, the median of 20 renders for the total and for each stage.
fn measure(rounds: usize, mut render: impl FnMut() -> Stats) -> Figures {
    let mut best: Option<Figures> = None;
    for _ in 0..rounds {
        let mut runs: Vec<(f64, Stats)> = (0..20)
            .map(|_| {
                let t = Instant::now();
                let s = render();
                (t.elapsed().as_secs_f64() * 1e3, s)
            })
            .collect();
        let median = |key: &dyn Fn(&(f64, Stats)) -> f64, runs: &mut Vec<(f64, Stats)>| {
            let mut v: Vec<f64> = runs.iter().map(key).collect();
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let f = Figures([
            median(&|r| r.0, &mut runs),
            median(&|r| r.1.ms_transform, &mut runs),
            median(&|r| r.1.ms_clip, &mut runs),
            median(&|r| r.1.ms_order, &mut runs),
            median(&|r| r.1.ms_fill, &mut runs),
            runs[runs.len() - 1].1.pixels_shaded as f64,
            runs[runs.len() - 1].1.polygons_drawn as f64,
        ]);
        if best.is_none_or(|b| f.0[0] < b.0[0]) {
            best = Some(f);
        }
    }
    best.unwrap_or_default()
}
