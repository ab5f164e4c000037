//! Recording the race: `play --record FILE` and the main menu's "record the race to" switch.
//!
//! A race started from the main menu with the switch on (or at once with `--no-menu`) is recorded to a
//! temporary file beside the target ([`Recording`]), and the target is replaced only when the recording
//! ends with at least one tick raced: at a restart, on the way back to the main menu, when a write fails,
//! and when the window closes whatever closed it ([`Race::finish_recording`], called after the window's
//! loop returns). Quitting from the main menu before racing leaves the target as it was. A race left
//! half-way is kept: its trace replays up to where it stopped.

use std::path::Path;

use super::{Race, Screen, header_for};
use crate::input::recording::{Kept, RecordError, Recording};

impl Race {
    /// Records races to `path`: at once when the race starts without the menu, else each race started from
    /// the main menu while its switch (now on, with this file) stays on. A path that cannot be recorded to
    /// (a folder, a missing folder) is refused now, before the window opens; `path` itself is not touched.
    pub fn record_to(mut self, path: &Path) -> Result<Self, RecordError> {
        let recording = Recording::start(path, &header_for(&self.world))?;
        self.record_to = (true, path.display().to_string());
        if self.screen == Screen::Race {
            self.recorder = Some(recording);
        } else {
            // Only a check: the race's header (its laps) is known when it starts.
            drop(recording);
        }
        Ok(self)
    }

    /// Starts recording a race about to start from the grid, when the main menu's switch asks for it.
    pub(super) fn start_recording(&mut self) {
        if !self.record_to.0 || self.recorder.is_some() || self.source.is_some() || self.world.tick != 0 {
            return;
        }
        let path = std::path::PathBuf::from(self.record_to.1.trim());
        match Recording::start(&path, &header_for(&self.world)) {
            Ok(r) => {
                self.notice = Some(format!("recording to {}", path.display()));
                self.recorder = Some(r);
            }
            Err(e) => self.notice = Some(format!("not recording: {e}")),
        }
    }

    /// Ends the recording in the race (`why` says what ended it), keeping what was raced; the HUD says
    /// what became of it.
    pub(super) fn end_recording(&mut self, why: &str) {
        let Some(mut rec) = self.recorder.take() else { return };
        self.notice = Some(match rec.finish() {
            Ok(kept) => {
                self.kept_a_race |= matches!(kept, Kept::Race { .. });
                format!("{why}: {kept}")
            }
            Err(e) => format!("{why}: {e}"),
        });
    }

    /// Ends the recording when the window has closed (by any path: Quit, Esc in the main menu, the window's
    /// close button, `--exit-after-frames`, an error): what was raced replaces the target. `None` when
    /// there was nothing to record to or a race was already kept; [`Kept::Nothing`] when the switch was on
    /// and no race was recorded in this run.
    pub fn finish_recording(&mut self) -> Result<Option<Kept>, RecordError> {
        match self.recorder.take() {
            Some(mut rec) => rec.finish().map(Some),
            None if self.record_to.0 && !self.kept_a_race => {
                Ok(Some(Kept::Nothing { path: std::path::PathBuf::from(self.record_to.1.trim()) }))
            }
            None => Ok(None),
        }
    }
}
