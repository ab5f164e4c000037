//! The race's sound in the window: the mixer shown every world the race steps to, and the audio device it
//! plays on, opened once when the window first draws.
//!
//! Each simulation tick is one [`Mixer::advance`] and one [`Mixer::render`] (the pairing the mixer needs),
//! exactly as `replay --headless --audio` writes its WAV, so a replay in the window plays the same sound.
//! While the race stands still (menus, pause, a frozen replay) the device still plays in real time: the
//! mixer is then held ([`Mixer::hold`]: the engines fade out, a menu click plays) one tick per 1/120 s of
//! real time. The samples wait in a short queue here and go to the device's ring as it has room: the
//! frame never waits for the device, and the device's callback never waits for the game.

use std::collections::VecDeque;

use super::prefs::SoundLevels;
use crate::audio::{CHANNELS, FRAMES_PER_TICK, Mixer, Output};
use crate::game::{TICK_HZ, World};

/// Most sound queued here beyond the device's ring (two ticks): what a frame's burst of ticks does not fit
/// in the ring waits here for the next frame; beyond it the oldest is dropped, so that a device that
/// started late or a long stall never leaves the sound lagging the picture (the ring holds at most a device
/// period and a frame's ticks more: [`crate::audio::Output::limit`]).
const MAX_QUEUED: usize = 2 * CHANNELS * FRAMES_PER_TICK;
/// Most real time a frame sounds by held ticks (seconds): a stall is not made up.
const MAX_HELD: f64 = 0.1;

/// Where the samples go.
enum Sink {
    /// No sound: not asked for (tests, headless), or no device.
    Off,
    /// The device is to be opened at the first frame (not before: a window that cannot open must not
    /// print a line about sound first).
    Pending,
    /// The device.
    Device(Output),
    /// Kept in memory, for tests.
    #[cfg(test)]
    Captured(Vec<f32>),
}

/// The race's sound: the mixer and where its samples go.
pub(super) struct Sound {
    mixer: Mixer,
    sink: Sink,
    /// Samples rendered and not yet taken by the device's ring, oldest first.
    queue: VecDeque<f32>,
    /// The block the mixer renders into.
    block: Vec<f32>,
    /// Ticks of real time not yet sounded while the race stands still.
    due: f64,
    /// The tick of the last world the mixer was shown (to show the grid once before the first tick).
    heard: Option<u64>,
}

impl Default for Sound {
    fn default() -> Self {
        Self {
            mixer: Mixer::new(),
            sink: Sink::Off,
            queue: VecDeque::new(),
            block: Vec::with_capacity(CHANNELS * FRAMES_PER_TICK),
            due: 0.0,
            heard: None,
        }
    }
}

impl Sound {
    /// Asks for the default audio device, opened at the first frame.
    pub(super) fn enable(&mut self) {
        self.sink = Sink::Pending;
    }

    /// Whether samples are made at all (a device, or a test's capture).
    fn live(&self) -> bool {
        !matches!(self.sink, Sink::Off | Sink::Pending)
    }

    /// Opens the device if it is still to be opened; with none, says so in one line and stays silent.
    fn open_pending(&mut self) {
        if matches!(self.sink, Sink::Pending) {
            self.sink = match crate::audio::open() {
                Ok(out) => Sink::Device(out),
                Err(e) => {
                    eprintln!("scanline-racer: no audio ({e}); playing silent");
                    Sink::Off
                }
            };
        }
    }

    /// Tells the mixer the volumes and mute the settings hold now.
    pub(super) fn levels(&mut self, levels: SoundLevels) {
        self.mixer.set_volume(levels.volume);
        self.mixer.set_effects_volume(levels.effects);
        self.mixer.set_muted(levels.muted);
    }

    /// A menu click.
    pub(super) fn click(&mut self) {
        self.mixer.click();
    }

    /// The race stepped to `world` (or shows it for the first time): one tick of its sound.
    pub(super) fn world(&mut self, world: &World) {
        self.open_pending();
        if !self.live() || self.heard == Some(world.tick) {
            return;
        }
        self.heard = Some(world.tick);
        self.mixer.advance(world);
        self.render();
    }

    /// A new race on the grid: the old one's sound ends cleanly (a fade of a tick or so), and the next world
    /// starts a fresh mixer at the same volumes (no impact heard from the cars jumping back to the grid).
    pub(super) fn restart(&mut self, levels: SoundLevels) {
        if self.live() {
            self.mixer.finish(&mut self.block);
            self.queue.extend(self.block.drain(..));
        }
        self.mixer = Mixer::new();
        self.levels(levels);
        self.heard = None;
    }

    /// Once a frame, after the race's ticks: opens the device at the first frame; while the race stands
    /// still (`moving` false) sounds the `dt` seconds of real time by held ticks; then hands the device's
    /// ring what it has room for.
    pub(super) fn frame(&mut self, dt: f64, moving: bool) {
        self.open_pending();
        if !self.live() {
            return;
        }
        if moving {
            self.due = 0.0;
        } else {
            self.due = (self.due + dt * f64::from(TICK_HZ)).min(MAX_HELD * f64::from(TICK_HZ));
            while self.due >= 1.0 {
                self.due -= 1.0;
                self.mixer.hold();
                self.render();
            }
        }
        self.flush();
    }

    /// One tick of samples into the queue.
    fn render(&mut self) {
        self.mixer.render(&mut self.block);
        self.queue.extend(self.block.drain(..));
    }

    /// Moves queued samples to the sink as far as it takes them; of what is left, keeps at most
    /// [`MAX_QUEUED`] (the newest whole frames).
    fn flush(&mut self) {
        match &mut self.sink {
            Sink::Device(out) => {
                let (a, b) = self.queue.as_slices();
                let mut taken = out.push(a);
                if taken == a.len() {
                    taken += out.push(b);
                }
                self.queue.drain(..taken);
                if self.queue.len() > MAX_QUEUED {
                    let extra = self.queue.len() - MAX_QUEUED;
                    self.queue.drain(..extra - extra % CHANNELS);
                }
            }
            #[cfg(test)]
            Sink::Captured(all) => all.extend(self.queue.drain(..)),
            Sink::Off | Sink::Pending => self.queue.clear(),
        }
    }
}

#[cfg(test)]
impl Sound {
    /// A sound that keeps what it plays, for tests.
    pub(super) fn captured() -> Self {
        Self { sink: Sink::Captured(vec![]), ..Self::default() }
    }

    /// What a captured sound has played so far.
    pub(super) fn played(&self) -> &[f32] {
        match &self.sink {
            Sink::Captured(all) => all,
            _ => &[],
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::game::track::tests_support::straight;
    use crate::game::{Controls, step};

    const TICK: usize = CHANNELS * FRAMES_PER_TICK;

    #[test]
    fn every_tick_and_every_held_tick_is_one_block_and_a_click_plays_while_held() {
        let mut w = World::with_laps(Arc::new(straight()), 8, 1);
        w.player_is_ai = true;
        let mut s = Sound::captured();
        s.world(&w);
        s.world(&w);
        assert_eq!(s.played().len(), 0, "nothing before the frame hands it on");
        s.frame(0.0, true);
        assert_eq!(s.played().len(), TICK, "the grid once, however often it is shown");
        for _ in 0..600 {
            step(&mut w, &Controls::default());
            s.world(&w);
            s.frame(f64::from(crate::game::DT), true);
        }
        assert_eq!(s.played().len(), 601 * TICK);
        let racing = rms(&s.played()[600 * TICK..]);
        // Paused for half a second in frames of 50 ms: 60 held ticks, the engines fading out in the first.
        for _ in 0..10 {
            s.frame(0.05, false);
        }
        assert_eq!(s.played().len(), 661 * TICK);
        let held = rms(&s.played()[620 * TICK..661 * TICK]);
        assert!(racing > 0.01 && held == 0.0, "racing {racing}, held {held}");
        s.click();
        s.frame(0.05, false);
        let click = rms(&s.played()[661 * TICK..]);
        assert!(click > 0.001, "the click is heard while held: {click}");
        // Back to the race: the engines come back.
        step(&mut w, &Controls::default());
        s.world(&w);
        s.world(&w);
        s.frame(0.0, true);
        let n = s.played().len();
        assert_eq!(n % TICK, 0);
        step(&mut w, &Controls::default());
        s.world(&w);
        s.frame(0.0, true);
        assert!(rms(&s.played()[n..]) > 0.01);
    }

    #[test]
    fn a_stall_is_sounded_for_at_most_a_tenth_of_a_second_and_off_makes_nothing() {
        let w = World::with_laps(Arc::new(straight()), 8, 1);
        let mut s = Sound::captured();
        s.world(&w);
        s.frame(5.0, false);
        assert_eq!(s.played().len(), 13 * TICK, "the grid, then a 5 s stall held for 0.1 s");
        let mut off = Sound::default();
        off.world(&w);
        off.frame(1.0, false);
        assert!(off.queue.is_empty() && off.heard.is_none());
    }

    fn rms(x: &[f32]) -> f32 {
        libm::sqrtf(x.iter().map(|v| v * v).sum::<f32>() / x.len().max(1) as f32)
    }
}
