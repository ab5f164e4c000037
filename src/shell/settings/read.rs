//! Reading the settings file at start ([`SettingsFile::load`]): its JSON object, then the settings in it
//! field by field, so that one field of the wrong type costs only that field (it gets its default and a
//! note naming it). Saving reads the object again, with [`read_object`], before it sets what changed.

use std::path::{Path, PathBuf};
use std::str::FromStr;

use serde::Deserialize;
use serde::de::DeserializeOwned;
use serde_json::{Map, Value};
use thiserror::Error;

use super::file::SettingsFile;
use super::values::Settings;
use crate::input::bindings::Bindings;
use crate::render::UnknownName;
use crate::shell::window::{MAX_SCALE, MIN_SCALE};
use crate::userfile::UserFileError;

/// Largest settings file read (a hand-edited file never comes near it).
const MAX_BYTES: u64 = 64 * 1024;

/// Why a settings file could not be used at all (it is then never written).
#[derive(Debug, Error)]
pub enum UnusableSettings {
    /// The path is not a regular file, is too big, is not UTF-8 text, or cannot be read.
    #[error(transparent)]
    File(#[from] UserFileError),
    /// The text is not JSON.
    #[error("{path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// What serde_json said (with the line and column).
        source: serde_json::Error,
    },
    /// The JSON is not an object (an array, a number, a string).
    #[error("{path}: not a JSON object")]
    NotObject {
        /// The file.
        path: PathBuf,
    },
}

/// The file's top-level JSON object as it is now: `None` when the file does not exist, an empty object when
/// it is empty (or only white space); only a regular file within the budget is read (a FIFO would block,
/// `/dev/zero` would never end).
pub(super) fn read_object(path: &Path) -> Result<Option<Map<String, Value>>, UnusableSettings> {
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
        Err(source) => Err(UnusableSettings::Json { path: path.to_path_buf(), source }),
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

/// Sets `slot` from the field `name` of `doc` when it is there and is one of the choice's command-line
/// names (`"4x"`); else leaves the default in `slot` and says so in `notes`, naming the choices.
fn named<T: FromStr<Err = UnknownName> + std::fmt::Display>(
    doc: &Map<String, Value>,
    name: &str,
    slot: &mut T,
    notes: &mut Vec<String>,
) {
    if let Some(v) = doc.get(name) {
        // A value that is not a string is refused as an unknown name is: no choice is named "".
        match T::from_str(v.as_str().unwrap_or("")) {
            Ok(x) => *slot = x,
            Err(e) => notes.push(format!("{name} {} is not {}: {slot} used", shown(v), e.expected)),
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
        field(doc, "volume", &mut s.volume, "a number", &mut notes);
        field(doc, "effects_volume", &mut s.effects_volume, "a number", &mut notes);
        field(doc, "muted", &mut s.muted, "true or false", &mut notes);
        named(doc, "antialias", &mut s.antialias, &mut notes);
        named(doc, "filter", &mut s.filter, &mut notes);
        named(doc, "mip", &mut s.mip, &mut notes);
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
}

#[cfg(test)]
mod tests {
    use super::super::tests::tmp;
    use super::*;
    use crate::input::bindings::Action;
    use crate::input::gamepad::DEFAULT_DEADZONE;
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
