//! Shows whether the reference image has converged: the bench's frames of each course's demo race drawn as
//! references at grids of 4, 8, 16 and 32 samples per axis of a pixel, each grid compared with the next
//! (FLIP mean over the frames, and the largest of any frame), and the bench's stability sequence drawn at
//! each grid, measured for shimmer against the sequence at the next grid.
//!
//! Both references are rounded to 8 bits a channel, so a pixel whose true value sits near a half step
//! rounds one way at N and the other at 2N; FLIP sees such one-step differences. The last column is the
//! FLIP mean with them set equal: what is left is the part of the difference beyond rounding.
//!
//! `cargo run --release --example convergence -- [width] [height] [frames] [sequence] [course,...] [grids]`
//! (defaults: 640x480, 8 frames (20 with the other views, as `bench` draws them), a sequence of 20, every
//! course, grids `4,8,16,32`; powers of two up to 128). Prints a Markdown table per course. It takes
//! minutes: a 32x32 reference is 64 drawings at 16 times the frame's pixels, a 128x128 one 64 drawings at
//! 256 times (about 15 s a 640x480 frame on two cores).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use scanline_racer::bench::{collect_frames, collect_sequence};
use scanline_racer::measure::{Shimmer, channel_diff, flip, reference_frame_at};
use scanline_racer::render::SKY_BLUE;
use scanline_racer::shell::race_scene::RaceScene;

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: usize| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (w, h, nframes, nseq) = (arg(0, 640), arg(1, 480), arg(2, 8), arg(3, 20));
    let chosen: Vec<&str> = args.get(4).map_or(COURSES.iter().map(|c| c.0).collect(), |a| a.split(',').collect());
    let grids: Vec<usize> =
        args.get(5).map_or(vec![4, 8, 16, 32], |a| a.split(',').map(|g| g.parse().expect("grid")).collect());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    for (course, trace) in COURSES.iter().filter(|c| chosen.contains(&c.0)) {
        let scene = RaceScene::load(&root.join("assets"), course).unwrap();
        let path = root.join("assets/replays").join(trace);
        let frames = collect_frames(&scene, &path, nframes).unwrap();
        let sequence = collect_sequence(&scene, &path, nseq).unwrap();
        let draw = |f: &scanline_racer::bench::BenchFrame, grid: usize| {
            reference_frame_at(&f.camera, &scene.draw_list(&f.instances), (w, h), SKY_BLUE, grid).unwrap()
        };
        let frames_at: Vec<Vec<Vec<u32>>> =
            grids.iter().map(|g| frames.iter().map(|f| draw(f, *g)).collect()).collect();
        let seq_at: Vec<Vec<Vec<u32>>> = grids.iter().map(|g| sequence.iter().map(|f| draw(f, *g)).collect()).collect();
        println!(
            "\n{course}, {w}x{h}: {} frames, a sequence of {}\n\n| grid N | against 2N: FLIP mean | largest frame's FLIP mean | shimmer RMS | shimmering % | FLIP mean beyond rounding |\n|---|---|---|---|---|---|",
            frames.len(),
            sequence.len()
        );
        for k in 0..grids.len().saturating_sub(1) {
            let flips: Vec<f64> = frames_at[k]
                .iter()
                .zip(&frames_at[k + 1])
                .map(|(a, b)| flip(b, a, w, h).map_or(0.0, |f| f64::from(f.mean)))
                .collect();
            let mean = flips.iter().sum::<f64>() / flips.len().max(1) as f64;
            let beyond: f64 = frames_at[k]
                .iter()
                .zip(&frames_at[k + 1])
                .map(|(a, b)| {
                    let a: Vec<u32> =
                        a.iter().zip(b).map(|(p, q)| if channel_diff(*p, *q) <= 1 { *q } else { *p }).collect();
                    flip(b, &a, w, h).map_or(0.0, |f| f64::from(f.mean))
                })
                .sum::<f64>()
                / flips.len().max(1) as f64;
            let worst = flips.iter().copied().fold(0.0, f64::max);
            let mut shimmer = Shimmer::default();
            for (a, b) in seq_at[k].iter().zip(&seq_at[k + 1]) {
                shimmer.push(b, a);
            }
            println!(
                "| {} vs {} | {mean:.4} | {worst:.4} | {:.2} | {:.3} | {beyond:.4} |",
                grids[k],
                grids[k + 1],
                shimmer.rms(),
                shimmer.shimmering_pct()
            );
        }
    }
}
