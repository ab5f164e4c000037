//! The demo traces in `assets/replays/`: races driven by scripted drivers through the same recording step
//! the window uses, so the bench, the headless replay tests and the performance comparison have fixed,
//! reproducible input.
//!
//! - `demo-race.trace`: a one-lap race of the full field (8 cars) with the player's car driven by the AI
//!   (the attract-mode driver), from the lights to three seconds after the player finishes (about 90 s).
//! - `demo-city.trace`: the same on the city's streets.
//! - `demo-mountain.trace`: the same on the mountain course.
//! - `scuffle.trace`: 30 s of a three-lap race driven by a clumsy script: too brave for the grip, braking
//!   late and weaving, so it runs into the pack and the barriers (contacts, spins, recoveries).

use std::path::Path;
use std::sync::Arc;

use scanline_racer::game::ai::{Driver, drive};
use scanline_racer::game::rules::Phase;
use scanline_racer::game::{Controls, TICK_HZ, Track, World};
use scanline_racer::input::replay::step_recorded;
use scanline_racer::input::trace::TraceWriter;
use scanline_racer::shell::race::{CHECKSUM_EVERY, header_for};
use scanline_racer::shell::race_scene::FIELD;

/// Longest a demo race may run before the generator gives up waiting for the finish (ticks).
const MAX_TICKS: u64 = 240 * TICK_HZ as u64;

fn io_err(e: impl std::fmt::Display) -> std::io::Error {
    std::io::Error::other(e.to_string())
}

/// Records `ticks` of a race of `laps` laps on `course`; `controls` drives the player's car and returns
/// `None` to stop.
fn record(
    path: &Path,
    (course, track): (&str, &Arc<Track>),
    laps: u32,
    mut controls: impl FnMut(&World) -> Option<Controls>,
) -> std::io::Result<u64> {
    let mut world = World::with_laps(track.clone(), FIELD, laps);
    let mut rec = TraceWriter::create(path, &header_for(&world, course)).map_err(io_err)?;
    while let Some(c) = controls(&world) {
        step_recorded(&mut world, c, Some(&mut rec), CHECKSUM_EVERY).map_err(io_err)?;
        if world.tick >= MAX_TICKS {
            break;
        }
    }
    rec.finish().map_err(io_err)?;
    Ok(world.tick)
}

/// A course's centre line from the generated tree.
fn track_of(track_dir: &Path, course: &str) -> std::io::Result<Arc<Track>> {
    let text = std::fs::read_to_string(track_dir.join(course).join("centerline.json"))?;
    Ok(Arc::new(Track::from_json(&text).map_err(io_err)?))
}

/// A one-lap race of the full field on `course`, the player's car driven by the attract-mode driver, to
/// three seconds after the player finishes.
fn demo_race(path: &Path, course: &str, track: &Arc<Track>) -> std::io::Result<u64> {
    let pilot = Driver::field(FIELD);
    let mut finished_at = None;
    record(path, (course, track), 1, |w| {
        if w.race.standings[0].finished.is_some() || w.race.phase == Phase::Finished {
            let at = *finished_at.get_or_insert(w.tick);
            if w.tick >= at + 3 * u64::from(TICK_HZ) {
                return None;
            }
        }
        Some(drive(&pilot, 0, &w.cars, &w.track, &w.params[0]))
    })
}

/// Writes the demo traces into `dir`, from the courses in `track_dir`.
pub fn generate(dir: &Path, track_dir: &Path) -> std::io::Result<()> {
    std::fs::create_dir_all(dir)?;
    let track = track_of(track_dir, "circuit")?;
    demo_race(&dir.join("demo-race.trace"), "circuit", &track)?;
    let city = track_of(track_dir, "city")?;
    demo_race(&dir.join("demo-city.trace"), "city", &city)?;
    let mountain = track_of(track_dir, "mountain")?;
    demo_race(&dir.join("demo-mountain.trace"), "mountain", &mountain)?;

    let clumsy = Driver { pace: 1.12, brake_margin: -4.0, apex: 4.5, pass_side: 0.0 };
    record(&dir.join("scuffle.trace"), ("circuit", &track), 3, |w| {
        if w.tick >= 30 * u64::from(TICK_HZ) {
            return None;
        }
        let mut c = drive(&clumsy, 0, &w.cars, &w.track, &w.params[0]);
        // A weave of about 1.3 s period on top of the line, stronger in the first lap's first corners.
        let phase = (w.tick % 160) as f32 / 160.0;
        let weave = if phase < 0.5 { 0.35 } else { -0.35 };
        c.steer = (c.steer + weave).clamp(-1.0, 1.0);
        Some(c)
    })?;
    Ok(())
}
