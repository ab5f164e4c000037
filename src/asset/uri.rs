//! Resolving the URIs a glTF file names, confined to the asset's own folder.
//!
//! `data:` URIs are decoded in memory. Any other scheme, an absolute path, or a path with a `..` component is
//! refused, so a file cannot make the loader read outside its folder; symbolic links that lead out of the
//! folder are refused too.

use std::path::{Component, Path, PathBuf};

use base64::Engine;

/// Largest external file or decoded `data:` URI accepted (512 MiB).
pub const MAX_BYTES: u64 = 512 << 20;

/// Why a URI was refused or could not be read.
#[derive(Debug, thiserror::Error, PartialEq, Eq)]
pub enum UriError {
    /// Not a `data:` URI and not a plain relative path.
    #[error("URI '{uri}' refused: {reason}")]
    Refused {
        /// The URI as written (shortened).
        uri: String,
        /// Why.
        reason: &'static str,
    },
    /// A `data:` URI whose payload does not decode.
    #[error("data URI does not decode: {0}")]
    BadData(String),
    /// The file could not be read.
    #[error("cannot read '{path}': {reason}")]
    Read {
        /// The path tried.
        path: PathBuf,
        /// The I/O error.
        reason: String,
    },
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

/// Returns the bytes a URI names, reading files only from inside `base_dir`.
pub fn resolve(uri: &str, base_dir: &Path) -> Result<Vec<u8>, UriError> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (meta, payload) = rest.split_once(',').ok_or_else(|| UriError::BadData("no ',' in data URI".into()))?;
        if payload.len() as u64 > MAX_BYTES * 4 / 3 + 4 {
            return Err(UriError::BadData("payload is larger than the limit".into()));
        }
        return if meta.ends_with(";base64") {
            base64::engine::general_purpose::STANDARD
                .decode(payload.trim())
                .map_err(|e| UriError::BadData(e.to_string()))
        } else {
            percent_decode(payload)
                .map(String::into_bytes)
                .ok_or_else(|| UriError::BadData("bad percent-encoding".into()))
        };
    }
    let refused = |reason| UriError::Refused { uri: short(uri), reason };
    let scheme_len = uri.find(':').unwrap_or(0);
    if scheme_len > 0 && uri[..scheme_len].chars().all(|c| c.is_ascii_alphanumeric() || "+-.".contains(c)) {
        return Err(refused("only data: URIs and relative paths are allowed"));
    }
    let decoded = percent_decode(uri).ok_or_else(|| refused("bad percent-encoding"))?;
    if decoded.is_empty() || decoded.contains('\0') {
        return Err(refused("empty path"));
    }
    let rel = Path::new(&decoded);
    if decoded.starts_with('/') || decoded.starts_with('\\') || rel.is_absolute() {
        return Err(refused("absolute paths are not allowed"));
    }
    if decoded.split(['/', '\\']).any(|c| c == "..")
        || rel.components().any(|c| !matches!(c, Component::Normal(_) | Component::CurDir))
    {
        return Err(refused("paths may not leave the asset's folder"));
    }
    let path = base_dir.join(rel);
    let read_err = |e: std::io::Error| UriError::Read { path: path.clone(), reason: e.to_string() };
    let canon = path.canonicalize().map_err(read_err)?;
    let base = base_dir.canonicalize().map_err(read_err)?;
    if !canon.starts_with(&base) {
        return Err(refused("the path leads out of the asset's folder through a link"));
    }
    let len = std::fs::metadata(&canon).map_err(read_err)?.len();
    if len > MAX_BYTES {
        return Err(refused("file is larger than the 512 MiB limit"));
    }
    std::fs::read(&canon).map_err(read_err)
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
    fn decodes_data_uris() {
        assert_eq!(resolve("data:application/octet-stream;base64,AAEC", Path::new(".")).unwrap(), [0, 1, 2]);
        assert_eq!(resolve("data:,a%20b", Path::new(".")).unwrap(), b"a b");
        assert!(matches!(resolve("data:;base64,@@@", Path::new(".")), Err(UriError::BadData(_))));
    }
}
