//! The eight cars and how each handles: one table of figures the simulation reads.
//!
//! Each car trades one strength for another so that none is best everywhere: a high top speed comes with
//! less grip or a slower pick-up, strong grip with a lower top speed. The figures are balanced so that on
//! every course the fastest AI lap of each car is within 3% of the best (`tests/integration/game.rs`
//! measures it). Car 1 keeps the handling every car had before the cars differed, which is also what a
//! race of simulation version 2 gives every car ([`super::setup::Handling::Same`]).

use super::car::CarParams;

/// Cars in the garage (one per model in `assets/cars/`).
pub const CARS: usize = 8;

/// One car's name and the figures that set it apart; the rest of its handling is [`CarParams::default`]'s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarSpec {
    /// What the menus call it.
    pub name: &'static str,
    /// Top speed on the flat (m/s).
    pub top_speed: f32,
    /// Engine acceleration from rest (m/s^2).
    pub engine: f32,
    /// Braking deceleration (m/s^2).
    pub brake: f32,
    /// Lateral grip limit on asphalt (m/s^2).
    pub grip: f32,
}

impl CarSpec {
    /// Seconds from rest to 100 km/h on the flat at full throttle, as the car model accelerates (the
    /// engine's push fading with the square of the share of top speed; rolling resistance ignored), in
    /// steps of the simulation's tick.
    #[must_use]
    pub fn zero_to_100(&self) -> f32 {
        let target = 100.0 / 3.6;
        let (mut v, mut t) = (0.0f32, 0.0f32);
        while v < target && t < 60.0 {
            v += self.engine * (1.0 - (v / self.top_speed).powi(2)).max(0.0) * super::timestep::DT;
            t += super::timestep::DT;
        }
        t
    }

    /// The car's full handling.
    #[must_use]
    pub fn params(&self) -> CarParams {
        CarParams {
            top_speed: self.top_speed,
            engine: self.engine,
            brake: self.brake,
            grip: self.grip,
            ..CarParams::default()
        }
    }
}

/// The garage, in model order (`car_1` first).
pub const GARAGE: [CarSpec; CARS] = [
    CarSpec { name: "Rosso", top_speed: 78.0, engine: 11.0, brake: 28.0, grip: 17.0 },
    CarSpec { name: "Blue Comet", top_speed: 82.0, engine: 10.6, brake: 27.0, grip: 16.8 },
    CarSpec { name: "Verde", top_speed: 75.0, engine: 12.0, brake: 29.0, grip: 17.3 },
    CarSpec { name: "Yellow Jacket", top_speed: 80.0, engine: 11.6, brake: 26.5, grip: 16.8 },
    CarSpec { name: "Bianca", top_speed: 76.5, engine: 10.8, brake: 31.0, grip: 17.2 },
    CarSpec { name: "Orange Arrow", top_speed: 84.0, engine: 10.4, brake: 27.5, grip: 16.6 },
    CarSpec { name: "Viola", top_speed: 75.5, engine: 12.4, brake: 28.5, grip: 17.1 },
    CarSpec { name: "Nero", top_speed: 79.0, engine: 11.2, brake: 29.5, grip: 16.9 },
];

/// Bounds each figure stays within (a car outside them would not be a racing car of this game).
pub const TOP_SPEED: std::ops::RangeInclusive<f32> = 65.0..=90.0;
/// See [`TOP_SPEED`].
pub const ENGINE: std::ops::RangeInclusive<f32> = 8.0..=14.0;
/// See [`TOP_SPEED`].
pub const BRAKE: std::ops::RangeInclusive<f32> = 22.0..=36.0;
/// See [`TOP_SPEED`].
pub const GRIP: std::ops::RangeInclusive<f32> = 14.0..=20.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn no_two_cars_alike_and_every_figure_within_bounds() {
        for (i, a) in GARAGE.iter().enumerate() {
            assert!(TOP_SPEED.contains(&a.top_speed), "{}", a.name);
            assert!(ENGINE.contains(&a.engine), "{}", a.name);
            assert!(BRAKE.contains(&a.brake), "{}", a.name);
            assert!(GRIP.contains(&a.grip), "{}", a.name);
            assert!(!a.name.is_empty() && a.name.len() <= 16, "{}", a.name);
            for b in &GARAGE[i + 1..] {
                assert_ne!(a.name, b.name);
                assert_ne!(a.params(), b.params(), "{} and {} handle alike", a.name, b.name);
            }
        }
        assert_eq!(GARAGE[0].params(), CarParams::default(), "car 1 keeps the handling every car had");
    }

    #[test]
    fn each_car_trades_one_strength_for_another() {
        // No car is at least as good as another in every figure.
        for a in &GARAGE {
            for b in &GARAGE {
                let better_everywhere = a.top_speed >= b.top_speed
                    && a.engine >= b.engine
                    && a.brake >= b.brake
                    && a.grip >= b.grip
                    && a != b;
                assert!(!better_everywhere, "{} beats {} in every figure", a.name, b.name);
            }
        }
    }
}
