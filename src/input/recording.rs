//! A race being recorded to a trace file: written to a new temporary file beside the target, and renamed
//! over the target only when there is a race to keep.
//!
//! Why: the target may hold a race the user wants to keep (their best race, or the very trace the ghost is
//! searched in: `play --ghost g.trace --record g.trace`), and a run that races nothing (quitting from the
//! main menu) must not cost it. So the target is untouched until [`Recording::finish`]: a race of at least
//! one tick replaces it (a race quit half-way is kept: its trace replays up to where it stopped, as a
//! crash-cut trace does); with nothing raced the temporary file is removed and the target stays as it was.
//! A process killed mid-race leaves the race in the temporary file (`.NAME.PID.N.tmp` beside `NAME`), and a
//! rename that fails leaves it there too and says so; a recorded race is never deleted. The next run that
//! records to `NAME` names such files ([`left_behind`]), so a race a SIGKILL or a power cut interrupted is
//! not forgotten in a hidden file.

use std::path::{Path, PathBuf};

use thiserror::Error;

use super::trace::{Header, TraceError, TraceWriter};
use crate::userfile::{UserFileError, WriteProblem, create_temp_sibling, temp_sibling, write_target};

/// Why a race could not be recorded or kept.
#[derive(Debug, Error)]
pub enum RecordError {
    /// The target exists and is not a regular file (a folder, a FIFO, a device).
    #[error("cannot record to {0}")]
    Target(#[from] UserFileError),
    /// The temporary file beside the target could not be created.
    #[error("cannot record to {}: {problem}", target.display())]
    Create {
        /// The file the race was to be recorded to.
        target: PathBuf,
        /// What stands in the way of a new file beside it.
        #[source]
        problem: WriteProblem,
    },
    /// Writing the trace failed.
    #[error("recording stopped: {0}")]
    Write(#[from] TraceError),
    /// The recorded race could not be moved into place; it is still in the temporary file.
    #[error("the race is recorded in {tmp} but could not be renamed to {target}: {problem}; rename it to keep it")]
    Keep {
        /// The temporary file holding the race.
        tmp: PathBuf,
        /// The file it was meant to replace.
        target: PathBuf,
        /// What failed.
        #[source]
        problem: KeepProblem,
    },
}

/// Why a recorded race could not be moved into place.
#[derive(Debug, Error)]
pub enum KeepProblem {
    /// The trace could not be flushed to the disk first.
    #[error(transparent)]
    Sync(TraceError),
    /// The rename failed.
    #[error(transparent)]
    Rename(std::io::Error),
}

/// What [`Recording::finish`] did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Kept {
    /// The race replaced the target.
    Race {
        /// The target, as named by the user.
        path: PathBuf,
        /// Ticks recorded.
        ticks: u64,
    },
    /// Nothing was raced: the temporary file is gone and the target is as it was.
    Nothing {
        /// The target, as named by the user.
        path: PathBuf,
    },
}

impl std::fmt::Display for Kept {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Kept::Race { path, ticks } => write!(
                f,
                "recorded {ticks} ticks ({:.1} s) to {}",
                *ticks as f64 / f64::from(crate::game::TICK_HZ),
                path.display()
            ),
            Kept::Nothing { path } => write!(f, "no race to record: {} not written", path.display()),
        }
    }
}

/// Races recorded to one target by runs that were killed before they could rename them into place.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LeftBehind {
    /// The target, as named by the user.
    pub target: PathBuf,
    /// The temporary files holding the races, in name order.
    pub files: Vec<PathBuf>,
}

impl std::fmt::Display for LeftBehind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let names: Vec<String> = self.files.iter().map(|p| p.display().to_string()).collect();
        match names.as_slice() {
            [one] => write!(
                f,
                "a race recorded to {} by a run that was killed is in {one}; rename it to keep it",
                self.target.display()
            ),
            _ => write!(
                f,
                "{} races recorded to {} by runs that were killed are in {}; rename one to keep it",
                names.len(),
                self.target.display(),
                names.join(", ")
            ),
        }
    }
}

/// The temporary recordings beside `target` (`.NAME.PID.N.tmp`, see [`crate::userfile::temp_sibling`])
/// that hold a race and whose process no longer runs; `None` when there are none. A file of a process that
/// still runs (another game recording to the same name) is not named.
#[must_use]
pub fn left_behind(target: &Path) -> Option<LeftBehind> {
    let dest = write_target(target);
    let name = dest.file_name()?.to_string_lossy().into_owned();
    let folder = crate::userfile::folder_of(&dest);
    let prefix = format!(".{name}.");
    let mut files: Vec<PathBuf> = std::fs::read_dir(folder)
        .ok()?
        .flatten()
        .filter_map(|entry| {
            let file = entry.file_name().to_string_lossy().into_owned();
            let middle = file.strip_prefix(&prefix)?.strip_suffix(".tmp")?;
            let (pid, n) = middle.split_once('.')?;
            let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
            let pid: u32 = pid.parse().ok().filter(|_| digits(n))?;
            // A bare target's folder is `.`: the file is named as the user would name it.
            let path = if folder == Path::new(".") { PathBuf::from(entry.file_name()) } else { entry.path() };
            (entry.file_type().is_ok_and(|t| t.is_file()) && !runs(pid) && holds_a_race(&path)).then_some(path)
        })
        .collect();
    files.sort();
    (!files.is_empty()).then(|| LeftBehind { target: target.to_path_buf(), files })
}

/// Whether another process numbered `pid` runs now: looked up in `/proc` where there is one, else asked
/// of `kill -0`. This process's own number is not another process: [`left_behind`] is asked before this
/// process records to the target, so a file of that name is a killed run's whose number was reused.
fn runs(pid: u32) -> bool {
    if pid == std::process::id() {
        return false;
    }
    if Path::new("/proc/self").exists() {
        return Path::new("/proc").join(pid.to_string()).exists();
    }
    std::process::Command::new("kill")
        .args(["-0", &pid.to_string()])
        .stderr(std::process::Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

/// Whether the trace at `path` holds at least one record after its header (a run killed before its first
/// tick left nothing to keep).
fn holds_a_race(path: &Path) -> bool {
    super::trace::TraceReader::open(path).is_ok_and(|(_, mut reader)| matches!(reader.next_record(), Ok(Some(_))))
}

/// A trace being written beside its target (see the module documentation).
pub struct Recording {
    /// The target as named by the user (for messages).
    target: PathBuf,
    /// The file the rename replaces: the target, or the file its symbolic link names.
    dest: PathBuf,
    /// The temporary file being written.
    tmp: PathBuf,
    /// `None` once finished.
    writer: Option<TraceWriter>,
}

impl Recording {
    /// Starts recording a race with `header` for `target`: checks that the target is a regular file or
    /// does not exist, and writes the header to a new temporary file beside it (never touching the target).
    pub fn start(target: &Path, header: &Header) -> Result<Self, RecordError> {
        let dest = write_target(target);
        match crate::userfile::check_regular(&dest, u64::MAX, "a trace") {
            Ok(_) => {}
            Err(e) if e.is_not_found() => {}
            Err(e) => return Err(e.into()),
        }
        let (tmp, file) = create_temp_sibling(&dest).map_err(|e| RecordError::Create {
            target: target.to_path_buf(),
            problem: WriteProblem::of(e, &temp_sibling(&dest)),
        })?;
        match TraceWriter::new(file, &tmp.display().to_string(), header) {
            Ok(w) => Ok(Self { target: target.to_path_buf(), dest, tmp, writer: Some(w) }),
            Err(e) => {
                let _ = std::fs::remove_file(&tmp);
                Err(e.into())
            }
        }
    }

    /// The writer, for [`super::replay::step_recorded`]; `None` once finished.
    pub fn writer(&mut self) -> Option<&mut TraceWriter> {
        self.writer.as_mut()
    }

    /// The file being recorded to, as named by the user.
    #[must_use]
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Ends the recording without keeping it: the temporary file is removed and the target is untouched.
    pub fn discard(&mut self) {
        if self.writer.take().is_some() {
            let _ = std::fs::remove_file(&self.tmp);
        }
    }

    /// Ends the recording: renames the temporary file over the target when at least one tick was
    /// recorded, else removes it. Calling it again does nothing and returns [`Kept::Nothing`].
    pub fn finish(&mut self) -> Result<Kept, RecordError> {
        let nothing = Kept::Nothing { path: self.target.clone() };
        let Some(mut writer) = self.writer.take() else {
            let _ = std::fs::remove_file(&self.tmp);
            return Ok(nothing);
        };
        let ticks = writer.ticks();
        if ticks == 0 {
            drop(writer);
            let _ = std::fs::remove_file(&self.tmp);
            return Ok(nothing);
        }
        let keep = |problem| RecordError::Keep { tmp: self.tmp.clone(), target: self.target.clone(), problem };
        writer.sync().map_err(|e| keep(KeepProblem::Sync(e)))?;
        drop(writer);
        std::fs::rename(&self.tmp, &self.dest).map_err(|e| keep(KeepProblem::Rename(e)))?;
        Ok(Kept::Race { path: self.target.clone(), ticks })
    }
}

impl Drop for Recording {
    /// A recording dropped without [`Recording::finish`] (a panic, an early return) is finished here; a
    /// failure can only be printed.
    fn drop(&mut self) {
        if self.writer.is_some()
            && let Err(e) = self.finish()
        {
            // Not `eprintln!`, which panics when the terminal has gone; the race is in the file either way.
            let _ = std::io::Write::write_fmt(&mut std::io::stderr(), format_args!("scanline-racer: error: {e}\n"));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::game::Controls;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("recording-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    fn header() -> Header {
        Header {
            course: "circuit".into(),
            car: 1,
            mode: "race".into(),
            difficulty: "normal".into(),
            sim_version: super::super::trace::SIM_VERSION,
            game_version: "test".into(),
            track_length_mm: 1000,
            cars: 8,
            laps: 3,
            seed: 0,
            tick_hz: crate::game::TICK_HZ,
            checksum_every: 120,
        }
    }

    fn files(d: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            std::fs::read_dir(d).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
        v.sort();
        v
    }

    #[test]
    fn nothing_raced_leaves_the_target_as_it_was() {
        let d = dir("nothing");
        let target = d.join("best.trace");
        std::fs::write(&target, b"the user's race").unwrap();
        let mut rec = Recording::start(&target, &header()).unwrap();
        assert_eq!(std::fs::read(&target).unwrap(), b"the user's race", "untouched while recording");
        assert_eq!(files(&d).len(), 2, "the temporary file is beside it: {:?}", files(&d));
        assert_eq!(rec.finish().unwrap(), Kept::Nothing { path: target.clone() });
        assert_eq!(std::fs::read(&target).unwrap(), b"the user's race");
        assert_eq!(files(&d), ["best.trace"]);
        // Dropped without finishing: the same.
        drop(Recording::start(&target, &header()).unwrap());
        assert_eq!(files(&d), ["best.trace"]);
    }

    #[test]
    fn a_race_replaces_the_target_and_a_failed_rename_keeps_the_race() {
        let d = dir("race");
        let target = d.join("best.trace");
        std::fs::write(&target, b"old").unwrap();
        let mut rec = Recording::start(&target, &header()).unwrap();
        for _ in 0..3 {
            rec.writer().unwrap().controls(Controls { steer: 0.5, throttle: 1.0, brake: 0.0 }).unwrap();
        }
        assert_eq!(rec.finish().unwrap(), Kept::Race { path: target.clone(), ticks: 3 });
        let bytes = std::fs::read(&target).unwrap();
        assert!(bytes.starts_with(super::super::trace::MAGIC) && bytes.ends_with(&[1, 0x00, 0x40, 255, 0]));
        assert_eq!(files(&d), ["best.trace"]);
        // The target turned into a folder with a file in it meanwhile: the rename fails, the race stays.
        let mut rec = Recording::start(&target, &header()).unwrap();
        rec.writer().unwrap().controls(Controls::default()).unwrap();
        std::fs::remove_file(&target).unwrap();
        std::fs::create_dir_all(target.join("inside")).unwrap();
        let e = rec.finish().unwrap_err();
        let RecordError::Keep { tmp, .. } = &e else { panic!("{e}") };
        assert!(tmp.exists() && std::fs::read(tmp).unwrap().starts_with(super::super::trace::MAGIC));
        let msg = e.to_string();
        assert!(msg.contains(&tmp.display().to_string()) && msg.ends_with("rename it to keep it"), "{msg}");
        assert!(!msg.contains('\n'));
    }

    #[test]
    fn a_killed_run_s_recording_is_named_and_a_running_one_s_is_not() {
        let d = dir("left");
        let target = d.join("race.trace");
        assert_eq!(left_behind(&target), None);
        // A race of one tick, as a killed run leaves it.
        let race = |path: &Path, ticks: usize| {
            let mut w = TraceWriter::new(std::fs::File::create(path).unwrap(), "test", &header()).unwrap();
            for _ in 0..ticks {
                w.controls(Controls::default()).unwrap();
            }
            w.sync().unwrap();
        };
        // No process has a PID this high (Linux's limit is 2^22).
        let dead = d.join(".race.trace.4294967290.0.tmp");
        race(&dead, 1);
        // This process's own number: a killed run's whose number was reused (as PID 1 in a container is).
        let reused = d.join(format!(".race.trace.{}.7.tmp", std::process::id()));
        race(&reused, 2);
        // Killed before its first tick: nothing to keep.
        race(&d.join(".race.trace.4294967292.0.tmp"), 0);
        for other in [".other.trace.4294967290.0.tmp", ".race.trace.x.0.tmp", ".race.trace.4294967290.tmp"] {
            race(&d.join(other), 1);
        }
        let left = left_behind(&target).unwrap();
        let mut want = vec![dead.clone(), reused.clone()];
        want.sort();
        assert_eq!(left.files, want);
        std::fs::remove_file(&reused).unwrap();
        let left = left_behind(&target).unwrap();
        assert_eq!(
            left.to_string(),
            format!(
                "a race recorded to {} by a run that was killed is in {}; rename it to keep it",
                target.display(),
                dead.display()
            )
        );
        race(&d.join(".race.trace.4294967291.0.tmp"), 1);
        let two = left_behind(&target).unwrap().to_string();
        assert!(two.starts_with("2 races recorded to") && two.ends_with("; rename one to keep it"), "{two}");
    }

    #[test]
    fn a_folder_is_refused_and_a_link_is_followed() {
        let d = dir("refuse");
        let e = Recording::start(&d, &header()).err().unwrap();
        assert!(e.to_string().ends_with("is a folder, not a regular file"), "{e}");
        #[cfg(unix)]
        {
            std::fs::write(d.join("real.trace"), b"old").unwrap();
            std::os::unix::fs::symlink("real.trace", d.join("link.trace")).unwrap();
            let mut rec = Recording::start(&d.join("link.trace"), &header()).unwrap();
            rec.writer().unwrap().controls(Controls::default()).unwrap();
            rec.finish().unwrap();
            assert!(std::fs::symlink_metadata(d.join("link.trace")).unwrap().file_type().is_symlink());
            assert!(std::fs::read(d.join("real.trace")).unwrap().starts_with(super::super::trace::MAGIC));
        }
    }
}
