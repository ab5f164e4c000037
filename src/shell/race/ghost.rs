//! The ghost car in the race: the lap it drives, from `--ghost FILE` (searched on a background thread while
//! the race runs) or from the player's own fastest lap, and where it is drawn each tick. It reads the world
//! being raced and says what changed in the race's notice; both are passed in.

use crate::game::World;
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

impl Ghost {
    /// Races against the fastest lap `search` finds in a trace: each faster lap it reports takes over
    /// before the green light or when the player crosses the line.
    pub(super) fn search(&mut self, search: GhostSearch) {
        self.search = Some(search);
    }

    /// Takes what the ghost search reported since the last frame, racing in `world`; `notice` says when
    /// the trace held no lap or the search failed, and which lap took over.
    pub(super) fn search_reports(&mut self, world: &World, notice: &mut Option<String>) {
        let Some(search) = self.search.as_mut() else { return };
        for found in search.poll() {
            match found {
                GhostFound::Faster(lap) => {
                    let best = self.pending.as_ref().or(self.lap.as_ref());
                    if best.is_none_or(|g| lap.ticks() < g.ticks()) {
                        self.pending = Some(lap);
                    }
                }
                GhostFound::End { laps } => {
                    if !laps {
                        *notice = Some("ghost: the trace holds no complete lap to race against".into());
                    }
                    self.search = None;
                    break;
                }
                GhostFound::Failed(e) => {
                    *notice = Some(format!("ghost: {e} (the laps before it are raced against)"));
                    self.search = None;
                    break;
                }
            }
        }
        if world.race.phase != Phase::Racing {
            self.take_pending(world, notice);
        }
    }

    /// Lets a lap the search found take over the ghost, when that does not make it jump: before the green
    /// light, or on the tick the player crosses the line in `world`; `notice` says so once racing.
    pub(super) fn take_pending(&mut self, world: &World, notice: &mut Option<String>) {
        let race = &world.race;
        let mid_lap = race.phase == Phase::Racing && world.tick != race.standings[0].lap_start;
        if mid_lap {
            return;
        }
        if let Some(lap) = self.pending.take()
            && self.lap.as_ref().is_none_or(|g| lap.ticks() < g.ticks())
        {
            if world.tick > 0 {
                *notice = Some(format!("ghost: the trace's best lap {}", format_ticks(lap.ticks())));
            }
            self.lap = Some(lap);
        }
    }

    /// Watches the player's laps in `world` after each tick: a lap faster than the ghost's becomes the
    /// ghost's, and `notice` says so.
    pub(super) fn observe(&mut self, world: &World, notice: &mut Option<String>) {
        if self.laps.observe(world)
            && let Some(best) = &self.laps.best
            && self.lap.as_ref().is_none_or(|g| best.ticks() < g.ticks())
        {
            *notice = Some(format!("best lap {}: the ghost drives it now", format_ticks(best.ticks())));
            self.lap = Some(best.clone());
        }
    }

    /// Where the ghost car is this tick of `world`, when `shown` (the setting): on its lap as far in as the
    /// player is into theirs.
    pub(super) fn pose(&self, world: &World, shown: bool) -> Option<Pose> {
        let race = &world.race;
        let me = &race.standings[0];
        if !shown || race.phase != Phase::Racing || me.finished.is_some() {
            return None;
        }
        self.lap.as_ref()?.pose(world.tick.saturating_sub(me.lap_start))
    }
}
