//! The files a command reads, known by what they are on disk rather than by how they were named, so that
//! an output path that reaches one of them (spelt differently, through a symbolic link, or as a hard link)
//! is refused before anything is drawn or written.
//!
//! Why: `render copy.gltf --out copy.gltf` replaced the scene with a PNG; `--out ./a/../copy.gltf`, a link
//! to it or a hard link to it would too. Two paths name one file when they lead to the same device and
//! inode (on Unix); elsewhere, when their canonical paths are equal.

use std::path::{Path, PathBuf};

use super::{FileProblem, UserFileError, write_target};

/// What a file is on disk, whatever path reaches it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileId(Id);

#[cfg(unix)]
type Id = (u64, u64);
#[cfg(not(unix))]
type Id = PathBuf;

impl FileId {
    /// The file `path` leads to (links followed), or `None` when it does not exist (an output that does
    /// not exist yet cannot be an input).
    #[must_use]
    pub fn of(path: &Path) -> Option<Self> {
        #[cfg(unix)]
        {
            use std::os::unix::fs::MetadataExt;
            std::fs::metadata(path).ok().map(|m| FileId((m.dev(), m.ino())))
        }
        #[cfg(not(unix))]
        {
            path.canonicalize().ok().map(FileId)
        }
    }
}

/// The files a command reads, each with what it is to the command ("the glTF scene", "the trace").
#[derive(Clone, Debug, Default)]
pub struct Inputs {
    files: Vec<(FileId, &'static str)>,
}

impl Inputs {
    /// No inputs yet.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the file `path` leads to as `what`; a path that does not exist adds nothing.
    pub fn add(&mut self, path: &Path, what: &'static str) {
        if let Some(id) = FileId::of(path) {
            self.files.push((id, what));
        }
    }

    /// Adds every path of `paths` as `what`.
    pub fn add_all<'p>(&mut self, paths: impl IntoIterator<Item = &'p PathBuf>, what: &'static str) {
        for p in paths {
            self.add(p, what);
        }
    }

    /// What the file `path` leads to is to the command, if it is one of its inputs.
    #[must_use]
    pub fn which(&self, path: &Path) -> Option<&'static str> {
        let id = FileId::of(&write_target(path))?;
        self.files.iter().find(|(f, _)| *f == id).map(|&(_, what)| what)
    }

    /// Refuses an output path that leads to one of the inputs: the error names the path and the input.
    pub fn check_output(&self, path: &Path) -> Result<(), UserFileError> {
        match self.which(path) {
            Some(what) => Err(UserFileError { path: path.to_path_buf(), problem: FileProblem::IsInput { what } }),
            None => Ok(()),
        }
    }
}

/// Refuses `path` when it leads to the same file as `other` (both outputs of one command; `other_flag`
/// names the second). Files that do not exist yet are compared as their folder's canonical path (links and
/// `..` resolved) joined with their name.
pub fn check_distinct(path: &Path, other: &Path, other_flag: &'static str) -> Result<(), UserFileError> {
    let (a, b) = (write_target(path), write_target(other));
    let same = match (FileId::of(&a), FileId::of(&b)) {
        (Some(x), Some(y)) => x == y,
        (None, None) => resolved(&a) == resolved(&b),
        _ => false,
    };
    if same {
        return Err(UserFileError { path: path.to_path_buf(), problem: FileProblem::SameOutput { other: other_flag } });
    }
    Ok(())
}

/// Where a new file named by `path` would be: its folder's canonical path joined with its name (the path
/// as it is when the folder does not exist, as then neither file can be written).
fn resolved(path: &Path) -> PathBuf {
    match (super::folder_of(path).canonicalize(), path.file_name()) {
        (Ok(folder), Some(name)) => folder.join(name),
        _ => path.to_path_buf(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_output_reaching_an_input_by_any_path_is_refused() {
        let d = std::env::temp_dir().join(format!("identity-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(d.join("sub")).unwrap();
        let scene = d.join("copy.gltf");
        std::fs::write(&scene, b"{}").unwrap();
        let mut inputs = Inputs::new();
        inputs.add(&scene, "the glTF scene");
        inputs.add(&d.join("missing.bin"), "a buffer");
        let e = inputs.check_output(&scene).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: it is the glTF scene, which this command reads (name another file for the output)",
                scene.display()
            )
        );
        assert_eq!(inputs.which(&d.join("sub/../copy.gltf")), Some("the glTF scene"));
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&scene, d.join("link.gltf")).unwrap();
            std::fs::hard_link(&scene, d.join("hard.gltf")).unwrap();
            assert_eq!(inputs.which(&d.join("link.gltf")), Some("the glTF scene"));
            assert_eq!(inputs.which(&d.join("hard.gltf")), Some("the glTF scene"));
            // A dangling link to a new file is not an input.
            std::os::unix::fs::symlink(d.join("new.png"), d.join("dangling.png")).unwrap();
            assert!(inputs.check_output(&d.join("dangling.png")).is_ok());
        }
        assert!(inputs.check_output(&d.join("copy.png")).is_ok());
        assert!(inputs.check_output(&d.join("missing.bin")).is_ok(), "a missing input is no input");
        // Two outputs: the same new file named two ways, or one existing file.
        let e = check_distinct(&d.join("new.trace"), &d.join("./new.trace"), "--record").unwrap_err();
        assert!(e.to_string().ends_with("--record names the same file"), "{e}");
        assert!(check_distinct(&scene, &d.join("sub/../copy.gltf"), "--record").is_err());
        assert!(check_distinct(&d.join("a.png"), &d.join("b.png"), "--record").is_ok());
        assert!(check_distinct(&d.join("sub/../new.png"), &d.join("new.png"), "--record").is_err());
    }
}
