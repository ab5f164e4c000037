//! Times a frame of the demo race as the game draws it (every object of the scene, most of them culled) as
//! the best of several rounds, for quick A/B comparisons of two builds on a noisy machine:
//! `cargo run --release --example race_frame -- [zbuffer|bucket-far|bucket-near] [threads] [rounds] [tick]
//! [width] [height] [aa]` (defaults: zbuffer, 2 threads, 5 rounds, tick 3000, 1280x720, the default
//! anti-aliasing; `aa` is a `--aa` name: off, 4x, 8x, 16x, ssaa).
//!
//! Unlike `render` on an exported frame, this keeps the instances the frame culls, as the window does.

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod timing;

use scanline_racer::input::replay::Replay;
use scanline_racer::render::{Method, RenderOptions, Renderer};
use scanline_racer::shell::race_scene::{FIELD, RaceScene, View, camera_for};

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
    let scene = RaceScene::load(&root.join("assets")).unwrap();
    let mut replay = Replay::open(&root.join("assets/replays/demo-race.trace"), scene.track.clone(), FIELD).unwrap();
    while replay.world.tick < tick && replay.advance().unwrap() {}
    let camera = camera_for(&replay.world, View::ChaseNear);
    let instances = scene.instances(&replay.world, None);
    let list = scene.draw_list(&instances);
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    let mut o = RenderOptions { method, threads, ..RenderOptions::default() };
    if let Some(aa) = args.get(6) {
        o.antialias = aa.parse().unwrap();
    }
    let timing::Timing { best, stages } =
        timing::best_of(rounds, || r.render(&mut frame, w, h, &camera, &list, &o).unwrap());
    let hash = timing::frame_hash(&frame);
    let [tr, cl, or, fi] = stages;
    println!(
        "{} aa {} {threads}t tick {tick} {w}x{h}: {best:.3} ms (best stages: transform {tr:.3}, clip {cl:.3}, order {or:.3}, fill {fi:.3} ms), frame {hash:016x}",
        method.name(),
        o.antialias
    );
}
