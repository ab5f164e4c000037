//! Reading and writing the user's files safely: regular files only, within a byte budget, and replacing a
//! file only through a new file renamed over it.
//!
//! Why: opening a FIFO for reading blocks until a writer appears, and `/dev/zero` or a character device
//! never ends, so every file the program reads (scenes, buffers, images, traces, settings, the centre line)
//! goes through [`open_regular`] / [`read_regular`], which look at what the path is before opening it and
//! read no more than the caller's budget. Writes that replace a file go through [`replace_atomically`], which
//! writes a sibling temporary file and renames it over the target (following a symbolic link to the file it
//! names), so a crash or a full disk never leaves a half-written file where the user's was.
//!
//! A write that fails says what stands in its way ([`WriteProblem`]: the missing folder, the permission,
//! the read-only or full device), and [`Inputs`] holds the files a command reads so that no output path,
//! however spelt or linked, writes over one of them.

mod identity;
mod paths;
mod problem;

pub use identity::{FileId, Inputs, check_distinct};
pub use paths::{create_temp_sibling, folder_of, temp_sibling, write_target};
pub use problem::{FileProblem, UserFileError, WriteProblem};

use std::fs::File;
use std::io::{Read, Write};
use std::path::Path;

fn io(path: &Path, e: std::io::Error) -> UserFileError {
    UserFileError::new(path, FileProblem::Io(e))
}

/// A failed write of `path`, saying what stands in its way.
fn write_failed(path: &Path, e: std::io::Error) -> UserFileError {
    UserFileError::new(path, FileProblem::Write(WriteProblem::of(e, path)))
}

fn not_regular(path: &Path, ft: std::fs::FileType) -> UserFileError {
    UserFileError::new(path, FileProblem::NotRegular { kind: kind_of(ft) })
}

/// What a file type is, in words, for messages.
fn kind_of(ft: std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if ft.is_fifo() {
            return "a FIFO";
        }
        if ft.is_char_device() || ft.is_block_device() {
            return "a device";
        }
        if ft.is_socket() {
            return "a socket";
        }
    }
    if ft.is_dir() { "a folder" } else { "not a regular file" }
}

/// Checks that `path` (after following links) is a regular file of at most `limit` bytes; returns its size.
pub fn check_regular(path: &Path, limit: u64, what: &'static str) -> Result<u64, UserFileError> {
    let meta = std::fs::metadata(path).map_err(|e| io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, meta.file_type()));
    }
    if meta.len() > limit {
        return Err(UserFileError::new(path, FileProblem::TooBig { size: meta.len(), limit, what }));
    }
    Ok(meta.len())
}

/// Opens `path` for reading if it is a regular file of at most `limit` bytes (checked before opening, so a
/// FIFO never blocks, and again on the open file); the reader stops at `limit` bytes whatever happens to
/// the file meanwhile.
pub fn open_regular(path: &Path, limit: u64, what: &'static str) -> Result<std::io::Take<File>, UserFileError> {
    check_regular(path, limit, what)?;
    let file = open_nonblocking(path).map_err(|e| io(path, e))?;
    let meta = file.metadata().map_err(|e| io(path, e))?;
    if !meta.is_file() {
        return Err(not_regular(path, meta.file_type()));
    }
    Ok(file.take(limit))
}

/// Opens `path` for reading without waiting for a writer: should the path have become a FIFO since it was
/// checked, the open returns at once and the check of the open file refuses it. (`O_NONBLOCK` has no
/// effect on reading a regular file.)
fn open_nonblocking(path: &Path) -> std::io::Result<File> {
    let mut options = std::fs::OpenOptions::new();
    options.read(true);
    #[cfg(any(target_os = "linux", target_os = "android"))]
    {
        use std::os::unix::fs::OpenOptionsExt;
        const O_NONBLOCK: i32 = 0o4000;
        options.custom_flags(O_NONBLOCK);
    }
    #[cfg(any(
        target_os = "macos",
        target_os = "ios",
        target_os = "freebsd",
        target_os = "openbsd",
        target_os = "netbsd"
    ))]
    {
        use std::os::unix::fs::OpenOptionsExt;
        const O_NONBLOCK: i32 = 0x0004;
        options.custom_flags(O_NONBLOCK);
    }
    options.open(path)
}

/// Reads a whole regular file of at most `limit` bytes.
pub fn read_regular(path: &Path, limit: u64, what: &'static str) -> Result<Vec<u8>, UserFileError> {
    let size = check_regular(path, limit, what)?;
    let mut reader = open_regular(path, limit, what)?;
    let mut out = Vec::with_capacity(usize::try_from(size).unwrap_or(0));
    reader.read_to_end(&mut out).map_err(|e| io(path, e))?;
    // A file that grew past the budget after the check: one byte more tells.
    let mut probe = [0u8; 1];
    if out.len() as u64 == limit && reader.into_inner().read(&mut probe).map_err(|e| io(path, e))? > 0 {
        return Err(UserFileError::new(path, FileProblem::TooBig { size: limit + 1, limit, what }));
    }
    Ok(out)
}

/// Reads a whole regular UTF-8 text file of at most `limit` bytes.
pub fn read_regular_text(path: &Path, limit: u64, what: &'static str) -> Result<String, UserFileError> {
    let bytes = read_regular(path, limit, what)?;
    String::from_utf8(bytes).map_err(|e| UserFileError::new(path, FileProblem::NotUtf8(e)))
}

/// Checks, before any long work, that `path` can take an output file: it does not exist or is a regular
/// file (not a folder, FIFO or device, which would fail or block only at the end), and its folder exists
/// and takes a new file (a probe file is made there and removed), so a missing folder, a missing
/// permission or a read-only device is said at once.
pub fn check_output(path: &Path) -> Result<(), UserFileError> {
    let target = write_target(path);
    match std::fs::metadata(&target) {
        Ok(meta) if !meta.is_file() => return Err(not_regular(&target, meta.file_type())),
        Ok(_) => {}
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
        Err(e) => return Err(write_failed(&target, e)),
    }
    match create_temp_sibling(&target) {
        Ok((probe, _)) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(write_failed(&target, e)),
    }
}

/// Replaces `path` (or the file its symbolic link names) with `bytes`: writes a temporary sibling, flushes
/// it, and renames it over the target, so the old file stays whole until the new one is.
pub fn replace_atomically(path: &Path, bytes: &[u8]) -> Result<(), UserFileError> {
    let target = write_target(path);
    if let Ok(meta) = std::fs::metadata(&target)
        && !meta.is_file()
    {
        return Err(not_regular(&target, meta.file_type()));
    }
    let old_permissions = std::fs::metadata(&target).ok().map(|m| m.permissions());
    // A new file: a stale file of a temporary name is never written through (it could be a link, or a race
    // a killed run left) nor removed.
    let (tmp, mut f) = create_temp_sibling(&target).map_err(|e| write_failed(&target, e))?;
    let result = (|| {
        f.write_all(bytes)?;
        // The new file keeps the old one's permissions (a private settings file stays private).
        if let Some(p) = old_permissions {
            f.set_permissions(p)?;
        }
        f.sync_all()?;
        std::fs::rename(&tmp, &target)
    })();
    result.map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        write_failed(&target, e)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn dir(name: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("userfile-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn refuses_folders_devices_and_big_files() {
        let d = dir("refuse");
        assert!(matches!(
            read_regular(&d, 10, "a test"),
            Err(UserFileError { problem: FileProblem::NotRegular { kind: "a folder" }, .. })
        ));
        #[cfg(unix)]
        assert!(matches!(
            read_regular(Path::new("/dev/zero"), 10, "a test"),
            Err(UserFileError { problem: FileProblem::NotRegular { kind: "a device" }, .. })
        ));
        let f = d.join("big");
        std::fs::write(&f, [1u8; 11]).unwrap();
        let e = read_regular(&f, 10, "a test").unwrap_err();
        assert_eq!(e.to_string(), format!("{}: 11 bytes is over the 10-byte limit for a test", f.display()));
        assert_eq!(read_regular(&f, 11, "a test").unwrap(), [1u8; 11]);
        assert!(read_regular(&d.join("missing"), 10, "a test").unwrap_err().is_not_found());
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let d = dir("fifo");
        let p = d.join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&p).status().map(|s| s.success()).unwrap_or(false);
        assert!(made, "mkfifo failed");
        assert!(matches!(
            read_regular(&p, 10, "a test"),
            Err(UserFileError { problem: FileProblem::NotRegular { kind: "a FIFO" }, .. })
        ));
    }

    #[cfg(unix)]
    #[test]
    fn replacing_keeps_a_link_a_link() {
        let d = dir("link");
        let real = d.join("real.json");
        std::fs::write(&real, "old").unwrap();
        let link = d.join("link.json");
        std::os::unix::fs::symlink("real.json", &link).unwrap();
        replace_atomically(&link, b"new").unwrap();
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "new");
        // A link to a link: the end of the chain is replaced, both links stay links.
        let outer = d.join("outer.json");
        std::os::unix::fs::symlink("link.json", &outer).unwrap();
        replace_atomically(&outer, b"newer").unwrap();
        assert!(std::fs::symlink_metadata(&outer).unwrap().file_type().is_symlink());
        assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read_to_string(&real).unwrap(), "newer");
        // A loop of links is not followed forever.
        let (a, b) = (d.join("a"), d.join("b"));
        std::os::unix::fs::symlink("b", &a).unwrap();
        std::os::unix::fs::symlink("a", &b).unwrap();
        let _ = write_target(&a);
        let leftovers: Vec<_> = std::fs::read_dir(&d)
            .unwrap()
            .filter_map(Result::ok)
            .filter(|e| e.path().extension() == Some("tmp".as_ref()))
            .collect();
        assert!(leftovers.is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn replacing_keeps_the_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let d = dir("perm");
        let f = d.join("private.json");
        std::fs::write(&f, "old").unwrap();
        std::fs::set_permissions(&f, std::fs::Permissions::from_mode(0o600)).unwrap();
        replace_atomically(&f, b"new").unwrap();
        assert_eq!(std::fs::metadata(&f).unwrap().permissions().mode() & 0o777, 0o600);
        assert_eq!(std::fs::read_to_string(&f).unwrap(), "new");
    }
}
