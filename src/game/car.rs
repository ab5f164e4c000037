//! The arcade car model: as simple as a racing game needs, tuned to feel right on a pad.
//!
//! State is a position on the ground plane, a heading and a velocity. Each tick:
//! - the engine pushes along the heading with a force that fades towards top speed; brakes and drag slow it;
//! - steering turns the car like a bicycle (yaw rate = speed x tan(steer angle) / wheelbase), with the
//!   steering lock shrinking as speed rises so full stick at 250 km/h is still a corner, not a spin;
//! - tyres remove sideways velocity up to a grip limit; beyond it the car slides;
//! - off the road (past the kerbs) grass adds drag and halves the grip;
//! - barriers stop the car: its position is clamped to the barrier line in track coordinates every tick,
//!   and its velocity into the barrier is removed, so no speed can carry it through.

use glam::{Vec2, Vec3};

use super::controls::Controls;
use super::track::{Location, Track, flat};

/// The car model's tuning. Units are metres, seconds and radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CarParams {
    /// Top speed on the flat (m/s): 78 m/s is 281 km/h.
    pub top_speed: f32,
    /// Engine acceleration from rest (m/s^2).
    pub engine: f32,
    /// Braking deceleration (m/s^2).
    pub brake: f32,
    /// Coasting deceleration from rolling resistance (m/s^2).
    pub rolling: f32,
    /// Steering lock at standstill (rad).
    pub steer_lock: f32,
    /// Speed (m/s) at which the lock has fallen to half.
    pub steer_fade: f32,
    /// Wheelbase (m).
    pub wheelbase: f32,
    /// Lateral grip limit (m/s^2) on asphalt.
    pub grip: f32,
    /// Grip multiplier on grass.
    pub grass_grip: f32,
    /// Extra deceleration on grass (m/s^2 per m/s).
    pub grass_drag: f32,
    /// Collision radius for car-to-car contact (m).
    pub radius: f32,
}

impl Default for CarParams {
    fn default() -> Self {
        Self {
            top_speed: 78.0,
            engine: 11.0,
            brake: 28.0,
            rolling: 0.6,
            steer_lock: 0.55,
            steer_fade: 22.0,
            wheelbase: 2.7,
            grip: 17.0,
            grass_grip: 0.5,
            grass_drag: 0.45,
            radius: 1.15,
        }
    }
}

/// Half the width of a car's body (m): how close its centre gets to a barrier.
pub const BODY_HALF_WIDTH: f32 = 1.0;
/// Width of the kerbs beyond the road edge that still count as road (m).
pub const KERB: f32 = 1.2;

/// One car's dynamic state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Car {
    /// Position on the ground plane (x, z).
    pub pos: Vec2,
    /// Heading: 0 faces -Z, positive turns towards +X.
    pub yaw: f32,
    /// Velocity on the ground plane (m/s).
    pub vel: Vec2,
    /// Where the car is on the track (updated every tick).
    pub loc: Location,
    /// True while the car is past the kerbs.
    pub on_grass: bool,
    /// Steering angle actually applied last tick (rad), for drawing the wheels and the HUD.
    pub steer_angle: f32,
}

impl Car {
    /// A car at rest at lap distance `s`, `lateral` metres right of the centre, facing along the track.
    #[must_use]
    pub fn on_grid(track: &Track, s: f32, lateral: f32) -> Self {
        let (p, dir) = track.point_at(s, lateral);
        let pos = flat(p);
        let loc = track.locate(pos, track.index_at(s));
        Self { pos, yaw: libm::atan2f(dir.x, -dir.y), vel: Vec2::ZERO, loc, on_grass: false, steer_angle: 0.0 }
    }

    /// Unit vector the car points along.
    #[must_use]
    pub fn forward(&self) -> Vec2 {
        Vec2::new(libm::sinf(self.yaw), -libm::cosf(self.yaw))
    }

    /// Forward speed (m/s, negative when reversing).
    #[must_use]
    pub fn speed(&self) -> f32 {
        self.vel.dot(self.forward())
    }

    /// World position including the road height.
    #[must_use]
    pub fn position3(&self) -> Vec3 {
        Vec3::new(self.pos.x, self.loc.height, self.pos.y)
    }

    /// Advances the car by `dt` seconds under `c` (already sanitized).
    pub fn step(&mut self, p: &CarParams, c: &Controls, track: &Track, dt: f32) {
        let fwd = self.forward();
        let right = Vec2::new(-fwd.y, fwd.x);
        let mut v_f = self.vel.dot(fwd);
        let mut v_l = self.vel.dot(right);
        // Engine, brakes, rolling resistance, grass.
        let headroom = (1.0 - (v_f / p.top_speed).max(0.0).powi(2)).max(0.0);
        let mut a = c.throttle * p.engine * headroom;
        let slowing = c.brake * p.brake + p.rolling + if self.on_grass { p.grass_drag * v_f.abs() } else { 0.0 };
        // Deceleration never reverses the car's direction within a tick.
        let stop = v_f.abs() / dt;
        a -= v_f.signum() * slowing.min(stop);
        v_f += a * dt;
        // Steering with a speed-sensitive lock, limited by grip.
        let lock = p.steer_lock / (1.0 + (v_f.abs() / p.steer_fade).powi(2));
        self.steer_angle = c.steer * lock;
        let grip = if self.on_grass { p.grip * p.grass_grip } else { p.grip };
        let mut yaw_rate = v_f * libm::tanf(self.steer_angle) / p.wheelbase;
        if v_f.abs() > 1.0 {
            let max_rate = grip / v_f.abs();
            yaw_rate = yaw_rate.clamp(-max_rate * 1.15, max_rate * 1.15);
        }
        self.yaw += yaw_rate * dt;
        // Tyres kill sideways velocity up to the grip limit; the rest is a slide.
        let kill = (v_l / dt).clamp(-grip, grip);
        v_l -= kill * dt;
        // Re-express the velocity along the new heading (the car turns, momentum mostly follows).
        let fwd2 = self.forward();
        let right2 = Vec2::new(-fwd2.y, fwd2.x);
        self.vel = fwd2 * v_f + right2 * v_l;
        self.pos += self.vel * dt;
        self.yaw = wrap_angle(self.yaw);
        self.settle(track);
    }

    /// Updates the track location, grass state and applies the barriers.
    pub fn settle(&mut self, track: &Track) {
        let mut loc = track.locate(self.pos, self.loc.index);
        let half = 0.5 * loc.width;
        // The car's centre stops a body half-width short of the barrier on that side.
        let side = usize::from(loc.lateral > 0.0);
        let limit = loc.barrier[side] - BODY_HALF_WIDTH;
        if loc.lateral.abs() > limit {
            // Clamp onto the barrier line and remove the velocity component into it, with a scrub.
            let (on_line, dir) = track.point_at(loc.s, limit * loc.lateral.signum());
            let right = Vec2::new(-dir.y, dir.x);
            self.pos = flat(on_line);
            let into = self.vel.dot(right) * loc.lateral.signum();
            if into > 0.0 {
                self.vel -= right * loc.lateral.signum() * into;
            }
            self.vel *= 0.97;
            loc = track.locate(self.pos, loc.index);
        }
        self.on_grass = loc.lateral.abs() > half + KERB;
        self.loc = loc;
    }
}

/// An angle folded into `[-pi, pi)`.
#[must_use]
pub fn wrap_angle(a: f32) -> f32 {
    (a + std::f32::consts::PI).rem_euclid(std::f32::consts::TAU) - std::f32::consts::PI
}

/// Pushes two overlapping cars apart and exchanges the velocity along the contact normal (inelastic).
pub fn collide(a: &mut Car, b: &mut Car, (pa, pb): (&CarParams, &CarParams)) {
    let d = b.pos - a.pos;
    let dist = d.length();
    let min = pa.radius + pb.radius;
    if dist >= min || (a.loc.height - b.loc.height).abs() > 3.0 {
        return; // apart, or on different levels of the crossing
    }
    let n = if dist > 1e-4 { d / dist } else { a.forward().perp() };
    let push = 0.5 * (min - dist);
    a.pos -= n * push;
    b.pos += n * push;
    let rel = (b.vel - a.vel).dot(n);
    if rel < 0.0 {
        let j = 0.5 * rel * 1.2;
        a.vel += n * j;
        b.vel -= n * j;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::game::track::tests_support::straight;

    #[test]
    fn accelerates_to_a_top_speed_and_brakes_to_a_stop() {
        let t = straight();
        let p = CarParams::default();
        let mut car = Car::on_grid(&t, 10.0, 0.0);
        let full = Controls { throttle: 1.0, ..Controls::default() };
        // 22 s of full throttle stays on the 2 km straight.
        for _ in 0..120 * 22 {
            car.step(&p, &full, &t, 1.0 / 120.0);
        }
        let top = car.speed();
        assert!(car.loc.s < 2000.0, "still on the straight: {:?}", car.loc);
        assert!(top > 0.85 * p.top_speed && top <= p.top_speed, "top speed {top}");
        let brake = Controls { brake: 1.0, ..Controls::default() };
        let mut ticks = 0;
        while car.speed() > 0.0 && ticks < 120 * 10 {
            car.step(&p, &brake, &t, 1.0 / 120.0);
            ticks += 1;
        }
        assert!(car.speed().abs() < 1e-3, "stops, does not reverse");
        assert!((ticks as f32 / 120.0) < top / (p.brake * 0.8), "braking from {top} took {ticks} ticks");
    }

    #[test]
    fn barriers_stop_a_car_at_top_speed_without_tunnelling() {
        let t = straight();
        let p = CarParams::default();
        let mut car = Car::on_grid(&t, 100.0, 0.0);
        car.vel = Vec2::new(p.top_speed, 0.0); // straight at the right-hand barrier
        for _ in 0..240 {
            car.step(&p, &Controls::default(), &t, 1.0 / 120.0);
            assert!(car.loc.lateral.abs() <= car.loc.barrier[1] - BODY_HALF_WIDTH + 1e-3, "{:?}", car.loc);
        }
        assert!(car.vel.x.abs() < 1.0, "velocity into the barrier is gone: {:?}", car.vel);
    }

    #[test]
    fn contact_separates_cars() {
        let t = straight();
        let p = CarParams::default();
        let mut a = Car::on_grid(&t, 100.0, 0.0);
        let mut b = Car::on_grid(&t, 101.0, 0.5);
        a.vel = Vec2::new(0.0, -20.0);
        collide(&mut a, &mut b, (&p, &p));
        assert!((b.pos - a.pos).length() >= 2.0 * p.radius - 1e-4);
        assert!(b.vel.length() > 0.0);
    }
}
