//! Where a write lands: the end of a chain of symbolic links, the folder a file goes in, and the temporary
//! sibling a file is written to before it is renamed into place.

use std::path::{Path, PathBuf};

/// The folder a file named by `path` goes in (`.` for a bare name).
#[must_use]
pub fn folder_of(path: &Path) -> &Path {
    path.parent().filter(|d| !d.as_os_str().is_empty()).unwrap_or(Path::new("."))
}

/// Most symbolic links followed to find the file a write replaces (Linux's own limit is 40).
const MAX_LINK_HOPS: usize = 40;

/// The file a write to `path` should replace: the end of its chain of symbolic links (so that a linked
/// settings file stays a link, and a link to a link too), else `path` itself. Relative link targets are
/// resolved against the folder of the link that names them. A chain longer than `MAX_LINK_HOPS` (a
/// loop) stops where it is, and the write then fails or replaces that link, never anything outside it.
#[must_use]
pub fn write_target(path: &Path) -> PathBuf {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_LINK_HOPS {
        match std::fs::read_link(&current) {
            Ok(target) if target.is_absolute() => current = target,
            Ok(target) => {
                let dir = current.parent().map(Path::to_path_buf).unwrap_or_default();
                current = dir.join(target);
            }
            Err(_) => break,
        }
    }
    current
}

/// A sibling of `target` that no other writer uses: `.NAME.PID.N.tmp` in the same folder, so that the
/// final rename stays within one file system.
#[must_use]
pub fn temp_sibling(target: &Path) -> PathBuf {
    use std::sync::atomic::{AtomicU32, Ordering};
    static NEXT: AtomicU32 = AtomicU32::new(0);
    let name = target.file_name().map_or_else(|| "file".into(), |n| n.to_string_lossy().into_owned());
    let n = NEXT.fetch_add(1, Ordering::Relaxed);
    let tmp = format!(".{name}.{}.{n}.tmp", std::process::id());
    target.parent().filter(|d| !d.as_os_str().is_empty()).map_or_else(|| PathBuf::from(&tmp), |d| d.join(&tmp))
}

/// Most temporary names tried beside one target before giving up (each taken name is another try).
const MAX_TEMP_TRIES: usize = 64;

/// Creates a new temporary sibling of `target` ([`temp_sibling`]) and opens it for writing. A name that is
/// taken (a file a killed run left, whose process number this run now has) is never written through: the
/// next name is tried.
pub fn create_temp_sibling(target: &Path) -> std::io::Result<(PathBuf, std::fs::File)> {
    let mut last = std::io::Error::from(std::io::ErrorKind::AlreadyExists);
    for _ in 0..MAX_TEMP_TRIES {
        let tmp = temp_sibling(target);
        match std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
            Ok(file) => return Ok((tmp, file)),
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}
