//! Race rules: the countdown, laps counted through checkpoints, lap and sector times, positions, the finish.
//!
//! All in ticks, updated inside `step`, so a replay reproduces every time to the tick. Laps are counted
//! from each car's continuous progress along the centre line (tracked through the car's own location, so
//! it cannot jump between the two levels of the crossing); a lap counts only after the car has passed the
//! two intermediate checkpoints of that lap in order, so cutting back across the line or reversing over it
//! never scores.

use super::timestep::TICK_HZ;

/// Sectors per lap (checkpoints at each third of the lap; the line closes the last).
pub const SECTORS: usize = 3;
/// Length of the countdown before the start (ticks): three seconds.
pub const COUNTDOWN_TICKS: u64 = 3 * TICK_HZ as u64;

/// Where the race is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Cars wait on the grid; the value is the ticks left.
    Countdown(u64),
    /// Green flag.
    Racing,
    /// The player has finished (the others finish their last lap).
    Finished,
}

/// One car's race.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Standing {
    /// Distance covered since the start (metres; negative on the grid behind the line).
    pub progress: f32,
    /// Last lap distance seen, to measure progress from tick to tick.
    pub last_s: f32,
    /// Completed laps.
    pub laps: u32,
    /// Checkpoints passed in the current lap (0..SECTORS-1).
    pub checkpoint: usize,
    /// Tick the current lap started (the start tick for the first).
    pub lap_start: u64,
    /// Tick the current sector started.
    pub sector_start: u64,
    /// Sector times of the lap in progress (ticks).
    pub sectors: [Option<u64>; SECTORS],
    /// Last completed lap time (ticks).
    pub last_lap: Option<u64>,
    /// Best lap time (ticks).
    pub best_lap: Option<u64>,
    /// Tick the car took the chequered flag.
    pub finished: Option<u64>,
}

/// A race's progress under the rules: phase, laps, checkpoints, times and positions. (Named apart from the
/// shell's `Race`, the race session in the window.)
#[derive(Clone, Debug, PartialEq)]
pub struct RaceProgress {
    /// Laps to run.
    pub laps: u32,
    /// Phase.
    pub phase: Phase,
    /// Tick of the green flag.
    pub start_tick: u64,
    /// Per car, in car order.
    pub standings: Vec<Standing>,
    /// Car indices in the order they finished.
    pub finish_order: Vec<usize>,
}

impl RaceProgress {
    /// A race of `laps` laps for cars starting at lap distances `start_s` (the grid, behind the line).
    #[must_use]
    pub fn new(laps: u32, start_s: &[f32], length: f32) -> Self {
        let standings = start_s
            .iter()
            .map(|&s| {
                // Behind the line counts as negative progress, so the first crossing starts lap 1.
                let behind = if s > 0.5 * length { s - length } else { s };
                Standing { progress: behind, last_s: s, ..Standing::default() }
            })
            .collect();
        Self {
            laps: laps.max(1),
            phase: Phase::Countdown(COUNTDOWN_TICKS),
            start_tick: COUNTDOWN_TICKS,
            standings,
            finish_order: vec![],
        }
    }

    /// True while cars must stay on the grid.
    #[must_use]
    pub fn holding(&self) -> bool {
        matches!(self.phase, Phase::Countdown(_))
    }

    /// Advances the rules by one tick (`tick` is the tick just simulated) given each car's lap distance.
    pub fn update(&mut self, tick: u64, lap_s: &[f32], length: f32) {
        if let Phase::Countdown(left) = self.phase {
            self.phase = if left <= 1 { Phase::Racing } else { Phase::Countdown(left - 1) };
            if self.phase == Phase::Racing {
                for st in &mut self.standings {
                    st.lap_start = tick;
                    st.sector_start = tick;
                }
            }
            return;
        }
        let sector_len = length / SECTORS as f32;
        for (i, (st, &s)) in self.standings.iter_mut().zip(lap_s).enumerate() {
            let mut d = (s - st.last_s).rem_euclid(length);
            if d > 0.5 * length {
                d -= length;
            }
            st.last_s = s;
            st.progress += d;
            if st.finished.is_some() {
                continue;
            }
            let into_lap = st.progress - st.laps as f32 * length;
            // Intermediate checkpoints, in order.
            if st.checkpoint + 1 < SECTORS && into_lap >= sector_len * (st.checkpoint + 1) as f32 {
                st.sectors[st.checkpoint] = Some(tick - st.sector_start);
                st.sector_start = tick;
                st.checkpoint += 1;
            }
            // The line: only after every intermediate checkpoint of this lap.
            if st.checkpoint + 1 == SECTORS && into_lap >= length {
                st.sectors[SECTORS - 1] = Some(tick - st.sector_start);
                let lap = tick - st.lap_start;
                st.last_lap = Some(lap);
                st.best_lap = Some(st.best_lap.map_or(lap, |b| b.min(lap)));
                st.laps += 1;
                st.checkpoint = 0;
                st.lap_start = tick;
                st.sector_start = tick;
                st.sectors = [None; SECTORS];
                if st.laps >= self.laps {
                    st.finished = Some(tick);
                    self.finish_order.push(i);
                }
            }
        }
        if self.standings.first().is_some_and(|p| p.finished.is_some()) {
            self.phase = Phase::Finished;
        }
    }

    /// Car indices from first to last: finishers in finishing order, then by progress; ties go to the lower
    /// car index so the order is always the same.
    #[must_use]
    pub fn order(&self) -> Vec<usize> {
        let rank = |j: usize| self.finish_order.iter().position(|&k| k == j).unwrap_or(usize::MAX);
        let mut cars: Vec<usize> = (0..self.standings.len()).collect();
        cars.sort_by(|&a, &b| {
            rank(a)
                .cmp(&rank(b))
                .then(self.standings[b].progress.total_cmp(&self.standings[a].progress))
                .then(a.cmp(&b))
        });
        cars
    }

    /// Race position (1-based) of car `i`.
    #[must_use]
    pub fn position(&self, i: usize) -> usize {
        self.order().iter().position(|&c| c == i).map_or(self.standings.len(), |p| p + 1)
    }
}

/// Ticks as `m:ss.mmm`.
#[must_use]
pub fn format_ticks(t: u64) -> String {
    let ms = t * 1000 / u64::from(TICK_HZ);
    format!("{}:{:02}.{:03}", ms / 60_000, (ms / 1000) % 60, ms % 1000)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn countdown_then_laps_through_checkpoints() {
        let len = 300.0;
        let mut r = RaceProgress::new(2, &[290.0], len);
        let mut tick = 0;
        let mut s = 290.0f32;
        while r.holding() {
            tick += 1;
            r.update(tick, &[s], len);
        }
        assert_eq!(tick, COUNTDOWN_TICKS);
        // 1 m per tick forwards: 10 m to the line, then two laps of 300 m.
        for _ in 0..700 {
            tick += 1;
            s = (s + 1.0).rem_euclid(len);
            r.update(tick, &[s], len);
        }
        let st = r.standings[0];
        assert_eq!(st.laps, 2);
        assert_eq!(st.best_lap, Some(300));
        assert_eq!(r.phase, Phase::Finished);
        assert_eq!(r.finish_order, [0]);
        assert_eq!(format_ticks(st.best_lap.unwrap_or(0)), "0:02.500");
    }

    #[test]
    fn reversing_over_the_line_does_not_score() {
        let len = 300.0;
        let mut r = RaceProgress::new(3, &[5.0], len);
        r.phase = Phase::Racing;
        let mut s = 5.0f32;
        // Back 20 m over the line, then forwards 40 m over it again: no lap.
        for k in 0..60u64 {
            s = (s + if k < 20 { -1.0 } else { 1.0 }).rem_euclid(len);
            r.update(k, &[s], len);
        }
        assert_eq!(r.standings[0].laps, 0);
    }

    #[test]
    fn positions_are_a_permutation() {
        let mut r = RaceProgress::new(3, &[10.0, 20.0, 30.0, 40.0], 1000.0);
        r.standings[2].progress = 55.0;
        let mut p: Vec<usize> = (0..4).map(|i| r.position(i)).collect();
        assert_eq!(p, [4, 3, 1, 2]);
        p.sort_unstable();
        assert_eq!(p, [1, 2, 3, 4]);
    }
}
