//! The integration tests: one test binary, one module per subject. They use the library's public API and
//! run the real binaries (`CARGO_BIN_EXE_*`) as children.
//!
//! One binary instead of one per file: the library and its dependencies are linked into a test executable
//! once, not once per file, which is most of the tests' build time and disk. Every module's tests share this
//! process and run in parallel threads, so a test changes nothing process-wide: no `std::env::set_var`, no
//! `set_current_dir`; a child gets its environment and folder on its own `Command`. The files a module
//! writes under `CARGO_TARGET_TMPDIR` are named apart from every other module's. Windowed games run one at
//! a time across the modules ([`common::xvfb::Xvfb`] holds a lock while its display is up).
//!
//! Run one module with a filter on its path: `cargo test --test integration golden::`. Data the tests read
//! stays beside this folder: `tests/golden`, `tests/samples`, `tests/scenes`, `tests/failures`,
//! `tests/hostile`, `tests/portable`.
//!
//! A new test file is a module declared here (a `tests/*.rs` file would be a binary of its own again);
//! [`every_test_file_is_a_module_of_this_binary`] fails otherwise.

#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

mod common;

mod architecture;
mod assets;
mod audio;
mod auto_quality;
mod cli;
mod coarse_depth;
mod conformance;
mod cutouts;
mod docs;
mod failures;
mod game;
mod gltf_fuzz;
mod golden;
mod hostile_files;
mod hostile_gltf;
mod lod_fade;
mod mipmaps;
mod outputs;
mod pipeline;
mod portable_maths;
mod reference;
mod replays;
mod stops;
mod trace;
mod trace_fuzz;
mod usage;
mod user_files;
mod view_lists;
mod watertight;
mod window;
mod workers;

/// Every `.rs` file in this folder is declared as a module above (a file that is not is never compiled, so
/// its tests would silently not run), and `tests/` holds no test file or folder cargo would build as a
/// second test binary.
#[test]
fn every_test_file_is_a_module_of_this_binary() {
    let tests = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let here = tests.join("integration");
    let main = std::fs::read_to_string(here.join("main.rs")).unwrap();
    for e in std::fs::read_dir(&here).unwrap() {
        let p = e.unwrap().path();
        let Some(name) = p.file_stem().and_then(|s| s.to_str()) else { continue };
        let is_module = if p.is_dir() { p.join("mod.rs").is_file() } else { p.extension().is_some_and(|x| x == "rs") };
        if is_module && name != "main" {
            let declaration = format!("mod {name};");
            assert!(main.lines().any(|l| l == declaration), "{} is not declared in main.rs", p.display());
        }
    }
    for e in std::fs::read_dir(&tests).unwrap() {
        let p = e.unwrap().path();
        let second_binary = p.extension().is_some_and(|x| x == "rs") || (p != here && p.join("main.rs").is_file());
        assert!(
            !second_binary,
            "{} would be a test binary of its own: make it a module of {}",
            p.display(),
            here.display()
        );
    }
}
