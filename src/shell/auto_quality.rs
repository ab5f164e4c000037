//! `auto` quality: the window's picture climbs and descends the preset ladder ([`Quality`]) from the
//! measured frame time, so each frame stays within a share of the refresh period.
//!
//! The rules, in the order they keep the picture steady:
//! - A frame's time counts through the median of the last [`WINDOW`] frames at the step in use: a spike
//!   of fewer than half of them moves nothing.
//! - Down: when that median is over the budget ([`SHARE`] of the frame period), or when at least
//!   [`LATE_LIMIT`] of the last [`LATE_FRAMES`] frames came more than half a period late (the cores are
//!   busy with other programs: the drawing itself may stay quick, since the renderer's threads take
//!   whatever bands are left, but the frames miss their refreshes, and a cheaper step asks for less of the
//!   cores).
//! - Up: only after [`ROOM_SECONDS`] in a row in which the next step's predicted time fits
//!   [`UP_MARGIN`] of the budget and no frame of the last [`LATE_FRAMES`] came late. The prediction is the current median times the ratio of the two steps'
//!   costs as the bench measured them ([`BENCH_COST`]).
//! - A step up that has to be taken back within [`TRIAL_SECONDS`] is a failed trial: that step is not
//!   tried again for [`BACK_OFF_SECONDS`], doubled with each failure in a row (at most
//!   [`MAX_BACK_OFF_SECONDS`]). So a machine on which a step costs more than the bench's ratio says tries
//!   it rarely and more rarely, and one whose cores another program took climbs back once they are free
//!   (a step held longer than a trial and then left is not held against it). Learned cost ratios, and a
//!   retry only once the frames below got cheaper than just after the step down, were tried first: each
//!   could keep a step away for good after a load that began just after the step up.
//! - At most one change every [`HOLD_SECONDS`].
//!
//! A time that sits at the budget therefore makes one step down and no step back: the step above is
//! predicted at the budget, which is over the margin.
//!
//! The controller is a pure function of the times and durations it is given; the window's clock feeds it.

use std::fmt;
use std::str::FromStr;

use crate::render::{Quality, UnknownName};

/// Frames whose median decides a step down.
pub const WINDOW: usize = 9;
/// Share of the frame period the drawing may take.
pub const SHARE: f64 = 0.7;
/// Share of the budget the next step's predicted time must fit before a step up.
pub const UP_MARGIN: f64 = 0.85;
/// A step up taken back within this many seconds was a failed trial.
pub const TRIAL_SECONDS: f64 = 5.0;
/// Seconds before a step that failed its trial is tried again (doubled with each failure in a row).
pub const BACK_OFF_SECONDS: f64 = 5.0;
/// The longest wait before a failed step is tried again.
pub const MAX_BACK_OFF_SECONDS: f64 = 80.0;
/// Seconds of room in a row before a step up.
pub const ROOM_SECONDS: f64 = 2.0;
/// Least seconds between two changes.
pub const HOLD_SECONDS: f64 = 1.0;
/// Frames over which late frames are counted (at most 32: they are bits of a word).
pub const LATE_FRAMES: u32 = 30;
/// Late frames among the last [`LATE_FRAMES`] that step down: a quarter, about 45 frames a second at 60 Hz.
pub const LATE_LIMIT: u32 = 8;
/// A frame this many periods after the one before is late (it missed at least one refresh).
pub const LATE_PERIODS: f64 = 1.5;

/// Each step's frame time relative to `low`'s: the means over the three courses of the presets' times
/// measured as the bench measures them (1 thread, 640x480; docs/performance.md, "Quality presets"); `ultra`'s
/// since it took `min-bilinear` texels and finer models (3.43x, 3.32x, 3.35x).
pub const BENCH_COST: [f64; 4] = [1.0, 1.6, 2.5, 3.4];

/// What the window's picture follows: a fixed preset, or `auto`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum QualityChoice {
    /// Climbs and descends the presets from the frame time (the window only).
    Auto,
    /// One preset.
    Fixed(Quality),
}

impl FromStr for QualityChoice {
    type Err = UnknownName;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        if s == "auto" {
            return Ok(QualityChoice::Auto);
        }
        s.parse().map(QualityChoice::Fixed).map_err(|_: UnknownName| UnknownName {
            setting: "quality",
            given: s.to_owned(),
            expected: "auto, low, medium, high or ultra",
        })
    }
}

impl fmt::Display for QualityChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            QualityChoice::Auto => f.write_str("auto"),
            QualityChoice::Fixed(q) => f.write_str(q.name()),
        }
    }
}

/// The `auto` controller: the step in use and what it has measured.
#[derive(Clone, Debug)]
pub struct AutoQuality {
    step: Quality,
    /// The last frame times at this step (ms), oldest first, at most [`WINDOW`].
    recent: Vec<f64>,
    /// Seconds of frames taken so far (the controller's clock).
    clock: f64,
    /// Whether the step in use was reached by a step up (then leaving it within a trial is a failure).
    climbed: bool,
    /// For each step: failed trials in a row, and the clock time before which it is not tried again.
    failures: [(u32, f64); 4],
    /// Seconds since the last change.
    since_change: f64,
    /// Seconds in a row with room for the next step.
    room: f64,
    /// Changes made so far.
    changes: u32,
    /// Which of the last [`LATE_FRAMES`] frames came late (bit 0 the newest).
    late: u32,
}

impl AutoQuality {
    /// A controller starting at `step` (the first change may come after [`HOLD_SECONDS`]).
    #[must_use]
    pub fn new(step: Quality) -> Self {
        Self {
            step,
            recent: Vec::with_capacity(WINDOW),
            clock: 0.0,
            climbed: false,
            failures: [(0, 0.0); 4],
            since_change: 0.0,
            room: 0.0,
            changes: 0,
            late: 0,
        }
    }

    /// The step in use.
    #[must_use]
    pub fn step(&self) -> Quality {
        self.step
    }

    /// How many times the step changed.
    #[must_use]
    pub fn changes(&self) -> u32 {
        self.changes
    }

    /// Takes a frame that took `ms` to draw, `seconds` after the one before, against a frame period of
    /// `period_ms`; the new step when it changes. Times that are not finite or not positive are ignored.
    pub fn frame(&mut self, ms: f64, seconds: f64, period_ms: f64) -> Option<Quality> {
        if !(ms.is_finite() && ms >= 0.0 && period_ms.is_finite() && period_ms > 0.0) {
            return None;
        }
        let seconds = if seconds.is_finite() { seconds.clamp(0.0, 1.0) } else { 0.0 };
        let late = seconds * 1e3 > LATE_PERIODS * period_ms;
        self.late = ((self.late << 1) | u32::from(late)) & ((1u32 << LATE_FRAMES.min(31)) - 1);
        self.since_change += seconds;
        self.clock += seconds;
        if self.climbed && self.since_change >= TRIAL_SECONDS {
            // The step up held: its trial passed.
            self.climbed = false;
            self.failures[self.step as usize].0 = 0;
        }
        if self.recent.len() == WINDOW {
            self.recent.remove(0);
        }
        self.recent.push(ms);
        let median = self.median()?;
        let budget = SHARE * period_ms;
        let next = self.step.up();
        let fits = next.is_some_and(|up| {
            let waited = self.clock >= self.failures[up as usize].1;
            waited
                && self.late == 0
                && median * BENCH_COST[up as usize] / BENCH_COST[self.step as usize] <= UP_MARGIN * budget
        });
        self.room = if fits { self.room + seconds } else { 0.0 };
        if self.since_change < HOLD_SECONDS {
            return None;
        }
        let to = if median > budget || self.late.count_ones() >= LATE_LIMIT {
            self.step.down()
        } else if self.room >= ROOM_SECONDS {
            next
        } else {
            None
        }?;
        if to < self.step && self.climbed {
            let (failed, _) = self.failures[self.step as usize];
            let wait = (BACK_OFF_SECONDS * f64::from(1u32 << failed.min(8))).min(MAX_BACK_OFF_SECONDS);
            self.failures[self.step as usize] = (failed + 1, self.clock + wait);
        }
        self.climbed = to > self.step;
        self.step = to;
        self.recent.clear();
        self.since_change = 0.0;
        self.room = 0.0;
        self.late = 0;
        self.changes += 1;
        Some(to)
    }

    /// The median of the window, once it is full.
    fn median(&self) -> Option<f64> {
        if self.recent.len() < WINDOW {
            return None;
        }
        let mut sorted = self.recent.clone();
        sorted.sort_by(f64::total_cmp);
        sorted.get(WINDOW / 2).copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Feeds `frames` frames of `ms(step, i)` at 60 Hz; the steps after each frame.
    fn run(auto: &mut AutoQuality, frames: usize, ms: impl Fn(Quality, usize) -> f64) -> Vec<Quality> {
        (0..frames)
            .map(|i| {
                auto.frame(ms(auto.step(), i), 1.0 / 60.0, 1000.0 / 60.0);
                auto.step()
            })
            .collect()
    }

    /// A machine on which each step costs the bench's ratio times `low_ms`.
    fn machine(low_ms: f64) -> impl Fn(Quality, usize) -> f64 {
        move |q, _| low_ms * BENCH_COST[q as usize]
    }

    #[test]
    fn a_machine_with_room_climbs_to_the_top_one_step_at_a_time() {
        let mut auto = AutoQuality::new(Quality::Low);
        let steps = run(&mut auto, 60 * 20, machine(1.0));
        assert_eq!(steps.last(), Some(&Quality::Ultra));
        assert_eq!(auto.changes(), 3);
        // The first step up waits for the hold and the run of room.
        let first = steps.iter().position(|s| *s != Quality::Low).unwrap();
        assert!(first as f64 / 60.0 >= ROOM_SECONDS, "{first}");
    }

    #[test]
    fn a_spike_does_not_step_down() {
        let mut auto = AutoQuality::new(Quality::High);
        // Four frames in every nine take 40 ms (over a 11.7 ms budget): fewer than half of the window.
        let steps = run(&mut auto, 60 * 10, |_, i| if i % 9 < 4 { 40.0 } else { 3.0 });
        assert!(steps.iter().all(|s| *s >= Quality::High), "{steps:?}");
        // And the same spikes at the top step, with room below them, do not either.
        let mut top = AutoQuality::new(Quality::Ultra);
        let steps = run(&mut top, 60 * 10, |_, i| if i % 9 < 4 { 40.0 } else { 3.0 });
        assert!(steps.iter().all(|s| *s == Quality::Ultra), "{steps:?}");
    }

    #[test]
    fn a_steady_overload_steps_down_within_its_window_and_back_up_after() {
        let mut auto = AutoQuality::new(Quality::High);
        run(&mut auto, 90, machine(2.0));
        assert_eq!(auto.step(), Quality::High);
        // From now on every frame takes three times as long (another program on the cores).
        let loaded = run(&mut auto, 60 * 6, |q, _| 3.0 * machine(2.0)(q, 0));
        let down = loaded.iter().position(|s| *s != Quality::High).unwrap();
        assert!(down < WINDOW, "stepped down after {down} frames");
        assert_eq!(loaded.last(), Some(&Quality::Medium));
        let unloaded = run(&mut auto, 60 * 10, machine(2.0));
        assert_eq!(unloaded.last(), Some(&Quality::Ultra));
    }

    #[test]
    fn missed_refreshes_step_down_though_the_drawing_is_quick_and_a_few_do_not() {
        // Frames that take 2 ms to draw but come every 16.7 or 33.3 ms: the cores are busy elsewhere.
        let feed = |auto: &mut AutoQuality, frames: usize, late_every: usize| -> Vec<Quality> {
            (0..frames)
                .map(|i| {
                    let seconds = if late_every > 0 && i % late_every == 0 { 2.0 } else { 1.0 } / 60.0;
                    auto.frame(2.0, seconds, 1000.0 / 60.0);
                    auto.step()
                })
                .collect()
        };
        let mut auto = AutoQuality::new(Quality::Ultra);
        // One frame in ten late (54 a second): fewer than the limit in any 30; nothing moves.
        let steps = feed(&mut auto, 60 * 5, 10);
        assert!(steps.iter().all(|s| *s == Quality::Ultra), "{steps:?}");
        // One in three late (45 a second): down within a second or so, one step a second at most.
        let steps = feed(&mut auto, 60 * 3, 3);
        let down = steps.iter().position(|s| *s != Quality::Ultra).unwrap();
        assert!(down <= 60 + WINDOW, "stepped down after {down} frames");
        assert!(steps.windows(2).filter(|w| w[0] != w[1]).count() <= 3);
        // The load gone, back to the top; no step up while frames still came late.
        let unloaded = feed(&mut auto, 60 * 12, 0);
        assert_eq!(unloaded.last(), Some(&Quality::Ultra), "climbed back: {}", auto.changes());
    }

    #[test]
    fn an_overload_that_drives_it_to_the_bottom_does_not_keep_it_there_once_it_ends() {
        let mut auto = AutoQuality::new(Quality::Low);
        run(&mut auto, 60 * 10, machine(1.0));
        assert_eq!(auto.step(), Quality::Ultra);
        // Ten times slower for 5 s: down to the bottom, one step a second.
        let loaded = run(&mut auto, 60 * 5, |q, i| machine(1.0)(q, i) * if i < 30 { 1.0 + i as f64 } else { 30.0 });
        assert_eq!(loaded.last(), Some(&Quality::Low));
        let unloaded = run(&mut auto, 60 * 12, machine(1.0));
        assert_eq!(unloaded.last(), Some(&Quality::Ultra), "climbed back: {}", auto.changes());
    }

    #[test]
    fn a_load_that_begins_just_after_a_step_up_does_not_keep_that_step_away_for_good() {
        let mut auto = AutoQuality::new(Quality::High);
        let climbed = run(&mut auto, 60 * 5, machine(1.0));
        let at = climbed.iter().position(|s| *s == Quality::Ultra).unwrap();
        // The load comes with the first frame at the top step (the window test does just this).
        let mut auto = AutoQuality::new(Quality::High);
        run(&mut auto, at + 1, machine(1.0));
        assert_eq!(auto.step(), Quality::Ultra);
        run(&mut auto, 60 * 5, |q, i| machine(1.0)(q, i) * 15.0);
        assert!(auto.step() < Quality::Ultra);
        let unloaded = run(&mut auto, 60 * 12, machine(1.0));
        assert_eq!(unloaded.last(), Some(&Quality::Ultra));
        // A load that slows every step but the cheapest (whose frames stay short): the same.
        // Under it `medium` is tried (the bench's ratio says it fits) and fails, and waits its back-off.
        let loaded = run(&mut auto, 60 * 10, |q, i| if q == Quality::Low { 1.2 } else { machine(1.0)(q, i) * 15.0 });
        assert!(loaded.iter().filter(|s| **s == Quality::Low).count() > loaded.len() / 2);
        let unloaded = run(&mut auto, 60 * 30, machine(1.0));
        assert_eq!(unloaded.last(), Some(&Quality::Ultra));
    }

    #[test]
    fn a_step_up_that_does_not_fit_is_tried_ever_more_rarely() {
        // The machine's high costs far more than the bench's ratio says.
        let mut auto = AutoQuality::new(Quality::Medium);
        let costly = |q: Quality, _: usize| if q >= Quality::High { 14.0 } else { 2.0 };
        let steps = run(&mut auto, 60 * 120, costly);
        let ups: Vec<usize> = (1..steps.len()).filter(|&i| steps[i] > steps[i - 1]).collect();
        // Tries at about 2 s, then after waits of 5, 10, 20 and 40 s: five in two minutes, each gap longer.
        assert!((4..=6).contains(&ups.len()), "{ups:?}");
        assert!(ups.windows(3).all(|w| w[2] - w[1] > w[1] - w[0]), "{ups:?}");
        let high = steps.iter().filter(|s| **s == Quality::High).count();
        assert!(high * 20 < steps.len(), "{high} of {} frames at high", steps.len());
    }

    #[test]
    fn a_time_at_the_threshold_steps_down_once_and_never_oscillates() {
        let budget = SHARE * 1000.0 / 60.0;
        let mut auto = AutoQuality::new(Quality::High);
        // At high the frames sit at the budget, a little over or under in turn.
        let steps = run(&mut auto, 60 * 60, |q, i| {
            budget * BENCH_COST[q as usize] / BENCH_COST[2] * if i % 2 == 0 { 1.02 } else { 0.99 }
        });
        assert_eq!(auto.changes(), 1, "{:?}", steps.iter().filter(|s| **s != Quality::Medium).count());
        assert_eq!(steps.last(), Some(&Quality::Medium));
    }

    #[test]
    fn changes_are_at_least_the_hold_apart_and_bad_times_are_ignored() {
        let mut auto = AutoQuality::new(Quality::Ultra);
        let steps = run(&mut auto, 60 * 5, |_, _| 100.0);
        let changes: Vec<usize> = (1..steps.len()).filter(|&i| steps[i] != steps[i - 1]).collect();
        assert_eq!(steps.last(), Some(&Quality::Low));
        for pair in changes.windows(2) {
            assert!((pair[1] - pair[0]) as f64 / 60.0 >= HOLD_SECONDS - 1e-9, "{changes:?}");
        }
        for bad in [f64::NAN, f64::INFINITY, -1.0] {
            assert_eq!(auto.frame(bad, 1.0, 16.7), None);
            assert_eq!(auto.frame(1.0, 1.0, bad), None);
        }
        assert_eq!("auto".parse(), Ok(QualityChoice::Auto));
        assert_eq!("ultra".parse(), Ok(QualityChoice::Fixed(Quality::Ultra)));
        let err = "max".parse::<QualityChoice>().unwrap_err().to_string();
        assert_eq!(err, "unknown quality 'max' (expected auto, low, medium, high or ultra)");
    }
}
