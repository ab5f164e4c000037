//! The settings file: key bindings, gamepad deadzone and curve, pixel scale, the ghost car, and the sound's
//! master and effects volumes and mute, kept between runs.
//!
//! JSON, at `--settings FILE`, else `$SCANLINE_RACER_SETTINGS`, else
//! `$XDG_CONFIG_HOME/scanline-racer/settings.json` (or `~/.config/...`). A missing or empty file means
//! defaults and is created at the first change. A field of the wrong type or out of range (`"scale": -1`,
//! `2.5`, `"deadzone": "wide"`) gets its default and is named in one warning line; the rest of the file is
//! used. A file that cannot be read or is not a JSON object means defaults and one line saying why, and it
//! is never written in that run: one typo must not cost the user the rest of the file.
//!
//! What the file holds is in `values` (the settings, their defaults and ranges) and the file as a run knows
//! it in `file` (where it is, what was last saved, whether it may be written), below the two that use them:
//! reading the file field by field is in `read`; saving a change onto the file as it is at that moment
//! (never a file that does not parse; unknown keys and hand edits kept) is in `save`. This file only ties
//! them together.

mod file;
mod read;
mod save;
mod values;

pub use file::{SettingsFile, default_path};
pub use read::UnusableSettings;
pub use save::SettingsError;
pub use values::{DEFAULT_VOLUME, LAPS_RANGE, Settings, VOLUME_RANGE};

#[cfg(test)]
mod tests {
    use std::path::PathBuf;

    use super::*;
    use crate::input::bindings::{Action, Bindings};
    use crate::input::gamepad::{DEFAULT_CURVE, DEFAULT_DEADZONE};

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
    fn the_sound_settings_load_back_and_bad_ones_are_refused_field_by_field() {
        let p = tmp("sound.json");
        let _ = std::fs::remove_file(&p);
        let (mut file, s, _) = SettingsFile::load(&p);
        assert_eq!((s.volume, s.effects_volume, s.muted), (DEFAULT_VOLUME, 1.0, false));
        let s = Settings { volume: 0.35, effects_volume: 0.5, muted: true, ..s };
        assert!(file.save(&s).unwrap());
        assert_eq!(
            std::fs::read_to_string(&p).unwrap(),
            "{\n  \"effects_volume\": 0.5,\n  \"muted\": true,\n  \"volume\": 0.35\n}\n"
        );
        let (_, back, note) = SettingsFile::load(&p);
        assert_eq!((back, note), (s, None));
        // Each bad value costs only its own field, and is named; the good ones beside it are used.
        for (text, want, said) in [
            (
                r#"{"volume": 1.5, "effects_volume": 0.25, "muted": true}"#,
                (1.0, 0.25, true),
                "volume 1.5 out of 0-1: 1 used",
            ),
            (r#"{"volume": -0.1, "muted": true}"#, (1.0, 1.0, true), "volume -0.1 out of 0-1: 1 used"),
            (
                r#"{"volume": "loud", "effects_volume": 0.25}"#,
                (1.0, 0.25, false),
                "volume \"loud\" is not a number: 1 used",
            ),
            (r#"{"volume": 0.5, "effects_volume": 2}"#, (0.5, 1.0, false), "effects_volume 2 out of 0-1: 1 used"),
            (
                r#"{"volume": 0.5, "effects_volume": null}"#,
                (0.5, 1.0, false),
                "effects_volume null is not a number: 1 used",
            ),
            (r#"{"volume": 0.5, "muted": "yes"}"#, (0.5, 1.0, false), "muted \"yes\" is not true or false: false used"),
            (r#"{"volume": 0.5, "muted": 1}"#, (0.5, 1.0, false), "muted 1 is not true or false: false used"),
        ] {
            std::fs::write(&p, text).unwrap();
            let (file, s, note) = SettingsFile::load(&p);
            assert_eq!((s.volume, s.effects_volume, s.muted), want, "{text}");
            let note = note.unwrap_or_default();
            assert!(note.contains(said) && !note.contains('\n'), "{text}: {note}");
            assert!(file.writable(), "{text}: a repaired file is still saved");
        }
    }

    #[test]
    fn picture_choices_load_back_by_name_and_bad_ones_are_refused_field_by_field() {
        use crate::render::{Antialias, Filter, MipMode};
        let p = tmp("picture.json");
        let _ = std::fs::remove_file(&p);
        let (mut file, s, _) = SettingsFile::load(&p);
        assert_eq!((s.antialias, s.filter, s.mip), (Antialias::Off, Filter::Nearest, MipMode::Polygon));
        // A picture fixed by the player (not `auto`, the default).
        assert!(s.auto_quality);
        let s = Settings {
            antialias: Antialias::Samples8,
            filter: Filter::Trilinear,
            mip: MipMode::Span,
            auto_quality: false,
            ..s
        };
        assert!(file.save(&s).unwrap());
        assert_eq!(
            std::fs::read_to_string(&p).unwrap(),
            "{\n  \"antialias\": \"8x\",\n  \"auto_quality\": false,\n  \"filter\": \"trilinear\",\n  \"mip\": \"span\"\n}\n"
        );
        let (_, back, note) = SettingsFile::load(&p);
        assert_eq!((back, note), (s, None));
        // A file from before `auto` that names a picture keeps it; one that names none is `auto`.
        std::fs::write(&p, r#"{"antialias": "ssaa"}"#).unwrap();
        assert!(!SettingsFile::load(&p).1.auto_quality);
        std::fs::write(&p, r#"{"ghost": false}"#).unwrap();
        assert!(SettingsFile::load(&p).1.auto_quality);
        for (text, want, said) in [
            (
                r#"{"antialias": "6x", "filter": "bilinear"}"#,
                (Antialias::Off, Filter::Bilinear, MipMode::Polygon),
                "antialias \"6x\" is not off, 4x, 8x, 16x, ssaa or rgss: off used",
            ),
            (
                r#"{"antialias": 4, "mip": "pixel"}"#,
                (Antialias::Off, Filter::Nearest, MipMode::Pixel),
                "antialias 4 is not off, 4x, 8x, 16x, ssaa or rgss: off used",
            ),
            (
                r#"{"antialias": "ssaa", "filter": ["trilinear"]}"#,
                (Antialias::Supersample2x2, Filter::Nearest, MipMode::Polygon),
                "filter [\"trilinear\"] is not nearest, bilinear, min-bilinear, area, trilinear, aniso2, aniso4, aniso8 or aniso16: nearest used",
            ),
            (
                r#"{"mip": "Pixel", "filter": "trilinear"}"#,
                (Antialias::Off, Filter::Trilinear, MipMode::Polygon),
                "mip \"Pixel\" is not",
            ),
        ] {
            std::fs::write(&p, text).unwrap();
            let (file, s, note) = SettingsFile::load(&p);
            assert_eq!((s.antialias, s.filter, s.mip), want, "{text}");
            let note = note.unwrap_or_default();
            assert!(note.contains(said) && !note.contains('\n'), "{text}: {note}");
            assert!(file.writable(), "{text}: a repaired file is still saved");
        }
        // A refused name stays in the file when another setting is saved: the user's text is theirs to fix.
        std::fs::write(&p, r#"{"antialias": "6x"}"#).unwrap();
        let (mut file, s, _) = SettingsFile::load(&p);
        assert!(file.save(&Settings { ghost: false, ..s }).unwrap());
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"antialias\": \"6x\",\n  \"ghost\": false\n}\n");
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
