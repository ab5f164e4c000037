//! Small helpers shared by the circuit's parts: the fixed-seed PRNG, errors, and scalar and plan maths.

use glam::Vec2;

/// A small deterministic PRNG (xorshift64*).
pub(super) struct Rng(u64);

impl Rng {
    pub(super) fn new(seed: u64) -> Self {
        Self(seed | 1)
    }

    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1).
    pub(super) fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    pub(super) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in lo..=hi.
    pub(super) fn int(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1).max(1) as u64) as i32
    }
}

pub(super) fn other(msg: String) -> std::io::Error {
    std::io::Error::other(format!("track: {msg}"))
}

pub(super) fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The left of a plan direction (x, z), seen from above with -Z ahead.
pub(super) fn left(d: Vec2) -> Vec2 {
    Vec2::new(d.y, -d.x)
}

/// Plan cross product (x, z).
pub(super) fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}

/// Distance between two positions on a closed loop of length `len`.
pub(super) fn loop_dist(a: f32, b: f32, len: f32) -> f32 {
    let d = (a - b).rem_euclid(len);
    d.min(len - d)
}

/// Rounds for JSON output (3 decimals, no negative zero).
pub(super) fn r3(v: f32) -> f64 {
    (f64::from(v) * 1000.0).round() / 1000.0 + 0.0
}
