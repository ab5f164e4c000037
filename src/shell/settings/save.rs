//! Saving the settings: the file is read again (a hand edit made while the game runs is kept) and only the
//! settings changed since the last save are set in its JSON object (keys this build does not know, and
//! settings left alone, stay as they are); the text is written to a temporary file beside it and renamed
//! over it (through a symbolic link, which stays a link), so a crash never leaves half a file. A file that
//! no longer reads as a JSON object at that moment is left alone, said once, and not written again in that
//! run; a file deleted meanwhile is created again with the changes.

use std::path::PathBuf;

use serde_json::Value;
use thiserror::Error;

use super::file::SettingsFile;
use super::read::{UnusableSettings, read_object};
use super::values::Settings;
use crate::userfile::UserFileError;

/// Why the settings could not be saved.
#[derive(Debug, Error)]
pub enum SettingsError {
    /// The file no longer reads as a JSON object (edited or replaced while the game ran): it is left as it
    /// is, and nothing more is saved in this run.
    #[error("settings {0} (it changed while the game ran); the file is left as it is and changes will not be saved")]
    Unusable(#[source] UnusableSettings),
    /// The settings' folder could not be created.
    #[error("cannot save settings: cannot create {path}: {source}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The file could not be written.
    #[error("cannot save settings: {0}")]
    File(#[from] UserFileError),
    /// A setting could not be turned into JSON (not expected: every setting is plain data).
    #[error("cannot save settings to {path}: {source}")]
    Json {
        /// The file.
        path: PathBuf,
        /// What serde_json said.
        source: serde_json::Error,
    },
}

impl SettingsFile {
    /// Saves the settings in `now` that changed since the last save onto the file as it is now (read again,
    /// so a hand edit made meanwhile is kept), leaving everything else in it as it is; returns whether the
    /// file was written (not when nothing changed or the file is left alone). A file that no longer reads as
    /// a JSON object is not written, now or later in this run ([`SettingsError::Unusable`], returned once).
    /// After a failure the change counts as saved, so that it is reported once, not at every frame.
    pub fn save(&mut self, now: &Settings) -> Result<bool, SettingsError> {
        if !self.writable || *now == self.saved {
            return Ok(false);
        }
        let json = |source: serde_json::Error| SettingsError::Json { path: self.path.clone(), source };
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
            std::fs::create_dir_all(dir).map_err(|source| SettingsError::Folder { path: dir.to_path_buf(), source })?;
        }
        crate::userfile::replace_atomically(&self.path, text.as_bytes())?;
        Ok(true)
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::tmp;
    use super::*;
    #[test]
    fn a_save_changes_only_the_changed_settings_and_keeps_unknown_keys() {
        let p = tmp("unknown.json");
        let text = "{\n  \"theme\": \"dark\",\n  \"scale\": 2,\n  \"deadzone\": 0.2\n}\n";
        std::fs::write(&p, text).unwrap();
        let (mut file, s, note) = SettingsFile::load(&p);
        let unknown = format!("settings {}: unknown key \"theme\" is not used", p.display());
        assert_eq!((s.scale, s.deadzone, note), (2, 0.2, Some(unknown)));
        assert!(file.save(&Settings { ghost: false, ..s.clone() }).unwrap());
        // Keys come out in name order; the values not changed are the file's own.
        let want = "{\n  \"deadzone\": 0.2,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
        assert!(file.save(&Settings { ghost: false, deadzone: 0.25, ..s }).unwrap());
        let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
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
}
