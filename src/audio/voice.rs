//! One car's continuous sounds: its engine, its tyres and what its wheels run over, placed in the stereo
//! field as the listener (the player's car) hears them.
//!
//! Each tick sets new targets (pitch, levels, pan) from the car's state; the samples of the tick move to them
//! in straight lines ([`Ramp`]), and every oscillator keeps its phase, so a gear change glides the pitch
//! within one tick and no level ever steps.

use glam::Vec2;

use super::dsp::{BandPass, Noise, OnePole, Ramp, SineTable, smoothstep};
use super::engine::{Engine, EngineNote};
use super::format::{FRAMES_PER_TICK, SAMPLE_RATE};
use crate::game::car::{Car, CarParams, KERB};

/// Partial weights of the engine note at full load: a buzzy, bright note.
const ON_LOAD: [f32; 8] = [1.0, 0.6, 0.45, 0.35, 0.25, 0.18, 0.12, 0.08];
/// Partial weights off the throttle: a duller burble of mostly the fundamental.
const OFF_LOAD: [f32; 8] = [1.0, 0.35, 0.15, 0.08, 0.04, 0.02, 0.01, 0.0];
/// Partials fade out between this frequency and 300 Hz above it, so the engine stays below the squeal band.
const PARTIAL_CEILING: f32 = 1500.0;
/// The player's engine level at full load (the mix's loudest continuous sound).
pub const ENGINE_LEVEL: f32 = 0.16;
/// The other cars' engines relative to the player's at the same distance.
const RIVAL_LEVEL: f32 = 0.6;
/// Tyre squeal's level at a full slide.
const SQUEAL_LEVEL: f32 = 0.12;
/// Centre of the squeal (Hz) at the onset of a slide; it rises with slip.
pub const SQUEAL_HZ: f32 = 2200.0;
/// The band-pass's damping for the squeal (narrow: a whine, not a hiss).
const SQUEAL_DAMPING: f32 = 0.06;
/// Scales the band-passed noise to about unit RMS.
const SQUEAL_NORM: f32 = 0.5;
/// Kerb and grass rumble's level at speed.
const RUMBLE_LEVEL: f32 = 0.1;
/// Spacing of the kerb's stripes (m): the rumble's frequency is speed over it.
const KERB_STRIPE: f32 = 0.5;
/// Speed of sound (m/s), for the Doppler shift.
const SOUND_SPEED: f32 = 343.0;

/// Where a sound sits for the listener: left and right gains and a Doppler pitch ratio.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spatial {
    /// Gain of the left channel.
    pub left: f32,
    /// Gain of the right channel.
    pub right: f32,
    /// Pitch ratio from the Doppler shift (1: no relative motion).
    pub pitch: f32,
}

impl Spatial {
    /// Front and centre at full level, no shift: the player's own car.
    pub const CENTRE: Self = Self { left: 1.0, right: 1.0, pitch: 1.0 };
}

/// How the `listener` hears a sound at `pos` moving at `vel`: constant-power pan by direction relative to the
/// listener's heading, a gain falling with distance, and the Doppler ratio of their speeds along the line
/// between them.
#[must_use]
pub fn place(listener: &Car, pos: Vec2, vel: Vec2) -> Spatial {
    let rel = pos - listener.pos;
    let d = rel.length();
    if d < 1.0 {
        return Spatial::CENTRE;
    }
    let u = rel / d;
    let fwd = listener.forward();
    let right = Vec2::new(-fwd.y, fwd.x);
    let pan = u.dot(right).clamp(-1.0, 1.0);
    let angle = (pan + 1.0) * std::f32::consts::FRAC_PI_4;
    let gain = 1.0 / (1.0 + (d - 2.0).max(0.0) / 12.0);
    // Constant power, scaled so that straight ahead is the same level as the centre.
    let s = gain * std::f32::consts::SQRT_2;
    let pitch = ((SOUND_SPEED + listener.vel.dot(u)) / (SOUND_SPEED + vel.dot(u))).clamp(0.7, 1.4);
    Spatial { left: s * libm::cosf(angle), right: s * libm::sinf(angle), pitch }
}

/// One car's engine, tyre and surface sounds.
#[derive(Clone, Debug)]
pub struct CarVoice {
    engine: Engine,
    note: Option<EngineNote>,
    phase: f32,
    kerb_phase: f32,
    noise: Noise,
    squeal: BandPass,
    grass: OnePole,
    freq: Ramp,
    engine_amp: Ramp,
    load: Ramp,
    squeal_amp: Ramp,
    squeal_coeff: Ramp,
    kerb_amp: Ramp,
    kerb_hz: Ramp,
    grass_amp: Ramp,
    left: Ramp,
    right: Ramp,
}

/// What a car's voice is asked to sound like this tick (levels before the stereo gains).
struct Targets {
    hz: f32,
    engine: f32,
    load: f32,
    squeal: f32,
    squeal_hz: f32,
    kerb: f32,
    kerb_hz: f32,
    grass: f32,
}

impl CarVoice {
    /// A silent voice for car `index` (its noise seeded by the index, so every car hisses differently).
    #[must_use]
    pub fn new(index: usize) -> Self {
        Self {
            engine: Engine::new(),
            note: None,
            phase: 0.0,
            kerb_phase: 0.0,
            noise: Noise::new(0x5eed_0000 ^ (index as u32).wrapping_mul(0x9e37_79b9)),
            squeal: BandPass::default(),
            grass: OnePole::default(),
            freq: Ramp::at(0.0),
            engine_amp: Ramp::at(0.0),
            load: Ramp::at(0.0),
            squeal_amp: Ramp::at(0.0),
            squeal_coeff: Ramp::at(BandPass::coeff(SQUEAL_HZ)),
            kerb_amp: Ramp::at(0.0),
            kerb_hz: Ramp::at(0.0),
            grass_amp: Ramp::at(0.0),
            left: Ramp::at(0.0),
            right: Ramp::at(0.0),
        }
    }

    /// The engine's state after the last tick (`None` before the first).
    #[must_use]
    pub fn note(&self) -> Option<EngineNote> {
        self.note
    }

    /// Sets this tick's targets from the car's new state; `player` for the listener's own car, `effects` the
    /// effects volume, `place` where the listener hears it; `silent` fades everything out (the end).
    pub fn update(&mut self, car: &Car, params: &CarParams, (player, effects): (bool, f32), place: Spatial) {
        let note = self.engine.update(car, params);
        self.note = Some(note);
        let t = targets(car, &note, player);
        let pitch = place.pitch;
        // The first tick starts the oscillators at their pitch; the levels still rise from zero.
        if self.freq.target() == 0.0 {
            self.freq = Ramp::at(t.hz * pitch);
            self.kerb_hz = Ramp::at(t.kerb_hz * pitch);
        }
        self.freq.set(t.hz * pitch);
        self.engine_amp.set(t.engine);
        self.load.set(t.load);
        self.squeal_amp.set(t.squeal * effects);
        self.squeal_coeff.set(BandPass::coeff(t.squeal_hz * pitch));
        self.kerb_amp.set(t.kerb * effects);
        self.kerb_hz.set(t.kerb_hz * pitch);
        self.grass_amp.set(t.grass * effects);
        self.left.set(place.left);
        self.right.set(place.right);
    }

    /// Fades the voice out over the next tick (the end of a race, a voice leaving the mix).
    pub fn silence(&mut self) {
        for r in [&mut self.engine_amp, &mut self.squeal_amp, &mut self.kerb_amp, &mut self.grass_amp] {
            r.set(0.0);
        }
        let (f, k, c, l) = (self.freq.target(), self.kerb_hz.target(), self.squeal_coeff.target(), self.load.target());
        self.freq.set(f);
        self.kerb_hz.set(k);
        self.squeal_coeff.set(c);
        self.load.set(l);
        self.left.set(self.left.target());
        self.right.set(self.right.target());
    }

    /// Adds one tick of this voice to `out` (interleaved stereo, [`FRAMES_PER_TICK`] frames).
    pub fn render(&mut self, sine: &SineTable, out: &mut [f32]) {
        let grass_k = OnePole::coeff(300.0);
        let inv_rate = 1.0 / SAMPLE_RATE as f32;
        for (n, frame) in out.chunks_exact_mut(2).take(FRAMES_PER_TICK).enumerate() {
            let t = n as f32 / FRAMES_PER_TICK as f32;
            let f = self.freq.at_frac(t);
            self.phase += f * inv_rate;
            self.phase -= libm::floorf(self.phase);
            let load = self.load.at_frac(t);
            let mut engine = 0.0;
            for (k, (on, off)) in ON_LOAD.iter().zip(OFF_LOAD).enumerate() {
                let h = (k + 1) as f32;
                let fade = ((PARTIAL_CEILING + 300.0 - h * f) / 300.0).clamp(0.0, 1.0);
                if fade > 0.0 {
                    engine += (off + (on - off) * load) * fade * sine.sin(h * self.phase);
                }
            }
            let x = self.noise.sample();
            let squeal = self.squeal.run(x, self.squeal_coeff.at_frac(t), SQUEAL_DAMPING) * SQUEAL_NORM;
            self.kerb_phase += self.kerb_hz.at_frac(t) * inv_rate;
            self.kerb_phase -= libm::floorf(self.kerb_phase);
            let kerb = sine.sin(self.kerb_phase) + 0.4 * sine.sin(2.0 * self.kerb_phase);
            let grass = self.grass.run(x, grass_k) * 6.0;
            let s = engine * 0.5 * self.engine_amp.at_frac(t)
                + squeal * self.squeal_amp.at_frac(t)
                + kerb * self.kerb_amp.at_frac(t)
                + grass * self.grass_amp.at_frac(t);
            frame[0] += s * self.left.at_frac(t);
            frame[1] += s * self.right.at_frac(t);
        }
    }
}

/// The levels and pitches a car's state asks for.
fn targets(car: &Car, note: &EngineNote, player: bool) -> Targets {
    let v = car.speed().abs();
    let fwd = car.forward();
    let slip = car.vel.dot(Vec2::new(-fwd.y, fwd.x)).abs();
    let base = if player { ENGINE_LEVEL } else { ENGINE_LEVEL * RIVAL_LEVEL };
    let half = 0.5 * car.loc.width;
    let off_road = car.loc.lateral.abs() - half;
    let on_kerb = off_road > 0.0 && off_road <= KERB && !car.on_grass;
    let moving = smoothstep(1.0, 20.0, v);
    Targets {
        hz: note.hz(),
        engine: base * (0.55 + 0.45 * note.load),
        load: note.load,
        squeal: SQUEAL_LEVEL * smoothstep(1.5, 6.0, slip) * smoothstep(2.0, 8.0, car.vel.length()),
        squeal_hz: SQUEAL_HZ + 40.0 * slip.min(15.0),
        kerb: if on_kerb { RUMBLE_LEVEL * moving } else { 0.0 },
        kerb_hz: (v / KERB_STRIPE).clamp(15.0, 160.0),
        grass: if car.on_grass { RUMBLE_LEVEL * moving } else { 0.0 },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::game::track::tests_support::straight;

    fn rms(v: &[f32]) -> f32 {
        libm::sqrtf(v.iter().map(|x| x * x).sum::<f32>() / v.len() as f32)
    }

    fn run(car: &Car, ticks: usize) -> Vec<f32> {
        let (sine, p) = (SineTable::new(), CarParams::default());
        let mut voice = CarVoice::new(0);
        let mut out = vec![];
        for _ in 0..ticks {
            voice.update(car, &p, (true, 1.0), Spatial::CENTRE);
            let mut buf = vec![0.0; 2 * FRAMES_PER_TICK];
            voice.render(&sine, &mut buf);
            out.extend(buf);
        }
        out
    }

    #[test]
    fn sliding_squeals_and_grass_rumbles() {
        let t = straight();
        let grip = Car::on_grid(&t, 100.0, 0.0);
        let mut slide = grip;
        slide.vel = slide.forward() * 20.0 + Vec2::new(-slide.forward().y, slide.forward().x) * 6.0;
        let mut grass = grip;
        grass.on_grass = true;
        grass.vel = grass.forward() * 20.0;
        let band = |v: &[f32]| {
            // Squeal-band energy: the signal minus itself one sample later stresses the high band.
            let d: Vec<f32> = v.windows(4).map(|w| w[2] - w[0]).collect();
            rms(&d)
        };
        // Two seconds each; the second is measured, after the levels have settled.
        let (a, b) = (run(&grip, 240), run(&slide, 240));
        let (a, b) = (band(&a[96_000..]), band(&b[96_000..]));
        assert!(b > 3.0 * a, "squeal band {b} sliding vs {a} gripping");
        let (g, r) = (run(&grass, 240), run(&Car { on_grass: false, ..grass }, 240));
        assert!(rms(&g[96_000..]) > 1.2 * rms(&r[96_000..]), "{} vs {}", rms(&g[96_000..]), rms(&r[96_000..]));
    }

    #[test]
    fn places_rivals_by_side_distance_and_approach() {
        let t = straight();
        let me = Car::on_grid(&t, 100.0, 0.0);
        let right = Vec2::new(-me.forward().y, me.forward().x);
        let r = place(&me, me.pos + right * 10.0, Vec2::ZERO);
        assert!(r.right > 3.0 * r.left, "{r:?}");
        let far = place(&me, me.pos + me.forward() * 200.0, Vec2::ZERO);
        let near = place(&me, me.pos + me.forward() * 10.0, Vec2::ZERO);
        assert!(near.left > 4.0 * far.left);
        let coming = place(&me, me.pos + me.forward() * 50.0, -me.forward() * 40.0);
        let going = place(&me, me.pos + me.forward() * 50.0, me.forward() * 40.0);
        assert!(coming.pitch > 1.1 && going.pitch < 0.95, "{coming:?} {going:?}");
        assert_eq!(place(&me, me.pos, me.vel), Spatial::CENTRE);
    }

    #[test]
    fn a_voice_fades_in_and_out_without_a_step() {
        let t = straight();
        let mut car = Car::on_grid(&t, 100.0, 0.0);
        car.vel = car.forward() * 30.0;
        let (sine, p) = (SineTable::new(), CarParams::default());
        let mut voice = CarVoice::new(3);
        let mut out = vec![];
        for tick in 0..40 {
            if tick < 30 {
                voice.update(&car, &p, (true, 1.0), Spatial::CENTRE);
            } else {
                voice.silence();
            }
            let mut buf = vec![0.0; 2 * FRAMES_PER_TICK];
            voice.render(&sine, &mut buf);
            out.extend(buf);
        }
        assert!(out[0].abs() < 1e-3, "starts from silence: {}", out[0]);
        assert!(out.windows(2).all(|w| (w[1] - w[0]).abs() < 0.2));
        assert!(out[31 * 2 * FRAMES_PER_TICK..].iter().all(|&x| x == 0.0), "ends in exact silence");
    }
}
