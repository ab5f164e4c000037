//! The ghost car: the player's fastest lap, replayed as a see-through car beside the live race.
//!
//! A ghost is the player car's pose at every tick of one lap, from crossing the line to crossing it again.
//! It comes from the laps driven so far in this race ([`LapRecorder`]) or from a trace file, replayed on a
//! background thread while the race runs ([`GhostSearch`]; [`best_lap_of_trace`] is the same search done at
//! once). It never touches the simulation: it is drawn, not raced, so it cannot collide and cannot change a
//! recording.
//!
//! Why a background thread: finding the fastest lap means replaying the whole trace, and a long trace (a
//! 50 MB one is about 22 hours of racing) took over 30 s with nothing on the screen. The header is checked
//! at once (a file that is not a trace of this track is refused before the window opens); the laps arrive
//! as they are found, the first after about one lap of replay (a fraction of a second).

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};

use glam::Vec3;

use super::replay::{Replay, ReplayError};
use crate::game::{Track, World};

/// Where the player's car was at one tick, as drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// Position (the car's reference point, on the road surface).
    pub position: Vec3,
    /// Heading (radians, as [`crate::game::car::Car::yaw`]).
    pub yaw: f32,
}

/// One lap of poses, a tick apart, the first at the tick the lap started.
#[derive(Clone, Debug, PartialEq)]
pub struct GhostLap {
    /// The poses.
    pub poses: Vec<Pose>,
}

impl GhostLap {
    /// The lap time in ticks.
    #[must_use]
    pub fn ticks(&self) -> u64 {
        self.poses.len() as u64
    }

    /// The pose `ticks_into_lap` ticks after the line, or `None` once the ghost has finished its lap.
    #[must_use]
    pub fn pose(&self, ticks_into_lap: u64) -> Option<Pose> {
        usize::try_from(ticks_into_lap).ok().and_then(|i| self.poses.get(i)).copied()
    }
}

/// Watches the player's laps tick by tick and keeps the fastest complete one.
#[derive(Clone, Debug, Default)]
pub struct LapRecorder {
    current: Vec<Pose>,
    lap_start: Option<u64>,
    laps: u32,
    /// The fastest complete lap so far.
    pub best: Option<GhostLap>,
}

/// Longest lap kept (ticks): ten minutes; a car parked longer starts its lap over, bounding memory.
const MAX_LAP_TICKS: usize = 10 * 60 * crate::game::TICK_HZ as usize;

impl LapRecorder {
    /// Forgets the lap in progress (a restarted race), keeping the best lap.
    pub fn restart(&mut self) {
        self.current.clear();
        self.lap_start = None;
        self.laps = 0;
    }

    /// Records the player's pose after a tick of `world`; returns true when that tick completed a lap that
    /// is the fastest so far.
    pub fn observe(&mut self, world: &World) -> bool {
        let st = &world.race.standings[0];
        let car = &world.cars[0];
        if world.race.holding() {
            return false;
        }
        let mut improved = false;
        if self.lap_start != Some(st.lap_start) {
            // A new lap began at `st.lap_start` (the green light, or the line just crossed).
            if st.laps > self.laps && self.lap_start.is_some() && !self.current.is_empty() {
                let lap = std::mem::take(&mut self.current);
                if self.best.as_ref().is_none_or(|b| lap.len() < b.poses.len()) {
                    self.best = Some(GhostLap { poses: lap });
                    improved = true;
                }
            }
            self.current.clear();
            self.lap_start = Some(st.lap_start);
            self.laps = st.laps;
        }
        if self.current.len() < MAX_LAP_TICKS {
            self.current.push(Pose { position: car.position3(), yaw: car.yaw });
        }
        improved
    }
}

/// Replays the trace at `path` on `track` with `cars` cars and returns the player's fastest complete lap in
/// it (`None` when the trace holds no complete lap).
pub fn best_lap_of_trace(path: &Path, track: Arc<Track>, cars: usize) -> Result<Option<GhostLap>, ReplayError> {
    let mut replay = Replay::open(path, track, cars)?;
    let mut laps = LapRecorder::default();
    while replay.advance()? {
        laps.observe(&replay.world);
    }
    Ok(laps.best)
}

/// What a [`GhostSearch`] reports.
#[derive(Debug)]
pub enum GhostFound {
    /// A lap faster than any found before in the trace.
    Faster(GhostLap),
    /// The trace is replayed to its end; `laps` says whether it held a complete lap.
    End {
        /// Whether any lap was found.
        laps: bool,
    },
    /// The replay stopped at an error (the laps found before it stand).
    Failed(ReplayError),
}

/// The fastest lap of a trace, searched for on a background thread (see the module documentation); the
/// thread stops when the search is dropped.
pub struct GhostSearch {
    found: Receiver<GhostFound>,
    stop: Arc<AtomicBool>,
    thread: Option<std::thread::JoinHandle<()>>,
}

/// Ticks replayed between looks at the stop flag (a few milliseconds).
const STOP_CHECK_TICKS: u64 = 256;

impl GhostSearch {
    /// Opens the trace at `path` for a race of `cars` cars on `track`, refusing at once a file that is not a
    /// trace of that track and field, and replays it on a background thread.
    pub fn start(path: &Path, track: Arc<Track>, cars: usize) -> Result<Self, ReplayError> {
        let mut replay = Replay::open(path, track, cars)?;
        let (tx, found) = channel();
        let stop = Arc::new(AtomicBool::new(false));
        let stopped = Arc::clone(&stop);
        let thread = std::thread::spawn(move || {
            let mut laps = LapRecorder::default();
            loop {
                if replay.world.tick.is_multiple_of(STOP_CHECK_TICKS) && stopped.load(Ordering::Relaxed) {
                    return;
                }
                let report = match replay.advance() {
                    Ok(true) if laps.observe(&replay.world) => laps.best.clone().map(GhostFound::Faster),
                    Ok(true) => None,
                    Ok(false) => {
                        let _ = tx.send(GhostFound::End { laps: laps.best.is_some() });
                        return;
                    }
                    Err(e) => {
                        let _ = tx.send(GhostFound::Failed(e));
                        return;
                    }
                };
                if let Some(r) = report
                    && tx.send(r).is_err()
                {
                    return;
                }
            }
        });
        Ok(Self { found, stop, thread: Some(thread) })
    }

    /// What the search reported since the last call, without waiting.
    pub fn poll(&mut self) -> Vec<GhostFound> {
        let mut out = vec![];
        loop {
            match self.found.try_recv() {
                Ok(f) => out.push(f),
                Err(TryRecvError::Empty | TryRecvError::Disconnected) => return out,
            }
        }
    }

    /// Waits for the next report (`None` once the search has ended and everything was taken).
    pub fn wait(&mut self) -> Option<GhostFound> {
        self.found.recv().ok()
    }
}

impl Drop for GhostSearch {
    /// Stops the thread and waits for it (at most [`STOP_CHECK_TICKS`] ticks of replay).
    fn drop(&mut self) {
        self.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
