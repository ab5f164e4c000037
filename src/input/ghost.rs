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
//! as they are found, the first after about one lap of replay (a fraction of a second). Only the fastest
//! lap not yet taken waits for the race (a one-lap slot, not a queue), and the thread stops within one tick
//! of replay when the search is dropped.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};

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

/// Replays the trace at `path` on `track` and returns the player's fastest complete lap in it (`None` when
/// the trace holds no complete lap).
pub fn best_lap_of_trace(path: &Path, track: Arc<Track>) -> Result<Option<GhostLap>, ReplayError> {
    let mut replay = Replay::open(path, track)?;
    let mut laps = LapRecorder::default();
    while replay.advance()? {
        laps.observe(&replay.world);
    }
    Ok(laps.best)
}

/// What a [`GhostSearch`] reports.
#[derive(Debug)]
pub enum GhostFound {
    /// The fastest lap found in the trace so far (faster than any reported before).
    Faster(GhostLap),
    /// The trace is replayed to its end; `laps` says whether it held a complete lap.
    End {
        /// Whether any lap was found.
        laps: bool,
    },
    /// The replay stopped at an error (the laps found before it stand).
    Failed(ReplayError),
}

/// What the search thread leaves for the race: one lap at most, so memory stays bounded however many
/// faster laps the trace holds and however rarely the race looks.
#[derive(Debug, Default)]
struct Slot {
    /// The fastest lap found and not yet taken (a faster one replaces it).
    faster: Option<GhostLap>,
    /// How the search ended ([`GhostFound::End`] or [`GhostFound::Failed`]), until taken.
    end: Option<GhostFound>,
    /// Whether the thread has returned (for any reason, a panic included).
    done: bool,
}

/// The state the search thread and its [`GhostSearch`] share.
#[derive(Debug, Default)]
struct Shared {
    slot: Mutex<Slot>,
    /// Signalled whenever the slot changes.
    changed: Condvar,
    /// Set when the search is dropped: the thread returns before its next tick.
    stop: AtomicBool,
}

impl Shared {
    /// The slot, even after a panic while it was held (its contents are whole at every step).
    fn slot(&self) -> MutexGuard<'_, Slot> {
        self.slot.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Changes the slot with `f` and wakes a waiting [`GhostSearch::wait`].
    fn update(&self, f: impl FnOnce(&mut Slot)) {
        f(&mut self.slot());
        self.changed.notify_all();
    }
}

/// Marks the search done when the thread returns, however it returns.
struct Done(Arc<Shared>);

impl Drop for Done {
    fn drop(&mut self) {
        self.0.update(|s| s.done = true);
    }
}

/// The fastest lap of a trace, searched for on a background thread (see the module documentation); the
/// thread stops when the search is dropped.
///
/// Only the fastest lap found and not yet taken is kept for the race (one slot, replaced by each faster
/// lap), and the thread looks at its stop flag before every tick it replays; a tick reads at most one
/// checksum record (the trace reader refuses a checksum not after the previous one), so stopping takes one
/// tick of replay whatever the trace holds.
pub struct GhostSearch {
    shared: Arc<Shared>,
    thread: Option<std::thread::JoinHandle<()>>,
}

impl GhostSearch {
    /// Opens the trace at `path` on `track`, refusing at once a file that is not a trace of that track, and
    /// replays it on a background thread.
    pub fn start(path: &Path, track: Arc<Track>) -> Result<Self, ReplayError> {
        let mut replay = Replay::open(path, track)?;
        let shared = Arc::new(Shared::default());
        let done = Done(Arc::clone(&shared));
        let thread = std::thread::spawn(move || {
            let shared = &done.0;
            let mut laps = LapRecorder::default();
            let end = loop {
                if shared.stop.load(Ordering::Relaxed) {
                    return;
                }
                match replay.advance() {
                    Ok(true) => {
                        if laps.observe(&replay.world)
                            && let Some(best) = &laps.best
                        {
                            let lap = best.clone();
                            shared.update(|s| s.faster = Some(lap));
                        }
                    }
                    Ok(false) => break GhostFound::End { laps: laps.best.is_some() },
                    Err(e) => break GhostFound::Failed(e),
                }
            };
            shared.update(|s| s.end = Some(end));
        });
        Ok(Self { shared, thread: Some(thread) })
    }

    /// What the search reported since the last call, without waiting: the fastest lap found since (if
    /// any), then how the search ended (once it has).
    pub fn poll(&mut self) -> Vec<GhostFound> {
        let mut slot = self.shared.slot();
        slot.faster.take().map(GhostFound::Faster).into_iter().chain(slot.end.take()).collect()
    }

    /// Waits for the next report (`None` once the search has ended and everything was taken).
    pub fn wait(&mut self) -> Option<GhostFound> {
        let mut slot = self.shared.slot();
        loop {
            if let Some(lap) = slot.faster.take() {
                return Some(GhostFound::Faster(lap));
            }
            if let Some(end) = slot.end.take() {
                return Some(end);
            }
            if slot.done {
                return None;
            }
            slot = self.shared.changed.wait(slot).unwrap_or_else(PoisonError::into_inner);
        }
    }

    /// Whether the search thread has finished (its last reports may still wait to be taken).
    #[must_use]
    pub fn done(&self) -> bool {
        self.shared.slot().done
    }
}

impl Drop for GhostSearch {
    /// Stops the thread and waits for it (one tick of replay).
    fn drop(&mut self) {
        self.shared.stop.store(true, Ordering::Relaxed);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}
