//! Builds the game's shipped assets (`assets/track/` and `assets/cars/`) into the program: writes a table
//! of `(path in the tree, include_bytes!(file))` to `$OUT_DIR/built_in_assets.rs`, which
//! `src/shell/built_in.rs` includes. An installed binary then races from any folder, with no `assets/`
//! beside it; `--assets DIR` and `$SCANLINE_RACER_ASSETS` still take a folder for anyone who edits them.

use std::path::{Path, PathBuf};

/// The folders of `assets/` the race loads.
const TREES: [&str; 2] = ["track", "cars"];

fn main() {
    let root = PathBuf::from(std::env::var_os("CARGO_MANIFEST_DIR").unwrap_or_default()).join("assets");
    let mut files: Vec<(String, PathBuf)> = Vec::new();
    for tree in TREES {
        let dir = root.join(tree);
        println!("cargo:rerun-if-changed={}", dir.display());
        if !dir.is_dir() {
            // Not an error: the asset generator (a binary of this package) is built before assets exist.
            println!("cargo:warning=no {} folder: the program is built without its assets", dir.display());
        }
        collect(&dir, tree, &mut files);
    }
    files.sort();
    let mut out = String::from(
        "/// The shipped assets, by their path under `assets/` (`track/circuit/circuit.gltf`), in name order.\n\
         pub static FILES: &[(&str, &[u8])] = &[\n",
    );
    for (name, path) in &files {
        out.push_str(&format!("    ({name:?}, include_bytes!({:?})),\n", path.display().to_string()));
    }
    out.push_str("];\n");
    let dest = PathBuf::from(std::env::var_os("OUT_DIR").unwrap_or_default()).join("built_in_assets.rs");
    if let Err(e) = std::fs::write(&dest, out) {
        println!("cargo:warning=cannot write {}: {e}", dest.display());
        std::process::exit(1);
    }
}

/// Every regular file under `dir` (links followed, as loading from the folder follows them), named
/// `prefix/relative/path`; hidden files and folders (`.name`, such as an editor's or a write's temporary
/// file) are left out, and so are names that are not UTF-8 (said as a warning: a glTF URI could not name
/// them anyway).
fn collect(dir: &Path, prefix: &str, files: &mut Vec<(String, PathBuf)>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    for entry in entries.flatten() {
        let path = entry.path();
        let Some(file) = entry.file_name().to_str().map(str::to_string) else {
            println!("cargo:warning=not built in (its name is not UTF-8): {}", path.display());
            continue;
        };
        if file.starts_with('.') {
            continue;
        }
        let name = format!("{prefix}/{file}");
        match std::fs::metadata(&path) {
            Ok(m) if m.is_dir() => collect(&path, &name, files),
            Ok(m) if m.is_file() => files.push((name, path)),
            _ => {}
        }
    }
}
