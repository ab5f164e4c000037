//! The settings file as a run knows it: where it is, the settings last loaded or saved there, and whether
//! it may be written; and where it is when no `--settings` is given.
//!
//! The record reading and saving share, below both: `read` makes it (`SettingsFile::load`), `save` writes
//! through it (`SettingsFile::save`).

use std::path::{Path, PathBuf};

use super::values::Settings;

/// The settings file: where it is, what was last loaded or saved, and whether it may be written.
#[derive(Clone, Debug)]
pub struct SettingsFile {
    /// Where the file is.
    pub(super) path: PathBuf,
    /// The settings as this run last loaded or saved them; a setting that differs from this is saved.
    pub(super) saved: Settings,
    /// False when the file could not be read as a JSON object (at start, or at a save): it is then left
    /// alone for the rest of the run.
    pub(super) writable: bool,
}

impl SettingsFile {
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
