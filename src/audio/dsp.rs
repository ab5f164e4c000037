//! The synthesiser's building blocks: a sine table, a seeded noise generator, filters and per-tick ramps.
//!
//! Everything here is plain `f32` arithmetic plus `libm` (no platform maths), so a sound computed on one
//! machine has the same bits on every other.

use super::format::SAMPLE_RATE;

/// Samples in one cycle of the sine table (a power of two, so the index wraps with a mask).
const TABLE_LEN: usize = 2048;

/// One cycle of a sine, read with linear interpolation: a sine per partial per sample at a fraction of
/// `libm::sinf`'s cost (eight engines of up to eight partials each at 48 kHz).
#[derive(Clone, Debug)]
pub struct SineTable {
    table: Vec<f32>,
}

impl Default for SineTable {
    fn default() -> Self {
        Self::new()
    }
}

impl SineTable {
    /// The table, filled once with `libm::sinf` (one extra sample so interpolation never wraps).
    #[must_use]
    pub fn new() -> Self {
        let table = (0..=TABLE_LEN).map(|i| libm::sinf(std::f32::consts::TAU * i as f32 / TABLE_LEN as f32)).collect();
        Self { table }
    }

    /// `sin(2 pi phase)` for a phase in cycles (any value; only its fraction counts).
    #[must_use]
    pub fn sin(&self, phase: f32) -> f32 {
        let x = (phase - libm::floorf(phase)) * TABLE_LEN as f32;
        let i = (x as usize).min(TABLE_LEN - 1);
        let f = x - i as f32;
        let (a, b) = (self.table[i], self.table[i + 1]);
        a + (b - a) * f
    }
}

/// A seeded xorshift generator: the only randomness in the sound, the same on every run.
#[derive(Clone, Copy, Debug)]
pub struct Noise {
    state: u32,
}

impl Noise {
    /// A generator from `seed` (zero, which xorshift cannot leave, is replaced).
    #[must_use]
    pub fn new(seed: u32) -> Self {
        Self { state: if seed == 0 { 0x9e37_79b9 } else { seed } }
    }

    /// The next value, uniform in `[-1, 1)`.
    pub fn sample(&mut self) -> f32 {
        let mut x = self.state;
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        self.state = x;
        (x >> 8) as f32 / (1u32 << 23) as f32 - 1.0
    }
}

/// A one-pole low-pass filter: smooths noise into rumble and takes the edge off bursts.
#[derive(Clone, Copy, Debug, Default)]
pub struct OnePole {
    y: f32,
}

impl OnePole {
    /// The coefficient for a cut-off of `hz`.
    #[must_use]
    pub fn coeff(hz: f32) -> f32 {
        1.0 - libm::expf(-std::f32::consts::TAU * hz / SAMPLE_RATE as f32)
    }

    /// Filters one sample with coefficient `k` (from [`OnePole::coeff`]).
    pub fn run(&mut self, x: f32, k: f32) -> f32 {
        self.y += k * (x - self.y);
        self.y
    }
}

/// A state-variable band-pass filter (Chamberlin's): the resonant body of the tyre squeal.
#[derive(Clone, Copy, Debug, Default)]
pub struct BandPass {
    low: f32,
    band: f32,
}

impl BandPass {
    /// The frequency coefficient for a centre of `hz` (stable below about a sixth of the sample rate).
    #[must_use]
    pub fn coeff(hz: f32) -> f32 {
        2.0 * libm::sinf(std::f32::consts::PI * hz.min(7000.0) / SAMPLE_RATE as f32)
    }

    /// Filters one sample: `f` from [`BandPass::coeff`], `damping` 2/Q (small: narrow and ringing).
    pub fn run(&mut self, x: f32, f: f32, damping: f32) -> f32 {
        self.low += f * self.band;
        let high = x - self.low - damping * self.band;
        self.band += f * high;
        self.band
    }
}

/// A value that moves linearly from where it was to a new target over one tick's samples, so that no
/// level, pan or pitch ever steps between two samples (a step in level is a click).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Ramp {
    from: f32,
    to: f32,
}

impl Ramp {
    /// A ramp resting at `v`.
    #[must_use]
    pub fn at(v: f32) -> Self {
        Self { from: v, to: v }
    }

    /// Starts a new tick: the ramp goes from its last target to `target`.
    pub fn set(&mut self, target: f32) {
        self.from = self.to;
        self.to = target;
    }

    /// The value a fraction `t` (0 to 1) through the tick.
    #[must_use]
    pub fn at_frac(&self, t: f32) -> f32 {
        self.from + (self.to - self.from) * t
    }

    /// The target of this tick.
    #[must_use]
    pub fn target(&self) -> f32 {
        self.to
    }
}

/// `0` below `a`, `1` above `b`, a smooth cubic between: turns a physical quantity into a level.
#[must_use]
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sine_table_matches_libm() {
        let s = SineTable::new();
        for k in 0..1000 {
            let p = k as f32 * 0.001_37 - 0.3;
            let want = libm::sinf(std::f32::consts::TAU * p);
            assert!((s.sin(p) - want).abs() < 1e-5, "phase {p}: {} vs {want}", s.sin(p));
        }
    }

    #[test]
    fn noise_is_seeded_bounded_and_centred() {
        let (mut a, mut b) = (Noise::new(7), Noise::new(7));
        let mut sum = 0.0f64;
        for _ in 0..100_000 {
            let x = a.sample();
            assert_eq!(x.to_bits(), b.sample().to_bits());
            assert!((-1.0..1.0).contains(&x));
            sum += f64::from(x);
        }
        assert!((sum / 100_000.0).abs() < 0.01, "mean {}", sum / 100_000.0);
        assert_ne!(Noise::new(8).sample(), Noise::new(7).sample());
    }

    #[test]
    fn band_pass_passes_its_centre_and_stops_far_frequencies() {
        let s = SineTable::new();
        let gain = |hz: f32| {
            let mut bp = BandPass::default();
            let f = BandPass::coeff(2000.0);
            let mut peak = 0.0f32;
            for n in 0..48_000 {
                let y = bp.run(s.sin(hz * n as f32 / SAMPLE_RATE as f32), f, 0.2);
                if n > 24_000 {
                    peak = peak.max(y.abs());
                }
            }
            peak
        };
        assert!(gain(2000.0) > 10.0 * gain(200.0), "{} vs {}", gain(2000.0), gain(200.0));
    }

    #[test]
    fn ramps_start_where_the_last_tick_ended() {
        let mut r = Ramp::at(1.0);
        r.set(3.0);
        assert_eq!(r.at_frac(0.0), 1.0);
        assert_eq!(r.at_frac(0.5), 2.0);
        r.set(0.0);
        assert_eq!(r.at_frac(0.0), 3.0);
        assert_eq!(smoothstep(1.0, 2.0, 0.0), 0.0);
        assert_eq!(smoothstep(1.0, 2.0, 5.0), 1.0);
    }
}
