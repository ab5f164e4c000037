//! The engine-speed curve: a six-speed gearbox that the sound infers from a car's road speed and its
//! acceleration, so the simulation needs no engine state (its checksums and traces stay as they are).
//!
//! Road speed in a gear gives the engine speed (`rpm = speed / GEAR_TOP[gear] * REDLINE_RPM`, never below
//! idle; in first gear a slipping clutch adds revs under load, so a launch revs before the car moves much).
//! The gearbox shifts up above [`UPSHIFT_RPM`] and down below [`DOWNSHIFT_RPM`], one gear a tick, and cuts
//! the load for [`SHIFT_TICKS`] after each shift (the throttle lifts while the clutch is out). The load
//! (how hard the engine is pushing, 0 to 1) is the forward acceleration the car model's engine would need
//! for the speed change seen, smoothed over a few ticks.

use crate::game::DT;
use crate::game::car::{Car, CarParams};

/// Engine speed with no load and no road speed.
pub const IDLE_RPM: f32 = 900.0;
/// Engine speed at each gear's top road speed.
pub const REDLINE_RPM: f32 = 8500.0;
/// Engine speed above which the gearbox shifts up.
pub const UPSHIFT_RPM: f32 = 7800.0;
/// Engine speed below which the gearbox shifts down.
pub const DOWNSHIFT_RPM: f32 = 4200.0;
/// Road speed (m/s) at the redline in each gear; top gear reaches the car's top speed (78 m/s) below it.
pub const GEAR_TOP: [f32; 6] = [20.0, 31.0, 42.0, 54.0, 66.0, 81.0];
/// Extra revs a slipping clutch allows in first gear at full load.
const LAUNCH_RPM: f32 = 2200.0;
/// Ticks the load is cut for after a shift (50 ms).
pub const SHIFT_TICKS: u32 = 6;
/// Cylinders of the (four-stroke) engine: each fires once every two turns.
pub const CYLINDERS: f32 = 6.0;

/// The engine's note for a given engine speed: the firing frequency of its cylinders (Hz).
#[must_use]
pub fn firing_hz(rpm: f32) -> f32 {
    rpm / 60.0 * CYLINDERS / 2.0
}

/// What the engine is doing in one tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineNote {
    /// Engine speed (revolutions per minute).
    pub rpm: f32,
    /// Gear, 0 (first) to 5 (sixth).
    pub gear: usize,
    /// Load, 0 (coasting or braking) to 1 (full throttle), after the shift cut.
    pub load: f32,
    /// True on the tick the gear changed.
    pub shifted: bool,
}

impl EngineNote {
    /// The note's fundamental (Hz).
    #[must_use]
    pub fn hz(&self) -> f32 {
        firing_hz(self.rpm)
    }
}

/// One car's gearbox and load estimate, advanced once per tick from the car's successive states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Engine {
    gear: usize,
    load: f32,
    shift_left: u32,
    last_speed: Option<f32>,
}

impl Default for Engine {
    fn default() -> Self {
        Self::new()
    }
}

impl Engine {
    /// An engine idling in first gear.
    #[must_use]
    pub fn new() -> Self {
        Self { gear: 0, load: 0.0, shift_left: 0, last_speed: None }
    }

    /// The engine after the tick that brought the car to `car` (`params` is the car model).
    pub fn update(&mut self, car: &Car, params: &CarParams) -> EngineNote {
        let speed = car.speed();
        let accel = self.last_speed.map_or(0.0, |last| (speed - last) / DT);
        self.last_speed = Some(speed);
        let v = speed.abs();
        // The throttle that explains the acceleration seen: the car model's engine force fades with speed.
        let headroom = (1.0 - (v / params.top_speed).powi(2)).max(0.15);
        let drag = params.rolling + if car.on_grass { params.grass_drag * v } else { 0.0 };
        let wanted = if v < 0.05 && accel.abs() < 1e-3 { 0.0 } else { (accel + drag) / (params.engine * headroom) };
        self.load += 0.25 * (wanted.clamp(0.0, 1.0) - self.load);
        let mut shifted = false;
        let in_gear = |g: usize| v / GEAR_TOP[g] * REDLINE_RPM;
        if self.gear + 1 < GEAR_TOP.len() && in_gear(self.gear) > UPSHIFT_RPM {
            self.gear += 1;
            shifted = true;
        } else if self.gear > 0 && in_gear(self.gear) < DOWNSHIFT_RPM {
            self.gear -= 1;
            shifted = true;
        }
        if shifted {
            self.shift_left = SHIFT_TICKS;
        }
        let cut = if self.shift_left > 0 {
            self.shift_left -= 1;
            0.0
        } else {
            1.0
        };
        let load = self.load * cut;
        let launch = if self.gear == 0 { LAUNCH_RPM * load * (1.0 - v / GEAR_TOP[0]).max(0.0) } else { 0.0 };
        let rpm = (in_gear(self.gear) + launch).clamp(IDLE_RPM, REDLINE_RPM);
        EngineNote { rpm, gear: self.gear, load, shifted }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn car_at(speed: f32) -> Car {
        let track = crate::game::track::tests_support::straight();
        let mut c = Car::on_grid(&track, 10.0, 0.0);
        c.vel = c.forward() * speed;
        c
    }

    #[test]
    fn idles_at_rest() {
        let mut e = Engine::new();
        let p = CarParams::default();
        for _ in 0..10 {
            let n = e.update(&car_at(0.0), &p);
            assert_eq!(n.rpm, IDLE_RPM);
            assert_eq!(n.gear, 0);
        }
    }

    #[test]
    fn accelerating_shifts_up_through_every_gear_and_braking_shifts_down() {
        let mut e = Engine::new();
        let p = CarParams::default();
        let (mut gears, mut last_rpm, mut v) = (vec![0], 0.0, 0.0f32);
        while v < 77.0 {
            v += 8.0 * DT;
            let n = e.update(&car_at(v), &p);
            assert!(n.rpm <= REDLINE_RPM && n.rpm >= IDLE_RPM);
            if n.shifted {
                gears.push(n.gear);
                assert!(n.rpm < last_rpm, "an upshift drops the revs: {last_rpm} -> {}", n.rpm);
                assert_eq!(n.load, 0.0, "the load is cut while shifting");
            } else if n.gear > 0 {
                assert!(n.rpm >= last_rpm, "revs rise in gear");
            }
            assert!(n.load <= 1.0);
            last_rpm = n.rpm;
        }
        assert_eq!(gears, [0, 1, 2, 3, 4, 5]);
        let (mut down, mut ticks) = (vec![], 0);
        while v > 1.0 {
            v -= 25.0 * DT;
            ticks += 1;
            let n = e.update(&car_at(v), &p);
            // The load estimate is smoothed: it has fallen to nothing within 20 ticks of braking.
            assert!(ticks < 20 || n.load < 0.05, "braking is no load: {}", n.load);
            if n.shifted {
                down.push(n.gear);
            }
        }
        assert_eq!(down, [4, 3, 2, 1, 0]);
    }

    #[test]
    fn load_follows_acceleration() {
        let p = CarParams::default();
        let (mut on, mut off) = (Engine::new(), Engine::new());
        let (mut a, mut b) = (30.0f32, 30.0f32);
        let (mut n_on, mut n_off) = (on.update(&car_at(a), &p), off.update(&car_at(b), &p));
        for _ in 0..30 {
            a += 8.0 * DT;
            b -= 0.6 * DT;
            n_on = on.update(&car_at(a), &p);
            n_off = off.update(&car_at(b), &p);
        }
        assert!(n_on.load > 0.8, "full throttle: {}", n_on.load);
        assert!(n_off.load < 0.1, "coasting: {}", n_off.load);
        let mut rev = car_at(0.0);
        rev.vel = -rev.forward() * 5.0;
        assert!(Engine::new().update(&rev, &p).rpm > IDLE_RPM, "reversing revs too");
    }
}
