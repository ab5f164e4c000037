//! Recording the race: `play --record FILE` and the main menu's "record the race to" switch.
//!
//! A race started from the main menu with the switch on (or at once with `--no-menu`) is recorded to a
//! temporary file beside the target ([`Recording`]), and the target is replaced only when the recording
//! ends with at least one tick raced: at a restart, on the way back to the main menu, when a write fails,
//! and when the window closes whatever closed it ([`Recorder::finish`], called through
//! `Race::finish_recording` after the window's loop returns). Quitting from the main menu before racing
//! leaves the target as it was. A race left half-way is kept: its trace replays up to where it stopped.
//! Each race is a recording of its own, and the last one raced wins: a race of one tick started from the
//! menu replaces a full race recorded earlier in the session (the README says so; keeping the longest would
//! make the file depend on races no longer shown anywhere).
//!
//! Every trace of a race starts with the header [`header_for`] makes and holds a checksum every
//! [`CHECKSUM_EVERY`] ticks; the asset generator writes the demo traces with the same two.

use std::path::{Path, PathBuf};

use crate::game::{TICK_HZ, World};
use crate::input::recording::{Kept, RecordError, Recording};
use crate::input::replay::lap_mm;
use crate::input::trace::{Header, SIM_VERSION};

/// Ticks between checksums in recorded traces: one second.
///
/// A replay checks its world against each, so a trace that drifts is caught within a second of play.
pub const CHECKSUM_EVERY: u32 = TICK_HZ;

/// The trace header for a race of `world` on the course named `course`.
///
/// One function for the recorder and the asset generator, so that a demo trace is read like a race
/// recorded in the game.
#[must_use]
pub fn header_for(world: &World, course: &str) -> Header {
    let setup = &world.setup;
    Header {
        course: course.to_string(),
        car: setup.car as u32 + 1,
        mode: setup.mode.name().to_string(),
        difficulty: setup.difficulty.name().to_string(),
        sim_version: match setup.handling {
            crate::game::Handling::Garage => SIM_VERSION,
            crate::game::Handling::Same => crate::input::trace::SAME_CARS_SIM_VERSION,
        },
        game_version: env!("CARGO_PKG_VERSION").to_string(),
        track_length_mm: lap_mm(world),
        cars: world.cars.len() as u32,
        laps: world.race.laps,
        seed: 0,
        tick_hz: TICK_HZ,
        checksum_every: CHECKSUM_EVERY,
    }
}

/// The main menu's "record the race to" switch and the file it records to.
#[derive(Clone, Debug)]
pub(super) struct RecordTo {
    /// Whether a race started from the main menu is recorded.
    pub(super) on: bool,
    /// The file name in the menu's text field.
    pub(super) text: String,
    /// The path given with `--record` and the text the field showed for it: while the field still shows
    /// that text, the race is recorded to this path exactly (a name with spaces around it, or one that is
    /// not UTF-8, would be another file once turned into text and trimmed).
    given: Option<(PathBuf, String)>,
}

impl Default for RecordTo {
    fn default() -> Self {
        Self { on: false, text: "race.trace".into(), given: None }
    }
}

impl RecordTo {
    /// The file to record to: the path given on the command line, unless a name was typed in the menu
    /// since (trimmed: spaces typed around a name are a slip).
    pub(super) fn path(&self) -> PathBuf {
        match &self.given {
            Some((path, shown)) if *shown == self.text => path.clone(),
            _ => PathBuf::from(self.text.trim()),
        }
    }
}

/// The race's recording: the trace being written, and the main menu's switch.
#[derive(Default)]
pub(super) struct Recorder {
    /// When recording, where the controls go (a file beside the target, renamed over it at the end).
    pub(super) recorder: Option<Recording>,
    /// The main menu's recording switch and the file it records to.
    pub(super) to: RecordTo,
    /// Whether a recorded race has replaced its target in this run.
    kept_a_race: bool,
    /// The files the run reads (settings, assets), which a name typed in the menu must not record over.
    pub(super) inputs: crate::userfile::Inputs,
    /// The course raced, which each trace's header names.
    pub(super) course: String,
}

impl Recorder {
    /// A recorder of races on `course`, not recording yet.
    pub(super) fn on(course: &str) -> Self {
        Self { course: course.to_string(), ..Self::default() }
    }

    /// Records races to `path`: at once when the race in `world` is `racing` (started without the menu),
    /// else each race started from the main menu while its switch (now on, with this file) stays on. A
    /// path that cannot be recorded to (a folder, a missing folder) is refused now, before the window
    /// opens; `path` itself is not touched.
    pub(super) fn record_to(&mut self, path: &Path, world: &World, racing: bool) -> Result<(), RecordError> {
        let recording = Recording::start(path, &header_for(world, &self.course))?;
        let shown = path.display().to_string();
        self.to = RecordTo { on: true, text: shown.clone(), given: Some((path.to_path_buf(), shown)) };
        if racing {
            self.recorder = Some(recording);
        } else {
            // Only a check: the race's header (its laps) is known when it starts.
            drop(recording);
        }
        Ok(())
    }

    /// Starts recording the race about to start from the grid of `world`, when the main menu's switch asks
    /// for it and the player's controls do not come from a trace (`replaying`); `notice` says where to, or
    /// why not.
    pub(super) fn start(&mut self, world: &World, replaying: bool, notice: &mut Option<String>) {
        if !self.to.on || self.recorder.is_some() || replaying || world.tick != 0 {
            return;
        }
        let path = self.to.path();
        if let Err(e) = self.inputs.check_output(&path) {
            *notice = Some(format!("not recording: {e}"));
            return;
        }
        // Races killed runs left beside the target are named once more where the player looks.
        let left = crate::input::recording::left_behind(&path).map(|l| format!("; {l}")).unwrap_or_default();
        match Recording::start(&path, &header_for(world, &self.course)) {
            Ok(r) => {
                *notice = Some(format!("recording to {}{left}", path.display()));
                self.recorder = Some(r);
            }
            Err(e) => *notice = Some(format!("not recording: {e}")),
        }
    }

    /// Ends the recording in the race (`why` says what ended it), keeping what was raced; `notice` says
    /// what became of it.
    pub(super) fn end(&mut self, why: &str, notice: &mut Option<String>) {
        let Some(mut rec) = self.recorder.take() else { return };
        *notice = Some(match rec.finish() {
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
    pub(super) fn finish(&mut self) -> Result<Option<Kept>, RecordError> {
        match self.recorder.take() {
            Some(mut r) => r.finish().map(Some),
            None if self.to.on && !self.kept_a_race => Ok(Some(Kept::Nothing { path: self.to.path() })),
            None => Ok(None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::screen::Screen;
    use super::super::tests::race_on_the_menu;
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("scanline-racer-record-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn names(dir: &Path) -> Vec<std::ffi::OsString> {
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name()).collect()
    }

    /// A path given with `--record` is recorded to exactly as given when the race starts from the main menu:
    /// spaces around the name and bytes that are not UTF-8 are kept, not trimmed or replaced.
    #[test]
    fn a_path_from_the_command_line_is_recorded_to_exactly_as_given() {
        let d = dir("exact");
        let mut odd: Vec<std::ffi::OsString> = vec![" spaced name.trace ".into()];
        #[cfg(unix)]
        odd.push(std::os::unix::ffi::OsStringExt::from_vec(b"not \xff utf-8.trace".to_vec()));
        for name in odd {
            let path = d.join(&name);
            // Quit on the main menu: nothing written, and the message names the file as given.
            let mut race = race_on_the_menu().record_to(&path).unwrap();
            assert_eq!(race.finish_recording().unwrap(), Some(Kept::Nothing { path: path.clone() }));
            assert!(names(&d).is_empty(), "{name:?}: {:?}", names(&d));
            // One tick raced from the menu: the race is kept under that very name.
            let mut race = race_on_the_menu().record_to(&path).unwrap();
            race.start_race();
            race.tick();
            assert_eq!(race.finish_recording().unwrap(), Some(Kept::Race { path: path.clone(), ticks: 1 }));
            assert_eq!(names(&d), std::slice::from_ref(&name));
            assert!(std::fs::read(&path).unwrap().starts_with(b"SRTRACE\0"));
            std::fs::remove_file(&path).unwrap();
        }
    }

    /// A name typed in the menu's field replaces the one from the command line, spaces around it trimmed.
    #[test]
    fn a_name_typed_in_the_menu_is_recorded_to_trimmed() {
        let d = dir("typed");
        let mut race = race_on_the_menu().record_to(&d.join("given.trace")).unwrap();
        race.recording.to.text = format!("  {}  ", d.join("typed.trace").display());
        race.start_race();
        race.tick();
        let typed = d.join("typed.trace");
        assert_eq!(race.finish_recording().unwrap(), Some(Kept::Race { path: typed, ticks: 1 }));
        assert_eq!(names(&d), ["typed.trace"]);
    }

    /// Controls records in the trace at `path`.
    fn ticks_in(path: &Path) -> usize {
        let (_, mut r) = crate::input::trace::TraceReader::open(path).unwrap();
        std::iter::from_fn(|| r.next_record().unwrap())
            .filter(|r| matches!(r, crate::input::trace::Record::Controls(_)))
            .count()
    }

    /// The last race raced wins, as the README says: a race of 300 ticks is kept on the way back to the main
    /// menu, and a second race from the menu quit after one tick replaces it.
    #[test]
    fn the_last_race_raced_replaces_the_file_even_when_quit_at_once() {
        let d = dir("last");
        let path = d.join("best.trace");
        let mut race = race_on_the_menu().record_to(&path).unwrap();
        race.start_race();
        for _ in 0..300 {
            race.tick();
        }
        // The pause menu's "Main menu".
        race.restart();
        race.screen = Screen::Menu;
        assert_eq!(ticks_in(&path), 300);
        race.start_race();
        race.tick();
        assert_eq!(race.finish_recording().unwrap(), Some(Kept::Race { path: path.clone(), ticks: 1 }));
        assert_eq!(ticks_in(&path), 1);
    }

    /// A name typed in the menu that leads to a file the run reads (the settings file) is not recorded
    /// to: the race runs unrecorded, the notice says why, and the file is as it was.
    #[test]
    fn a_name_typed_in_the_menu_never_records_over_an_input() {
        let d = dir("input");
        let settings = d.join("settings.json");
        std::fs::write(&settings, b"{}").unwrap();
        let mut inputs = crate::userfile::Inputs::new();
        inputs.add(&settings, "the settings file");
        let mut race = race_on_the_menu().reading(inputs).record_to(&d.join("given.trace")).unwrap();
        race.recording.to.text = settings.display().to_string();
        race.start_race();
        race.tick();
        assert!(race.recording.recorder.is_none(), "not recording");
        let notice = race.notice.clone().unwrap_or_default();
        assert!(notice.starts_with("not recording: ") && notice.contains("it is the settings file"), "{notice}");
        assert_eq!(race.finish_recording().unwrap(), Some(Kept::Nothing { path: settings.clone() }));
        assert_eq!(std::fs::read(&settings).unwrap(), b"{}");
    }
}
