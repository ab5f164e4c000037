//! The mixer: every car's voice and every one-shot, summed, turned down or muted, and kept below full scale
//! by a limiter, one simulation tick of samples at a time.
//!
//! Its output is a pure function of the worlds it is shown (in order) and the volume calls between them:
//! no clock, no randomness but seeded generators, `libm` for maths. The headless replay writes it to a WAV
//! file; the window will push the same samples to the audio device.

use super::dsp::{Ramp, SineTable};
use super::events::{OneShot, contacts};
use super::format::{CHANNELS, FRAMES_PER_TICK};
use super::voice::{CarVoice, Spatial, place};
use crate::game::World;
use crate::game::car::Car;
use crate::game::rules::Phase;

/// Level above which the limiter turns the mix down.
const LIMIT: f32 = 0.7;
/// Where the soft clip starts, and the most it ever reaches (below full scale, whatever comes in).
const KNEE: f32 = 0.8;
/// The most the soft clip ever outputs.
pub const CEILING: f32 = 0.98;
/// The limiter's attack per sample (reaches a peak within about 0.2 ms) and release (about 150 ms).
const ATTACK: f32 = 0.3;
const RELEASE: f32 = 1.0 / 7200.0;
/// Ticks of silence written after everything has faded at the end.
const SILENT_TAIL_TICKS: usize = 2;

/// The race's sound: advance it by each world, render a tick of samples after each.
#[derive(Clone, Debug)]
pub struct Mixer {
    sine: SineTable,
    voices: Vec<CarVoice>,
    shots: Vec<OneShot>,
    prev_cars: Vec<Car>,
    prev_count: Option<u64>,
    prev_phase: Option<Phase>,
    player_finished: bool,
    volume: f32,
    effects: f32,
    muted: bool,
    master: Ramp,
    effects_ramp: Ramp,
    env: f32,
    buf: Vec<f32>,
}

impl Default for Mixer {
    fn default() -> Self {
        Self::new()
    }
}

impl Mixer {
    /// A silent mixer at full volume, not muted; it starts sounding with the first world it is shown.
    #[must_use]
    pub fn new() -> Self {
        Self {
            sine: SineTable::new(),
            voices: vec![],
            shots: vec![],
            prev_cars: vec![],
            prev_count: None,
            prev_phase: None,
            player_finished: false,
            volume: 1.0,
            effects: 1.0,
            muted: false,
            master: Ramp::at(1.0),
            effects_ramp: Ramp::at(1.0),
            env: 0.0,
            buf: vec![0.0; CHANNELS * FRAMES_PER_TICK],
        }
    }

    /// Sets the master volume (0 to 1), reached smoothly over the next tick.
    pub fn set_volume(&mut self, volume: f32) {
        self.volume = if volume.is_finite() { volume.clamp(0.0, 1.0) } else { 0.0 };
    }

    /// Sets the effects volume (0 to 1): tyres, surfaces, impacts, beeps and clicks; the engines keep theirs.
    pub fn set_effects_volume(&mut self, volume: f32) {
        self.effects = if volume.is_finite() { volume.clamp(0.0, 1.0) } else { 0.0 };
    }

    /// Mutes or unmutes everything (a fade of one tick, not a click).
    pub fn set_muted(&mut self, muted: bool) {
        self.muted = muted;
    }

    /// Whether the mixer is muted.
    #[must_use]
    pub fn muted(&self) -> bool {
        self.muted
    }

    /// Plays a menu click (at the effects volume).
    pub fn click(&mut self) {
        self.shots.push(OneShot::click());
    }

    /// The engine speed car `index` was given at the last world (rpm), or `None` before the first.
    #[must_use]
    pub fn engine_rpm(&self, index: usize) -> Option<f32> {
        self.voices.get(index).and_then(CarVoice::note).map(|n| n.rpm)
    }

    /// Takes the world of the tick just simulated: every car's voice gets its new targets, and impacts,
    /// beeps and the finish are started from what changed since the last world.
    pub fn advance(&mut self, world: &World) {
        let Some(listener) = world.cars.first().copied() else {
            return;
        };
        if self.voices.len() != world.cars.len() {
            self.voices = (0..world.cars.len()).map(CarVoice::new).collect();
            self.prev_cars.clear();
        }
        for (i, (voice, car)) in self.voices.iter_mut().zip(&world.cars).enumerate() {
            let at = if i == 0 { Spatial::CENTRE } else { place(&listener, car.pos, car.vel) };
            voice.update(car, &world.params[i], (i == 0, self.effects), at);
        }
        if self.prev_cars.len() == world.cars.len() {
            for c in contacts(&world.track, &world.params, &self.prev_cars, &world.cars) {
                let at = if c.cars.0 == 0 || c.cars.1 == Some(0) {
                    Spatial::CENTRE
                } else {
                    place(&listener, c.pos, listener.vel)
                };
                self.shots.push(OneShot::impact(c.speed, at));
            }
        }
        self.race_events(world);
        self.prev_cars.clone_from(&world.cars);
        self.master.set(if self.muted { 0.0 } else { self.volume });
        self.effects_ramp.set(self.effects);
    }

    /// Holds the sound while the race stands still (a pause, a menu, a frozen replay): in place of
    /// [`Mixer::advance`] before a [`Mixer::render`], every car's voice fades out over the next tick and stays
    /// silent while one-shots (a menu click) play on; the next `advance` fades the voices back in.
    ///
    /// Why: the device plays on in real time while the world does not move, and a voice cut off mid-wave
    /// clicks, while one held at its last note drones through the pause menu.
    pub fn hold(&mut self) {
        for v in &mut self.voices {
            v.silence();
        }
        self.master.set(if self.muted { 0.0 } else { self.volume });
        self.effects_ramp.set(self.effects);
    }

    /// The countdown's beeps (one a second, then the start's tone) and the player's finish.
    fn race_events(&mut self, world: &World) {
        let phase = world.race.phase;
        if let Phase::Countdown(left) = phase {
            let secs = left.div_ceil(u64::from(crate::game::TICK_HZ));
            if self.prev_count != Some(secs) {
                self.shots.push(OneShot::beep(false));
            }
            self.prev_count = Some(secs);
        } else if matches!(self.prev_phase, Some(Phase::Countdown(_))) {
            self.shots.push(OneShot::beep(true));
        }
        self.prev_phase = Some(phase);
        let finished = world.race.standings.first().is_some_and(|s| s.finished.is_some());
        if finished && !self.player_finished {
            self.shots.extend(OneShot::chime());
        }
        self.player_finished = finished;
    }

    /// Appends one tick of sound ([`FRAMES_PER_TICK`] interleaved stereo frames) to `out`.
    pub fn render(&mut self, out: &mut Vec<f32>) {
        self.buf.fill(0.0);
        for v in &mut self.voices {
            v.render(&self.sine, &mut self.buf);
        }
        let fx = self.effects_ramp.target();
        for s in &mut self.shots {
            s.render(&self.sine, &mut self.buf, fx);
        }
        self.shots.retain(|s| !s.done());
        for (n, frame) in self.buf.chunks_exact(CHANNELS).enumerate() {
            let g = self.master.at_frac(n as f32 / FRAMES_PER_TICK as f32);
            let (l, r) = (frame[0] * g, frame[1] * g);
            let peak = l.abs().max(r.abs());
            let k = if peak > self.env { ATTACK } else { RELEASE };
            self.env += k * (peak - self.env);
            let limit = if self.env > LIMIT { LIMIT / self.env } else { 1.0 };
            out.push(soft_clip(l * limit));
            out.push(soft_clip(r * limit));
        }
    }

    /// Ends the sound: every voice fades out within a tick, every one-shot within its release, then a few
    /// ticks of silence; appends it all to `out`. The mixer is silent afterwards until shown a world again.
    pub fn finish(&mut self, out: &mut Vec<f32>) {
        for v in &mut self.voices {
            v.silence();
        }
        for s in &mut self.shots {
            s.cut();
        }
        self.render(out);
        for v in &mut self.voices {
            v.silence();
        }
        while !self.shots.is_empty() {
            self.render(out);
        }
        for _ in 0..SILENT_TAIL_TICKS {
            self.render(out);
        }
    }
}

/// Leaves `x` alone below the knee and bends it smoothly towards [`CEILING`] above, so nothing the limiter
/// lets through can clip.
#[must_use]
pub fn soft_clip(x: f32) -> f32 {
    let a = x.abs();
    if a <= KNEE {
        x
    } else {
        let room = CEILING - KNEE;
        x.signum() * (KNEE + room * libm::tanhf((a - KNEE) / room))
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::game::track::tests_support::straight;
    use crate::game::{Controls, step};

    fn race(ticks: u64, mute_at: Option<u64>) -> Vec<f32> {
        let mut w = World::with_laps(Arc::new(straight()), 8, 1);
        w.player_is_ai = true;
        let mut m = Mixer::new();
        let mut out = vec![];
        m.advance(&w);
        m.render(&mut out);
        for _ in 0..ticks {
            step(&mut w, &Controls::default());
            m.set_muted(mute_at.is_some_and(|t| w.tick >= t));
            m.advance(&w);
            m.render(&mut out);
        }
        m.finish(&mut out);
        out
    }

    #[test]
    fn the_same_race_sounds_the_same_bit_for_bit() {
        let (a, b) = (race(900, None), race(900, None));
        assert_eq!(a.len(), b.len());
        assert!(a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()));
        assert!(a.iter().all(|x| x.abs() <= CEILING));
        assert!(a[a.len() - 2 * FRAMES_PER_TICK..].iter().all(|&x| x == 0.0), "ends in silence");
    }

    #[test]
    fn countdown_beeps_three_times_then_the_start_tone() {
        let mut w = World::with_laps(Arc::new(straight()), 2, 1);
        let mut m = Mixer::new();
        let mut beeps = 0;
        for _ in 0..400 {
            m.advance(&w);
            beeps += m.shots.len();
            m.shots.clear();
            step(&mut w, &Controls::default());
        }
        assert_eq!(beeps, 4);
    }

    #[test]
    fn muting_fades_to_silence_without_a_step() {
        let out = race(700, Some(600));
        // Block k is the sound after the world of tick k: tick 600's block fades, the rest is silent.
        let at = 601 * 2 * FRAMES_PER_TICK;
        assert!(out[at..700 * 2 * FRAMES_PER_TICK].iter().all(|&x| x == 0.0));
        assert!(out[at - 4 * FRAMES_PER_TICK..at - 2 * FRAMES_PER_TICK].iter().any(|&x| x != 0.0));
        let jump = out[at - 2000..at + 2000].windows(3).map(|w| (w[2] - w[0]).abs()).fold(0.0, f32::max);
        assert!(jump < 0.1, "mute jumps by {jump}");
    }

    #[test]
    fn holding_fades_the_engines_within_a_tick_and_lets_a_click_play() {
        let mut w = World::with_laps(Arc::new(straight()), 8, 1);
        w.player_is_ai = true;
        let mut m = Mixer::new();
        let mut out = vec![];
        for _ in 0..600 {
            step(&mut w, &Controls::default());
            m.advance(&w);
            m.render(&mut out);
        }
        let tick = 2 * FRAMES_PER_TICK;
        for _ in 0..3 {
            m.hold();
            m.render(&mut out);
        }
        assert!(out[600 * tick..601 * tick].iter().any(|&x| x != 0.0), "the first held tick fades");
        assert!(out[601 * tick..].iter().all(|&x| x == 0.0), "then silence");
        let jump = out[599 * tick..602 * tick].windows(3).map(|w| (w[2] - w[0]).abs()).fold(0.0, f32::max);
        assert!(jump < 0.1, "holding jumps by {jump}");
        m.click();
        m.hold();
        let at = out.len();
        m.render(&mut out);
        assert!(out[at..].iter().any(|&x| x != 0.0), "a click plays while held");
    }

    #[test]
    fn the_soft_clip_never_reaches_full_scale() {
        for x in [0.0f32, 0.5, 0.8, 0.9, 1.0, 2.0, 100.0, 1e30] {
            assert!(soft_clip(x) < 1.0 && soft_clip(-x) > -1.0 && soft_clip(x) >= soft_clip(x * 0.99));
        }
        assert_eq!(soft_clip(0.5), 0.5);
    }
}
