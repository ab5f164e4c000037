//! AI drivers: follow a racing line at a pace of their own, brake for what is coming, pass slower cars.
//!
//! No rubber-banding: a driver's pace does not depend on the player's position. Variety comes from each
//! driver's pace (share of the grip they dare use), braking margin, preferred line and reaction to traffic.

use super::car::{Car, CarParams};
use super::controls::Controls;
use super::track::{Track, flat};

/// One AI driver's character.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Driver {
    /// Share of the car's grip used in corners (0.8 cautious to 0.97 brave).
    pub pace: f32,
    /// Extra braking distance in metres (late brakers have less).
    pub brake_margin: f32,
    /// How far (m) inside a corner the driver aims, relative to the centre.
    pub apex: f32,
    /// Lateral offset (m) taken to pass a car ahead.
    pub pass_side: f32,
}

impl Driver {
    /// This driver with its pace multiplied by `factor` (the race's difficulty): a share of the grip it
    /// dares use in corners, never the grip itself.
    #[must_use]
    pub fn with_pace(self, factor: f32) -> Self {
        Self { pace: self.pace * factor, ..self }
    }

    /// The `i`-th driver of a field: paces and lines differ, deterministically.
    #[must_use]
    pub fn field(i: usize) -> Self {
        let k = i as f32;
        Self {
            pace: 0.86 + 0.015 * ((i * 5) % 8) as f32,
            brake_margin: 6.0 + 3.0 * ((i * 3) % 4) as f32,
            apex: 2.0 + 0.5 * (k % 3.0),
            pass_side: if i.is_multiple_of(2) { 3.5 } else { -3.5 },
        }
    }
}

/// Decides one tick of controls for `me` (index `idx` in `cars`).
#[must_use]
pub fn drive(driver: &Driver, idx: usize, cars: &[Car], track: &Track, params: &CarParams) -> Controls {
    let me = &cars[idx];
    let speed = me.speed().max(0.0);
    let s = me.loc.s;
    // Target speed: the slowest corner within braking distance, at this driver's share of the grip.
    let horizon = speed * speed / (2.0 * params.brake * 0.8) + driver.brake_margin + 20.0;
    let mut target = params.top_speed;
    let mut d = 0.0;
    while d <= horizon {
        let k = track.curvature_at(s + d).abs().max(1e-4);
        let corner = (driver.pace * params.grip / k).sqrt();
        // Speed we may have now and still slow to `corner` in the distance left.
        let allowed = (corner * corner + 2.0 * params.brake * 0.8 * (d - driver.brake_margin).max(0.0)).sqrt();
        target = target.min(allowed);
        d += 5.0;
    }
    // Line: inside of the coming corner, or to the side of a slower car just ahead.
    let look = 8.0 + 0.45 * speed;
    let k_ahead = track.curvature_at(s + look);
    let mut lateral = (-k_ahead.signum() * driver.apex).clamp(-4.0, 4.0) * (k_ahead.abs() * 200.0).min(1.0);
    for (j, other) in cars.iter().enumerate() {
        if j == idx {
            continue;
        }
        let gap = (other.loc.s - s).rem_euclid(track.length());
        if gap < 25.0 && (other.loc.lateral - me.loc.lateral).abs() < 2.5 && other.speed() < speed + 2.0 {
            lateral = other.loc.lateral + driver.pass_side;
            if gap < 10.0 {
                target = target.min(other.speed());
            }
        }
    }
    // Never negative (a road under 2.4 m wide) nor NaN: `clamp` panics when its bounds cross.
    let half = (0.5 * me.loc.width - 1.2).max(0.0);
    let (aim, _) = track.point_at(s + look, lateral.clamp(-half, half));
    let to = flat(aim) - me.pos;
    let fwd = me.forward();
    let err = libm::asinf(fwd.perp_dot(to.normalize_or(fwd)));
    // perp_dot > 0 means the target is to the right (x right, z towards the viewer, y up).
    let steer = (err * 2.2).clamp(-1.0, 1.0);
    let (throttle, brake) = if speed < target - 1.0 {
        (1.0, 0.0)
    } else if speed > target + 1.5 {
        (0.0, ((speed - target) / 8.0).clamp(0.2, 1.0))
    } else {
        (0.4, 0.0)
    };
    Controls { steer, throttle, brake }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn a_road_narrower_than_a_car_is_driven_without_a_panic() {
        // 2 m wide: the aiming margin (1.2 m each side) is wider than the road's half.
        let pts: Vec<(Vec3, f32, f32)> = (0..200)
            .map(|i| i as f32 / 200.0 * std::f32::consts::TAU)
            .map(|a| (Vec3::new(100.0 * libm::cosf(a), 0.0, -100.0 * libm::sinf(a)), 0.0, 2.0))
            .collect();
        let track = Track::new(&pts).unwrap_or_else(|e| panic!("{e}"));
        let car = Car::on_grid(&track, 10.0, 0.0);
        let c = drive(&Driver::field(1), 0, &[car], &track, &CarParams::default());
        assert!(c.steer.is_finite() && c.throttle.is_finite() && c.brake.is_finite(), "{c:?}");
    }
}
