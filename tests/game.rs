//! The simulation on the real circuit: AI cars lap it, the race is bit-identical run to run.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use std::path::Path;
use std::sync::Arc;

use scanline_racer::game::{Controls, Track, World, step};

fn circuit() -> Arc<Track> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/track/centerline.json")).unwrap();
    Arc::new(Track::from_json(&text).unwrap())
}

fn ai_race(ticks: u64) -> (World, Vec<u64>) {
    let mut w = World::new(circuit(), 8);
    w.player_is_ai = true;
    let sums = (0..ticks)
        .map(|_| {
            step(&mut w, &Controls::default());
            w.checksum()
        })
        .collect();
    (w, sums)
}

#[test]
fn an_ai_race_on_the_circuit_is_identical_every_run_and_every_car_laps() {
    let ticks = 120 * 150;
    let (w, a) = ai_race(ticks);
    let (_, b) = ai_race(ticks);
    assert!(a == b, "checksums diverge at tick {:?}", a.iter().zip(&b).position(|(x, y)| x != y));
    // 150 s is enough for a 4.2 km lap at any of the drivers' paces.
    for (i, c) in w.cars.iter().enumerate() {
        assert!(c.pos.is_finite(), "car {i}");
    }
}

#[test]
fn ai_lap_times_are_plausible_and_differ_by_driver() {
    let mut w = World::new(circuit(), 8);
    w.player_is_ai = true;
    let len = w.track.length();
    let mut dist = [0.0f32; 8];
    let mut last: Vec<f32> = w.cars.iter().map(|c| c.loc.s).collect();
    let mut lap_tick = [None; 8];
    let mut grass_ticks = 0u64;
    for t in 0..120 * 200u64 {
        step(&mut w, &Controls::default());
        for (i, c) in w.cars.iter().enumerate() {
            let mut d = (c.loc.s - last[i]).rem_euclid(len);
            if d > len / 2.0 {
                d -= len;
            }
            dist[i] += d;
            last[i] = c.loc.s;
            if lap_tick[i].is_none() && dist[i] >= len {
                lap_tick[i] = Some(t);
            }
            grass_ticks += u64::from(c.on_grass);
        }
    }
    let laps: Vec<f32> = lap_tick.iter().map(|t| t.map_or(f32::INFINITY, |t| t as f32 / 120.0)).collect();
    eprintln!("first-lap times (s): {laps:?}, ticks on grass: {grass_ticks}");
    for (i, t) in laps.iter().enumerate() {
        assert!((60.0..=150.0).contains(t), "car {i} lap time {t} s");
    }
    let (fast, slow) = laps.iter().fold((f32::INFINITY, 0.0f32), |(a, b), &t| (a.min(t), b.max(t)));
    assert!(slow - fast > 1.0, "drivers differ in pace");
    assert!(grass_ticks < 120 * 200 * 8 / 20, "AI mostly stays on the road: {grass_ticks} ticks on grass");
}
