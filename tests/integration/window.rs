//! The window under a real X server (Xvfb): it opens, draws what the headless renderer draws, and quits;
//! with no display it fails with one line naming the headless command.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use crate::common::xvfb::{Xvfb, xdotool};
use crate::common::*;

#[test]
fn window_shows_the_same_frame_as_the_headless_renderer() {
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window");
    std::fs::create_dir_all(&dir).unwrap();
    let shot = dir.join("window.png");
    let headless = dir.join("headless.png");
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args([
            "play",
            "--demo",
            "--width",
            "320",
            "--height",
            "240",
            "--exit-after-frames",
            "5",
            "--screenshot",
            shot.to_str().unwrap(),
        ])
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", settings_file("default", None))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(out.status.success(), "play failed: {}", String::from_utf8_lossy(&out.stderr));
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenes/courtyard.gltf");
    let r = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["render", scene.to_str().unwrap(), "--camera", "0", "--width", "320", "--height", "240"])
        .args(["--out", headless.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(r.status.success());
    let (a, w, h) = read_png(&shot).expect("screenshot written");
    let (b, _, _) = read_png(&headless).unwrap();
    assert_eq!((w, h), (320, 240));
    // The window rebuilds the camera from a yaw and pitch, so a few edge pixels may round differently.
    let wrong = a.iter().zip(&b).filter(|(p, q)| channel_diff(**p, **q) > 8).count();
    assert!(wrong * 200 < w * h, "{wrong} pixels differ between window and headless frames");
    assert!(a.iter().filter(|&&p| p != 0x87ceeb).count() > w * h / 3, "the scene is drawn");
}

#[test]
fn scaled_internal_resolution_and_a_user_scene() {
    let Some(x) = Xvfb::start() else { return };
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-scaled.png");
    let duck = samples().join("Duck/Duck.gltf");
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["play", "--scene", duck.to_str().unwrap(), "--width", "300", "--height", "200", "--scale", "3"])
        .args(["--method", "bucket-near", "--exit-after-frames", "3", "--screenshot", shot.to_str().unwrap()])
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", settings_file("default", None))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (px, w, h) = read_png(&shot).unwrap();
    assert_eq!((w, h), (100, 67), "internal frame is the window divided by the scale, rounded up");
    assert!(px.iter().any(|&p| p != 0x87ceeb), "the duck is drawn");
}

#[test]
fn the_race_runs_in_the_window_with_the_cars_on_the_circuit() {
    let Some(x) = Xvfb::start() else { return };
    let shot = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-race.png");
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args([
            "play",
            "--width",
            "320",
            "--height",
            "180",
            "--exit-after-frames",
            "20",
            "--screenshot",
            shot.to_str().unwrap(),
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", settings_file("default", None))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (px, w, h) = read_png(&shot).unwrap();
    assert_eq!((w, h), (320, 180));
    // The chase camera looks at the player's red car from behind: red dominates the lower middle.
    let red = (h / 2..h)
        .flat_map(|y| (w / 3..2 * w / 3).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = px[y * w + x];
            (p >> 16) & 0xff > 150 && (p >> 8) & 0xff < 80 && p & 0xff < 80
        })
        .count();
    assert!(red > 500, "the player's car is in view ({red} red pixels)");
    assert!(px[..w * 20].iter().all(|&p| p == 0x87ceeb), "sky at the top");
}

/// The race draws with the settings file's picture (2x2 supersampling here: edges and distant texels
/// blend), unless the command line gives another for the run; neither run rewrites the file.
#[test]
fn the_race_draws_the_settings_file_s_picture_unless_the_command_line_says_otherwise() {
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-picture");
    std::fs::create_dir_all(&dir).unwrap();
    let text = "{\"antialias\": \"ssaa\"}";
    let shot = |name: &str, settings: &Path, args: &[&str]| {
        let shot = dir.join(format!("{name}.png"));
        let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
            .args(["play", "--width", "320", "--height", "180", "--exit-after-frames", "10"])
            .args(args)
            .args(["--screenshot", shot.to_str().unwrap()])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .env("DISPLAY", &x.display)
            .env("SCANLINE_RACER_SETTINGS", settings)
            .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
            .output()
            .unwrap();
        assert!(out.status.success(), "{name}: {}", String::from_utf8_lossy(&out.stderr));
        read_png(&shot).unwrap().0
    };
    // A file that fixes the picture (no `auto`) at the defaults: the renderer's plain picture.
    let plain = shot("plain", &settings_file("picture-none", Some("{\"auto_quality\": false}")), &[]);
    let saved = settings_file("picture-ssaa", Some(text));
    let smooth = shot("ssaa", &saved, &[]);
    let overridden = shot("overridden", &saved, &["--aa", "off"]);
    assert_eq!(std::fs::read_to_string(&saved).unwrap(), text, "the file is left as it is");
    let differ = |a: &[u32], b: &[u32]| a.iter().zip(b).filter(|(p, q)| channel_diff(**p, **q) > 8).count();
    let n = 320 * 180;
    // On the grid before the start nothing moves, so the frames compare pixel for pixel (measured: 4782
    // pixels, 8.3%, differ between the plain and supersampled frames; none between the plain two).
    assert!(differ(&plain, &smooth) * 25 > n, "the file's ssaa is drawn ({} pixels differ)", differ(&plain, &smooth));
    assert!(differ(&plain, &overridden) * 1000 < n, "--aa off wins ({} pixels differ)", differ(&plain, &overridden));
}

#[test]
fn no_display_is_one_line_naming_the_headless_command() {
    for display in [None, Some(":4242")] {
        let mut cmd = Command::new(env!("CARGO_BIN_EXE_scanline-racer"));
        cmd.env_remove("WAYLAND_DISPLAY").env_remove("WAYLAND_SOCKET");
        match display {
            Some(d) => cmd.env("DISPLAY", d),
            None => cmd.env_remove("DISPLAY"),
        };
        let out = cmd.output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains("no display") && err.contains("scanline-racer render"), "{err}");
        assert!(err.contains("scanline-racer replay TRACE --headless"), "{err}");
    }
}

#[test]
fn a_replayed_race_in_the_window_shows_the_frame_the_headless_renderer_draws() {
    // Drive the real binary in a real window with a recorded race, stop at a tick, screenshot the X display
    // and compare it with the headless replay's frame of the same tick.
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-replay");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let trace = dir.join("race.trace");
    record_trace(&trace, 120 * 8);
    let (w, h, tick) = (320usize, 180usize, 720u64);
    let mut child = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", trace.to_str().unwrap(), "--width", "320", "--height", "180", "--lod", "close"])
        .args(["--stop-at", &tick.to_string(), "--no-hud"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", settings_file("default", None))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Wait for the line saying the replay froze at the tick.
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        use std::io::BufRead;
        for line in std::io::BufReader::new(stderr).lines().map_while(Result::ok) {
            let _ = tx.send(line);
        }
    });
    let deadline = Instant::now() + Duration::from_secs(90);
    let mut seen = vec![];
    loop {
        match rx.recv_timeout(Duration::from_millis(200)) {
            Ok(line) if line.contains("replay stopped at tick") => {
                seen.push(line);
                break;
            }
            Ok(line) => seen.push(line),
            Err(_) if Instant::now() > deadline => {
                let _ = child.kill();
                panic!("the replay did not reach tick {tick}: {seen:?}");
            }
            Err(_) => {
                if let Ok(Some(st)) = child.try_wait() {
                    panic!("the replay window exited early ({st}): {seen:?}");
                }
            }
        }
    }
    assert!(seen.last().is_some_and(|l| l.ends_with(&format!("tick {tick}"))), "{seen:?}");
    // Let the frozen frame be presented, then take the X display.
    std::thread::sleep(Duration::from_millis(700));
    let dump = Command::new("xwd").args(["-root", "-silent", "-display", &x.display]).output().unwrap_or_else(|e| {
        panic!("cannot run xwd ({e}): run scripts/test, which installs it (apt-get install x11-apps)")
    });
    let _ = child.kill();
    let _ = child.wait();
    assert!(dump.status.success());
    let (screen, sw, _) = read_xwd(&dump.stdout).expect("a 32-bit ZPixmap dump");
    // No window manager under Xvfb: the window's pixels sit at the display's top-left corner.
    let window: Vec<u32> = (0..h).flat_map(|y| screen[y * sw..y * sw + w].to_vec()).collect();
    let frames = dir.join("frames");
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", trace.to_str().unwrap(), "--headless", "--frames", frames.to_str().unwrap()])
        .args(["--every", &tick.to_string(), "--width", "320", "--height", "180", "--lod", "close"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let (headless, _, _) = read_png(&frames.join(format!("frame_{tick:06}.png"))).unwrap();
    let wrong = window.iter().zip(&headless).filter(|(a, b)| channel_diff(**a, **b) > 8).count();
    if wrong > 0 {
        write_png(&dir.join("window.png"), &window, w, h);
    }
    assert_eq!(wrong, 0, "the window differs from the headless frame in {wrong} pixels (see {})", dir.display());
}

/// A settings file for the game under test (so a developer's own settings never leak into tests): absent
/// for defaults, or with `json`.
fn settings_file(name: &str, json: Option<&str>) -> std::path::PathBuf {
    let p = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("settings-{name}.json"));
    match json {
        Some(j) => std::fs::write(&p, j).unwrap(),
        None => {
            let _ = std::fs::remove_file(&p);
        }
    }
    p
}

/// Checksum records in a trace file so far (each is tag 2 + 16 bytes; controls are tag 1 + 4 bytes).
fn trace_records(path: &Path) -> (u64, u64, u64) {
    use scanline_racer::input::trace::{Record, TraceReader};
    let Ok((_, mut r)) = TraceReader::open(path) else { return (0, 0, 0) };
    let (mut sums, mut throttle, mut steer) = (0, 0, 0);
    while let Ok(Some(rec)) = r.next_record() {
        match rec {
            Record::Checksum { .. } => sums += 1,
            Record::Controls(c) => {
                throttle += u64::from(c.throttle > 0.0);
                steer += u64::from(c.steer != 0.0);
            }
        }
    }
    (sums, throttle, steer)
}

#[test]
fn a_race_driven_with_rebound_keys_recorded_and_killed_replays_its_prefix_with_every_checksum() {
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-killed");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    // Recording over an older trace: a killed game never got to replace it, so it stays whole, and the
    // race so far is in the temporary file beside it.
    let target = dir.join("race.trace");
    std::fs::write(&target, b"an older race").unwrap();
    let recording = || -> std::path::PathBuf {
        let tmp = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).find(|p| p != &target);
        tmp.unwrap_or_else(|| dir.join("none yet"))
    };
    // Rebound keys from the settings file: T throttle, J and L steer (the arrows then do nothing).
    let settings = settings_file(
        "rebound",
        Some(r#"{"keys":{"throttle":["KeyT"],"steer_left":["KeyJ"],"steer_right":["KeyL"]}}"#),
    );
    let mut game = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["play", "--no-menu", "--width", "320", "--height", "180", "--record", target.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", &settings)
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let Some(wid) = xdotool(&x.display, &["search", "--sync", "--name", "scanline-racer"]) else {
        let _ = game.kill();
        let _ = game.wait();
        return;
    };
    let wid = wid.lines().next().unwrap().to_string();
    xdotool(&x.display, &["windowfocus", "--sync", &wid]);
    // Scripted driving: hold the throttle through the countdown and after, with steering taps.
    xdotool(&x.display, &["keydown", "t"]);
    let t = Instant::now();
    let mut tap = 0;
    while trace_records(&recording()).0 < 6 && t.elapsed() < Duration::from_secs(60) {
        let key = if tap % 2 == 0 { "j" } else { "l" };
        xdotool(&x.display, &["keydown", key]);
        std::thread::sleep(Duration::from_millis(300));
        xdotool(&x.display, &["keyup", key]);
        std::thread::sleep(Duration::from_millis(200));
        tap += 1;
    }
    // Killed mid-race, with no chance to flush or clean up.
    game.kill().unwrap();
    let _ = game.wait();
    assert_eq!(std::fs::read(&target).unwrap(), b"an older race");
    let trace = recording();
    let name = trace.file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with(".race.trace.") && name.ends_with(".tmp"), "{name}");
    let (sums, throttle, steer) = trace_records(&trace);
    assert!(sums >= 6, "the recording reached {sums} checksums in 60 s");
    assert!(
        throttle > 120 && steer > 20,
        "the scripted keys were recorded: {throttle} throttle, {steer} steering ticks"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", trace.to_str().unwrap(), "--headless"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    // Every checksum in the prefix matches the replayed world's: identical up to the kill.
    assert!(err.contains(&format!(", {sums} checksums verified")), "{err} (trace has {sums})");
}

/// The lines `X Y text` the game writes of its menus' text ([`scanline_racer::shell::ui::UI_TEXT_ENV`]).
fn ui_text(path: &Path) -> Vec<(i32, i32, String)> {
    std::fs::read_to_string(path)
        .unwrap_or_default()
        .lines()
        .filter_map(|l| {
            let mut parts = l.splitn(3, ' ');
            Some((parts.next()?.parse().ok()?, parts.next()?.parse().ok()?, parts.next()?.to_string()))
        })
        .collect()
}

/// Waits until a line of the menus' text satisfies `want`; returns it.
fn wait_for_text(path: &Path, game: &mut std::process::Child, want: impl Fn(&str) -> bool) -> (i32, i32, String) {
    let t = Instant::now();
    loop {
        if let Some(line) = ui_text(path).into_iter().find(|(_, _, s)| want(s)) {
            return line;
        }
        assert!(game.try_wait().unwrap().is_none(), "the game ended early");
        assert!(t.elapsed() < Duration::from_secs(60), "not on screen after 60 s: {:?}", ui_text(path));
        std::thread::sleep(Duration::from_millis(100));
    }
}

#[test]
fn settings_show_keys_as_keyboards_label_them_and_the_file_keeps_winit_s_names() {
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-key-names");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let json = r#"{"keys":{"throttle":["Numpad0"],"brake":["Space"],"steer_left":["ArrowLeft","KeyA"]}}"#;
    let settings = settings_file("key-names", Some(json));
    let text = dir.join("ui.txt");
    let mut game = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["play", "--width", "800", "--height", "600"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", &settings)
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .env(scanline_racer::shell::ui::UI_TEXT_ENV, &text)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    // The main menu's line of keys, then a click on its Settings button.
    let (_, _, keys) = wait_for_text(&text, &mut game, |s| s.starts_with("Keys: "));
    assert!(keys.starts_with("Keys: Left/A and "), "{keys}");
    assert!(keys.contains("Num 0 accelerates, Space brakes"), "{keys}");
    let (bx, by, _) = wait_for_text(&text, &mut game, |s| s == "Settings");
    let Some(wid) = xdotool(&x.display, &["search", "--sync", "--name", "scanline-racer"]) else {
        let _ = game.kill();
        return;
    };
    let wid = wid.lines().next().unwrap().to_string();
    let (cx, cy) = ((bx + 8).to_string(), (by + 6).to_string());
    xdotool(&x.display, &["mousemove", "--window", &wid, &cx, &cy, "click", "1"]);
    wait_for_text(&text, &mut game, |s| s.starts_with("Keys (click"));
    let shown: Vec<String> = ui_text(&text).into_iter().map(|(_, _, s)| s).collect();
    for label in ["Num 0", "Space", "Left, A"] {
        assert!(shown.iter().any(|s| s == label), "{label} in Settings: {shown:?}");
    }
    for name in ["Numpad0", "ArrowLeft", "KeyA", "ArrowUp"] {
        assert!(!shown.iter().any(|s| s.contains(name)), "winit's {name} shown: {shown:?}");
    }
    // The screen as the player sees it, to look at.
    let shot = Command::new("xwd").args(["-root", "-silent", "-display", &x.display]).output().unwrap();
    if let Some((px, w, h)) = read_xwd(&shot.stdout) {
        write_png(&dir.join("settings.png"), &px, w, h);
    }
    let _ = game.kill();
    let _ = game.wait();
    assert_eq!(std::fs::read_to_string(&settings).unwrap(), json, "the file keeps winit's names, untouched");
}

/// Clicks at the top-left corner of the text `(x, y, _)` of the window `wid`, a few pixels in.
fn click_text(display: &str, wid: &str, (x, y, _): &(i32, i32, String)) {
    let (cx, cy) = ((x + 6).to_string(), (y + 6).to_string());
    xdotool(display, &["mousemove", "--window", wid, &cx, &cy, "click", "1"]);
}

/// The main menu picks the third course, the fifth car and Time Trial, and Race starts that race: alone on
/// the mountain course's grid in car 5 (the HUD says TIME TRIAL), and the settings file remembers the
/// choices.
#[test]
fn the_menu_picks_a_course_a_car_and_time_trial_and_races_it() {
    let Some(x) = Xvfb::start() else { return };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("window-menu-choices");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let settings = dir.join("settings.json");
    let text = dir.join("ui.txt");
    let mut game = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["play", "--width", "800", "--height", "600"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("DISPLAY", &x.display)
        .env("SCANLINE_RACER_SETTINGS", &settings)
        .env("SCANLINE_RACER_RECORDS", dir.join("records.json"))
        .env(scanline_racer::shell::ui::UI_TEXT_ENV, &text)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let combo = wait_for_text(&text, &mut game, |s| s == "Green Valley Circuit");
    let Some(wid) = xdotool(&x.display, &["search", "--sync", "--name", "scanline-racer"]) else {
        let _ = game.kill();
        return;
    };
    let wid = wid.lines().next().unwrap().to_string();
    click_text(&x.display, &wid, &combo);
    let third = wait_for_text(&text, &mut game, |s| s.starts_with("Eagle Pass ("));
    click_text(&x.display, &wid, &third);
    wait_for_text(&text, &mut game, |s| s == "Eagle Pass");
    for n in 2..=5 {
        let next = wait_for_text(&text, &mut game, |s| s == ">");
        click_text(&x.display, &wid, &next);
        let name = scanline_racer::game::garage::GARAGE[n - 1].name;
        wait_for_text(&text, &mut game, |s| s == format!("{n} {name}"));
    }
    let trial = wait_for_text(&text, &mut game, |s| s == "Time Trial");
    click_text(&x.display, &wid, &trial);
    // The choices are saved as they are made.
    let t = Instant::now();
    while !std::fs::read_to_string(&settings).unwrap_or_default().contains("time-trial") {
        assert!(t.elapsed() < Duration::from_secs(30), "settings: {:?}", std::fs::read_to_string(&settings));
        std::thread::sleep(Duration::from_millis(100));
    }
    // The Race button, below the mode's Race choice.
    let race = ui_text(&text).into_iter().filter(|(_, _, s)| s == "Race").max_by_key(|l| l.1).unwrap();
    click_text(&x.display, &wid, &race);
    wait_for_text(&text, &mut game, |s| s == "TIME TRIAL");
    std::thread::sleep(Duration::from_millis(500));
    let shot = Command::new("xwd").args(["-root", "-silent", "-display", &x.display]).output().unwrap();
    if let Some((px, w, h)) = read_xwd(&shot.stdout) {
        write_png(&dir.join("time-trial.png"), &px, w, h);
    }
    let _ = game.kill();
    let _ = game.wait();
    let saved: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&settings).unwrap()).unwrap();
    assert_eq!(saved["course"], "mountain", "{saved}");
    assert_eq!(saved["car"], 5, "{saved}");
    assert_eq!(saved["mode"], "time-trial", "{saved}");
}
