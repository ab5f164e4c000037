//! Files that are not what they claim: a FIFO, `/dev/zero` or a folder wherever the game reads a file (a
//! trace to replay, a ghost, a bench trace, the settings, the centre line), and degenerate centre lines.
//! Each is refused (or, for settings, reported and replaced by defaults) at once, in one line, without a
//! panic; every child is killed after a time bound, and still running then is a failure.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use crate::common::*;

/// Seconds a refusal may take (loading the race's assets takes about one in a debug build).
const BOUND: u64 = 30;

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("hostile-files").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn demo() -> String {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/replays/demo-race.trace").display().to_string()
}

/// The game run from the repository with no display and a settings file of the test's own.
fn game(dir: &Path, args: &[&str]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
    c.args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("SCANLINE_RACER_RECORDS", Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("SCANLINE_RACER_ASSETS")
        .env("SCANLINE_RACER_SETTINGS", dir.join("settings.json"));
    c
}

fn run(dir: &Path, args: &[&str]) -> Output {
    run_bounded(&mut game(dir, args), BOUND, &args.join(" "))
}

/// A FIFO, `/dev/zero` and a folder, each with the words the refusal must use.
fn not_files(dir: &Path) -> Vec<(PathBuf, &'static str)> {
    let fifo = dir.join("pipe.trace");
    mkfifo(&fifo);
    let folder = dir.join("folder.trace");
    std::fs::create_dir_all(&folder).unwrap();
    vec![(fifo, "is a FIFO"), (PathBuf::from("/dev/zero"), "is a device"), (folder, "is a folder")]
}

#[test]
fn a_trace_that_is_not_a_file_is_refused_in_one_line_by_every_command() {
    let dir = tmp("traces");
    for (path, words) in not_files(&dir) {
        let p = path.to_str().unwrap();
        let out = dir.join("out");
        let o = out.to_str().unwrap();
        for args in [
            vec!["replay", p, "--headless"],
            vec!["replay", p],
            vec!["export-frame", p, "--tick", "10", "--out", &format!("{o}.glb")],
            vec!["play", "--ghost", p],
            vec!["bench", "--quick", "--trace", p, "--out", o],
        ] {
            let r = run(&dir, &args);
            assert_one_line(&r, &[p, words]);
            assert!(!String::from_utf8_lossy(&r.stderr).contains("header"), "{args:?}: not a header problem");
        }
    }
}

#[test]
fn an_output_that_is_not_a_file_is_refused_before_the_work_and_an_old_file_is_replaced_whole() {
    let dir = tmp("outputs");
    let duck = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/samples/Duck/Duck.gltf");
    let duck = duck.to_str().unwrap();
    for ext in ["png", "glb"] {
        // Outputs named with the extension their command writes (a device through a link named so).
        let fifo = dir.join(format!("pipe.{ext}"));
        mkfifo(&fifo);
        let folder = dir.join(format!("folder.{ext}"));
        std::fs::create_dir_all(&folder).unwrap();
        let zero = dir.join(format!("zero.{ext}"));
        let _ = std::fs::remove_file(&zero);
        std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
        for (path, words) in [(fifo, "is a FIFO"), (zero, "is a device"), (folder, "is a folder")] {
            let p = path.to_str().unwrap();
            let r = match ext {
                "png" => run(&dir, &["render", duck, "--out", p]),
                _ => run(&dir, &["export-frame", &demo(), "--tick", "10", "--out", p]),
            };
            assert_one_line(&r, &["--out", words]);
        }
    }
    let missing = dir.join("no-such-folder/frame.png");
    let r = run(&dir, &["render", duck, "--out", missing.to_str().unwrap()]);
    assert_one_line(&r, &["--out", "no such folder"]);
    // An existing output is replaced by a whole new file (written beside it and renamed), nothing left over.
    let out = dir.join("duck.png");
    std::fs::write(&out, b"an older picture").unwrap();
    let r = run(&dir, &["render", duck, "--out", out.to_str().unwrap(), "--width", "32", "--height", "24"]);
    assert!(r.status.success(), "{}", String::from_utf8_lossy(&r.stderr));
    assert_eq!(read_png(&out).map(|(_, w, h)| (w, h)), Some((32, 24)));
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
}

#[test]
fn a_settings_file_that_is_not_a_file_gives_defaults_and_one_warning() {
    let dir = tmp("settings");
    for (path, words) in not_files(&dir) {
        let p = path.to_str().unwrap();
        // No display: the warning comes first, then the one-line error that there is no window to open.
        let r = run(&dir, &["play", "--settings", p]);
        let err = String::from_utf8_lossy(&r.stderr);
        assert_eq!(r.status.code(), Some(1), "{err}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 2, "{err}");
        assert!(lines[0].starts_with("warning: settings ") && lines[0].contains(p), "{err}");
        assert!(lines[0].contains(words) && lines[0].contains("defaults used"), "{err}");
        assert!(lines[1].contains("no display"), "{err}");
    }
}

/// A copy of the assets with `track/circuit/centerline.json` made by `make`.
fn assets_with_centre_line(name: &str, make: impl FnOnce(&Path)) -> PathBuf {
    let dir = tmp(name).join("assets");
    copy_assets(&dir);
    let line = dir.join("track/circuit/centerline.json");
    std::fs::remove_file(&line).unwrap();
    make(&line);
    dir
}

fn replay_with_assets(assets: &Path) -> Output {
    let mut c = game(assets, &["replay", &demo(), "--headless"]);
    c.env("SCANLINE_RACER_ASSETS", assets);
    run_bounded(&mut c, BOUND, "replay with a broken centre line")
}

#[test]
fn a_centre_line_that_is_not_a_file_is_refused_in_one_line() {
    let fifo = assets_with_centre_line("line-fifo", mkfifo);
    assert_one_line(&replay_with_assets(&fifo), &["centerline.json", "is a FIFO"]);
    #[cfg(unix)]
    {
        let zero = assets_with_centre_line("line-zero", |p| std::os::unix::fs::symlink("/dev/zero", p).unwrap());
        assert_one_line(&replay_with_assets(&zero), &["centerline.json", "is a device"]);
    }
}

/// A centre line of `points` (x, z) at height 0, 12 m wide.
fn centre_line(points: &[(f64, f64)]) -> String {
    let samples: Vec<serde_json::Value> =
        points.iter().map(|&(x, z)| serde_json::json!({"p": [x, 0.0, z], "bank": 0.0, "width": 12.0})).collect();
    serde_json::json!({ "samples": samples }).to_string()
}

#[test]
fn degenerate_centre_lines_are_refused_naming_the_sample() {
    let circle = |n: usize, r: f64| -> Vec<(f64, f64)> {
        (0..n).map(|i| libm::sincos(i as f64 / n as f64 * std::f64::consts::TAU)).map(|(s, c)| (r * c, r * s)).collect()
    };
    let mut repeated = circle(100, 200.0);
    repeated[41] = repeated[40];
    let mut far = circle(100, 200.0);
    far[7] = (1e30, 5.0);
    type Case<'a> = (&'a str, Vec<(f64, f64)>, &'a [&'a str]);
    let cases: Vec<Case> = vec![
        ("identical", vec![(10.0, 20.0); 8], &["sample 0", "too close"]),
        ("huge", [(1e30, 1e30), (-1e30, 1e30), (-1e30, -1e30), (1e30, -1e30)].repeat(2), &["sample 0", "1e6"]),
        ("far", far, &["sample 7", "1e6"]),
        ("repeated", repeated, &["sample 40", "too close"]),
        ("short", circle(100, 10.0), &["lap of 63", "at least 200"]),
        ("few", circle(5, 200.0), &["5 samples", "at least 8"]),
    ];
    for (name, points, words) in cases {
        let assets =
            assets_with_centre_line(&format!("line-{name}"), |p| std::fs::write(p, centre_line(&points)).unwrap());
        let mut needles = vec!["centerline.json"];
        needles.extend_from_slice(words);
        assert_one_line(&replay_with_assets(&assets), &needles);
    }
}
