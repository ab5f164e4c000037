//! Times a frame of the demo race as the game draws it (every object of the scene, most of them culled) as
//! the best of several rounds, for quick A/B comparisons of two builds on a noisy machine:
//! `cargo run --release --example race_frame -- [zbuffer|bucket-far|bucket-near] [threads] [rounds] [tick]
//! [width] [height] [filter] [mip] [aa]` (defaults: zbuffer, 2 threads, 5 rounds, tick 3000, 1280x720,
//! nearest, off, off; `aa` is a `--aa` name: off, 4x, 8x, 16x, ssaa). With `mips` for the filter it times
//! every filter and mip choice of the chart, a round of each in turn (so a busy machine slows them alike),
//! and prints each one's ratio to the default (nearest, off).
//!
//! Unlike `render` on an exported frame, this keeps the instances the frame culls, as the window does.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod timing;

use scanline_racer::input::replay::Replay;
use scanline_racer::render::{Antialias, Filter, Method, MipMode, RenderOptions, Renderer};
use scanline_racer::shell::race_scene::{DEFAULT_COURSE, RaceScene, View, camera_for};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let method = match args.first().map_or("zbuffer", String::as_str) {
        "bucket-far" => Method::BucketFar,
        "bucket-near" => Method::BucketNear,
        _ => Method::ZBuffer,
    };
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (threads, rounds, tick) = (arg(1, 2), arg(2, 5), arg(3, 3000) as u64);
    let (w, h) = (arg(4, 1280), arg(5, 720));
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = RaceScene::load(&root.join("assets"), DEFAULT_COURSE).unwrap();
    let mut replay = Replay::open(&root.join("assets/replays/demo-race.trace"), scene.track.clone()).unwrap();
    while replay.world.tick < tick && replay.advance().unwrap() {}
    let camera = camera_for(&replay.world, View::ChaseNear);
    let instances = scene.instances(&replay.world, None);
    let list = scene.draw_list(&instances);
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    if args.get(6).map(String::as_str) == Some("mips") {
        sweep(
            &mut r,
            (&mut frame, w, h),
            &camera,
            &list,
            RenderOptions { method, threads, ..Default::default() },
            rounds,
        );
        return;
    }
    let filter: Filter = args.get(6).map_or(Ok(Filter::Nearest), |a| a.parse()).unwrap();
    let mip: MipMode = args.get(7).map_or(Ok(MipMode::Off), |a| a.parse()).unwrap();
    let antialias: Antialias = args.get(8).map_or(Ok(Antialias::Off), |a| a.parse()).unwrap();
    let o = RenderOptions { method, threads, filter, mip, antialias, ..RenderOptions::default() };
    let timing::Timing { best, stages } =
        timing::best_of(rounds, || r.render(&mut frame, w, h, &camera, &list, &o).unwrap());
    let hash = timing::frame_hash(&frame);
    let [tr, cl, or, fi] = stages;
    println!(
        "{} {threads}t tick {tick} {w}x{h} {} mip {mip} aa {}: {best:.3} ms (best stages: transform {tr:.3}, clip {cl:.3}, order {or:.3}, fill {fi:.3} ms), frame {hash:016x}",
        method.name(),
        filter.name(),
        o.antialias
    );
}

/// Times every filter and mip choice, a round of 40 frames of each in turn, and prints each one's best
/// against the default's.
fn sweep(
    r: &mut Renderer,
    (frame, w, h): (&mut [u32], usize, usize),
    camera: &scanline_racer::render::Camera,
    list: &scanline_racer::render::DrawList<'_>,
    base: RenderOptions,
    rounds: usize,
) {
    let configs: Vec<(Filter, MipMode)> =
        Filter::ALL.into_iter().flat_map(|f| MipMode::ALL.into_iter().map(move |m| (f, m))).collect();
    let mut best = vec![f64::INFINITY; configs.len()];
    for _ in 0..rounds {
        for (b, &(filter, mip)) in best.iter_mut().zip(&configs) {
            let o = RenderOptions { filter, mip, ..base };
            *b = b.min(timing::best_of(1, || r.render(frame, w, h, camera, list, &o).unwrap()).best);
        }
    }
    for (b, (filter, mip)) in best.iter().zip(&configs) {
        println!("{:9} mip {:7}: {b:8.3} ms, {:.2}x nearest/off", filter.name(), mip.name(), b / best[0]);
    }
}
