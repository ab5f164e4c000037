//! Writes where a picture's error lies: one of the bench's frames of a course drawn with a preset (or a
//! point, as `examples/presets` names them) and as the reference, with the FLIP map between them, as PNGs.
//!
//! `cargo run --release --example error_map -- COURSE FRAME POINT OUT_DIR` (for example `mountain 3 ultra
//! /tmp/map`): writes `reference.png`, `test.png` and `flip.png` (the per-pixel error, white is 1), and
//! prints the FLIP mean and the share of it from pixels on a geometric edge (a pixel whose polygon-id
//! neighbourhood in the reference differs: approximated by a colour step above 48 in the reference).

#![allow(clippy::unwrap_used, clippy::expect_used)]

mod points;

use scanline_racer::bench::collect_frames;
use scanline_racer::measure::{flip, reference_frame};
use scanline_racer::render::{RenderOptions, Renderer, SKY_BLUE};
use scanline_racer::shell::race_scene::RaceScene;

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

fn save(path: &std::path::Path, img: &[u32], w: usize, h: usize) {
    let rgb: Vec<u8> = img.iter().flat_map(|p| [(p >> 16) as u8, (p >> 8) as u8, *p as u8]).collect();
    image::save_buffer(path, &rgb, w as u32, h as u32, image::ColorType::Rgb8).unwrap();
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let course = args.first().map_or("mountain", String::as_str);
    let index: usize = args.get(1).and_then(|a| a.parse().ok()).unwrap_or(0);
    let point = args.get(2).map_or("ultra", String::as_str);
    let out = std::path::PathBuf::from(args.get(3).map_or("/tmp/error-map", String::as_str));
    std::fs::create_dir_all(&out).unwrap();
    let (w, h) = (640, 480);
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let trace = COURSES.iter().find(|c| c.0 == course).expect("a course").1;
    let scene = RaceScene::load(&root.join("assets"), course).unwrap();
    let frames = collect_frames(&scene, &root.join("assets/replays").join(trace), 8).unwrap();
    let f = &frames[index.min(frames.len() - 1)];
    let list = scene.draw_list(&f.instances);
    let reference = reference_frame(&f.camera, &list, w, h, SKY_BLUE).unwrap();
    let mut test = vec![0u32; w * h];
    let o = RenderOptions { threads: 2, ..points::options(point) };
    Renderer::new().render(&mut test, w, h, &f.camera, &list, &o).unwrap();
    let e = flip(&reference, &test, w, h).unwrap();
    let map: Vec<u32> = e.map.iter().map(|&v| (v.clamp(0.0, 1.0) * 255.0) as u32 * 0x010101).collect();
    save(&out.join("reference.png"), &reference, w, h);
    save(&out.join("test.png"), &test, w, h);
    save(&out.join("flip.png"), &map, w, h);
    // Pixels next to a strong step in the reference (a geometric or texel edge) against the rest.
    let step = |a: u32, b: u32| (0..3).map(|s| ((a >> (8 * s)) & 0xff).abs_diff((b >> (8 * s)) & 0xff)).max().unwrap();
    let (mut edge, mut flat, mut n_edge) = (0.0f64, 0.0f64, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            let p = reference[y * w + x];
            let near = [
                reference[y * w + x - 1],
                reference[y * w + x + 1],
                reference[(y - 1) * w + x],
                reference[(y + 1) * w + x],
            ];
            let v = f64::from(e.map[y * w + x]);
            if near.iter().any(|&q| step(p, q) > 48) {
                edge += v;
                n_edge += 1;
            } else {
                flat += v;
            }
        }
    }
    let n = (w * h) as f64;
    println!(
        "{course} {} {point}: FLIP mean {:.4}; from pixels at a strong step ({:.1}% of pixels) {:.4}, elsewhere {:.4}",
        f.name,
        e.mean,
        n_edge as f64 / n * 100.0,
        edge / n,
        flat / n
    );
}
