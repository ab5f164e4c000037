//! Polygons drawn over each course's whole demo race with level-of-detail changes swapped and cross-faded:
//! what the fades cost in polygons, against the swaps they replace.
//!
//! `cargo run --release --example lod_polygons -- [every] [width] [height] [course,...]` (defaults: every
//! second tick, 320x240, every course). Two renderers follow the race from the chase camera, each keeping
//! its LOD history as the game does: one with `lod_fade` off, one with it on. Prints the mean polygons
//! drawn per frame of each, the pops per minute with swaps (a third renderer's LOD choice every frame at
//! 60 Hz, counted by `bench`'s rule, `bench::frames::pops`), and the changes of model per minute with fades
//! (a fourth's: an instance seen in a frame and the one before with another chosen model; each starts a
//! fade, where the swap would pop).

#![allow(clippy::unwrap_used, clippy::expect_used)]

use scanline_racer::game::TICK_HZ;
use scanline_racer::input::replay::Replay;
use scanline_racer::render::{RenderOptions, Renderer};
use scanline_racer::shell::race_scene::{RaceScene, View, camera_for};

/// An instance's chosen mesh and whether it is fading, as `Renderer::frame_lod` gives it.
type Choice = Option<(usize, bool)>;

/// The demo race of each course.
const COURSES: [(&str, &str); 3] =
    [("circuit", "demo-race.trace"), ("city", "demo-city.trace"), ("mountain", "demo-mountain.trace")];

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: u64| args.get(i).and_then(|a| a.parse().ok()).unwrap_or(default);
    let (every, w, h) = (arg(0, 2).max(1), arg(1, 320) as usize, arg(2, 240) as usize);
    let chosen: Vec<&str> = args.get(3).map_or(COURSES.iter().map(|c| c.0).collect(), |a| a.split(',').collect());
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut frame = vec![0u32; w * h];
    println!("every {every} ticks at {w}x{h}, chase camera, 1 thread\n");
    println!(
        "| course | frames | polygons drawn, swap | with fades | change | pops/min, swap | changes/min with fades |"
    );
    println!("|---|---|---|---|---|---|---|");
    for (course, trace) in COURSES.iter().filter(|c| chosen.contains(&c.0)) {
        let scene = RaceScene::load(&root.join("assets"), course).unwrap();
        let mut replay = Replay::open(&root.join("assets/replays").join(trace), scene.track.clone()).unwrap();
        let (mut swap, mut fade, mut choice) = (Renderer::new(), Renderer::new(), Renderer::new());
        let (mut last, mut changes): (Vec<Choice>, u64) = (Vec::new(), 0);
        let (mut swap_choice, mut last_swap, mut pops): (Renderer, Vec<Choice>, u64) = (Renderer::new(), Vec::new(), 0);
        let plain = RenderOptions { threads: 1, ..RenderOptions::default() };
        let faded = RenderOptions { lod_fade: true, ..plain };
        let (mut frames, mut sum_swap, mut sum_fade) = (0u64, 0u64, 0u64);
        loop {
            if replay.world.tick.is_multiple_of(u64::from(TICK_HZ / 60)) {
                let camera = camera_for(&replay.world, View::ChaseNear);
                let instances = scene.instances(&replay.world, None);
                let now = choice.frame_lod(w, h, &camera, &scene.draw_list(&instances), &faded);
                let changed = |(a, b): (&Choice, &Choice)| matches!((a, b), (Some((m, _)), Some((n, _))) if m != n);
                changes += now.iter().zip(&last).filter(|&p| changed(p)).count() as u64;
                last = now;
                let swapped = swap_choice.frame_lod(w, h, &camera, &scene.draw_list(&instances), &plain);
                pops += scanline_racer::bench::frames::pops(&last_swap, &swapped);
                last_swap = swapped;
            }
            if replay.world.tick.is_multiple_of(every) {
                let camera = camera_for(&replay.world, View::ChaseNear);
                let instances = scene.instances(&replay.world, None);
                let list = scene.draw_list(&instances);
                sum_swap += swap.render(&mut frame, w, h, &camera, &list, &plain).unwrap().polygons_drawn;
                sum_fade += fade.render(&mut frame, w, h, &camera, &list, &faded).unwrap().polygons_drawn;
                frames += 1;
            }
            if !replay.advance().unwrap() {
                break;
            }
        }
        let (a, b) = (sum_swap as f64 / frames as f64, sum_fade as f64 / frames as f64);
        let minutes = replay.world.tick as f64 / f64::from(TICK_HZ) / 60.0;
        println!(
            "| {course} | {frames} | {a:.1} | {b:.1} | {:+.2}% | {:.0} | {:.0} |",
            (b / a - 1.0) * 100.0,
            pops as f64 / minutes,
            changes as f64 / minutes
        );
    }
}
