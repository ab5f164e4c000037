//! The ghost car in the race: the lap it drives, from `--ghost FILE` (searched on a background thread while
//! the race runs) or from the player's own fastest lap, and where it is drawn each tick.

use super::Race;
use crate::game::rules::{Phase, format_ticks};
use crate::input::ghost::{GhostFound, GhostLap, GhostSearch, LapRecorder, Pose};

/// The ghost car's state. Whether it is drawn is a setting (`prefs`).
#[derive(Default)]
pub(super) struct Ghost {
    /// The player's laps so far, the fastest kept for the ghost.
    pub(super) laps: LapRecorder,
    /// The lap the ghost car drives (from `--ghost FILE`, or the fastest lap of this session).
    pub(super) lap: Option<GhostLap>,
    /// The search for the fastest lap of `--ghost FILE`, while it runs.
    search: Option<GhostSearch>,
    /// A faster lap from the search, waiting for the player to cross the line (the ghost never jumps mid-lap).
    pending: Option<GhostLap>,
}

impl Race {
    /// Races against `lap` as a see-through ghost car from the start (a faster lap driven now replaces it).
    #[must_use]
    pub fn with_ghost(mut self, lap: GhostLap) -> Self {
        self.ghost.lap = Some(lap);
        self
    }

    /// Races against the fastest lap `search` finds in a trace: each faster lap it reports takes over
    /// before the green light or when the player crosses the line; the HUD says when the trace held none.
    #[must_use]
    pub fn with_ghost_search(mut self, search: GhostSearch) -> Self {
        self.ghost.search = Some(search);
        self
    }

    /// Takes what the ghost search reported since the last frame.
    pub(super) fn ghost_search_reports(&mut self) {
        let Some(search) = self.ghost.search.as_mut() else { return };
        for found in search.poll() {
            match found {
                GhostFound::Faster(lap) => {
                    let best = self.ghost.pending.as_ref().or(self.ghost.lap.as_ref());
                    if best.is_none_or(|g| lap.ticks() < g.ticks()) {
                        self.ghost.pending = Some(lap);
                    }
                }
                GhostFound::End { laps } => {
                    if !laps {
                        self.notice = Some("ghost: the trace holds no complete lap to race against".into());
                    }
                    self.ghost.search = None;
                    break;
                }
                GhostFound::Failed(e) => {
                    self.notice = Some(format!("ghost: {e} (the laps before it are raced against)"));
                    self.ghost.search = None;
                    break;
                }
            }
        }
        if self.world.race.phase != Phase::Racing {
            self.take_pending_ghost();
        }
    }

    /// Lets a lap the search found take over the ghost, when that does not make it jump: before the green
    /// light, or on the tick the player crosses the line.
    pub(super) fn take_pending_ghost(&mut self) {
        let race = &self.world.race;
        let mid_lap = race.phase == Phase::Racing && self.world.tick != race.standings[0].lap_start;
        if mid_lap {
            return;
        }
        if let Some(lap) = self.ghost.pending.take()
            && self.ghost.lap.as_ref().is_none_or(|g| lap.ticks() < g.ticks())
        {
            if self.world.tick > 0 {
                self.notice = Some(format!("ghost: the trace's best lap {}", format_ticks(lap.ticks())));
            }
            self.ghost.lap = Some(lap);
        }
    }

    /// Where the ghost car is this tick: on its lap as far in as the player is into theirs.
    pub(super) fn ghost_pose(&self) -> Option<Pose> {
        let race = &self.world.race;
        let me = &race.standings[0];
        if !self.prefs.show_ghost || race.phase != Phase::Racing || me.finished.is_some() {
            return None;
        }
        self.ghost.lap.as_ref()?.pose(self.world.tick.saturating_sub(me.lap_start))
    }
}
