//! Why a user's file could not be read or written: the path and the problem, down to what stands in the
//! way of a write (the folder that is missing, the permission, the device that is read-only or full).
//!
//! Why the write problems: `std::io::Error`'s own words name the symptom of the call that failed ("No such
//! file or directory" for a new file whose folder is missing), not the thing that is wrong, and the path
//! they come with is the file's, not the folder's.

use std::path::{Path, PathBuf};

use thiserror::Error;

/// Why a user's file could not be read or written: the path, and what is wrong with it.
#[derive(Debug, Error)]
#[error("{path}: {problem}")]
pub struct UserFileError {
    /// The path (for a write through a link, the file the link leads to).
    pub path: PathBuf,
    /// What is wrong with it.
    #[source]
    pub problem: FileProblem,
}

/// What is wrong with a user's file.
#[derive(Debug, Error)]
pub enum FileProblem {
    /// The path does not exist or cannot be examined, opened, read or written.
    #[error("{}", io_reason(.0))]
    Io(#[source] std::io::Error),
    /// The file cannot be written: what stands in the way (the folder, the permission, the device).
    #[error(transparent)]
    Write(WriteProblem),
    /// An output path names a file the command reads (by another name, a link or a hard link too).
    #[error("it is {what}, which this command reads (name another file for the output)")]
    IsInput {
        /// Which input it is ("the glTF scene", "the trace", ...).
        what: &'static str,
    },
    /// Two outputs of one command name the same file.
    #[error("{other} names the same file")]
    SameOutput {
        /// The other output's flag (`--record`).
        other: &'static str,
    },
    /// The file is not UTF-8 text.
    #[error("not UTF-8 text ({0})")]
    NotUtf8(#[source] std::string::FromUtf8Error),
    /// The path names something that is not a regular file (a folder, a FIFO, a device, a socket).
    #[error("is {kind}, not a regular file")]
    NotRegular {
        /// What it is instead ("a folder", "a FIFO", ...).
        kind: &'static str,
    },
    /// The file is larger than the reader's budget.
    #[error("{size} bytes is over the {limit}-byte limit for {what}")]
    TooBig {
        /// Its size in bytes (or the bytes read before the budget ran out).
        size: u64,
        /// The budget in bytes.
        limit: u64,
        /// What kind of file the budget is for ("a glTF file", "a settings file", ...).
        what: &'static str,
    },
}

/// An I/O error as the one-line messages say it: "no such file" for a missing path, else the operating
/// system's words.
fn io_reason(e: &std::io::Error) -> String {
    if e.kind() == std::io::ErrorKind::NotFound { "no such file".to_string() } else { e.to_string() }
}

impl UserFileError {
    pub(super) fn new(path: &Path, problem: FileProblem) -> Self {
        Self { path: path.to_path_buf(), problem }
    }

    /// Whether the error means the path does not exist.
    #[must_use]
    pub fn is_not_found(&self) -> bool {
        matches!(&self.problem, FileProblem::Io(e) if e.kind() == std::io::ErrorKind::NotFound)
    }
}

/// Why a file could not be written, naming what is missing or in the way.
#[derive(Debug, Error)]
pub enum WriteProblem {
    /// The folder the file goes in does not exist.
    #[error("no such folder {}", .0.display())]
    NoFolder(PathBuf),
    /// A part of the path the file goes in is a file, not a folder.
    #[error("{} is a file, not a folder", .0.display())]
    NotAFolder(PathBuf),
    /// The user may not create files in the folder (or replace the file).
    #[error("no permission to write in the folder {}", .0.display())]
    NoPermission(PathBuf),
    /// The folder exists but takes no new files (a virtual file system such as `/proc`).
    #[error("the folder {} takes no new files ({})", .0.display(), .1.kind())]
    NoNewFiles(PathBuf, #[source] std::io::Error),
    /// The folder is on a read-only file system.
    #[error("the folder {} is on a read-only file system", .0.display())]
    ReadOnly(PathBuf),
    /// The device holding the folder is full.
    #[error("no space left on the device holding {}", .0.display())]
    DeviceFull(PathBuf),
    /// The user's disk quota is used up.
    #[error("the disk quota for {} is used up", .0.display())]
    Quota(PathBuf),
    /// Anything else: the operating system's words.
    #[error("{0}")]
    Other(#[source] std::io::Error),
}

impl WriteProblem {
    /// What `e`, met while writing `file` (or a temporary file beside it), says is in the way.
    #[must_use]
    pub fn of(e: std::io::Error, file: &Path) -> Self {
        use std::io::ErrorKind as K;
        let folder = super::paths::folder_of(file).to_path_buf();
        match e.kind() {
            K::NotFound if std::fs::metadata(&folder).is_err() => WriteProblem::NoFolder(folder),
            K::NotFound => WriteProblem::NoNewFiles(folder, e),
            K::NotADirectory => match first_non_folder(&folder) {
                Some(part) => WriteProblem::NotAFolder(part),
                None => WriteProblem::Other(e),
            },
            K::PermissionDenied => WriteProblem::NoPermission(folder),
            K::ReadOnlyFilesystem => WriteProblem::ReadOnly(folder),
            K::StorageFull => WriteProblem::DeviceFull(folder),
            K::QuotaExceeded => WriteProblem::Quota(folder),
            _ => WriteProblem::Other(e),
        }
    }
}

/// The first part of `folder`, from the root down, that exists and is not a folder.
fn first_non_folder(folder: &Path) -> Option<PathBuf> {
    let mut parts: Vec<&Path> = folder.ancestors().collect();
    parts.reverse();
    parts
        .into_iter()
        .filter(|p| !p.as_os_str().is_empty())
        .find(|p| std::fs::metadata(p).is_ok_and(|m| !m.is_dir()))
        .map(Path::to_path_buf)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::{Error, ErrorKind};

    #[test]
    fn each_error_names_what_is_in_the_way() {
        let d = std::env::temp_dir().join(format!("write-problem-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        let file = d.join("a-file");
        std::fs::write(&file, b"x").unwrap();
        let missing = d.join("no/dir/s.png");
        let msg = |k: ErrorKind, p: &Path| WriteProblem::of(Error::from(k), p).to_string();
        assert_eq!(msg(ErrorKind::NotFound, &missing), format!("no such folder {}", d.join("no/dir").display()));
        assert_eq!(
            msg(ErrorKind::NotADirectory, &file.join("sub/s.png")),
            format!("{} is a file, not a folder", file.display())
        );
        let out = d.join("s.png");
        assert_eq!(
            msg(ErrorKind::PermissionDenied, &out),
            format!("no permission to write in the folder {}", d.display())
        );
        assert_eq!(
            msg(ErrorKind::ReadOnlyFilesystem, &out),
            format!("the folder {} is on a read-only file system", d.display())
        );
        assert_eq!(msg(ErrorKind::StorageFull, &out), format!("no space left on the device holding {}", d.display()));
        assert_eq!(msg(ErrorKind::PermissionDenied, Path::new("s.png")), "no permission to write in the folder .");
        // A folder that exists but refuses a new file (as /proc does).
        assert_eq!(
            msg(ErrorKind::NotFound, &out),
            format!("the folder {} takes no new files (entity not found)", d.display())
        );
        assert!(matches!(WriteProblem::of(Error::from(ErrorKind::Interrupted), &out), WriteProblem::Other(_)));
    }
}
