//! The simulation on the real circuit: AI cars lap it, the race is bit-identical run to run.

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
fn a_full_ai_race_finishes_with_plausible_lap_times_and_a_clean_order() {
    let mut w = World::with_laps(circuit(), 8, 2);
    w.player_is_ai = true;
    let mut grass_ticks = 0u64;
    while w.race.finish_order.len() < 8 && w.tick < 120 * 400 {
        step(&mut w, &Controls::default());
        grass_ticks += w.cars.iter().filter(|c| c.on_grass).count() as u64;
    }
    assert_eq!(w.race.finish_order.len(), 8, "every car finishes 2 laps within 400 s");
    let mut order = w.race.finish_order.clone();
    order.sort_unstable();
    assert_eq!(order, (0..8).collect::<Vec<_>>());
    let best: Vec<f32> = w.race.standings.iter().map(|s| s.best_lap.unwrap_or(u64::MAX) as f32 / 120.0).collect();
    eprintln!("best laps (s): {best:?}; finish order {:?}; ticks on grass {grass_ticks}", w.race.finish_order);
    for (i, t) in best.iter().enumerate() {
        assert!((60.0..=150.0).contains(t), "car {i} best lap {t} s");
        assert_eq!(w.race.position(w.race.finish_order[i]), i + 1);
    }
    let (fast, slow) = best.iter().fold((f32::INFINITY, 0.0f32), |(a, b), &t| (a.min(t), b.max(t)));
    assert!(slow - fast > 0.5, "drivers differ in pace");
    assert!(grass_ticks < w.tick * 8 / 20, "AI mostly stays on the road: {grass_ticks} car-ticks on grass");
}
