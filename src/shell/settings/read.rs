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
use super::values::{CURVE_RANGE, DEADZONE_RANGE, LOD_BIAS_RANGE, MIP_BIAS_RANGE, Settings, VOLUME_RANGE, shown_range};
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

/// Sets the number `slot` from the field `name` of `doc` like [`field`], when it is within `range`; a
/// number out of it, or too large for an `f32` (`1e308` is a JSON number, but infinity as an `f32`), keeps
/// the default, and the note names the number as the file writes it, not as the `f32` it became.
fn number(
    doc: &Map<String, Value>,
    name: &str,
    slot: &mut f32,
    range: std::ops::RangeInclusive<f32>,
    notes: &mut Vec<String>,
) {
    if let Some(Value::Number(n)) = doc.get(name)
        && let Some(x) = n.as_f64()
    {
        if x.is_finite() && x > 0.0 && !(x as f32).is_finite() {
            notes.push(format!("{name} {} is too large: {slot} used", written(n)));
        } else if !range.contains(&(x as f32)) {
            notes.push(format!("{name} {} out of {}: {slot} used", written(n), shown_range(&range)));
        } else {
            *slot = x as f32;
        }
        return;
    }
    field(doc, name, slot, "a number", notes);
}

/// A JSON number as a person writes it: whole numbers in full, very large or very small ones with an
/// exponent (`1e308`, not serde_json's `1e+308` nor a 309-digit expansion), others in decimal (`0.35`).
fn written(n: &serde_json::Number) -> String {
    if n.is_i64() || n.is_u64() {
        return n.to_string();
    }
    let x = n.as_f64().unwrap_or(f64::NAN);
    if x != 0.0 && !(1e-4..1e16).contains(&x.abs()) { format!("{x:e}") } else { format!("{x}") }
}

/// A refused name that knows the names it could have been (for the settings file's notes).
trait Accepted {
    /// The names accepted, as a note lists them.
    fn accepted(&self) -> &'static str;
}

impl Accepted for UnknownName {
    fn accepted(&self) -> &'static str {
        self.expected
    }
}

impl Accepted for crate::game::setup::UnknownChoice {
    fn accepted(&self) -> &'static str {
        self.accepted
    }
}

/// Sets `slot` from the field `name` of `doc` when it is there and is one of the choice's command-line
/// names (`"4x"`, `"time-trial"`); else leaves the default in `slot` and says so in `notes`, naming the
/// choices.
fn named<T: FromStr<Err: Accepted> + std::fmt::Display>(
    doc: &Map<String, Value>,
    name: &str,
    slot: &mut T,
    notes: &mut Vec<String>,
) {
    if let Some(v) = doc.get(name) {
        // A value that is not a string is refused as an unknown name is: no choice is named "".
        match T::from_str(v.as_str().unwrap_or("")) {
            Ok(x) => *slot = x,
            Err(e) => notes.push(format!("{name} {} is not {}: {slot} used", shown(v), e.accepted())),
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
    /// The settings in a settings file's object, field by field: a field that is not of its type, or a
    /// number out of its range, gets its default and a note naming it as written, and the others are used;
    /// a key this build does not know gets a note naming the nearest known key (it stays in the file).
    /// The scale and the keys are checked after, by [`Settings::sanitized`].
    #[must_use]
    pub fn from_object(doc: &Map<String, Value>) -> (Self, Vec<String>) {
        let mut s = Settings::default();
        let mut notes = vec![];
        if let Some(v) = doc.get("keys") {
            s.keys = keys_of(v, &mut notes);
        }
        number(doc, "deadzone", &mut s.deadzone, DEADZONE_RANGE, &mut notes);
        number(doc, "curve", &mut s.curve, CURVE_RANGE, &mut notes);
        let whole = format!("a whole number from {MIN_SCALE} to {MAX_SCALE}");
        field(doc, "scale", &mut s.scale, &whole, &mut notes);
        field(doc, "ghost", &mut s.ghost, "true or false", &mut notes);
        number(doc, "volume", &mut s.volume, VOLUME_RANGE, &mut notes);
        number(doc, "effects_volume", &mut s.effects_volume, VOLUME_RANGE, &mut notes);
        field(doc, "muted", &mut s.muted, "true or false", &mut notes);
        named(doc, "antialias", &mut s.antialias, &mut notes);
        named(doc, "filter", &mut s.filter, &mut notes);
        named(doc, "mip", &mut s.mip, &mut notes);
        field(doc, "lod_fade", &mut s.lod_fade, "true or false", &mut notes);
        number(doc, "lod_bias", &mut s.lod_bias, LOD_BIAS_RANGE, &mut notes);
        number(doc, "mip_bias", &mut s.mip_bias, MIP_BIAS_RANGE, &mut notes);
        field(doc, "auto_quality", &mut s.auto_quality, "true or false", &mut notes);
        if !doc.contains_key("auto_quality") && ["antialias", "filter", "mip"].iter().any(|k| doc.contains_key(*k)) {
            // A file from before `auto` that names a picture keeps it: the player chose it.
            s.auto_quality = false;
        }
        field(doc, "course", &mut s.course, "a course's name", &mut notes);
        field(doc, "car", &mut s.car, &format!("a whole number from 1 to {}", crate::game::garage::CARS), &mut notes);
        named(doc, "mode", &mut s.mode, &mut notes);
        named(doc, "difficulty", &mut s.difficulty, &mut notes);
        field(doc, "laps", &mut s.laps, "a whole number from 1 to 9", &mut notes);
        notes.extend(unknown_keys(doc));
        (s, notes)
    }
}

/// The names the settings file's top level may have: the fields of [`Settings`], as it writes them.
fn known_keys() -> Vec<String> {
    match serde_json::to_value(Settings::default()) {
        Ok(Value::Object(map)) => map.keys().cloned().collect(),
        _ => vec![],
    }
}

/// A note for each top-level key this build does not know (a typo such as `deadzon` would otherwise go
/// unnoticed), naming the nearest known key when one is close; such keys stay in the file.
fn unknown_keys(doc: &Map<String, Value>) -> Vec<String> {
    let known = known_keys();
    doc.keys()
        .filter(|k| !known.contains(k))
        .map(|k| {
            let name = shown(&Value::String(k.clone()));
            match nearest(k, &known) {
                Some(near) => format!("unknown key {name} (did you mean \"{near}\"?) is not used"),
                None => format!("unknown key {name} is not used"),
            }
        })
        .collect()
}

/// The known name closest to `word` by edit distance, when it is close enough to be a typo of it (at most
/// a third of the longer name's letters differ, and at most 3).
fn nearest<'k>(word: &str, known: &'k [String]) -> Option<&'k str> {
    if word.len() > 64 {
        return None;
    }
    known
        .iter()
        .map(|k| (edit_distance(word, k), k))
        .filter(|(d, k)| *d <= 3 && *d * 3 <= word.chars().count().max(k.chars().count()))
        .min_by_key(|(d, _)| *d)
        .map(|(_, k)| k.as_str())
}

/// Edit distance between two short strings, by characters: insertions, deletions, substitutions and
/// swaps of two neighbours (`scael` is one edit from `scale`), each counting one.
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1).min(d[i][j - 1] + 1).min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

/// Most notes the warning line names one by one; the rest are counted.
const MAX_NOTES: usize = 6;
/// Most characters of one note (a key name may be as long as the file).
const MAX_NOTE_CHARS: usize = 200;

/// The notes as one line of bounded length: the first [`MAX_NOTES`], each cut at [`MAX_NOTE_CHARS`], and
/// how many more there are. A file of thousands of bad key names made a warning of half a megabyte, which
/// the menu then laid out (150 MB at peak where a normal start takes 37 MB); the line now stays the same
/// size whatever the file holds.
fn summarised(notes: &[String]) -> String {
    let mut parts: Vec<String> = notes
        .iter()
        .take(MAX_NOTES)
        .map(|n| match n.char_indices().nth(MAX_NOTE_CHARS) {
            Some((end, _)) => format!("{}...", &n[..end]),
            None => n.clone(),
        })
        .collect();
    if notes.len() > MAX_NOTES {
        parts.push(format!("and {} more", notes.len() - MAX_NOTES));
    }
    parts.join("; ")
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
        let note = (!notes.is_empty()).then(|| format!("settings {}: {}", path.display(), summarised(&notes)));
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
            let want = format!(
                "settings {}: scale {written} is not a whole number from 1 to 8: 1 used; unknown key \"theme\" is not used",
                p.display()
            );
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

    #[test]
    fn numbers_are_named_as_written_and_unknown_keys_by_their_nearest_name() {
        let p = tmp("typos.json");
        let text = r#"{"deadzon": 0.2, "keyz": {}, "deadzone": 1e308, "curve": 1e30, "volume": -2, "effects_volume": 0.5, "colour": 1}"#;
        std::fs::write(&p, text).unwrap();
        let (mut file, s, note) = SettingsFile::load(&p);
        assert_eq!((s.deadzone, s.curve, s.volume, s.effects_volume), (DEFAULT_DEADZONE, 1.6, 1.0, 0.5));
        let want = format!(
            "settings {}: deadzone 1e308 is too large: {DEFAULT_DEADZONE} used; curve 1e30 out of 1-3: 1.6 used; \
             volume -2 out of 0-1: 1 used; unknown key \"colour\" is not used; \
             unknown key \"deadzon\" (did you mean \"deadzone\"?) is not used; \
             unknown key \"keyz\" (did you mean \"keys\"?) is not used",
            p.display()
        );
        assert_eq!(note.as_deref(), Some(want.as_str()));
        // The unknown keys stay in the file when a change is saved.
        assert!(file.save(&Settings { ghost: false, ..s }).unwrap());
        let back: Map<String, Value> = serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        for k in ["deadzon", "keyz", "colour", "ghost"] {
            assert!(back.contains_key(k), "{k} kept: {back:?}");
        }
        assert_eq!(nearest("scael", &known_keys()), Some("scale"));
        assert_eq!(nearest("zzz", &known_keys()), None);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
    }

    #[test]
    fn a_file_of_thousands_of_bad_keys_makes_one_short_line() {
        let p = tmp("many-keys.json");
        let names: Vec<String> = (0..5000).map(|i| format!("KeyQ{i}")).collect();
        let long = "K".repeat(10_000);
        let doc = serde_json::json!({"keys": {"throttle": names, "brake": [long]}});
        std::fs::write(&p, doc.to_string()).unwrap();
        let (_, s, note) = SettingsFile::load(&p);
        assert_eq!(s.keys.keys(Action::Throttle), Bindings::default().keys(Action::Throttle));
        let note = note.unwrap();
        assert!(note.len() < 2_000, "{} bytes", note.len());
        let more: usize = note.rsplit_once("; and ").and_then(|(_, n)| n.strip_suffix(" more")?.parse().ok()).unwrap();
        assert!(more > 4990, "{note}");
        assert!(note.contains("key \"KeyQ0\" for throttle is not a key name"), "{note}");
    }
}
