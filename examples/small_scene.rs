//! Times the `cargo bench` small-polygon scene (20,000 triangles of about 4.5 pixels at 640x480) as the best
//! of several rounds, for quick A/B comparisons of two builds on a noisy machine:
//! `cargo run --release --example small_scene -- [zbuffer|bucket-far|bucket-near] [threads] [rounds]`.

#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../benches/scenes/mod.rs"]
mod scenes;

use std::time::Instant;

use glam::Mat4;
use scanline_racer::render::{DrawList, Instance, Method, RenderOptions, Renderer};

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let method = match args.first().map_or("zbuffer", String::as_str) {
        "bucket-far" => Method::BucketFar,
        "bucket-near" => Method::BucketNear,
        _ => Method::ZBuffer,
    };
    let threads: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(1);
    let rounds: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(5);
    let tris = scenes::small_triangles();
    let meshes = [scenes::triangles(&tris)];
    let instances = [Instance::new(0, Mat4::IDENTITY)];
    let list = DrawList { meshes: &meshes, textures: &[], instances: &instances, lod_sets: &[], view_lists: None };
    let (w, h) = (640, 480);
    let camera = scenes::ortho(w, h);
    let mut frame = vec![0u32; w * h];
    let mut r = Renderer::new();
    let o = RenderOptions { method, threads, ..RenderOptions::default() };
    let mut best = f64::INFINITY;
    let mut stages = [f64::INFINITY; 4];
    for _ in 0..rounds {
        let mut times: Vec<f64> = (0..40)
            .map(|_| {
                let t = Instant::now();
                let s = r.render(&mut frame, w, h, &camera, &list, &o).unwrap();
                let ms = t.elapsed().as_secs_f64() * 1e3;
                for (b, v) in stages.iter_mut().zip([s.ms_transform, s.ms_clip, s.ms_order, s.ms_fill]) {
                    *b = b.min(v);
                }
                ms
            })
            .collect();
        times.sort_by(f64::total_cmp);
        best = best.min(times[times.len() / 2]);
    }
    let hash = frame.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &p| (h ^ u64::from(p)).wrapping_mul(0x100_0000_01b3));
    let [tr, cl, or, fi] = stages;
    println!(
        "{} {threads}t: {best:.3} ms, {:.2} M polygons/s (best stages: transform {tr:.3}, clip {cl:.3}, order {or:.3}, fill {fi:.3} ms), frame {hash:016x}",
        method.name(),
        tris.len() as f64 / best / 1e3
    );
}
