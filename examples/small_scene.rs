//! Times the `cargo bench` small-polygon scene (20,000 triangles of about 4.5 pixels at 640x480) as the best
//! of several rounds, for quick A/B comparisons of two builds on a noisy machine:
//! `cargo run --release --example small_scene -- [zbuffer|bucket-far|bucket-near] [threads] [rounds]`.

#![allow(clippy::unwrap_used, clippy::expect_used)]

#[path = "../benches/scenes/mod.rs"]
mod scenes;
mod timing;

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
    let timing::Timing { best, stages } =
        timing::best_of(rounds, || r.render(&mut frame, w, h, &camera, &list, &o).unwrap());
    let hash = timing::frame_hash(&frame);
    let [tr, cl, or, fi] = stages;
    println!(
        "{} {threads}t: {best:.3} ms, {:.2} M polygons/s (best stages: transform {tr:.3}, clip {cl:.3}, order {or:.3}, fill {fi:.3} ms), frame {hash:016x}",
        method.name(),
        tris.len() as f64 / best / 1e3
    );
}
