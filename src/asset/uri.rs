//! Resolving the URIs a glTF file names, confined to the asset's own folder.
//!
//! `data:` URIs are decoded in memory. Any other scheme, an absolute path, or a path whose `..` components
//! climb above the folder is refused (`sub/../tri.bin` stays inside and is read), so a file cannot make the
//! loader read outside its folder; symbolic links that lead out of the folder are refused too. Each refusal
//! says what the URI breaks: a NUL byte is not an empty path, and a folder is not a file. Files are only
//! located first ([`locate`]: canonical path and size, nothing read), so that the loader can read a file
//! named twice once and refuse one over its budget before reading it; reading goes through
//! [`crate::userfile`] (regular files only: a FIFO or a device is refused without blocking).

use std::path::{Component, Path, PathBuf};

use base64::Engine;

use crate::userfile::{UserFileError, check_regular, read_regular};

/// Largest external file or decoded `data:` URI accepted (512 MiB).
pub const MAX_BYTES: u64 = 512 << 20;

/// Why a URI was refused or could not be read.
#[derive(Debug, thiserror::Error)]
pub enum UriError {
    /// Not a `data:` URI and not a plain relative path.
    #[error("URI '{uri}' refused: {why}")]
    Refused {
        /// The URI as written (shortened).
        uri: String,
        /// Why.
        why: Refusal,
    },
    /// A `data:` URI whose payload does not decode.
    #[error("data URI does not decode: {0}")]
    BadData(#[source] DataProblem),
    /// The file is not a regular file, is too big, or could not be read.
    #[error(transparent)]
    File(#[from] UserFileError),
    /// The path could not be resolved.
    #[error("cannot read '{path}': {source}")]
    Read {
        /// The path tried.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
}

/// Why a URI that is not a `data:` URI was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum Refusal {
    /// It has a scheme other than `data:`.
    #[error("the scheme '{0}:' is not read: only data: URIs and relative paths are")]
    Scheme(String),
    /// A `%` not followed by two hexadecimal digits, or bytes that are not UTF-8.
    #[error("bad percent-encoding")]
    PercentEncoding,
    /// Nothing at all.
    #[error("the URI is empty")]
    Empty,
    /// A NUL byte (`%00`), which no file name may hold.
    #[error("it holds a NUL byte (%00), which no file name may hold")]
    Nul,
    /// It ends in `/`: a folder, not a file.
    #[error("it names a folder, not a file")]
    Folder,
    /// An absolute path.
    #[error("absolute paths are not allowed")]
    Absolute,
    /// Its `..` components climb above the asset's folder (or it has a root or drive prefix).
    #[error("its '..' parts climb above the asset's folder")]
    LeavesFolder,
    /// A path inside the folder that a symbolic link leads out of it.
    #[error("the path leads out of the asset's folder through a link")]
    LinkLeavesFolder,
}

/// What is wrong with a `data:` URI.
#[derive(Debug, thiserror::Error)]
pub enum DataProblem {
    /// No `,` between the media type and the payload.
    #[error("no ',' in data URI")]
    NoComma,
    /// A payload that would decode to more than [`MAX_BYTES`].
    #[error("payload of {chars} characters is larger than the limit of {MAX_BYTES} bytes")]
    TooLarge {
        /// Characters in the payload.
        chars: usize,
    },
    /// A base64 payload that is not base64.
    #[error("{0}")]
    Base64(#[source] base64::DecodeError),
    /// A `%` not followed by two hexadecimal digits, or bytes that are not UTF-8.
    #[error("bad percent-encoding")]
    PercentEncoding,
}

fn short(uri: &str) -> String {
    let mut s: String = uri.chars().take(80).collect();
    if s.len() < uri.len() {
        s.push('…');
    }
    s
}

fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

/// Where the files a glTF file names are found: in its folder on disk, or in a table of files built into
/// the program (the game's own assets, so that an installed binary needs no folder beside it).
#[derive(Clone, Copy, Debug)]
pub enum Base<'a> {
    /// A folder on disk: URIs are paths relative to it and may not leave it.
    Folder(&'a Path),
    /// Files in memory, by their path in a tree (`track/circuit/circuit.bin`); URIs are relative to `dir` (its
    /// path in that tree, `""` for the top) and may not leave the tree.
    Embedded {
        /// The glTF file's folder in the tree (`track`).
        dir: &'a str,
        /// Every file of the tree, by path.
        files: &'a [(&'a str, &'a [u8])],
    },
}

/// Where the bytes a URI names are: in the URI itself (`data:`, still encoded), in a file inside the
/// asset's folder (its canonical path, so two spellings of one file are one source), or in a file built
/// into the program.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Located<'u> {
    /// A `data:` URI's payload.
    Data {
        /// Whether the payload is base64 (else percent-encoded).
        base64: bool,
        /// The encoded payload.
        payload: &'u str,
    },
    /// A file built into the program, by its path in the tree (normalised: one file, one name).
    Embedded {
        /// Its path in the tree.
        name: String,
        /// Its bytes.
        bytes: &'u [u8],
    },
    /// A regular file inside the asset's folder.
    File {
        /// Its canonical path.
        path: PathBuf,
        /// Its size in bytes when it was located.
        size: u64,
    },
}

impl Located<'_> {
    /// The most bytes reading this source gives (exact for a file, a bound for a `data:` URI), known
    /// before reading it, so that a budget can refuse it before the memory is taken.
    #[must_use]
    pub fn size_bound(&self) -> u64 {
        match self {
            Located::Data { base64: true, payload } => (payload.len() as u64).div_ceil(4) * 3,
            Located::Data { base64: false, payload } => payload.len() as u64,
            Located::Embedded { bytes, .. } => bytes.len() as u64,
            Located::File { size, .. } => *size,
        }
    }

    /// Reads (or decodes) the bytes: a file through [`crate::userfile::read_regular`], no more than the
    /// size it had when located.
    pub fn read(&self) -> Result<Vec<u8>, UriError> {
        match self {
            Located::Data { base64: true, payload } => base64::engine::general_purpose::STANDARD
                .decode(payload.trim())
                .map_err(|e| UriError::BadData(DataProblem::Base64(e))),
            Located::Data { base64: false, payload } => {
                percent_decode(payload).map(String::into_bytes).ok_or(UriError::BadData(DataProblem::PercentEncoding))
            }
            Located::Embedded { bytes, .. } => Ok(bytes.to_vec()),
            Located::File { path, size } => Ok(read_regular(path, *size, WHAT)?),
        }
    }
}

/// What the files a glTF file names are called in size errors.
const WHAT: &str = "a file a glTF file names";

/// Finds what a URI names without reading it: a `data:` URI is checked for shape and size, a relative
/// path must stay inside the base folder (also through links) and be a regular file of at most
/// [`MAX_BYTES`], or name a file of the embedded tree.
pub fn locate<'u>(uri: &'u str, base: Base<'u>) -> Result<Located<'u>, UriError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (meta, payload) = rest.split_once(',').ok_or(UriError::BadData(DataProblem::NoComma))?;
        if payload.len() as u64 > MAX_BYTES * 4 / 3 + 4 {
            return Err(UriError::BadData(DataProblem::TooLarge { chars: payload.len() }));
        }
        return Ok(Located::Data { base64: meta.ends_with(";base64"), payload });
    }
    let refused = |why| UriError::Refused { uri: short(uri), why };
    let scheme_len = uri.find(':').unwrap_or(0);
    if scheme_len > 0 && uri[..scheme_len].chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)) {
        return Err(refused(Refusal::Scheme(short(&uri[..scheme_len]))));
    }
    let decoded = percent_decode(uri).ok_or_else(|| refused(Refusal::PercentEncoding))?;
    if decoded.is_empty() {
        return Err(refused(Refusal::Empty));
    }
    if decoded.contains('\0') {
        return Err(refused(Refusal::Nul));
    }
    let rel = Path::new(&decoded);
    if decoded.starts_with('/') || decoded.starts_with('\\') || rel.is_absolute() {
        return Err(refused(Refusal::Absolute));
    }
    if decoded.ends_with(['/', '\\']) {
        return Err(refused(Refusal::Folder));
    }
    if climbs_out(&decoded)
        || rel.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir | Component::ParentDir))
    {
        return Err(refused(Refusal::LeavesFolder));
    }
    let base_dir = match base {
        Base::Folder(dir) => dir,
        Base::Embedded { dir, files } => {
            let name = normalised(dir, &decoded);
            let found = files.iter().find(|(n, _)| *n == name);
            return match found {
                Some((_, bytes)) => Ok(Located::Embedded { name, bytes }),
                None => Err(UriError::Read {
                    path: PathBuf::from(format!("{name} (built into the program)")),
                    source: std::io::Error::from(std::io::ErrorKind::NotFound),
                }),
            };
        }
    };
    // The folder's own path joined with the URI's: the system resolves the `..` parts (through links, as
    // it will when reading), and the canonical path must still be inside the folder.
    let path = base_dir.join(rel);
    let read_err = |source: std::io::Error| UriError::Read { path: path.clone(), source };
    let canon = path.canonicalize().map_err(read_err)?;
    let base = base_dir.canonicalize().map_err(read_err)?;
    if !canon.starts_with(&base) {
        return Err(refused(Refusal::LinkLeavesFolder));
    }
    let size = check_regular(&canon, MAX_BYTES, WHAT)?;
    Ok(Located::File { path: canon, size })
}

/// Whether a relative path's `..` parts, taken in order, climb above its start (`a/../../b` does,
/// `sub/../tri.bin` does not). Both separators count, as a file written on Windows may use `\`.
fn climbs_out(decoded: &str) -> bool {
    let mut depth = 0usize;
    for part in decoded.split(['/', '\\']) {
        match part {
            "" | "." => {}
            ".." => match depth.checked_sub(1) {
                Some(d) => depth = d,
                None => return true,
            },
            _ => depth += 1,
        }
    }
    false
}

/// The path in an embedded tree of the relative path `rel` (checked not to climb out) from the folder
/// `dir`: `.` and `..` resolved, `/` between the parts (a `\\` is part of a name, as in a folder on Unix).
fn normalised(dir: &str, rel: &str) -> String {
    let mut parts: Vec<&str> = dir.split('/').filter(|p| !p.is_empty()).collect();
    for part in rel.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            p => parts.push(p),
        }
    }
    parts.join("/")
}

/// Returns the bytes a URI names, reading files only from inside `base_dir` ([`locate`], then
/// [`Located::read`]).
pub fn resolve(uri: &str, base_dir: &Path) -> Result<Vec<u8>, UriError> {
    locate(uri, Base::Folder(base_dir))?.read()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_escapes_and_schemes() {
        let base = Path::new(".");
        for uri in ["../secret.bin", "a/../../b.bin", "/etc/passwd", "file:///etc/passwd", "http://x/y.bin", "%2e%2e/x"]
        {
            assert!(matches!(resolve(uri, base), Err(UriError::Refused { .. })), "{uri}");
        }
        assert!(matches!(resolve("missing-file.bin", base), Err(UriError::Read { .. })));
    }

    #[test]
    fn a_path_that_stays_inside_is_read_and_each_refusal_says_why() {
        let d = std::env::temp_dir().join(format!("uri-inside-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("sub")).unwrap();
        std::fs::write(d.join("tri.bin"), [1u8, 2, 3]).unwrap();
        for inside in ["sub/../tri.bin", "./sub/./../tri.bin", "sub%2F..%2Ftri.bin"] {
            assert_eq!(resolve(inside, &d).unwrap(), [1, 2, 3], "{inside}");
        }
        let why = |uri: &str| match locate(uri, Base::Folder(&d)) {
            Err(UriError::Refused { why, .. }) => why.to_string(),
            other => panic!("{uri}: {other:?}"),
        };
        assert_eq!(why("tri%00.bin"), "it holds a NUL byte (%00), which no file name may hold");
        assert_eq!(why(""), "the URI is empty");
        assert_eq!(why("sub/../../tri.bin"), "its '..' parts climb above the asset's folder");
        assert_eq!(why("sub/"), "it names a folder, not a file");
        assert_eq!(
            why("https://example.com/tri.bin"),
            "the scheme 'https:' is not read: only data: URIs and relative paths are"
        );
        assert_eq!(
            locate("tri%00.bin", Base::Folder(&d)).unwrap_err().to_string(),
            "URI 'tri%00.bin' refused: it holds a NUL byte (%00), which no file name may hold"
        );
    }

    #[test]
    fn locating_reads_nothing_and_names_one_file_one_way() {
        let d = std::env::temp_dir().join(format!("uri-locate-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("sub")).unwrap();
        std::fs::write(d.join("sub/a.bin"), [7u8; 5]).unwrap();
        let a = locate("sub/a.bin", Base::Folder(&d)).unwrap();
        let b = locate("./sub/%61.bin", Base::Folder(&d)).unwrap();
        assert_eq!(a, b, "two spellings locate one canonical path");
        assert_eq!(a.size_bound(), 5);
        assert_eq!(a.read().unwrap(), [7u8; 5]);
        assert_eq!(locate("data:;base64,AAECAw==", Base::Folder(&d)).unwrap().size_bound(), 6, "a bound, not exact");
        #[cfg(unix)]
        {
            let fifo = d.join("pipe.bin");
            assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
            let e = locate("pipe.bin", Base::Folder(&d)).unwrap_err();
            assert!(e.to_string().ends_with("is a FIFO, not a regular file"), "{e}");
        }
    }

    #[test]
    fn a_built_in_tree_is_resolved_like_a_folder_and_never_left() {
        let files: &[(&str, &[u8])] = &[("track/a.bin", b"a"), ("track/sub/b.bin", b"b"), ("top.bin", b"t")];
        let base = Base::Embedded { dir: "track", files };
        let read = |uri: &str| locate(uri, base).and_then(|l| l.read());
        for (uri, want) in [("a.bin", b"a"), ("./sub/../a.bin", b"a"), ("sub%2Fb.bin", b"b")] {
            assert_eq!(read(uri).unwrap(), want, "{uri}");
        }
        // As in a folder, nothing above the glTF file's own folder is reached.
        for uri in ["../top.bin", "sub/../../x", "/track/a.bin", "a%00.bin", "", "file:///etc/passwd", "sub/"] {
            assert!(matches!(read(uri), Err(UriError::Refused { .. })), "{uri}");
        }
        let e = read("sub\\b.bin").unwrap_err();
        assert_eq!(e.to_string(), "cannot read 'track/sub\\b.bin (built into the program)': entity not found");
    }

    #[test]
    fn decodes_data_uris() {
        assert_eq!(resolve("data:application/octet-stream;base64,AAEC", Path::new(".")).unwrap(), [0, 1, 2]);
        assert_eq!(resolve("data:,a%20b", Path::new(".")).unwrap(), b"a b");
        assert!(matches!(resolve("data:;base64,@@@", Path::new(".")), Err(UriError::BadData(_))));
    }
}
