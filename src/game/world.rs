//! The world and its fixed-timestep step: the whole simulation is `step(&mut World, &Controls)`.
//!
//! Pure and deterministic: no clock (time is the tick count), no OS randomness, no hash maps; cars are
//! processed in index order. The same start and the same controls give the same bits on every run.

use std::sync::Arc;

use super::ai::{Driver, drive};
use super::car::{Car, CarParams, collide};
use super::controls::Controls;
use super::garage::GARAGE;
use super::rules::RaceProgress;
use super::setup::{Handling, RaceSetup};
use super::timestep::DT;
use super::track::Track;

/// Everything that changes during a race.
#[derive(Clone, Debug)]
pub struct World {
    /// Ticks since the start.
    pub tick: u64,
    /// The track (shared, never changes).
    pub track: Arc<Track>,
    /// All cars; index 0 is the player.
    pub cars: Vec<Car>,
    /// The AI drivers of cars 1.. (index `i` drives car `i + 1`), at the setup's difficulty.
    pub drivers: Vec<Driver>,
    /// Each car's handling, by its index in `cars`.
    pub params: Vec<CarParams>,
    /// Each car's garage index (its model and name), by its index in `cars`.
    pub models: Vec<usize>,
    /// What decided the race before its first tick.
    pub setup: RaceSetup,
    /// True when car 0 is driven by the AI too (attract mode, tests).
    pub player_is_ai: bool,
    /// The race rules' state: countdown, laps, times, positions.
    pub race: RaceProgress,
}

impl World {
    /// A race start of `laps` laps: `cars` cars on a two-column staggered grid behind the start line, player
    /// last, the player in car 1, each car with its own handling.
    #[must_use]
    pub fn with_laps(track: Arc<Track>, cars: usize, laps: u32) -> Self {
        Self::for_race(track, &RaceSetup { laps, field: cars, ..RaceSetup::default() })
    }

    /// A three-lap race start of `cars` cars (see [`World::with_laps`]).
    #[must_use]
    pub fn new(track: Arc<Track>, cars: usize) -> Self {
        Self::with_laps(track, cars, 3)
    }

    /// The start of the race `setup` describes: its cars on a two-column staggered grid behind the start line,
    /// the player last.
    #[must_use]
    pub fn for_race(track: Arc<Track>, setup: &RaceSetup) -> Self {
        let cars = setup.cars();
        // Slot k: 8 m behind the line per row pair, alternating sides; the player (car 0) takes the last slot.
        let slot = |k: usize| {
            let s = track.length() - 8.0 - 8.0 * k as f32;
            let lateral = if k.is_multiple_of(2) { -3.0 } else { 3.0 };
            (s, lateral)
        };
        let order: Vec<usize> = (0..cars).map(|i| if i == 0 { cars - 1 } else { i - 1 }).collect();
        let list: Vec<Car> = order
            .iter()
            .map(|&k| {
                let (s, lat) = slot(k);
                Car::on_grid(&track, s, lat)
            })
            .collect();
        let starts: Vec<f32> = list.iter().map(|c| c.loc.s).collect();
        let models = setup.models();
        let params = models
            .iter()
            .map(|&m| match setup.handling {
                Handling::Garage => GARAGE[m].params(),
                Handling::Same => CarParams::default(),
            })
            .collect();
        let pace = setup.difficulty.pace();
        Self {
            tick: 0,
            drivers: (0..cars.saturating_sub(1)).map(|i| Driver::field(i).with_pace(pace)).collect(),
            race: RaceProgress::new(setup.laps, &starts, track.length()),
            cars: list,
            track,
            params,
            models,
            setup: *setup,
            player_is_ai: false,
        }
    }

    /// A checksum of the state (bit patterns of every car's position, heading and velocity, and the tick).
    #[must_use]
    pub fn checksum(&self) -> u64 {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |v: u64| {
            h ^= v;
            h = h.wrapping_mul(0x0100_0000_01b3);
        };
        eat(self.tick);
        for c in &self.cars {
            for f in [c.pos.x, c.pos.y, c.yaw, c.vel.x, c.vel.y] {
                eat(u64::from(f.to_bits()));
            }
        }
        h
    }
}

/// Advances the world by one tick; `controls` drive car 0 unless the player is AI (or has finished: then
/// the AI brings the car round).
pub fn step(world: &mut World, controls: &Controls) {
    let n = world.cars.len();
    world.tick += 1;
    if world.race.holding() {
        world.race.update(world.tick, &[], world.track.length());
        return;
    }
    let player_done = world.race.standings.first().is_some_and(|s| s.finished.is_some());
    let mut inputs = Vec::with_capacity(n);
    for i in 0..n {
        let c = if i == 0 && !world.player_is_ai && !player_done {
            controls.sanitized()
        } else {
            let driver = if i == 0 { Driver::field(n) } else { world.drivers[i - 1] };
            drive(&driver, i, &world.cars, &world.track, &world.params[i]).sanitized()
        };
        inputs.push(c);
    }
    for ((car, c), p) in world.cars.iter_mut().zip(&inputs).zip(&world.params) {
        car.step(p, c, &world.track, DT);
    }
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = world.cars.split_at_mut(j);
            collide(&mut a[i], &mut b[0], (&world.params[i], &world.params[j]));
        }
    }
    for car in &mut world.cars {
        car.settle(&world.track);
    }
    let lap_s: Vec<f32> = world.cars.iter().map(|c| c.loc.s).collect();
    world.race.update(world.tick, &lap_s, world.track.length());
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::game::track::tests_support::straight;

    fn race(ticks: u64) -> Vec<u64> {
        let mut w = World::new(Arc::new(straight()), 8);
        w.player_is_ai = true;
        (0..ticks)
            .map(|_| {
                step(&mut w, &Controls::default());
                w.checksum()
            })
            .collect()
    }

    #[test]
    fn ai_race_is_bit_identical_run_to_run() {
        let a = race(120 * 20);
        let b = race(120 * 20);
        assert_eq!(a, b);
    }

    #[test]
    fn ai_cars_go_round_the_track_and_stay_on_it() {
        let mut w = World::new(Arc::new(straight()), 8);
        w.player_is_ai = true;
        let start: Vec<f32> = w.cars.iter().map(|c| c.loc.s).collect();
        let mut travelled = [0.0f32; 8];
        let mut last = start.clone();
        for _ in 0..120 * 90 {
            step(&mut w, &Controls::default());
            for (i, c) in w.cars.iter().enumerate() {
                let d = (c.loc.s - last[i]).rem_euclid(w.track.length());
                travelled[i] += if d > w.track.length() / 2.0 { d - w.track.length() } else { d };
                last[i] = c.loc.s;
                assert!(c.pos.is_finite());
            }
        }
        for (i, t) in travelled.iter().enumerate() {
            assert!(*t > w.track.length() * 0.9, "car {i} travelled only {t} m in 90 s");
        }
        assert!(w.cars.iter().all(|c| !c.on_grass), "AI ends on the road");
    }

    #[test]
    fn nan_controls_are_harmless() {
        let mut w = World::new(Arc::new(straight()), 2);
        let bad = Controls { steer: f32::NAN, throttle: f32::INFINITY, brake: -3.0 };
        for _ in 0..600 {
            step(&mut w, &bad);
        }
        assert!(w.cars.iter().all(|c| c.pos.is_finite() && c.vel.is_finite()));
    }
}
