//! Bad usage exits 2 with clap's usage error, for every command and every flag with a range; output folders
//! that cannot hold the output are refused in one line before any long work; the pixel scale has one range
//! shared by the flag and the settings file.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::*;

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("usage");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The game run from the repository with no display and a settings file of the test's own.
fn run(args: &[&str], secs: u64) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    c.args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("SCANLINE_RACER_SETTINGS", tmp("no-settings.json"))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"));
    run_bounded(&mut c, secs, &args.join(" "))
}

#[test]
fn out_of_range_values_are_usage_errors_in_every_command() {
    let trace = "assets/replays/demo-race.trace";
    let scene = "tests/scenes/courtyard.gltf";
    let cases: &[(&[&str], &str)] = &[
        (&["render", scene, "--width", "0"], "--width"),
        (&["render", scene, "--height", "16385"], "--height"),
        (&["render", scene, "--repeat", "0"], "--repeat"),
        (&["render", scene, "--buckets", "0"], "--buckets"),
        (&["render", scene, "--background", "256,0,0"], "--background"),
        (&["render", scene, "--background", "1,2"], "--background"),
        (&["render", scene, "--lod-bias", "NaN"], "--lod-bias"),
        (&["render", scene, "--filter", "anisotropic"], "--filter"),
        (&["render", scene, "--mip", "vertex"], "--mip"),
        (&["replay", trace, "--headless", "--filter", "linear"], "--filter"),
        (&["replay", trace, "--headless", "--mip", "on"], "--mip"),
        (&["play", "--width", "0"], "--width"),
        (&["play", "--height", "20000"], "--height"),
        (&["play", "--laps", "0"], "--laps"),
        (&["play", "--laps", "100"], "--laps"),
        (&["play", "--scale", "0"], "--scale"),
        (&["play", "--scale", "9"], "--scale"),
        (&["play", "--scale", "17"], "--scale"),
        (&["replay", trace, "--headless", "--width", "0"], "--width"),
        (&["replay", trace, "--headless", "--height", "0"], "--height"),
        (&["replay", trace, "--headless", "--every", "0"], "--every"),
        (&["export-frame", trace, "--tick", "5", "--out", "x.glb", "--width", "0"], "--width"),
        (&["export-frame", trace, "--tick", "5", "--out", "x.glb", "--height", "0"], "--height"),
        (&["bench", "--width", "0"], "--width"),
        (&["bench", "--height", "8193"], "--height"),
        (&["bench", "--frames", "0"], "--frames"),
        (&["bench", "--repeats", "0"], "--repeats"),
        // Thousands of threads took a minute to start before failing: 256 is the ceiling.
        (&["render", scene, "--threads", "100000"], "--threads"),
        (&["render", scene, "--threads", "257"], "--threads"),
        (&["play", "--threads", "100000"], "--threads"),
        (&["replay", trace, "--headless", "--threads", "100000"], "--threads"),
        (&["bench", "--threads", "100000"], "--threads"),
    ];
    for (args, flag) in cases {
        let o = run(args, 20);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        let first = err.lines().next().unwrap_or_default();
        assert!(first.starts_with("error: invalid value") && first.contains(flag), "{args:?}: {err}");
        if *flag == "--threads" {
            assert!(first.ends_with("is not in 0..=256"), "{args:?}: {err}");
        }
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    assert!(!Path::new(env!("CARGO_MANIFEST_DIR")).join("x.glb").exists(), "nothing was written");
    // A name that is not a value is named with the values it may be (the renderer's `UnknownName`).
    let o = run(&["render", scene, "--mip", "vertex"], 20);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("unknown mip level choice 'vertex' (expected off, polygon, span or pixel)"), "{err}");
}

#[test]
fn an_output_folder_that_is_a_file_is_refused_in_one_line_saying_what_to_do() {
    let file = tmp("a-file");
    std::fs::write(&file, b"mine").unwrap();
    let f = file.to_str().unwrap();
    let o = run(&["replay", "assets/replays/demo-race.trace", "--headless", "--frames", f], 20);
    assert_one_line(&o, &["--frames", f, "is a file, not a folder", "name a folder"]);
    let o = run(&["bench", "--quick", "--out", f], 20);
    assert_one_line(&o, &["--out", f, "is a file, not a folder", "name a folder"]);
    assert_eq!(std::fs::read(&file).unwrap(), b"mine", "the file is left as it was");
}

#[test]
fn an_unwritable_bench_folder_fails_before_the_sweep() {
    // A folder under a file can never be made; the full sweep (minutes) must not run first.
    let file = tmp("not-a-folder");
    std::fs::write(&file, b"mine").unwrap();
    let out = file.join("bench");
    let o = run(&["bench", "--out", out.to_str().unwrap()], 20);
    assert_one_line(&o, &["--out", out.to_str().unwrap(), "cannot write into this folder"]);
    assert!(!String::from_utf8_lossy(&o.stderr).contains("configurations"), "the sweep did not start");
}

#[test]
fn the_settings_file_accepts_every_scale_the_flag_accepts() {
    for (scale, warned) in [(8, false), (1, false), (9, true), (0, true)] {
        let settings = tmp(&format!("scale-{scale}.json"));
        std::fs::write(&settings, format!("{{\"scale\": {scale}}}")).unwrap();
        let o = run(&["play", "--settings", settings.to_str().unwrap()], 20);
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_eq!(err.contains(&format!("scale {scale} out of 1-8")), warned, "{err}");
        // Without a warning the one line is that there is no display to open the window on.
        assert_eq!(err.lines().count(), if warned { 2 } else { 1 }, "{err}");
    }
}

#[test]
fn key_bindings_that_cannot_work_are_named_in_the_one_warning() {
    let settings = tmp("keys.json");
    // A misspelt key, and the default steering keys given to other actions.
    let json = r#"{"keys": {"throttle": ["ArowUp"], "brake": ["ArrowLeft", "KeyA"], "steer_left": ["KeyX"]}}"#;
    for (json, want) in [
        (
            json.replace(r#", "steer_left": ["KeyX"]"#, ""),
            vec![
                r#"key "ArowUp" for throttle is not a key name (names are like ArrowUp, KeyW, Space, Digit7): dropped"#,
                // Actions left with no key are repaired in the order Settings lists them.
                "steer left is not in the file and its default ArrowLeft is bound to brake, KeyA is bound to brake: \
                 KeyJ used instead",
                "throttle had no key: default ArrowUp, KeyW used",
            ],
        ),
        (
            json.to_string(),
            vec![
                r#"key "ArowUp" for throttle is not a key name (names are like ArrowUp, KeyW, Space, Digit7): dropped"#,
                "throttle had no key: default ArrowUp, KeyW used",
            ],
        ),
    ] {
        std::fs::write(&settings, &json).unwrap();
        let o = run(&["play", "--settings", settings.to_str().unwrap()], 20);
        let err = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!((o.status.code(), lines.len()), (Some(1), 2), "{err}");
        assert_eq!(lines[0], format!("warning: settings {}: {}", settings.display(), want.join("; ")));
        assert!(lines[1].contains("no display"), "{err}");
    }
    assert_eq!(std::fs::read_to_string(&settings).unwrap(), json, "the file is not rewritten");
}

#[test]
fn a_recording_that_cannot_start_is_one_line_and_touches_nothing() {
    let dir = tmp("record");
    let _ = std::fs::remove_dir_all(&dir);
    let folder = dir.join("a-folder.trace");
    std::fs::create_dir_all(&folder).unwrap();
    let f = folder.to_str().unwrap();
    assert_one_line(&run(&["play", "--record", f], 20), &["cannot record to", f, "is a folder"]);
    let missing = dir.join("no-such-folder/race.trace");
    let m = missing.to_str().unwrap();
    let folder = missing.parent().unwrap().display().to_string();
    assert_one_line(&run(&["play", "--record", m], 20), &["cannot record to", m, &format!("no such folder {folder}")]);
    // With no display the window never opens: one line, and the trace recorded over is as it was.
    let best = dir.join("best.trace");
    std::fs::write(&best, b"the user's race").unwrap();
    assert_one_line(&run(&["play", "--record", best.to_str().unwrap()], 20), &["no display"]);
    assert_eq!(std::fs::read(&best).unwrap(), b"the user's race");
    let mut names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    names.sort();
    assert_eq!(names, ["a-folder.trace", "best.trace"], "no temporary file is left");
}

/// A scale the file cannot hold as a whole number is one warning naming it, not a refused file.
#[test]
fn a_scale_that_is_not_a_whole_number_is_named_in_one_warning() {
    for (scale, shown) in [("-1", "-1"), ("2.5", "2.5"), ("5e9", "5000000000.0")] {
        let settings = tmp(&format!("scale-{scale}.json"));
        std::fs::write(&settings, format!("{{\"scale\": {scale}, \"deadzone\": 0.2}}")).unwrap();
        let o = run(&["play", "--settings", settings.to_str().unwrap()], 20);
        let err = String::from_utf8_lossy(&o.stderr);
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!((o.status.code(), lines.len()), (Some(1), 2), "{err}");
        let want = format!(
            "warning: settings {}: scale {shown} is not a whole number from 1 to 8: 1 used",
            settings.display()
        );
        assert_eq!(lines[0], want);
        assert!(lines[1].contains("no display"), "{err}");
    }
}
