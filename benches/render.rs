//! `cargo bench`: the renderer on the demo race's frames and on synthetic scenes, each beside a yardstick
//! measured in the same run: the z-buffer (for other methods) and a flat-colour fill of the same spans
//! (untextured copies of the same polygons), so a speed is read as a ratio, not an absolute on a noisy
//! machine.
//!
//! - `race/*`: tick 3000 of `assets/replays/demo-race.trace` at 1280x720, 1 and 2 threads.
//! - `small/*`: 20,000 triangles of about 8 pixels each at 640x480: polygons per second.
//! - `huge/*`: 8 screen-filling quads at 1280x720: pixels per second.
//! - `deep/*`: 64 overlapping half-screen quads at 640x480 (depth complexity 32): overdraw.

#![allow(clippy::unwrap_used, clippy::expect_used, missing_docs)]

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::{Mat4, Vec2, Vec3, Vec4};
use scanline_racer::input::replay::Replay;
use scanline_racer::render::{
    Camera, DrawList, Instance, Material, Mesh, MeshBuilder, Method, Projection, RenderOptions, Renderer, Vertex,
};
use scanline_racer::shell::race_scene::{FIELD, RaceScene, View, camera_for};

fn ortho(w: usize, h: usize) -> Camera {
    let (hw, hh) = (w as f32 * 0.5, h as f32 * 0.5);
    Camera {
        view: Mat4::from_translation(Vec3::new(-hw, -hh, -1000.0)),
        projection: Projection::Orthographic { xmag: hw, ymag: hh, znear: 1.0, zfar: 3000.0 },
    }
}

/// A mesh of flat triangles `(x, y, z)` in pixels, colours cycling.
fn triangles(tris: &[[Vec3; 3]]) -> Mesh {
    let mut b = MeshBuilder::new();
    let m = b.material(Material { double_sided: true, ..Material::default() });
    for (i, t) in tris.iter().enumerate() {
        let c = Vec4::new((i % 7) as f32 / 7.0, (i % 5) as f32 / 5.0, (i % 3) as f32 / 3.0, 1.0);
        let idx: Vec<u32> = t.iter().map(|&p| b.vertex(Vertex { position: p, uv: Vec2::ZERO, color: c })).collect();
        b.polygon(&idx, m);
    }
    b.build().unwrap()
}

fn bench_scene(c: &mut Criterion, group: &str, mesh: Mesh, (w, h): (usize, usize), throughput: Throughput) {
    let meshes = [mesh];
    let instances = [Instance::new(0, Mat4::IDENTITY)];
    let list = DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
    let camera = ortho(w, h);
    let mut g = c.benchmark_group(group);
    g.throughput(throughput);
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    for method in [Method::ZBuffer, Method::BucketFar, Method::BucketNear] {
        let o = RenderOptions { method, threads: 1, ..RenderOptions::default() };
        g.bench_function(method.name(), |b| b.iter(|| r.render(&mut frame, w, h, &camera, &list, &o).unwrap()));
    }
    g.finish();
}

fn synthetic(c: &mut Criterion) {
    // Small: a 200 x 100 grid of 3x3-pixel right triangles (about 4.5 pixels each), random depths.
    let mut small = vec![];
    let mut seed = 1u32;
    for gy in 0..100 {
        for gx in 0..200 {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let z = (seed >> 8) as f32 / 16_777_216.0 * 100.0;
            let (x, y) = (gx as f32 * 3.2, gy as f32 * 4.8);
            small.push([Vec3::new(x, y, z), Vec3::new(x + 3.0, y, z), Vec3::new(x, y + 3.0, z)]);
        }
    }
    let n = small.len() as u64;
    bench_scene(c, "small", triangles(&small), (640, 480), Throughput::Elements(n));
    // Huge: 8 screen-filling quads at different depths.
    let (w, h) = (1280.0f32, 720.0f32);
    let mut huge = vec![];
    for k in 0..8 {
        let z = k as f32 * 10.0;
        huge.push([Vec3::new(0.0, 0.0, z), Vec3::new(w, 0.0, z), Vec3::new(w, h, z)]);
        huge.push([Vec3::new(0.0, 0.0, z), Vec3::new(w, h, z), Vec3::new(0.0, h, z)]);
    }
    bench_scene(c, "huge", triangles(&huge), (1280, 720), Throughput::Elements(8 * 1280 * 720));
    // Deep: 64 half-screen quads stacked, half of them over any pixel.
    let mut deep = vec![];
    for k in 0..64 {
        let (x0, z) = ((k % 2) as f32 * 320.0, k as f32);
        deep.push([Vec3::new(x0, 0.0, z), Vec3::new(x0 + 320.0, 0.0, z), Vec3::new(x0 + 320.0, 480.0, z)]);
        deep.push([Vec3::new(x0, 0.0, z), Vec3::new(x0 + 320.0, 480.0, z), Vec3::new(x0, 480.0, z)]);
    }
    bench_scene(c, "deep", triangles(&deep), (640, 480), Throughput::Elements(64 * 320 * 480));
}

fn race(c: &mut Criterion) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = RaceScene::load(&root.join("assets")).unwrap();
    let mut replay = Replay::open(&root.join("assets/replays/demo-race.trace"), scene.track.clone(), FIELD).unwrap();
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
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(20).warm_up_time(std::time::Duration::from_millis(500))
        .measurement_time(std::time::Duration::from_secs(2));
    targets = race, synthetic
}
criterion_main!(benches);
