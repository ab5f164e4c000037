//! The player's records: the best lap per course, car, mode and difficulty, and the best race time per the
//! same and the laps, kept in `records.json` in the XDG data folder (`~/.local/share/scanline-racer/`), with
//! the time trial's ghosts in `ghosts/` beside it.
//!
//! The file follows the settings file's rules: read only when it is a regular file, within a byte budget;
//! written through a temporary file renamed over it; and a file that does not parse is never written (the
//! records of the run are kept in memory and a notice says why they are not saved).

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::game::{Difficulty, Mode};
use crate::userfile::UserFileError;

/// Largest records file read (thousands of records fit in a few hundred KB).
pub const MAX_RECORDS_BYTES: u64 = 1024 * 1024;
/// Most records kept of each kind (the slowest go first).
const MAX_RECORDS: usize = 2000;

/// What a record is of: the course, the car (1 to 8), the mode and the difficulty.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct RecordKey {
    /// The course's name.
    pub course: String,
    /// The car, 1 to 8.
    pub car: u32,
    /// `race` or `time-trial`.
    pub mode: String,
    /// `easy`, `normal` or `hard`.
    pub difficulty: String,
}

impl RecordKey {
    /// The key of a race on `course` in `car` (its garage index) of `mode` and `difficulty`; a time trial
    /// has no AI, so its difficulty is always `normal` (one record, and one ghost, per course and car).
    #[must_use]
    pub fn new(course: &str, car: usize, mode: Mode, difficulty: Difficulty) -> Self {
        let difficulty = if mode == Mode::TimeTrial { Difficulty::Normal } else { difficulty };
        Self {
            course: course.to_string(),
            car: car as u32 + 1,
            mode: mode.name().to_string(),
            difficulty: difficulty.name().to_string(),
        }
    }
}

/// A best lap.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct LapRecord {
    /// What it is the best lap of.
    #[serde(flatten)]
    pub key: RecordKey,
    /// The lap's time in simulation ticks (1/120 s).
    pub ticks: u64,
}

/// A best race.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct RaceRecord {
    /// What it is the best race of.
    #[serde(flatten)]
    pub key: RecordKey,
    /// Laps of the race.
    pub laps: u32,
    /// From the green light to the flag, in ticks.
    pub ticks: u64,
}

/// Every record. A file with any other top-level key is not a records file (so that another JSON file
/// named by mistake is refused, never overwritten).
#[derive(Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Records {
    /// The best laps, one per key.
    #[serde(default)]
    pub laps: Vec<LapRecord>,
    /// The best races, one per key and laps.
    #[serde(default)]
    pub races: Vec<RaceRecord>,
}

impl Records {
    /// Takes every record of `other` (a faster one replaces the one here).
    pub fn merge(&mut self, other: &Records) {
        for r in &other.laps {
            self.lap(&r.key, r.ticks);
        }
        for r in &other.races {
            self.race(&r.key, r.laps, r.ticks);
        }
    }

    /// The best lap of `key`, if any.
    #[must_use]
    pub fn best_lap(&self, key: &RecordKey) -> Option<u64> {
        self.laps.iter().find(|r| r.key == *key).map(|r| r.ticks)
    }

    /// Takes a lap of `ticks` for `key`; true when it is a new best.
    pub fn lap(&mut self, key: &RecordKey, ticks: u64) -> bool {
        match self.laps.iter_mut().find(|r| r.key == *key) {
            Some(r) if r.ticks <= ticks => false,
            Some(r) => {
                r.ticks = ticks;
                true
            }
            None => {
                trim(&mut self.laps, |r| r.ticks);
                self.laps.push(LapRecord { key: key.clone(), ticks });
                true
            }
        }
    }

    /// Takes a race of `laps` laps in `ticks` for `key`; true when it is a new best.
    pub fn race(&mut self, key: &RecordKey, laps: u32, ticks: u64) -> bool {
        match self.races.iter_mut().find(|r| r.key == *key && r.laps == laps) {
            Some(r) if r.ticks <= ticks => false,
            Some(r) => {
                r.ticks = ticks;
                true
            }
            None => {
                trim(&mut self.races, |r| r.ticks);
                self.races.push(RaceRecord { key: key.clone(), laps, ticks });
                true
            }
        }
    }

    /// The `n` best laps on `course`, fastest first (ties in key order).
    #[must_use]
    pub fn top_laps(&self, course: &str, n: usize) -> Vec<&LapRecord> {
        let mut v: Vec<&LapRecord> = self.laps.iter().filter(|r| r.key.course == course).collect();
        v.sort_by(|a, b| a.ticks.cmp(&b.ticks).then_with(|| a.key.cmp(&b.key)));
        v.truncate(n);
        v
    }
}

/// Makes room for one more record: keeps the fastest [`MAX_RECORDS`] - 1 (the one added next always stays).
fn trim<T>(list: &mut Vec<T>, ticks: impl Fn(&T) -> u64) {
    if list.len() >= MAX_RECORDS {
        list.sort_by_key(&ticks);
        list.truncate(MAX_RECORDS - 1);
    }
}

/// Where the records are: `$SCANLINE_RACER_RECORDS`, else `$XDG_DATA_HOME/scanline-racer/records.json`, else
/// `~/.local/share/scanline-racer/records.json`; `None` with no home.
#[must_use]
pub fn default_path() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("SCANLINE_RACER_RECORDS").filter(|p| !p.is_empty()) {
        return Some(PathBuf::from(p));
    }
    let data = std::env::var_os("XDG_DATA_HOME").filter(|p| !p.is_empty()).map(PathBuf::from).or_else(|| {
        std::env::var_os("HOME").filter(|p| !p.is_empty()).map(|h| PathBuf::from(h).join(".local/share"))
    })?;
    Some(data.join("scanline-racer").join("records.json"))
}

/// Why the records could not be read or saved.
#[derive(Debug, thiserror::Error)]
pub enum RecordsError {
    /// The file is not a regular file, is too big, or cannot be read or written.
    #[error("records: {0}")]
    File(#[from] UserFileError),
    /// The file is not the JSON records are kept in: it is left as it is, and this run's records are not
    /// saved.
    #[error("records: {path} does not parse ({source}); it is left as it is and this run's records are not saved")]
    Json {
        /// The file.
        path: PathBuf,
        /// What the parser said.
        source: serde_json::Error,
    },
    /// The records could not be written as JSON (cannot happen with these types; kept typed).
    #[error("records: cannot write them as JSON: {0}")]
    Encode(#[source] serde_json::Error),
    /// The folder for the file could not be made.
    #[error("records: cannot make the folder {path}: {source}")]
    Folder {
        /// The folder.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
}

/// The records file and the records in it.
#[derive(Debug)]
pub struct RecordsFile {
    path: PathBuf,
    /// The records (from the file, and this run's).
    pub records: Records,
    /// False when the file did not parse: then it is never written.
    writable: bool,
}

impl RecordsFile {
    /// Reads the records at `path` (a missing file is no records); a file that cannot be read or does not
    /// parse gives no records, a file never written, and the error saying why.
    #[must_use]
    pub fn load(path: &Path) -> (Self, Option<RecordsError>) {
        let mut file = Self { path: path.to_path_buf(), records: Records::default(), writable: true };
        match crate::userfile::read_regular_text(path, MAX_RECORDS_BYTES, "a records file") {
            Ok(text) => match serde_json::from_str(&text) {
                Ok(r) => file.records = r,
                Err(source) => {
                    file.writable = false;
                    return (file, Some(RecordsError::Json { path: path.to_path_buf(), source }));
                }
            },
            Err(e) if e.is_not_found() => {}
            Err(e) => {
                file.writable = false;
                return (file, Some(e.into()));
            }
        }
        (file, None)
    }

    /// The file's path.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Where the time trial's ghost of `key` is kept: `ghosts/COURSE-car-N.trace` beside the records.
    #[must_use]
    pub fn ghost_path(&self, key: &RecordKey) -> PathBuf {
        crate::userfile::folder_of(&self.path).join("ghosts").join(format!("{}-car-{}.trace", key.course, key.car))
    }

    /// Whether the file may be written (it parsed, or there was none).
    #[must_use]
    pub fn writable(&self) -> bool {
        self.writable
    }

    /// Writes the records through a temporary file renamed over the file (making its folder), merged with
    /// the file as it is now (another run's records, or a hand edit, are kept; the faster of two stays); a
    /// file that did not parse, when read or now, is not written.
    pub fn save(&mut self) -> Result<(), RecordsError> {
        if !self.writable {
            return Ok(());
        }
        let (now, problem) = RecordsFile::load(&self.path);
        if let Some(e) = problem {
            self.writable = false;
            return Err(e);
        }
        self.records.merge(&now.records);
        let folder = crate::userfile::folder_of(&self.path);
        std::fs::create_dir_all(folder)
            .map_err(|source| RecordsError::Folder { path: folder.to_path_buf(), source })?;
        let mut text = serde_json::to_string_pretty(&self.records).map_err(RecordsError::Encode)?;
        text.push('\n');
        crate::userfile::replace_atomically(&self.path, text.as_bytes())?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("records-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn key(course: &str, car: usize) -> RecordKey {
        RecordKey::new(course, car, Mode::TimeTrial, Difficulty::Normal)
    }

    #[test]
    fn records_round_trip_and_keep_only_the_best() {
        let d = dir("round");
        let path = d.join("sub/records.json");
        let (mut f, e) = RecordsFile::load(&path);
        assert!(e.is_none() && f.records == Records::default());
        assert!(f.records.lap(&key("city", 4), 9000));
        assert!(!f.records.lap(&key("city", 4), 9100), "slower is no record");
        assert!(f.records.lap(&key("city", 4), 8900));
        assert!(f.records.lap(&key("city", 1), 8800));
        assert!(f.records.lap(&key("circuit", 1), 8000));
        assert!(f.records.race(&key("city", 4), 3, 30000));
        assert!(f.records.race(&key("city", 4), 5, 50000), "another number of laps is another record");
        f.save().unwrap();
        let (g, e) = RecordsFile::load(&path);
        assert!(e.is_none());
        assert_eq!(g.records, f.records);
        let top: Vec<u64> = g.records.top_laps("city", 5).iter().map(|r| r.ticks).collect();
        assert_eq!(top, vec![8800, 8900]);
        assert_eq!(g.records.best_lap(&key("city", 4)), Some(8900));
        assert_eq!(g.ghost_path(&key("city", 4)), d.join("sub/ghosts/city-car-5.trace"));
    }

    #[test]
    fn a_hostile_records_file_is_refused_and_never_rewritten() {
        let d = dir("hostile");
        let path = d.join("records.json");
        std::fs::write(&path, "{ not json").unwrap();
        let (mut f, e) = RecordsFile::load(&path);
        assert!(matches!(e, Some(RecordsError::Json { .. })), "{e:?}");
        assert!(f.records.lap(&key("city", 0), 100));
        f.save().unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), "{ not json", "a file that did not parse is kept");
        // A folder, and a file over the budget, are refused with the file error.
        let (_, e) = RecordsFile::load(&d);
        assert!(matches!(e, Some(RecordsError::File(_))), "{e:?}");
        let big = d.join("big.json");
        std::fs::write(&big, vec![b' '; MAX_RECORDS_BYTES as usize + 1]).unwrap();
        let (mut f, e) = RecordsFile::load(&big);
        assert!(matches!(e, Some(RecordsError::File(_))), "{e:?}");
        f.save().unwrap();
        assert_eq!(std::fs::metadata(&big).unwrap().len(), MAX_RECORDS_BYTES + 1, "not written either");
        // Wrong types inside valid JSON do not parse either, and another JSON file (a settings file named
        // by mistake) is no records file.
        std::fs::write(&path, "{\"laps\": [{\"course\": 3}]}").unwrap();
        assert!(matches!(RecordsFile::load(&path).1, Some(RecordsError::Json { .. })));
        std::fs::write(&path, "{\"scale\": 2}").unwrap();
        assert!(matches!(RecordsFile::load(&path).1, Some(RecordsError::Json { .. })));
    }

    #[test]
    fn a_save_goes_through_a_temporary_file_so_a_kill_leaves_the_old_file() {
        let d = dir("atomic");
        let path = d.join("records.json");
        let (mut f, _) = RecordsFile::load(&path);
        f.records.lap(&key("city", 0), 100);
        f.save().unwrap();
        let before = std::fs::read(&path).unwrap();
        // A kill during a save leaves a temporary sibling at most: the file itself is the old one, whole.
        std::fs::write(crate::userfile::temp_sibling(&path), b"{\"laps\": [").unwrap();
        let (g, e) = RecordsFile::load(&path);
        assert!(e.is_none());
        assert_eq!(g.records.best_lap(&key("city", 0)), Some(100));
        assert_eq!(std::fs::read(&path).unwrap(), before);
        // The next save replaces the file whole, merged with what another run saved meanwhile.
        let (mut g, _) = RecordsFile::load(&path);
        let (mut other, _) = RecordsFile::load(&path);
        other.records.lap(&key("circuit", 2), 70);
        other.save().unwrap();
        g.records.lap(&key("city", 0), 90);
        g.save().unwrap();
        let now = RecordsFile::load(&path).0.records;
        assert_eq!(now.best_lap(&key("city", 0)), Some(90));
        assert_eq!(now.best_lap(&key("circuit", 2)), Some(70), "the other run's record is kept");
    }
}
