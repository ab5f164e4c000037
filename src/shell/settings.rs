//! The settings file: key bindings, gamepad deadzone and curve, pixel scale and the ghost car, kept between
//! runs.
//!
//! JSON, at `--settings FILE`, else `$SCANLINE_RACER_SETTINGS`, else
//! `$XDG_CONFIG_HOME/scanline-racer/settings.json` (or `~/.config/...`). A missing file means defaults; an
//! unreadable or broken one means defaults and one line saying why, and it is only replaced when a setting
//! is changed. Saved by writing a temporary file beside it and renaming, so a crash never leaves half a file.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

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
        let (keys, key_notes) = self.keys.repaired();
        self.keys = keys;
        notes.extend(key_notes);
        (self, notes)
    }

    /// Reads `path`: defaults when it does not exist; defaults and a one-line reason when it cannot be used.
    #[must_use]
    pub fn load(path: &Path) -> (Self, Option<String>) {
        let shown = path.display();
        // Only a regular file within the budget is read: a FIFO would block, /dev/zero would never end.
        let text = match crate::userfile::read_regular_text(path, MAX_BYTES, "a settings file") {
            Ok(t) => t,
            Err(e) if e.is_not_found() => return (Self::default(), None),
            Err(e) => return (Self::default(), Some(format!("settings {e}; defaults used"))),
        };
        match serde_json::from_str::<Settings>(&text) {
            Ok(s) => {
                let (s, notes) = s.sanitized();
                let note = (!notes.is_empty()).then(|| format!("settings {shown}: {}", notes.join("; ")));
                (s, note)
            }
            Err(e) => (Self::default(), Some(format!("settings {shown}: {e}; defaults used"))),
        }
    }

    /// Writes the settings to `path` (creating its folder), atomically.
    pub fn save(&self, path: &Path) -> Result<(), String> {
        let fail = |e: std::io::Error| format!("cannot save settings to {}: {e}", path.display());
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(fail)?;
        }
        let json = serde_json::to_string_pretty(self).map_err(|e| e.to_string())?;
        let tmp = path.with_extension("json.tmp");
        std::fs::write(&tmp, json + "\n").map_err(fail)?;
        std::fs::rename(&tmp, path).map_err(fail)
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
        assert_eq!(Settings::load(&p), (Settings::default(), None));
        let mut s = Settings { deadzone: 0.2, curve: 2.0, scale: 3, ..Settings::default() };
        s.keys.bind(Action::Throttle, "Space").unwrap();
        s.save(&p).unwrap();
        assert_eq!(Settings::load(&p), (s, None));
    }

    #[test]
    fn broken_files_give_defaults_and_one_line() {
        for (name, text) in [
            ("garbage.json", "{not json"),
            ("types.json", r#"{"deadzone":"wide"}"#),
            ("binary.json", "\u{0}\u{1}\u{2}"),
        ] {
            let p = tmp(name);
            std::fs::write(&p, text).unwrap();
            let (s, note) = Settings::load(&p);
            assert_eq!(s, Settings::default(), "{name}");
            let note = note.unwrap();
            assert!(note.contains(name) && !note.contains('\n'), "{note}");
        }
        let p = tmp("big.json");
        std::fs::write(&p, vec![b' '; 100_000]).unwrap();
        assert!(Settings::load(&p).1.unwrap().contains("over the 65536-byte limit"));
    }

    #[test]
    fn out_of_range_values_are_repaired_and_said() {
        let p = tmp("range.json");
        std::fs::write(&p, r#"{"deadzone":5.0,"curve":0.1,"scale":0,"keys":{"brake":["Escape"]}}"#).unwrap();
        let (s, note) = Settings::load(&p);
        assert_eq!((s.deadzone, s.curve, s.scale), (DEFAULT_DEADZONE, DEFAULT_CURVE, 1));
        assert_eq!(s.keys, Bindings::default());
        let note = note.unwrap();
        assert!(note.contains("deadzone 5") && note.contains("Escape"), "{note}");
    }
}
