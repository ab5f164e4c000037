//! Measures where four samples a pixel are best placed: the bench's frames of a course drawn as `ultra`
//! draws them (one frame at twice the size, box-filtered: an ordered 2x2 grid) and as four frames of the
//! frame's own size, each shifted by a sub-pixel offset and averaged, on an ordered grid, a rotated grid
//! (RGSS) and two grids with four rows or four columns of samples. It prints each picture's FLIP mean
//! against the 64x64 reference over the 20 bench frames, its shimmer over the 20-frame stability
//! sequence, and its time over the plain frame's (best of 3, alternated).
//!
//! `cargo run --release --example sample_patterns -- [course,...] [mip] [threads]` (defaults: every
//! course, `off`, 2 threads; 640x480, as `bench`). Every picture uses one mip choice (`off` compares the
//! patterns alone: the four small frames would otherwise pick levels a step blurrier than the big one), no
//! LOD cross-fade and LOD bias +1, as `ultra`; about a minute a course. `--aa rgss` draws the rotated
//! grid (with textures a level finer); this measures the patterns alone.

#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Instant;

use scanline_racer::bench::{BenchFrame, collect_frames, collect_sequence};
use scanline_racer::measure::{Shimmer, flip, reference_frame};
use scanline_racer::render::{Antialias, MipMode, RenderOptions, Renderer, SKY_BLUE};
use scanline_racer::shell::race_scene::RaceScene;

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

/// The four-frame patterns: name and each frame's offset in pixels (a multiple of the fill's 1/16 pixel).
const PATTERNS: [(&str, [[f32; 2]; 4]); 4] = [
    ("ordered 4x1", [[-0.25, -0.25], [0.25, -0.25], [-0.25, 0.25], [0.25, 0.25]]),
    ("rotated 4x1", [[-0.125, -0.375], [0.375, -0.125], [0.125, 0.375], [-0.375, 0.125]]),
    ("four rows 4x1", [[-0.25, -0.375], [-0.25, 0.125], [0.25, -0.125], [0.25, 0.375]]),
    ("four columns 4x1", [[-0.375, -0.25], [0.125, -0.25], [-0.125, 0.25], [0.375, 0.25]]),
];

const W: usize = 640;
const H: usize = 480;

/// The rounded mean, channel by channel, of four frames.
fn mean4(frames: &[Vec<u32>]) -> Vec<u32> {
    (0..W * H)
        .map(|i| {
            let ch = |s: u32| (frames.iter().map(|f| (f[i] >> s) & 0xff).sum::<u32>() + 2) / 4;
            (ch(16) << 16) | (ch(8) << 8) | ch(0)
        })
        .collect()
}

/// One picture of `frame`: `None` for the 2x2 supersampled frame, else the mean of four shifted frames.
fn draw(r: &mut Renderer, scene: &RaceScene, f: &BenchFrame, base: &RenderOptions, pattern: Option<usize>) -> Vec<u32> {
    let list = scene.draw_list(&f.instances);
    let mut one = |o: &RenderOptions| {
        let mut img = vec![0u32; W * H];
        r.render(&mut img, W, H, &f.camera, &list, o).unwrap();
        img
    };
    match pattern {
        None => one(&RenderOptions { antialias: Antialias::Supersample2x2, ..*base }),
        Some(p) => {
            let frames: Vec<Vec<u32>> =
                PATTERNS[p].1.iter().map(|&o| one(&RenderOptions { pixel_offset: o, ..*base })).collect();
            mean4(&frames)
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let chosen: Vec<&str> = args.first().map_or(COURSES.iter().map(|c| c.0).collect(), |a| a.split(',').collect());
    let mip: MipMode = args.get(1).map_or("off", String::as_str).parse().unwrap();
    let threads: usize = args.get(2).and_then(|a| a.parse().ok()).unwrap_or(2);
    let base = RenderOptions { threads, mip, lod_bias: 1.0, ..RenderOptions::default() };
    let plain = RenderOptions { threads, ..RenderOptions::default() };
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let pictures: Vec<(&str, Option<usize>)> = std::iter::once(("2x2 at twice the size", None))
        .chain((0..PATTERNS.len()).map(|p| (PATTERNS[p].0, Some(p))))
        .collect();
    for (course, trace) in COURSES.iter().filter(|c| chosen.contains(&c.0)) {
        let scene = RaceScene::load(&root.join("assets"), course).unwrap();
        let path = root.join("assets/replays").join(trace);
        let frames = collect_frames(&scene, &path, 8).unwrap();
        let sequence = collect_sequence(&scene, &path, 20).unwrap();
        let (mut flips, mut times, mut plain_time) = (vec![0.0f64; pictures.len()], vec![0.0f64; pictures.len()], 0.0);
        let mut renderers: Vec<Renderer> = (0..=pictures.len()).map(|_| Renderer::new()).collect();
        for f in &frames {
            let reference = reference_frame(&f.camera, &scene.draw_list(&f.instances), W, H, SKY_BLUE).unwrap();
            let mut best = vec![f64::MAX; pictures.len() + 1];
            for round in 0..3 {
                for (i, (r, &(_, p))) in renderers.iter_mut().zip(&pictures).enumerate() {
                    let t = Instant::now();
                    let img = draw(r, &scene, f, &base, p);
                    best[i] = best[i].min(t.elapsed().as_secs_f64());
                    if round == 0 {
                        flips[i] += f64::from(flip(&reference, &img, W, H).unwrap().mean);
                    }
                }
                // The plain frame: one of the four frames of the ordered pattern, without the LOD bias.
                let t = Instant::now();
                let list = scene.draw_list(&f.instances);
                let mut img = vec![0u32; W * H];
                renderers[pictures.len()].render(&mut img, W, H, &f.camera, &list, &plain).unwrap();
                best[pictures.len()] = best[pictures.len()].min(t.elapsed().as_secs_f64());
            }
            (0..pictures.len()).for_each(|i| times[i] += best[i]);
            plain_time += best[pictures.len()];
        }
        let mut shimmer: Vec<Shimmer> = vec![Shimmer::default(); pictures.len()];
        let mut renderers: Vec<Renderer> = (0..pictures.len()).map(|_| Renderer::new()).collect();
        for f in &sequence {
            let reference = reference_frame(&f.camera, &scene.draw_list(&f.instances), W, H, SKY_BLUE).unwrap();
            for (i, &(_, p)) in pictures.iter().enumerate() {
                shimmer[i].push(&reference, &draw(&mut renderers[i], &scene, f, &base, p));
            }
        }
        println!("\n{course}, {W}x{H}, mip {mip:?}, {threads} thread(s), {} frames\n", frames.len());
        println!("| picture | x plain frame | FLIP mean | shimmer RMS |");
        println!("|---|---|---|---|");
        for (i, (name, _)) in pictures.iter().enumerate() {
            let n = frames.len() as f64;
            println!("| {name} | {:.2} | {:.4} | {:.2} |", times[i] / plain_time, flips[i] / n, shimmer[i].rms());
        }
    }
}
