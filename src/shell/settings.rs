//! The settings file: key bindings, gamepad deadzone and curve, pixel scale and the ghost car, kept between
//! runs.
//!
//! JSON, at `--settings FILE`, else `$SCANLINE_RACER_SETTINGS`, else
//! `$XDG_CONFIG_HOME/scanline-racer/settings.json` (or `~/.config/...`). A missing file means defaults and
//! is created at the first change. A file that cannot be read or does not parse means defaults and one line
//! saying why, and it is never written in that run: one typo must not cost the user the rest of the file.
//! A change is saved by updating only the changed settings in the file's JSON object as read (keys this
//! build does not know, and settings left alone, stay as they were), written to a temporary file beside it
//! and renamed over it (through a symbolic link, which stays a link), so a crash never leaves half a file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use thiserror::Error;

use crate::input::bindings::Bindings;
use crate::input::gamepad::{DEFAULT_CURVE, DEFAULT_DEADZONE};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};
use crate::userfile::UserFileError;

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

/// Why the settings could not be saved.
#[derive(Debug, Error)]
pub enum SettingsError {
    /// The settings' folder could not be created.
    #[error("cannot save settings: cannot create {path}: {reason}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The operating system's reason.
        reason: String,
    },
    /// The file could not be written.
    #[error("cannot save settings: {0}")]
    File(#[from] UserFileError),
    /// A setting could not be turned into JSON (not expected: every setting is plain data).
    #[error("cannot save settings to {path}: {reason}")]
    Json {
        /// The file.
        path: PathBuf,
        /// What serde_json said.
        reason: String,
    },
}

/// The settings file as read at start: where it is, its JSON object, what was last loaded or saved, and
/// whether it may be written.
#[derive(Clone, Debug)]
pub struct SettingsFile {
    path: PathBuf,
    /// The file's top-level object as read (empty when the file did not exist), updated by each save.
    doc: Map<String, Value>,
    /// The settings as the file holds them now; a setting that differs from this is saved.
    saved: Settings,
    /// False when the file exists but could not be read or parsed: it is then left alone.
    writable: bool,
}

impl SettingsFile {
    /// Reads `path`: its settings (defaults when it does not exist or cannot be used), the file to save
    /// changes to, and one line for the user when something in it was not used (`None` when all was well).
    #[must_use]
    pub fn load(path: &Path) -> (Self, Settings, Option<String>) {
        let shown = path.display();
        let mut file = Self { path: path.to_path_buf(), doc: Map::new(), saved: Settings::default(), writable: false };
        let refused = |file: Self, why: String| {
            let note =
                format!("settings {why}; defaults used; the file is left as it is and changes will not be saved");
            (file, Settings::default(), Some(note))
        };
        // Only a regular file within the budget is read: a FIFO would block, /dev/zero would never end.
        let text = match crate::userfile::read_regular_text(path, MAX_BYTES, "a settings file") {
            Ok(t) => t,
            Err(e) if e.is_not_found() => {
                file.writable = true;
                return (file, Settings::default(), None);
            }
            Err(e) => return refused(file, e.to_string()),
        };
        let doc = match serde_json::from_str::<Value>(&text) {
            Ok(Value::Object(doc)) => doc,
            Ok(_) => return refused(file, format!("{shown}: not a JSON object")),
            Err(e) => return refused(file, format!("{shown}: {e}")),
        };
        let settings = match Settings::deserialize(Value::Object(doc.clone())) {
            Ok(s) => s,
            Err(e) => return refused(file, format!("{shown}: {e}")),
        };
        let (settings, notes) = settings.sanitized();
        let note = (!notes.is_empty()).then(|| format!("settings {shown}: {}", notes.join("; ")));
        file.doc = doc;
        file.saved = settings.clone();
        file.writable = true;
        (file, settings, note)
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Whether changes are saved (false when the file could not be read or parsed at start).
    #[must_use]
    pub fn writable(&self) -> bool {
        self.writable
    }

    /// Takes `settings` as what the file holds, so that only a later change to them is saved (a value given
    /// on the command line for this run only).
    pub fn assume_saved(&mut self, settings: Settings) {
        self.saved = settings;
    }

    /// Saves the settings in `now` that differ from the file's, leaving everything else in the file as it is;
    /// returns whether the file was written (not when nothing changed or the file is left alone). After a
    /// failure the change counts as saved, so that it is reported once, not at every frame.
    pub fn save(&mut self, now: &Settings) -> Result<bool, SettingsError> {
        if !self.writable || *now == self.saved {
            return Ok(false);
        }
        let json = |e: serde_json::Error| SettingsError::Json { path: self.path.clone(), reason: e.to_string() };
        // Through text, so that an `f32` such as 0.2 is written as 0.2 (a direct `to_value` widens it to
        // 0.20000000298023224).
        let value = |s: &Settings| serde_json::to_string(s).and_then(|t| serde_json::from_str::<Value>(&t));
        let (old, new) = (value(&self.saved).map_err(json)?, value(now).map_err(json)?);
        self.saved = now.clone();
        if let (Value::Object(old), Value::Object(new)) = (old, new) {
            for (key, value) in new {
                if old.get(&key) != Some(&value) {
                    self.doc.insert(key, value);
                }
            }
        }
        let mut text = serde_json::to_string_pretty(&self.doc).map_err(json)?;
        text.push('\n');
        let target = crate::userfile::write_target(&self.path);
        if let Some(dir) = target.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)
                .map_err(|e| SettingsError::Folder { path: dir.to_path_buf(), reason: e.to_string() })?;
        }
        crate::userfile::replace_atomically(&self.path, text.as_bytes())?;
        Ok(true)
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

    fn tmp(name: &str) -> PathBuf {
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
            ("types.json", r#"{"deadzone":"wide"}"#),
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
    fn a_save_changes_only_the_changed_settings_and_keeps_unknown_keys() {
        let p = tmp("unknown.json");
        let text = "{\n  \"theme\": \"dark\",\n  \"scale\": 2,\n  \"deadzone\": 0.2\n}\n";
        std::fs::write(&p, text).unwrap();
        let (mut file, s, note) = SettingsFile::load(&p);
        assert_eq!((s.scale, s.deadzone, note), (2, 0.2, None));
        assert!(file.save(&Settings { ghost: false, ..s.clone() }).unwrap());
        // Keys come out in name order; the values not changed are the file's own.
        let want = "{\n  \"deadzone\": 0.2,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
        assert!(file.save(&Settings { ghost: false, deadzone: 0.25, ..s }).unwrap());
        let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
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

    #[cfg(unix)]
    #[test]
    fn a_linked_settings_file_stays_a_link() {
        let (real, link) = (tmp("real-settings.json"), tmp("link-settings.json"));
        std::fs::write(&real, "{\"ghost\": false}\n").unwrap();
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink("real-settings.json", &link).unwrap();
        let (mut file, s, _) = SettingsFile::load(&link);
        assert!(!s.ghost);
        assert!(file.save(&Settings { scale: 3, ..s }).unwrap());
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "{\n  \"ghost\": false,\n  \"scale\": 3\n}\n");
    }
}
