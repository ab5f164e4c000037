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
//! A change is saved by reading the file again (a hand edit made while the game runs is kept) and setting
//! only the settings changed since the last save in its JSON object (keys this build does not know, and
//! settings left alone, stay as they are), written to a temporary file beside it and renamed over it
//! (through a symbolic link, which stays a link), so a crash never leaves half a file. A file that no
//! longer reads as a JSON object at that moment is left alone, said once, and not written again in that
//! run; a file deleted meanwhile is created again with the changes.

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;
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

/// Why a settings file could not be used at all (it is then never written).
#[derive(Debug, Error)]
pub enum UnusableSettings {
    /// The path is not a regular file, is too big, is not UTF-8 text, or cannot be read.
    #[error(transparent)]
    File(#[from] UserFileError),
    /// The text is not JSON.
    #[error("{path}: {reason}")]
    Json {
        /// The file.
        path: PathBuf,
        /// What serde_json said (with the line and column).
        reason: String,
    },
    /// The JSON is not an object (an array, a number, a string).
    #[error("{path}: not a JSON object")]
    NotObject {
        /// The file.
        path: PathBuf,
    },
}

/// Why the settings could not be saved.
#[derive(Debug, Error)]
pub enum SettingsError {
    /// The file no longer reads as a JSON object (edited or replaced while the game ran): it is left as it
    /// is, and nothing more is saved in this run.
    #[error("settings {0} (it changed while the game ran); the file is left as it is and changes will not be saved")]
    Unusable(#[source] UnusableSettings),
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

/// The file's top-level JSON object as it is now: `None` when the file does not exist, an empty object when
/// it is empty (or only white space); only a regular file within the budget is read (a FIFO would block,
/// `/dev/zero` would never end).
fn read_object(path: &Path) -> Result<Option<Map<String, Value>>, UnusableSettings> {
    let text = match crate::userfile::read_regular_text(path, MAX_BYTES, "a settings file") {
        Ok(t) => t,
        Err(e) if e.is_not_found() => return Ok(None),
        Err(e) => return Err(e.into()),
    };
    if text.trim().is_empty() {
        return Ok(Some(Map::new()));
    }
    match serde_json::from_str::<Value>(&text) {
        Ok(Value::Object(doc)) => Ok(Some(doc)),
        Ok(_) => Err(UnusableSettings::NotObject { path: path.to_path_buf() }),
        Err(e) => Err(UnusableSettings::Json { path: path.to_path_buf(), reason: e.to_string() }),
    }
}

/// A JSON value as a warning shows it: at most 40 characters.
fn shown(v: &Value) -> String {
    let text = v.to_string();
    match text.char_indices().nth(40) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text,
    }
}

/// Sets `slot` from the field `name` of `doc` when it is there and of `slot`'s type; else leaves the
/// default in `slot` and says so in `notes` (`what` names the type wanted: "a number").
fn field<T: DeserializeOwned + std::fmt::Display>(
    doc: &Map<String, Value>,
    name: &str,
    slot: &mut T,
    what: &str,
    notes: &mut Vec<String>,
) {
    if let Some(v) = doc.get(name) {
        match T::deserialize(v) {
            Ok(x) => *slot = x,
            Err(_) => notes.push(format!("{name} {} is not {what}: {slot} used", shown(v))),
        }
    }
}

/// The key bindings of the `keys` field, action by action: an entry that is not a known action with a list
/// of key names is dropped and said (the action then gets its default keys, see [`Bindings::repaired`]).
fn keys_of(v: &Value, notes: &mut Vec<String>) -> Bindings {
    let Value::Object(map) = v else {
        notes.push(format!("keys {} is not an object of actions and their keys: default keys used", shown(v)));
        return Bindings::default();
    };
    let mut good = Map::new();
    for (action, keys) in map {
        if crate::input::bindings::Action::deserialize(Value::String(action.clone())).is_err() {
            notes.push(format!("keys: {} is not an action: dropped", shown(&Value::String(action.clone()))));
        } else if Vec::<String>::deserialize(keys).is_err() {
            notes.push(format!("keys: {action} {} is not a list of key names: dropped", shown(keys)));
        } else {
            good.insert(action.clone(), keys.clone());
        }
    }
    // Every entry left is an action with a list of names, so this cannot fail; defaults if it somehow did.
    Bindings::deserialize(Value::Object(good)).unwrap_or_default()
}

impl Settings {
    /// The settings in a settings file's object, field by field: a field that is not of its type gets its
    /// default and a note naming it, and the others are used (keys this build does not know are ignored).
    /// Ranges are checked after, by [`Settings::sanitized`].
    #[must_use]
    pub fn from_object(doc: &Map<String, Value>) -> (Self, Vec<String>) {
        let mut s = Settings::default();
        let mut notes = vec![];
        if let Some(v) = doc.get("keys") {
            s.keys = keys_of(v, &mut notes);
        }
        field(doc, "deadzone", &mut s.deadzone, "a number", &mut notes);
        field(doc, "curve", &mut s.curve, "a number", &mut notes);
        let whole = format!("a whole number from {MIN_SCALE} to {MAX_SCALE}");
        field(doc, "scale", &mut s.scale, &whole, &mut notes);
        field(doc, "ghost", &mut s.ghost, "true or false", &mut notes);
        (s, notes)
    }
}

impl SettingsFile {
    /// Reads `path`: its settings (defaults when it does not exist or cannot be used), the file to save
    /// changes to, and one line for the user when something in it was not used (`None` when all was well).
    #[must_use]
    pub fn load(path: &Path) -> (Self, Settings, Option<String>) {
        let mut file = Self { path: path.to_path_buf(), saved: Settings::default(), writable: false };
        let doc = match read_object(path) {
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

    /// Saves the settings in `now` that changed since the last save onto the file as it is now (read again,
    /// so a hand edit made meanwhile is kept), leaving everything else in it as it is; returns whether the
    /// file was written (not when nothing changed or the file is left alone). A file that no longer reads as
    /// a JSON object is not written, now or later in this run ([`SettingsError::Unusable`], returned once).
    /// After a failure the change counts as saved, so that it is reported once, not at every frame.
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
        let mut doc = match read_object(&self.path) {
            Ok(doc) => doc.unwrap_or_default(),
            Err(e) => {
                self.writable = false;
                return Err(SettingsError::Unusable(e));
            }
        };
        if let (Value::Object(old), Value::Object(new)) = (old, new) {
            for (key, value) in new {
                if old.get(&key) != Some(&value) {
                    doc.insert(key, value);
                }
            }
        }
        let mut text = serde_json::to_string_pretty(&doc).map_err(json)?;
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

    #[test]
    fn a_hand_edit_made_while_the_game_runs_is_kept() {
        let p = tmp("hand.json");
        std::fs::write(&p, "{\"scale\": 2}\n").unwrap();
        let (mut file, s, _) = SettingsFile::load(&p);
        assert!(file.save(&Settings { ghost: false, ..s.clone() }).unwrap());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"ghost\": false,\n  \"scale\": 2\n}\n");
        // By hand, while the game runs: a key of the user's own, and the scale back to 1.
        std::fs::write(&p, "{\"ghost\": false, \"scale\": 1, \"theme\": \"dark\"}").unwrap();
        assert!(file.save(&Settings { ghost: false, deadzone: 0.25, ..s }).unwrap());
        let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 1,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want, "the game's two changes and the hand edit");
    }

    #[test]
    fn a_file_that_stops_parsing_while_the_game_runs_is_left_alone_and_said_once() {
        let p = tmp("broken-later.json");
        std::fs::write(&p, "{}").unwrap();
        let (mut file, s, _) = SettingsFile::load(&p);
        std::fs::write(&p, "{\"scale\": 2,}").unwrap();
        let e = file.save(&Settings { scale: 3, ..s.clone() }).unwrap_err();
        let want = format!(
            "settings {}: trailing comma at line 1 column 13 (it changed while the game ran); the file is left as \
             it is and changes will not be saved",
            p.display()
        );
        assert_eq!(e.to_string(), want);
        assert!(!file.writable());
        // Said once: a later change is not saved either, and not said again, even once the file is fixed.
        std::fs::write(&p, "{\"scale\": 2}").unwrap();
        assert!(!file.save(&Settings { scale: 4, ..s.clone() }).unwrap());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\"scale\": 2}");
        // A file turned into a folder is not written either.
        let d = tmp("folder-later.json");
        let _ = std::fs::remove_dir(&d);
        let _ = std::fs::remove_file(&d);
        let (mut file, s, _) = SettingsFile::load(&d);
        std::fs::create_dir(&d).unwrap();
        let e = file.save(&Settings { scale: 3, ..s }).unwrap_err();
        assert!(e.to_string().contains("is a folder, not a regular file (it changed"), "{e}");
        assert!(std::fs::read_dir(&d).unwrap().next().is_none(), "nothing written into the folder");
    }

    #[test]
    fn a_file_deleted_while_the_game_runs_is_written_again_with_the_changes() {
        let p = tmp("deleted.json");
        std::fs::write(&p, "{\"theme\": \"dark\", \"scale\": 2}").unwrap();
        let (mut file, s, _) = SettingsFile::load(&p);
        std::fs::remove_file(&p).unwrap();
        assert!(file.save(&Settings { ghost: false, ..s }).unwrap());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"ghost\": false\n}\n");
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

    #[test]
    fn a_field_of_the_wrong_type_gets_its_default_and_the_rest_of_the_file_is_used() {
        for (scale, written) in [("-1", "-1"), ("2.5", "2.5"), ("5e9", "5000000000.0"), ("\"big\"", "\"big\"")] {
            let p = tmp("wrong-scale.json");
            std::fs::write(&p, format!("{{\"theme\": \"dark\", \"scale\": {scale}, \"deadzone\": 0.2}}")).unwrap();
            let (mut file, s, note) = SettingsFile::load(&p);
            assert_eq!((s.scale, s.deadzone, file.writable()), (1, 0.2, true), "{scale}");
            let want = format!("settings {}: scale {written} is not a whole number from 1 to 8: 1 used", p.display());
            assert_eq!(note.as_deref(), Some(want.as_str()));
            // Saved like any file: the unknown key stays, and so does the scale no change touched.
            assert!(file.save(&Settings { ghost: false, ..s }).unwrap());
            let want = format!(
                "{{\n  \"deadzone\": 0.2,\n  \"ghost\": false,\n  \"scale\": {written},\n  \"theme\": \"dark\"\n}}\n"
            );
            assert_eq!(std::fs::read_to_string(&p).unwrap(), want, "{scale}");
        }
        let p = tmp("wrong-types.json");
        let text = r#"{"deadzone": "wide", "curve": 2, "ghost": "no", "keys": {"fly": ["KeyF"], "brake": "Space", "throttle": ["KeyT"]}}"#;
        std::fs::write(&p, text).unwrap();
        let (file, s, note) = SettingsFile::load(&p);
        assert_eq!((s.deadzone, s.curve, s.ghost, file.writable()), (DEFAULT_DEADZONE, 2.0, true, true));
        assert_eq!(s.keys.keys(Action::Throttle), ["KeyT"]);
        assert_eq!(s.keys.keys(Action::Brake), Bindings::default().keys(Action::Brake));
        let note = note.unwrap();
        for part in [
            "keys: \"fly\" is not an action: dropped",
            "keys: brake \"Space\" is not a list of key names: dropped",
            &format!("deadzone \"wide\" is not a number: {DEFAULT_DEADZONE} used"),
            "ghost \"no\" is not true or false: true used",
        ] {
            assert!(note.contains(part), "{part} in {note}");
        }
        assert!(!note.contains('\n'), "{note}");
    }
}
