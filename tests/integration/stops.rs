//! A recorded race stopped politely is kept: SIGTERM, SIGHUP and SIGINT, and the X server going away, end
//! the window as Quit does (the race so far is renamed to its name, one line says so, the exit status says
//! why), and the trace replays with every checksum verified; SIGKILL leaves the temporary file, and the
//! next run that records to that name names it.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::xvfb::Xvfb;

/// A fresh folder for one test's files.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("stops").join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The game racing at once (autopilot, so the race moves) recording to `target`, on `display`, with a
/// settings file of its own beside the test's folder; its stderr is captured.
fn racing(display: &str, target: &Path, extra: &[&str]) -> Child {
    let settings = target.parent().unwrap().with_extension("settings.json");
    Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["play", "--no-menu", "--autopilot", "--width", "320", "--height", "180", "--record"])
        .arg(target)
        .args(extra)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", display)
        .env("SCANLINE_RACER_SETTINGS", settings)
        .env("SCANLINE_RACER_RECORDS", Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// The temporary recording beside `target` (`.NAME.PID.N.tmp`), once it exists.
fn temporary(target: &Path) -> Option<PathBuf> {
    let prefix = format!(".{}.", target.file_name().unwrap().to_string_lossy());
    std::fs::read_dir(target.parent().unwrap())
        .unwrap()
        .flatten()
        .map(|e| e.path())
        .find(|p| p.file_name().unwrap().to_string_lossy().starts_with(&prefix))
}

/// Checksum records in a trace so far.
fn checksums(path: &Path) -> u64 {
    use scanline_racer::input::trace::{Record, TraceReader};
    let Ok((_, mut r)) = TraceReader::open(path) else { return 0 };
    let mut n = 0;
    while let Ok(Some(rec)) = r.next_record() {
        n += u64::from(matches!(rec, Record::Checksum { .. }));
    }
    n
}

/// Waits until the race being recorded to `target` has `sums` checksums (a second of racing each).
fn wait_for_race(game: &mut Child, target: &Path, sums: u64) {
    let t = Instant::now();
    while temporary(target).is_none_or(|tmp| checksums(&tmp) < sums) {
        if let Ok(Some(status)) = game.try_wait() {
            panic!("the game ended early ({status})");
        }
        assert!(t.elapsed() < Duration::from_secs(90), "no {sums} checksums recorded in 90 s");
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The game's exit code and its stderr lines, less the one saying there is no sound card here.
fn ended(game: Child) -> (Option<i32>, Vec<String>) {
    let out = game.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!err.contains("panicked"), "{err}");
    (out.status.code(), err.lines().filter(|l| !l.contains("no audio")).map(str::to_string).collect())
}

/// Replays `trace` headless; returns (checksums verified, checksums in the file).
fn replayed(trace: &Path) -> (u64, u64) {
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .arg("replay")
        .arg(trace)
        .arg("--headless")
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let verified = err
        .split(", ")
        .find_map(|part| part.strip_suffix(" checksums verified")?.parse().ok())
        .unwrap_or_else(|| panic!("no checksum count in: {err}"));
    (verified, checksums(trace))
}

/// Nothing but `names` in `dir`: no temporary file is left.
fn only(dir: &Path, names: &[&str]) {
    let mut found: Vec<String> =
        std::fs::read_dir(dir).unwrap().flatten().map(|e| e.file_name().to_string_lossy().into_owned()).collect();
    found.sort();
    assert_eq!(found, names);
}

#[test]
fn sigterm_sighup_and_sigint_keep_the_race_and_give_the_signal_s_status() {
    let Some(x) = Xvfb::start() else { return };
    for (signal, status) in [("TERM", 143), ("HUP", 129), ("INT", 130)] {
        let dir = folder(&format!("signal-{signal}"));
        let target = dir.join("race.trace");
        // Recording over an older race: the stopped race replaces it.
        std::fs::write(&target, b"an older race").unwrap();
        let mut game = racing(&x.display, &target, &[]);
        wait_for_race(&mut game, &target, 2);
        let sent = Command::new("kill").args(["-s", signal, &game.id().to_string()]).status().unwrap();
        assert!(sent.success());
        let (code, lines) = ended(game);
        assert_eq!(code, Some(status), "SIG{signal}: {lines:?}");
        assert_eq!(lines.len(), 1, "one line: {lines:?}");
        let want = format!("scanline-racer: stopped by SIG{signal}; recorded ");
        assert!(lines[0].starts_with(&want), "{lines:?}");
        assert!(lines[0].ends_with(&format!(" to {}", target.display())), "{lines:?}");
        only(&dir, &["race.trace"]);
        let (verified, sums) = replayed(&target);
        assert!(sums >= 2 && verified == sums, "SIG{signal}: {verified} of {sums} checksums verified");
    }
}

#[test]
fn the_x_server_going_away_keeps_the_race() {
    let Some(x) = Xvfb::start() else { return };
    let dir = folder("display-lost");
    let target = dir.join("race.trace");
    let mut game = racing(&x.display, &target, &[]);
    wait_for_race(&mut game, &target, 2);
    drop(x);
    let (code, lines) = ended(game);
    assert_eq!(code, Some(1), "{lines:?}");
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert!(lines[0].starts_with("recorded ") && lines[0].ends_with(&format!(" to {}", target.display())));
    assert_eq!(lines[1], "scanline-racer: error: window: the display connection failed");
    assert!(temporary(&target).is_none(), "no temporary file is left");
    let (verified, sums) = replayed(&target);
    assert!(sums >= 2 && verified == sums, "{verified} of {sums} checksums verified");
}

#[test]
fn sigkill_leaves_the_temporary_file_and_the_next_start_names_it() {
    let Some(x) = Xvfb::start() else { return };
    let dir = folder("killed");
    let target = dir.join("race.trace");
    let mut game = racing(&x.display, &target, &[]);
    wait_for_race(&mut game, &target, 1);
    game.kill().unwrap();
    let _ = game.wait();
    let tmp = temporary(&target).expect("the race is in its temporary file");
    assert!(!target.exists());
    let sums = checksums(&tmp);
    // The next run that records to the name says where the race is, and leaves it there.
    let game = racing(&x.display, &target, &["--exit-after-frames", "3"]);
    let (code, lines) = ended(game);
    assert_eq!(code, Some(0), "{lines:?}");
    let want = format!(
        "note: a race recorded to {} by a run that was killed is in {}; rename it to keep it",
        target.display(),
        tmp.display()
    );
    assert_eq!(lines.first(), Some(&want), "{lines:?}");
    assert!(tmp.exists(), "the killed run's race is never removed");
    let (verified, in_file) = replayed(&tmp);
    assert_eq!((verified, in_file), (sums, sums));
}
