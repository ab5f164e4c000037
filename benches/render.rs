//! `cargo bench`: the renderer on the demo race's frames and on synthetic scenes, each beside a yardstick
//! measured in the same run: the z-buffer (for other methods) and a flat-colour fill of the same spans
//! (untextured copies of the same polygons), so a speed is read as a ratio, not an absolute on a noisy
//! machine.
//!
//! - `race/*`: tick 3000 of `assets/replays/demo-race.trace` at 1280x720, 1 and 2 threads.
//! - `small/*`: 20,000 triangles of about 4.5 pixels each at 640x480: polygons per second, 1 and 2 threads
//!   (`examples/small_scene.rs` times the same scene as a best of rounds, steadier for comparing builds).
//! - `huge/*`: 8 screen-filling quads at 1280x720: pixels per second.
//! - `deep/*`: 64 overlapping half-screen quads at 640x480 (depth complexity 32): overdraw.
//! - `race/audio-1s`: the mixer over the second of the demo race from tick 3000 (all eight cars' voices),
//!   beside the frame time: its time divided by one second is its share of real time.

#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

mod scenes;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Mat4, Vec3};
use scanline_racer::audio::Mixer;
use scanline_racer::game::TICK_HZ;
use scanline_racer::input::replay::Replay;
use scanline_racer::render::{DrawList, Instance, Mesh, Method, RenderOptions, Renderer};
use scanline_racer::shell::race_scene::{DEFAULT_COURSE, RaceScene, View, camera_for};

/// Benches `mesh` seen by a pixel-unit camera under each method, with each thread count of `threads`.
fn bench_scene(
    c: &mut Criterion,
    (group, threads): (&str, &[usize]),
    mesh: Mesh,
    (w, h): (usize, usize),
    throughput: Throughput,
) {
    let meshes = [mesh];
    let instances = [Instance::new(0, Mat4::IDENTITY)];
    let list = DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
    let camera = scenes::ortho(w, h);
    let mut g = c.benchmark_group(group);
    g.throughput(throughput);
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    for &t in threads {
        for method in [Method::ZBuffer, Method::BucketFar, Method::BucketNear] {
            let o = RenderOptions { method, threads: t, ..RenderOptions::default() };
            let name = format!("{}/{t}t", method.name());
            g.bench_function(name, |b| b.iter(|| r.render(&mut frame, w, h, &camera, &list, &o).unwrap()));
        }
    }
    g.finish();
}

fn synthetic(c: &mut Criterion) {
    let small = scenes::small_triangles();
    let n = small.len() as u64;
    bench_scene(c, ("small", &[1, 2]), scenes::triangles(&small), (640, 480), Throughput::Elements(n));
    // Huge: 8 screen-filling quads at different depths.
    let (w, h) = (1280.0f32, 720.0f32);
    let mut huge = vec![];
    for k in 0..8 {
        let z = k as f32 * 10.0;
        huge.push([Vec3::new(0.0, 0.0, z), Vec3::new(w, 0.0, z), Vec3::new(w, h, z)]);
        huge.push([Vec3::new(0.0, 0.0, z), Vec3::new(w, h, z), Vec3::new(0.0, h, z)]);
    }
    bench_scene(c, ("huge", &[1]), scenes::triangles(&huge), (1280, 720), Throughput::Elements(8 * 1280 * 720));
    // Deep: 64 half-screen quads stacked, half of them over any pixel.
    let mut deep = vec![];
    for k in 0..64 {
        let (x0, z) = ((k % 2) as f32 * 320.0, k as f32);
        deep.push([Vec3::new(x0, 0.0, z), Vec3::new(x0 + 320.0, 0.0, z), Vec3::new(x0 + 320.0, 480.0, z)]);
        deep.push([Vec3::new(x0, 0.0, z), Vec3::new(x0 + 320.0, 480.0, z), Vec3::new(x0, 480.0, z)]);
    }
    bench_scene(c, ("deep", &[1]), scenes::triangles(&deep), (640, 480), Throughput::Elements(64 * 320 * 480));
}

fn race(c: &mut Criterion) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = RaceScene::load(&root.join("assets"), DEFAULT_COURSE).unwrap();
    let mut replay = Replay::open(&root.join("assets/replays/demo-race.trace"), scene.track.clone()).unwrap();
    while replay.world.tick < 3000 && replay.advance().unwrap() {}
    let camera = camera_for(&replay.world, View::ChaseNear);
    let instances = scene.instances(&replay.world, None);
    let list = scene.draw_list(&instances);
    // The yardstick: the same frame with every texture dropped (flat colour through the same spans).
    let flat = DrawList { textures: &[], ..list };
    let (w, h) = (1280, 720);
    let mut frame = vec![0u32; w * h];
    let mut g = c.benchmark_group("race");
    g.throughput(Throughput::Elements((w * h) as u64));
    let mut r = Renderer::new();
    for threads in [1, 2] {
        for (name, method, l) in [
            ("zbuffer", Method::ZBuffer, &list),
            ("bucket-near", Method::BucketNear, &list),
            ("zbuffer-flat", Method::ZBuffer, &flat),
        ] {
            let o = RenderOptions { method, threads, ..RenderOptions::default() };
            g.bench_function(format!("{name}/{threads}t"), |b| {
                b.iter(|| r.render(&mut frame, w, h, &camera, l, &o).unwrap())
            });
        }
    }
    // The sound of one second of the same race (120 worlds), from a mixer already running.
    let mut worlds = vec![];
    while worlds.len() < TICK_HZ as usize && replay.advance().unwrap() {
        worlds.push(replay.world.clone());
    }
    let mut samples = Vec::with_capacity(2 * 48_000);
    g.throughput(Throughput::Elements(48_000));
    g.bench_function("audio-1s", |b| {
        b.iter(|| {
            let mut mixer = Mixer::new();
            samples.clear();
            for w in &worlds {
                mixer.advance(w);
                mixer.render(&mut samples);
            }
        })
    });
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = race, synthetic
}
criterion_main!(benches);
