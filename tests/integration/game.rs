//! The simulation on the real circuit: AI cars lap it, the race is bit-identical run to run.

use std::path::Path;
use std::sync::Arc;

use scanline_racer::game::{Controls, Track, World, step};

fn circuit() -> Arc<Track> {
    let text =
        std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/track/circuit/centerline.json"))
            .unwrap();
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

/// Every course the assets hold, by name, with its centre line.
fn courses() -> Vec<(String, Arc<Track>)> {
    let assets =
        scanline_racer::shell::race_scene::Assets::Folder(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"));
    let names = assets.course_names();
    assert!(names.len() >= 2, "{names:?}");
    names
        .into_iter()
        .map(|name| {
            let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("assets/track/{name}/centerline.json"));
            let track = Arc::new(Track::from_json(&std::fs::read_to_string(path).unwrap()).unwrap());
            (name, track)
        })
        .collect()
}

/// On every course, every car of a full AI field completes a lap (none is stuck anywhere), the cars finish
/// within a few percent of each other, and the race is the same every run.
#[test]
fn every_car_completes_a_lap_of_every_course_under_ai_control() {
    for (name, track) in courses() {
        let run = || {
            let mut w = World::with_laps(track.clone(), 8, 1);
            w.player_is_ai = true;
            let mut stuck = [0u32; 8];
            while w.race.finish_order.len() < 8 && w.tick < 120 * 300 {
                step(&mut w, &Controls::default());
                for (i, c) in w.cars.iter().enumerate() {
                    // A car slower than 2 m/s after the start for 10 s on end is stuck.
                    let slow = w.tick > 120 * 8 && c.speed().abs() < 2.0;
                    stuck[i] = if slow { stuck[i] + 1 } else { 0 };
                    assert!(stuck[i] < 120 * 10, "{name}: car {i} stuck at s = {} m (tick {})", c.loc.s, w.tick);
                }
            }
            w
        };
        let w = run();
        assert_eq!(w.race.finish_order.len(), 8, "{name}: every car finishes a lap within 300 s");
        let times: Vec<f32> = w.race.standings.iter().map(|s| s.finished.unwrap_or(u64::MAX) as f32 / 120.0).collect();
        let (fast, slow) = times.iter().fold((f32::INFINITY, 0.0f32), |(a, b), &t| (a.min(t), b.max(t)));
        eprintln!("{name}: finish times (s) {times:?}, spread {:.1}%", (slow / fast - 1.0) * 100.0);
        assert!(slow <= fast * 1.06, "{name}: the AI field finishes within 6%: {fast} s to {slow} s");
        assert_eq!(run().checksum(), w.checksum(), "{name}: the same race every run");
    }
}

/// The cars are balanced: on every course, each car's fastest AI lap (alone, two laps, the second flying)
/// is within 3% of the best car's.
#[test]
fn every_car_laps_every_course_within_three_percent_of_the_best() {
    use scanline_racer::game::garage::{CARS, GARAGE};
    use scanline_racer::game::{Mode, RaceSetup};
    let mut slow = vec![];
    for (name, track) in courses() {
        let laps: Vec<f32> = (0..CARS)
            .map(|car| {
                let setup = RaceSetup { mode: Mode::TimeTrial, laps: 2, car, ..RaceSetup::default() };
                let mut w = World::for_race(track.clone(), &setup);
                w.player_is_ai = true;
                while w.race.standings[0].finished.is_none() && w.tick < 120 * 400 {
                    step(&mut w, &Controls::default());
                }
                let best = w.race.standings[0].best_lap.unwrap_or_else(|| panic!("{name}: car {} laps", car + 1));
                best as f32 / 120.0
            })
            .collect();
        let best = laps.iter().copied().fold(f32::INFINITY, f32::min);
        let report: Vec<String> = laps
            .iter()
            .zip(&GARAGE)
            .map(|(t, c)| format!("{} {t:.2} s (+{:.1}%)", c.name, (t / best - 1.0) * 100.0))
            .collect();
        eprintln!("{name}: {}", report.join(", "));
        for (t, c) in laps.iter().zip(&GARAGE) {
            if *t > best * 1.03 {
                slow.push(format!("{name}: {} laps in {t:.2} s, over 3% behind the best {best:.2} s", c.name));
            }
        }
    }
    assert!(slow.is_empty(), "{}", slow.join("; "));
}
