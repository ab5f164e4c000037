//! The settings file: key bindings, gamepad deadzone and curve, pixel scale and the ghost car, kept between
//! runs.
//!
//! JSON, at `--settings FILE`, else `$SCANLINE_RACER_SETTINGS`, else
//! `$XDG_CONFIG_HOME/scanline-racer/settings.json` (or `~/.config/...`). A missing or empty file means
//! defaults and is created at the first change. A field of the wrong type or out of range (`"scale": -1`,
//! `2.5`, `"deadzone": "wide"`) gets its default and is named in one warning line; the rest of the file is
//! used. A file that cannot be read or is not a JSON object means defaults and one line saying why, and it
//! is never written in that run: one typo must not cost the user the rest of the file.
//!
//! Reading the file field by field is in `read`; saving a change onto the file as it is at that moment
//! (never a file that does not parse; unknown keys and hand edits kept) is in `save`.

mod read;
mod save;

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

pub use read::UnusableSettings;
pub use save::SettingsError;

use crate::input::bindings::Bindings;
use crate::input::gamepad::{DEFAULT_CURVE, DEFAULT_DEADZONE};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

/// Largest settings file read (a hand-edited file never comes near it).
const MAX_BYTES: u64 = 64 * 1024;

/// Everything the settings file holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Keyboard bindings.
    pub keys: Bindings,
    /// Gamepad stick deadzone (radial), 0 to 0.3.
    pub deadzone: f32,
    /// Gamepad steering response exponent, 1 (linear) to 3.
    pub curve: f32,
    /// Window pixels per rendered pixel, 1 to [`MAX_SCALE`].
    pub scale: u32,
    /// Whether the ghost car (the best lap) is drawn.
    pub ghost: bool,
}

impl Default for Settings {
    fn default() -> Self {
        Self { keys: Bindings::default(), deadzone: DEFAULT_DEADZONE, curve: DEFAULT_CURVE, scale: 1, ghost: true }
    }
}

impl Settings {
    /// The settings with every value in range (NaN and out-of-range numbers back to defaults or clamped)
    /// and the bindings repaired; the notes say what changed.
    #[must_use]
    pub fn sanitized(mut self) -> (Self, Vec<String>) {
        let d = Settings::default();
        let mut notes = vec![];
        if !self.deadzone.is_finite() || !(0.0..=0.3).contains(&self.deadzone) {
            notes.push(format!("deadzone {} out of 0-0.3: {} used", self.deadzone, d.deadzone));
            self.deadzone = d.deadzone;
        }
        if !self.curve.is_finite() || !(1.0..=3.0).contains(&self.curve) {
            notes.push(format!("curve {} out of 1-3: {} used", self.curve, d.curve));
            self.curve = d.curve;
        }
        if !(MIN_SCALE..=MAX_SCALE).contains(&self.scale) {
            notes.push(format!("scale {} out of {MIN_SCALE}-{MAX_SCALE}: {MIN_SCALE} used", self.scale));
            self.scale = MIN_SCALE;
        }
        let (keys, key_notes) = self.keys.repaired(crate::shell::keys::is_key_name);
        self.keys = keys;
        notes.extend(key_notes);
        (self, notes)
    }
}

/// The settings file: where it is, what was last loaded or saved, and whether it may be written.
#[derive(Clone, Debug)]
pub struct SettingsFile {
    path: PathBuf,
    /// The settings as this run last loaded or saved them; a setting that differs from this is saved.
    saved: Settings,
    /// False when the file could not be read as a JSON object (at start, or at a save): it is then left
    /// alone for the rest of the run.
    writable: bool,
}

impl SettingsFile {
    /// Reads `path`: its settings (defaults when it does not exist or cannot be used), the file to save
    /// changes to, and one line for the user when something in it was not used (`None` when all was well).
    #[must_use]
    pub fn load(path: &Path) -> (Self, Settings, Option<String>) {
        let mut file = Self { path: path.to_path_buf(), saved: Settings::default(), writable: false };
        let doc = match read::read_object(path) {
            Ok(Some(doc)) => doc,
            Ok(None) => {
                file.writable = true;
                return (file, Settings::default(), None);
            }
            Err(e) => {
                let note =
                    format!("settings {e}; defaults used; the file is left as it is and changes will not be saved");
                return (file, Settings::default(), Some(note));
            }
        };
        let (settings, mut notes) = Settings::from_object(&doc);
        let (settings, range_notes) = settings.sanitized();
        notes.extend(range_notes);
        let note = (!notes.is_empty()).then(|| format!("settings {}: {}", path.display(), notes.join("; ")));
        file.saved = settings.clone();
        file.writable = true;
        (file, settings, note)
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether changes are saved (false once the file could not be read as a JSON object, at start or at a
    /// save).
    #[must_use]
    pub fn writable(&self) -> bool {
        self.writable
    }

    /// Takes `settings` as what the file holds, so that only a later change to them is saved (a value given
    /// on the command line for this run only).
    pub fn assume_saved(&mut self, settings: Settings) {
        self.saved = settings;
    }
}

/// Where the settings live when no `--settings` is given: `$SCANLINE_RACER_SETTINGS`, else the XDG config
/// folder; `None` with no home folder to put it in.
#[must_use]
pub fn default_path() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SCANLINE_RACER_SETTINGS").filter(|p| !p.is_empty()) {
        return Some(PathBuf::from(p));
    }
    let config = std::env::var_os("XDG_CONFIG_HOME")
        .filter(|p| !p.is_empty())
        .map(PathBuf::from)
        .or_else(|| std::env::var_os("HOME").filter(|p| !p.is_empty()).map(|h| PathBuf::from(h).join(".config")))?;
    Some(config.join("scanline-racer").join("settings.json"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::input::bindings::Action;

    pub(super) fn tmp(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("scanline-racer-settings-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        dir.join(name)
    }

    #[test]
    fn saved_settings_load_back_and_a_missing_file_is_defaults() {
        let p = tmp("a/settings.json");
        let _ = std::fs::remove_file(&p);
        let (mut file, s, note) = SettingsFile::load(&p);
        assert_eq!((s, note, file.writable()), (Settings::default(), None, true));
        let mut s = Settings { deadzone: 0.2, curve: 2.0, scale: 3, ..Settings::default() };
        s.keys.bind(Action::Throttle, "Space").unwrap();
        assert!(file.save(&s).unwrap());
        assert!(!file.save(&s).unwrap(), "nothing changed: nothing written");
        let (_, back, note) = SettingsFile::load(&p);
        assert_eq!((back, note), (s, None));
    }

    #[test]
    fn broken_files_give_defaults_and_one_line_and_are_never_written() {
        for (name, text) in [
            ("garbage.json", "{not json"),
            ("comma.json", "{\"scale\": 2,}"),
            ("array.json", "[1, 2]"),
            ("binary.json", "\u{0}\u{1}\u{2}"),
        ] {
            let p = tmp(name);
            std::fs::write(&p, text).unwrap();
            let (mut file, s, note) = SettingsFile::load(&p);
            assert_eq!(s, Settings::default(), "{name}");
            let note = note.unwrap();
            assert!(note.contains(name) && !note.contains('\n'), "{note}");
            assert!(note.ends_with("defaults used; the file is left as it is and changes will not be saved"), "{note}");
            assert!(!file.save(&Settings { scale: 2, ..Settings::default() }).unwrap());
            assert_eq!(std::fs::read_to_string(&p).unwrap(), text, "{name} is untouched");
        }
        let p = tmp("big.json");
        std::fs::write(&p, vec![b' '; 100_000]).unwrap();
        let (mut file, _, note) = SettingsFile::load(&p);
        assert!(note.unwrap().contains("over the 65536-byte limit"));
        assert!(!file.save(&Settings { scale: 2, ..Settings::default() }).unwrap());
    }

    #[test]
    fn out_of_range_values_are_repaired_and_said() {
        let p = tmp("range.json");
        std::fs::write(&p, r#"{"deadzone":5.0,"curve":0.1,"scale":0,"keys":{"brake":["Escape"]}}"#).unwrap();
        let (_, s, note) = SettingsFile::load(&p);
        assert_eq!((s.deadzone, s.curve, s.scale), (DEFAULT_DEADZONE, DEFAULT_CURVE, 1));
        assert_eq!(s.keys, Bindings::default());
        let note = note.unwrap();
        assert!(note.contains("deadzone 5") && note.contains("Escape"), "{note}");
        assert!(!note.contains("not be saved"), "a repaired file is still saved: {note}");
    }

    #[test]
    fn an_empty_file_is_no_settings_yet() {
        let p = tmp("empty.json");
        std::fs::write(&p, "").unwrap();
        let (mut file, s, note) = SettingsFile::load(&p);
        assert_eq!((&s, note, file.writable()), (&Settings::default(), None, true));
        assert!(file.save(&Settings { scale: 2, ..s }).unwrap());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"scale\": 2\n}\n");
    }
}
