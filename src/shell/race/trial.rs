//! The player's records and the time trial's ghost: at the player's finish the best lap and the race time
//! go into the records file (`shell::records`), and in a time trial every tick is recorded beside the
//! ghost's trace of that course and car, which the recording replaces only when the session's best lap
//! beats the record; the next time trial races against it.

use crate::game::{Controls, Mode, RaceSetup, World};
use crate::input::ghost::GhostSearch;
use crate::input::recording::Recording;
use crate::shell::records::{LapRecord, RecordKey, RecordsFile};

/// The records and the time trial being recorded.
#[derive(Default)]
pub(super) struct Trials {
    /// The records file (none: records are not kept, as in tests and replays).
    pub(super) file: Option<RecordsFile>,
    /// The time trial being recorded for the ghost.
    recording: Option<Recording>,
    /// Whether the player's finish has been taken into the records.
    noted: bool,
}

impl Trials {
    /// A fresh start of the race `setup` on `course`: a time trial raced (not replayed) is recorded for its
    /// ghost, and the ghost of the record is returned to race against; `notice` says what failed.
    pub(super) fn restart(
        &mut self,
        world: &World,
        (course, setup): (&str, &RaceSetup),
        replaying: bool,
        notice: &mut Option<String>,
    ) -> Option<GhostSearch> {
        self.end();
        self.noted = false;
        let file = self.file.as_ref()?;
        if setup.mode != Mode::TimeTrial || replaying {
            return None;
        }
        let key = RecordKey::new(course, setup.car, setup.mode, setup.difficulty);
        let path = file.ghost_path(&key);
        let search = if path.is_file() {
            GhostSearch::start(&path, world.track.clone()).map_err(|e| *notice = Some(format!("ghost: {e}"))).ok()
        } else {
            None
        };
        let header = super::record::header_for(world, course);
        let started = crate::userfile::folder_of(&path);
        match std::fs::create_dir_all(started)
            .map_err(|e| e.to_string())
            .and_then(|()| Recording::start(&path, &header).map_err(|e| e.to_string()))
        {
            Ok(r) => self.recording = Some(r),
            Err(e) => *notice = Some(format!("the time trial's ghost is not saved: {e}")),
        }
        search
    }

    /// Records the controls `c` the world just stepped with (and its checksum on the trace's interval); a
    /// failed write ends the recording, said in `notice`.
    pub(super) fn tick(&mut self, world: &World, c: Controls, notice: &mut Option<String>) {
        let Some(w) = self.recording.as_mut().and_then(Recording::writer) else { return };
        let every = u64::from(super::record::CHECKSUM_EVERY);
        let written = w.controls(c).and_then(|()| {
            if world.tick.is_multiple_of(every) { w.checksum(world.tick, world.checksum()) } else { Ok(()) }
        });
        if let Err(e) = written {
            *notice = Some(format!("the time trial's ghost is not saved: {e}"));
            self.end();
        }
    }

    /// At the player's finish in `world` (once a race): the best lap and race time go into the records
    /// (`counts` false for a replay or the autopilot: nothing is taken) and the time trial's ghost is kept
    /// when its best lap is a record; `notice` says so, or why the records were not saved.
    pub(super) fn observe(
        &mut self,
        world: &World,
        (course, setup): (&str, &RaceSetup),
        counts: bool,
        notice: &mut Option<String>,
    ) {
        let Some(me) = world.race.standings.first() else { return };
        let (Some(done), false) = (me.finished, self.noted) else { return };
        self.noted = true;
        let Some(file) = self.file.as_mut().filter(|_| counts) else {
            self.end();
            return;
        };
        let key = RecordKey::new(course, setup.car, setup.mode, setup.difficulty);
        let lap_record = me.best_lap.is_some_and(|lap| file.records.lap(&key, lap));
        let race_record = file.records.race(&key, world.race.laps, done.saturating_sub(world.race.start_tick));
        if lap_record || race_record {
            match file.save() {
                Err(e) => *notice = Some(e.to_string()),
                Ok(()) => *notice = Some(format!("a new record{}", if lap_record { ": your best lap" } else { "" })),
            }
        }
        // The ghost is replaced only by a record the file keeps (one it could not read knows no records).
        match (self.recording.as_mut(), lap_record && file.writable()) {
            (Some(r), true) => {
                if let Err(e) = r.finish() {
                    *notice = Some(format!("the time trial's ghost is not saved: {e}"));
                }
                self.recording = None;
            }
            _ => self.end(),
        }
    }

    /// The five best laps on `course`.
    pub(super) fn top(&self, course: &str) -> Vec<LapRecord> {
        self.file.as_ref().map(|f| f.records.top_laps(course, 5).into_iter().cloned().collect()).unwrap_or_default()
    }

    /// Ends the time trial's recording without keeping it.
    pub(super) fn end(&mut self) {
        if let Some(mut r) = self.recording.take() {
            r.discard();
        }
    }
}

impl Drop for Trials {
    /// A time trial left unfinished is not a ghost: its recording is removed.
    fn drop(&mut self) {
        self.end();
    }
}
