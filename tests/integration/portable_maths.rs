//! The simulation, the replays' frames and the asset generator do not depend on the platform's maths library.
//!
//! glibc, macOS and Windows give `sin`, `cos`, `tan`, `atan2`, ... to within an ulp but round some results
//! differently in the last place; a simulation that calls the system's library would replay a trace recorded
//! on Linux differently elsewhere. Here a stand-in for such a library (`tests/portable/perturbed_libm.c`:
//! glibc's result moved by one ulp for about half the inputs) is compiled with the system C compiler and
//! preloaded (`LD_PRELOAD`) into the real binaries:
//!
//! - a probe program shows that it is loaded and changes results (so the test can fail);
//! - both demo traces replay headless under it with every checksum verified, and the frames written every
//!   600 ticks are byte-identical to the same replay without it;
//! - the asset generator writes exactly the committed `assets/` under it.
//!
//! Before the project used a portable maths library (the `libm` crate), the demo race diverged under it at
//! tick 480. Linux (glibc) only: `LD_PRELOAD` is how the test swaps the library.

#![cfg(all(target_os = "linux", target_env = "gnu"))]

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::files_under;
use std::sync::OnceLock;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn tmp() -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("portable-maths");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn cc(args: &[&str]) {
    let out = Command::new("cc").args(args).output().expect("a C compiler (cc) to build the test's stand-in libm");
    assert!(out.status.success(), "cc {args:?}: {}", String::from_utf8_lossy(&out.stderr));
}

/// The perturbed maths library, built once.
fn shim() -> &'static Path {
    static SHIM: OnceLock<PathBuf> = OnceLock::new();
    SHIM.get_or_init(|| {
        let so = tmp().join("perturbed_libm.so");
        let src = root().join("tests/portable/perturbed_libm.c");
        cc(&["-O1", "-shared", "-fPIC", "-o", so.to_str().unwrap(), src.to_str().unwrap(), "-ldl", "-lm"]);
        so
    })
}

fn run(mut cmd: Command, perturbed: bool) -> Output {
    if perturbed {
        cmd.env("LD_PRELOAD", shim());
    }
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{cmd:?} (perturbed maths: {perturbed}) failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

#[test]
fn the_stand_in_library_is_loaded_and_changes_results() {
    let probe = tmp().join("probe");
    let src = root().join("tests/portable/probe.c");
    cc(&["-O0", "-o", probe.to_str().unwrap(), src.to_str().unwrap(), "-lm"]);
    let plain = run(Command::new(&probe), false).stdout;
    let perturbed = run(Command::new(&probe), true).stdout;
    let (a, b) = (String::from_utf8(plain).unwrap(), String::from_utf8(perturbed).unwrap());
    assert_eq!(a.lines().count(), 8);
    let differing = a.lines().zip(b.lines()).filter(|(x, y)| x != y).count();
    assert!(differing >= 2, "the stand-in changed {differing} of 8 lines:\n{a}\n{b}");
}

/// Replays `trace` headless, writing a small frame every 600 ticks into `dir`; returns the frames by name.
fn replay_frames(trace: &str, dir: &Path, perturbed: bool) -> (String, BTreeMap<String, Vec<u8>>) {
    let _ = std::fs::remove_dir_all(dir);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    cmd.current_dir(root())
        .args(["replay", trace, "--headless", "--every", "600", "--width", "192", "--height", "108", "--frames"])
        .arg(dir);
    let out = run(cmd, perturbed);
    let summary = String::from_utf8_lossy(&out.stderr).trim().to_string();
    let frames = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| (p.file_name().unwrap().to_string_lossy().into_owned(), std::fs::read(&p).unwrap()))
        .collect();
    (summary, frames)
}

#[test]
fn demo_traces_replay_with_the_same_checksums_and_frames_under_another_maths_library() {
    for trace in ["assets/replays/demo-race.trace", "assets/replays/scuffle.trace"] {
        let name = Path::new(trace).file_stem().unwrap().to_string_lossy().into_owned();
        let (plain_summary, plain) = replay_frames(trace, &tmp().join(format!("{name}-plain")), false);
        let (summary, perturbed) = replay_frames(trace, &tmp().join(format!("{name}-perturbed")), true);
        assert!(plain.len() >= 5, "{trace}: only {} frames", plain.len());
        assert_eq!(summary, plain_summary, "{trace}: the replay's summary differs under another maths library");
        let differing: Vec<_> = plain.iter().filter(|(k, v)| perturbed.get(*k) != Some(*v)).map(|(k, _)| k).collect();
        assert!(differing.is_empty(), "{trace}: frames {differing:?} differ under another maths library");
    }
}

#[test]
fn the_asset_generator_writes_the_committed_assets_under_another_maths_library() {
    let out = tmp().join("assets-perturbed");
    let _ = std::fs::remove_dir_all(&out);
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_assetgen"));
    cmd.arg(&out);
    run(cmd, true);
    let (made, committed) = (files_under(&out), files_under(&root().join("assets")));
    let stale: Vec<_> =
        made.iter().filter(|(k, v)| committed.get(*k) != Some(*v)).map(|(k, _)| k.display().to_string()).collect();
    assert!(stale.is_empty(), "under another maths library the generator writes different {stale:?}");
    assert_eq!(made.len(), committed.len());
}
