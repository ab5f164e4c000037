//! The sounds that happen once: impacts, the countdown's beeps, the finish and menu clicks; and the
//! detection of impacts from two successive world states (the simulation has no events).
//!
//! Every one-shot has an envelope that starts from zero over at least a millisecond and ends at exactly
//! zero, so no start or end is a click.

use glam::Vec2;

use super::dsp::{Noise, OnePole, SineTable};
use super::format::SAMPLE_RATE;
use super::voice::Spatial;
use crate::game::car::{BODY_HALF_WIDTH, Car, CarParams};
use crate::game::track::Track;

/// Closing speed (m/s) below which a touch makes no impact sound (a car resting on a barrier, a nudge).
pub const IMPACT_MIN_SPEED: f32 = 0.8;
/// Closing speed (m/s) of the loudest impact.
pub const IMPACT_FULL_SPEED: f32 = 25.0;
/// The loudest impact's level.
const IMPACT_LEVEL: f32 = 0.5;
/// Countdown beep and start tone (Hz).
pub const BEEP_HZ: [f32; 2] = [880.0, 1760.0];
/// The finish chime's notes (Hz): C, E, G and the octave.
const CHIME_HZ: [f32; 4] = [523.25, 659.26, 783.99, 1046.5];

/// A contact seen between two ticks: where, and how fast the bodies closed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// Where it happened (ground plane).
    pub pos: Vec2,
    /// Closing speed along the contact normal (m/s).
    pub speed: f32,
    /// The cars involved (the second is `None` for a barrier).
    pub cars: (usize, Option<usize>),
}

/// Contacts between the world's cars `before` and `after` one tick: a car clamped onto a barrier that was
/// moving into it, and two cars touching that were closing on each other (`params` each car's handling,
/// by index; a car past its end has the last's).
#[must_use]
pub fn contacts(track: &Track, params: &[CarParams], before: &[Car], after: &[Car]) -> Vec<Contact> {
    let radius = |k: usize| params.get(k).or(params.last()).map_or(0.0, |p| p.radius);
    let mut out = vec![];
    for (i, (b, a)) in before.iter().zip(after).enumerate() {
        let side = usize::from(a.loc.lateral > 0.0);
        let limit = a.loc.barrier[side] - BODY_HALF_WIDTH;
        if a.loc.lateral.abs() >= limit - 1e-3 {
            let (_, dir) = track.point_at(a.loc.s, 0.0);
            let outward = Vec2::new(-dir.y, dir.x) * a.loc.lateral.signum();
            let speed = b.vel.dot(outward) - a.vel.dot(outward);
            if speed > IMPACT_MIN_SPEED {
                out.push(Contact { pos: a.pos, speed, cars: (i, None) });
            }
        }
    }
    for i in 0..after.len().min(before.len()) {
        for j in i + 1..after.len().min(before.len()) {
            let d = after[j].pos - after[i].pos;
            let dist = d.length();
            if dist > radius(i) + radius(j) + 0.02 || (after[i].loc.height - after[j].loc.height).abs() > 3.0 {
                continue;
            }
            let n = if dist > 1e-4 { d / dist } else { after[i].forward().perp() };
            let speed = -(before[j].vel - before[i].vel).dot(n);
            if speed > IMPACT_MIN_SPEED {
                out.push(Contact { pos: 0.5 * (after[i].pos + after[j].pos), speed, cars: (i, Some(j)) });
            }
        }
    }
    out
}

/// The level of an impact at closing speed `speed` (before placing it).
#[must_use]
pub fn impact_level(speed: f32) -> f32 {
    IMPACT_LEVEL * libm::powf((speed / IMPACT_FULL_SPEED).clamp(0.0, 1.0), 0.7)
}

/// What a one-shot sounds like.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Kind {
    /// A sine beep with a little second harmonic.
    Beep { hz: f32 },
    /// A thud whose pitch drops, over a crunch of low-passed noise.
    Impact { thud_hz: f32 },
    /// A bell-like note with a long decay.
    Chime { hz: f32 },
    /// A short tick for menus.
    Click,
}

/// A sound that plays once and ends.
#[derive(Clone, Debug)]
pub struct OneShot {
    kind: Kind,
    /// Samples to wait before starting.
    delay: u32,
    age: u32,
    len: u32,
    attack: u32,
    /// Exponential decay time (samples; 0 holds the level until the release).
    decay: f32,
    release: u32,
    level: f32,
    place: Spatial,
    phase: f32,
    noise: Noise,
    lp: OnePole,
}

/// Seconds to samples.
fn samples(s: f32) -> u32 {
    (s * SAMPLE_RATE as f32) as u32
}

impl OneShot {
    fn new(kind: Kind, (len, attack, decay, release): (f32, f32, f32, f32), level: f32, place: Spatial) -> Self {
        Self {
            kind,
            delay: 0,
            age: 0,
            len: samples(len),
            attack: samples(attack).max(1),
            decay: decay * SAMPLE_RATE as f32,
            release: samples(release).max(1),
            level,
            place,
            phase: 0.0,
            noise: Noise::new(0x1a2b_3c4d ^ level.to_bits()),
            lp: OnePole::default(),
        }
    }

    /// A countdown beep (`go` for the start's higher, longer tone).
    #[must_use]
    pub fn beep(go: bool) -> Self {
        let (hz, len) = if go { (BEEP_HZ[1], 0.5) } else { (BEEP_HZ[0], 0.15) };
        Self::new(Kind::Beep { hz }, (len, 0.005, 0.0, 0.02), 0.22, Spatial::CENTRE)
    }

    /// An impact at closing speed `speed`, heard at `place`.
    #[must_use]
    pub fn impact(speed: f32, place: Spatial) -> Self {
        let thud_hz = 70.0 + 2.0 * speed.min(40.0);
        Self::new(Kind::Impact { thud_hz }, (0.3, 0.0015, 0.07, 0.01), impact_level(speed), place)
    }

    /// The finish chime: four notes in a rising arpeggio.
    #[must_use]
    pub fn chime() -> Vec<Self> {
        CHIME_HZ
            .iter()
            .enumerate()
            .map(|(k, &hz)| {
                let mut s = Self::new(Kind::Chime { hz }, (1.4, 0.004, 0.45, 0.05), 0.12, Spatial::CENTRE);
                s.delay = samples(0.12 * k as f32);
                s
            })
            .collect()
    }

    /// A menu click.
    #[must_use]
    pub fn click() -> Self {
        Self::new(Kind::Click, (0.012, 0.001, 0.003, 0.002), 0.15, Spatial::CENTRE)
    }

    /// True once the sound has ended.
    #[must_use]
    pub fn done(&self) -> bool {
        self.age >= self.len
    }

    /// Ends the sound within its release time (the end of the race's audio).
    pub fn cut(&mut self) {
        self.delay = 0;
        let end = self.age.saturating_add(self.release).min(self.len);
        self.len = end;
    }

    /// The envelope at the current age: linear attack, exponential decay, linear release to exactly zero.
    fn envelope(&self) -> f32 {
        let a = self.age as f32;
        let attack = (a / self.attack as f32).min(1.0);
        let decay = if self.decay > 0.0 { libm::expf(-a / self.decay) } else { 1.0 };
        let release = ((self.len - self.age) as f32 / self.release as f32).min(1.0);
        attack * decay * release
    }

    /// Adds up to `frames` frames of the sound to interleaved stereo `out`, scaled by `gain`.
    pub fn render(&mut self, sine: &SineTable, out: &mut [f32], gain: f32) {
        let inv = 1.0 / SAMPLE_RATE as f32;
        let crunch_k = OnePole::coeff(1500.0);
        for frame in out.chunks_exact_mut(2) {
            if self.delay > 0 {
                self.delay -= 1;
                continue;
            }
            if self.done() {
                return;
            }
            let env = self.envelope();
            let s = match self.kind {
                Kind::Beep { hz } => {
                    self.phase += hz * inv;
                    sine.sin(self.phase) + 0.2 * sine.sin(2.0 * self.phase)
                }
                Kind::Impact { thud_hz } => {
                    let t = self.age as f32 * inv;
                    self.phase += thud_hz * (0.6 + 0.4 * libm::expf(-t / 0.05)) * inv;
                    let crunch = self.lp.run(self.noise.sample(), crunch_k);
                    0.7 * sine.sin(self.phase) + 1.6 * crunch * libm::expf(-t / 0.03)
                }
                Kind::Chime { hz } => {
                    self.phase += hz * inv;
                    sine.sin(self.phase) + 0.3 * sine.sin(3.0 * self.phase) * env
                }
                Kind::Click => {
                    self.phase += 2000.0 * inv;
                    sine.sin(self.phase)
                }
            };
            self.phase -= libm::floorf(self.phase);
            let v = s * env * self.level * gain;
            frame[0] += v * self.place.left;
            frame[1] += v * self.place.right;
            self.age += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::game::track::tests_support::straight;

    fn play(mut s: OneShot) -> Vec<f32> {
        let sine = SineTable::new();
        let mut out = vec![0.0; 2 * 48_000 * 2];
        s.render(&sine, &mut out, 1.0);
        assert!(s.done(), "a one-shot ends");
        out
    }

    #[test]
    fn one_shots_start_and_end_at_zero_without_jumps() {
        let shots = [OneShot::beep(false), OneShot::beep(true), OneShot::impact(30.0, Spatial::CENTRE)];
        for s in shots.into_iter().chain(OneShot::chime()).chain([OneShot::click()]) {
            let kind = s.kind;
            let out = play(s);
            assert!(out[0].abs() < 0.01, "{kind:?} starts at {}", out[0]);
            let left: Vec<f32> = out.chunks(2).map(|f| f[0]).collect();
            let jumps = |x: &[f32]| x.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f32::max);
            // The attack's first millisecond is no steeper than the sound that follows it (10% for the click,
            // whose decay starts within it).
            let (onset, body) = (jumps(&left[..48]), jumps(&left[48..4800]));
            assert!(onset <= 1.1 * body, "{kind:?} starts with a jump of {onset}, its body's steepest is {body}");
            assert_eq!(*out.last().unwrap_or(&1.0), 0.0, "{kind:?} ends at zero");
        }
    }

    #[test]
    fn harder_impacts_are_louder() {
        let peak = |v: f32| play(OneShot::impact(v, Spatial::CENTRE)).iter().fold(0.0f32, |m, x| m.max(x.abs()));
        assert!(peak(20.0) > 1.5 * peak(5.0), "{} vs {}", peak(20.0), peak(5.0));
        assert!(peak(5.0) > 1.5 * peak(1.0));
    }

    #[test]
    fn barrier_and_car_contacts_are_detected_with_their_speed() {
        let t = straight();
        let p = CarParams::default();
        let mut a = Car::on_grid(&t, 100.0, 0.0);
        let b = a;
        let right = Vec2::new(-a.forward().y, a.forward().x);
        a.vel = right * 12.0;
        let before = [a, Car::on_grid(&t, 300.0, 0.0)];
        // Past the barrier: the car model clamps it onto the barrier line and removes the speed into it.
        let mut after = before;
        after[0].pos += right * 50.0;
        after[0].settle(&t);
        let c = contacts(&t, std::slice::from_ref(&p), &before, &after);
        assert_eq!(c.len(), 1, "{c:?}");
        assert!((c[0].speed - 12.0).abs() < 0.5 && c[0].cars == (0, None), "{c:?}");
        assert!(contacts(&t, std::slice::from_ref(&p), &after, &after).is_empty(), "resting on the barrier is silent");
        // Two cars closing at 8 m/s, touching.
        let mut x = [b, b];
        x[1].pos += b.forward() * 2.0 * p.radius;
        let mut y = x;
        y[0].vel = b.forward() * 8.0;
        let c = contacts(&t, std::slice::from_ref(&p), &y, &x);
        assert_eq!(c.len(), 1);
        assert!((c[0].speed - 8.0).abs() < 1e-3 && c[0].cars == (0, Some(1)));
        assert!(contacts(&t, std::slice::from_ref(&p), &x, &x).is_empty(), "touching without closing is silent");
    }
}
