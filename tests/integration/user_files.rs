//! The user's files survive the game, in a real window (Xvfb, keys typed with xdotool): a trace recorded
//! over is replaced only by a race actually raced, however the window closes; a settings file with a typo is
//! never overwritten; a save keeps keys this build does not know and keeps a link a link; the scale the `=`
//! key reaches is one the next start accepts; a hand edit made while the game runs survives its next save.
//! Every file is checked byte for byte; every game is killed after a time bound (a hang fails the test).
//!
//! The games run one at a time, as every windowed game of this binary does ([`Xvfb`] holds a lock).

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::xvfb::{Xvfb, xdotool};

/// Seconds a game may run before it is killed and the test fails.
const BOUND: u64 = 60;

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("user-files").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn demo_trace() -> Vec<u8> {
    std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/replays/demo-race.trace")).unwrap()
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> =
        std::fs::read_dir(dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    v.sort();
    v
}

/// A game in a window on `x`, with its stderr going to `dir/stderr` and the settings file `settings`.
struct Game {
    child: Child,
    stderr: PathBuf,
    display: String,
}

impl Game {
    fn start(x: &Xvfb, dir: &Path, settings: &Path, args: &[&str]) -> Game {
        let stderr = dir.join("stderr");
        let child = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
            .args(["play", "--width", "320", "--height", "180"])
            .args(args)
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("DISPLAY", &x.display)
            .env_remove("WAYLAND_DISPLAY")
            .env("SCANLINE_RACER_SETTINGS", settings)
            .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
            .stdout(Stdio::null())
            .stderr(std::fs::File::create(&stderr).unwrap())
            .spawn()
            .unwrap();
        Game { child, stderr, display: x.display.clone() }
    }

    /// Types `keys` (xdotool names) into the window once it is up, `pause` apart; false when xdotool is
    /// not installed (the test is then not run, as `tests/integration/window.rs` does).
    fn type_keys(&mut self, keys: &[&str], pause: Duration) -> bool {
        let Some(wid) = xdotool(&self.display, &["search", "--sync", "--name", "scanline-racer"]) else {
            return false;
        };
        let wid = wid.lines().next().unwrap().to_string();
        xdotool(&self.display, &["windowfocus", "--sync", &wid]);
        // The window is mapped before its first frame: let the game draw the menu first.
        std::thread::sleep(Duration::from_millis(1500));
        self.press(keys, pause);
        true
    }

    /// Types `keys` into the window (focused by [`Game::type_keys`] before), `pause` apart.
    fn press(&self, keys: &[&str], pause: Duration) {
        for k in keys {
            xdotool(&self.display, &["key", k]);
            std::thread::sleep(pause);
        }
    }

    /// How long after `since` the game's window was up (or the game had ended: its window came and went
    /// between two looks), looking every 50 ms; a game with no window after `limit` is killed and fails
    /// the test. `None` when xdotool is not installed.
    fn window_up_after(&mut self, since: Instant, limit: Duration) -> Option<Duration> {
        xdotool(&self.display, &["version"])?;
        loop {
            let search = Command::new("xdotool")
                .args(["search", "--name", "^scanline-racer"])
                .env("DISPLAY", &self.display)
                .output()
                .unwrap();
            if (search.status.success() && !search.stdout.is_empty()) || self.child.try_wait().unwrap().is_some() {
                return Some(since.elapsed());
            }
            if since.elapsed() > limit {
                let _ = self.child.kill();
                let _ = self.child.wait();
                panic!("no window after {limit:?}: {}", std::fs::read_to_string(&self.stderr).unwrap());
            }
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    /// The window's X id, once it is up.
    fn window(&self) -> Option<String> {
        let wid = xdotool(&self.display, &["search", "--sync", "--name", "scanline-racer"])?;
        Some(wid.lines().next().unwrap().to_string())
    }

    /// Waits for the game to exit (killing it and failing after [`BOUND`] seconds); its exit code and stderr.
    fn wait(mut self) -> (Option<i32>, String) {
        let t = Instant::now();
        let status = loop {
            if let Some(st) = self.child.try_wait().unwrap() {
                break st;
            }
            if t.elapsed() > Duration::from_secs(BOUND) {
                let _ = self.child.kill();
                let _ = self.child.wait();
                panic!("the game still ran after {BOUND} s: {}", std::fs::read_to_string(&self.stderr).unwrap());
            }
            std::thread::sleep(Duration::from_millis(50));
        };
        let err = std::fs::read_to_string(&self.stderr).unwrap();
        assert!(!err.contains("panicked"), "{err}");
        // With no audio device (here: no sound server) the game says so in one line first; the rest is
        // what these tests check.
        let audio = err.lines().filter(|l| l.starts_with("scanline-racer: no audio (")).count();
        assert!(audio <= 1, "the missing audio device is said once: {err}");
        let err: String =
            err.lines().filter(|l| !l.starts_with("scanline-racer: no audio (")).map(|l| format!("{l}\n")).collect();
        (status.code(), err)
    }
}

/// Ticks in a trace and the checksums a headless replay verified, or the replay's error.
fn replayed(trace: &Path) -> Result<String, String> {
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", trace.to_str().unwrap(), "--headless"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr).trim().to_string();
    if out.status.success() { Ok(err) } else { Err(err) }
}

#[test]
fn quitting_without_racing_leaves_the_trace_recorded_over_as_it_was() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("no-race");
    let settings = dir.join("settings.json");
    let best = dir.join("best.trace");
    let b = best.to_str().unwrap();
    // Quit from the main menu by the frame limit, by Esc, and with the same file as the ghost.
    let runs: [(&[&str], &[&str]); 3] = [
        (&["--record", b, "--exit-after-frames", "30"], &[]),
        (&["--record", b], &["Escape"]),
        (&["--ghost", b, "--record", b, "--exit-after-frames", "30"], &[]),
    ];
    for (args, keys) in runs {
        std::fs::write(&best, demo_trace()).unwrap();
        let mut game = Game::start(&x, &dir, &settings, args);
        if !keys.is_empty() && !game.type_keys(keys, Duration::from_millis(300)) {
            return;
        }
        let (code, err) = game.wait();
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert_eq!(err.trim_end(), format!("no race to record: {b} not written"), "{args:?}");
        assert!(std::fs::read(&best).unwrap() == demo_trace(), "{args:?}: best.trace changed");
        assert_eq!(names(&dir), ["best.trace", "stderr"], "{args:?}: no temporary file is left");
    }
}

#[test]
fn a_race_replaces_the_trace_recorded_over_however_the_window_closes() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("race");
    let settings = dir.join("settings.json");
    let best = dir.join("best.trace");
    let b = best.to_str().unwrap();
    // Raced without the menu and stopped by the frame limit; raced from the main menu (Enter starts the race
    // with its "record the race to" switch on, as --record sets it); the window destroyed under the game.
    for how in ["frames", "menu", "destroyed"] {
        std::fs::write(&best, demo_trace()).unwrap();
        let (code, err) = match how {
            "frames" => {
                let args = ["--no-menu", "--autopilot", "--record", b, "--exit-after-frames", "120"];
                Game::start(&x, &dir, &settings, &args).wait()
            }
            "menu" => {
                let mut game = Game::start(&x, &dir, &settings, &["--autopilot", "--record", b]);
                if !game.type_keys(&["Return"], Duration::from_millis(2500)) {
                    return;
                }
                // Back out of the race: Esc pauses, and the window is then closed under the game.
                game.type_keys(&["Escape"], Duration::from_millis(300));
                let wid = game.window().unwrap();
                xdotool(&game.display, &["windowclose", &wid]);
                game.wait()
            }
            _ => {
                let game = Game::start(&x, &dir, &settings, &["--no-menu", "--autopilot", "--record", b]);
                let Some(wid) = game.window() else { return };
                std::thread::sleep(Duration::from_millis(3000));
                xdotool(&game.display, &["windowclose", &wid]);
                game.wait()
            }
        };
        let lines: Vec<&str> = err.lines().collect();
        let recorded = lines.first().copied().unwrap_or_default();
        assert!(recorded.starts_with("recorded ") && recorded.ends_with(&format!(" to {b}")), "{how}: {err}");
        match (how, code) {
            ("frames", _) => assert_eq!((code, lines.len()), (Some(0), 1), "{how}: {err}"),
            // A window destroyed under the game may end it cleanly or as an error, depending on which call
            // to the X server notices first: either way the race is kept first, and an error is one line.
            (_, Some(0)) => assert_eq!(lines.len(), 1, "{how}: {err}"),
            (_, Some(1)) => {
                assert_eq!(lines.len(), 2, "{how}: {err}");
                assert!(lines[1].starts_with("scanline-racer: error: "), "{how}: {err}");
            }
            _ => panic!("{how}: exit {code:?}: {err}"),
        }
        let bytes = std::fs::read(&best).unwrap();
        assert!(bytes != demo_trace() && bytes.starts_with(b"SRTRACE\0"), "{how}: best.trace was not replaced");
        let ticks: u64 = recorded.split(' ').nth(1).unwrap().parse().unwrap();
        let replay = replayed(&best).unwrap_or_else(|e| panic!("{how}: {e}"));
        assert!(replay.starts_with(&format!("replayed {ticks} ticks")), "{how}: {replay} ({recorded})");
        assert_eq!(names(&dir), ["best.trace", "stderr"], "{how}: no temporary file is left");
    }
}

/// Starts the game on the main menu with `settings`, presses `=` `times` times and Esc; its stderr.
fn press_equal(x: &Xvfb, dir: &Path, settings: &Path, times: usize) -> Option<String> {
    let mut keys = vec!["equal"; times];
    keys.push("Escape");
    let mut game = Game::start(x, dir, settings, &[]);
    if !game.type_keys(&keys, Duration::from_millis(150)) {
        return None;
    }
    let (code, err) = game.wait();
    assert_eq!(code, Some(0), "{err}");
    Some(err)
}

#[test]
fn a_settings_file_that_does_not_parse_is_never_overwritten() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("typo");
    let settings = dir.join("settings.json");
    let text = "{\n  \"keys\": {\"throttle\": [\"KeyT\"]},\n  \"scale\": 2,\n}\n";
    std::fs::write(&settings, text).unwrap();
    let Some(err) = press_equal(&x, &dir, &settings, 1) else { return };
    assert_eq!(std::fs::read_to_string(&settings).unwrap(), text);
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with(&format!("warning: settings {}: trailing comma", settings.display())), "{err}");
    assert!(err.trim_end().ends_with("defaults used; the file is left as it is and changes will not be saved"));
    assert_eq!(names(&dir), ["settings.json", "stderr"]);
}

#[test]
fn a_save_keeps_unknown_keys_and_a_linked_file_stays_a_link() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("keep");
    let real = dir.join("real.json");
    std::fs::write(&real, "{\"theme\": \"dark\", \"scale\": 2, \"keys\": {\"throttle\": [\"KeyT\"]}}").unwrap();
    let link = dir.join("settings.json");
    std::os::unix::fs::symlink("real.json", &link).unwrap();
    let Some(err) = press_equal(&x, &dir, &link, 1) else { return };
    // The key this build does not know is named, and kept.
    assert_eq!(err, format!("warning: settings {}: unknown key \"theme\" is not used\n", link.display()));
    assert!(std::fs::symlink_metadata(&link).unwrap().file_type().is_symlink(), "still a link");
    let want = "{\n  \"keys\": {\n    \"throttle\": [\n      \"KeyT\"\n    ]\n  },\n  \"scale\": 3,\n  \"theme\": \"dark\"\n}\n";
    assert_eq!(std::fs::read_to_string(&real).unwrap(), want);
    assert_eq!(names(&dir), ["real.json", "settings.json", "stderr"]);
}

#[test]
fn the_largest_scale_the_key_reaches_is_saved_and_accepted_at_the_next_start() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("scale");
    let settings = dir.join("settings.json");
    let Some(err) = press_equal(&x, &dir, &settings, 12) else { return };
    assert_eq!(err, "");
    assert_eq!(std::fs::read_to_string(&settings).unwrap(), "{\n  \"scale\": 8\n}\n");
    // The next start reads it without a word and draws at that scale (320x180 / 8 = 40x23 pixels).
    let shot = dir.join("shot.png");
    let args = ["--exit-after-frames", "3", "--screenshot", shot.to_str().unwrap()];
    let (code, err) = Game::start(&x, &dir, &settings, &args).wait();
    assert_eq!((code, err.as_str()), (Some(0), ""));
    let img = image::open(&shot).unwrap();
    assert_eq!((img.width(), img.height()), (40, 23));
}

#[test]
fn a_long_ghost_trace_does_not_hold_up_the_window() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("long-ghost");
    // 50 MB: ten million ticks, 23 hours of racing; replaying it all took over 60 s before the window opened.
    let ghost = dir.join("long.trace");
    crate::common::write_idle_trace(&ghost, 10_000_000);
    assert!(std::fs::metadata(&ghost).unwrap().len() > 50_000_000);
    let t = Instant::now();
    let args = ["--no-menu", "--ghost", ghost.to_str().unwrap(), "--exit-after-frames", "30"];
    let mut game = Game::start(&x, &dir, &dir.join("settings.json"), &args);
    // Up in a second or two here; the bound is for a loaded machine, and still far from the old minute.
    let Some(up) = game.window_up_after(t, Duration::from_secs(30)) else { return };
    let (code, err) = game.wait();
    assert_eq!((code, err.as_str()), (Some(0), ""), "window up after {up:?}");
    let _ = std::fs::remove_file(&ghost);
}

/// A key added to the settings file by hand while the game runs survives the game's next save: `=` saves
/// the scale, the file is edited, `=` saves again.
#[test]
fn a_hand_edit_made_while_the_game_runs_survives_its_next_save() {
    let Some(x) = Xvfb::start() else { return };
    let dir = tmp("hand-edit");
    let settings = dir.join("settings.json");
    std::fs::write(&settings, "{\"scale\": 2}").unwrap();
    let mut game = Game::start(&x, &dir, &settings, &[]);
    if !game.type_keys(&["equal"], Duration::from_millis(300)) {
        return;
    }
    let saved = |want: &str| {
        let t = Instant::now();
        while std::fs::read_to_string(&settings).unwrap() != want {
            assert!(t.elapsed() < Duration::from_secs(20), "never saved: {want:?}");
            std::thread::sleep(Duration::from_millis(50));
        }
    };
    saved("{\n  \"scale\": 3\n}\n");
    std::fs::write(&settings, "{\"scale\": 3, \"theme\": \"dark\"}").unwrap();
    game.press(&["equal"], Duration::from_millis(300));
    saved("{\n  \"scale\": 4,\n  \"theme\": \"dark\"\n}\n");
    game.press(&["Escape"], Duration::from_millis(300));
    let (code, err) = game.wait();
    assert_eq!((code, err.as_str()), (Some(0), ""));
    assert_eq!(names(&dir), ["settings.json", "stderr"]);
}
