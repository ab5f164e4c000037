//! The race's soundtrack as `replay TRACE --headless --audio OUT.wav` writes it, for the demo traces in
//! `assets/replays/`, checked against the world states the same trace replays to.
//!
//! The WAV's block of 400 frames number `t` is the sound after the world of tick `t` (tick 0 is the grid).
//! Pitch is found by a Goertzel scan (0.4% steps, 30-700 Hz, Hann window) of 0.5 s windows.
//!
//! The last test plays the same race in the window on a private PulseAudio server and records it.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex, OnceLock};

use scanline_racer::audio::FRAMES_PER_TICK;
use scanline_racer::audio::engine::{Engine, EngineNote, IDLE_RPM, firing_hz};
use scanline_racer::game::car::BODY_HALF_WIDTH;
use scanline_racer::game::rules::Phase;
use scanline_racer::game::{Track, World};
use scanline_racer::input::replay::Replay;

/// Frames a tick.
const TICK: usize = FRAMES_PER_TICK;
/// Ticks in a 0.5 s analysis window.
const WINDOW_TICKS: usize = 60;
/// Largest sample-to-sample jump allowed around gear changes and voice starts, as a share of full scale,
/// beside the sound's own steepest slope (see `no_clicks_at_gear_changes_and_voice_starts`).
const CLICK_BOUND: f32 = 0.12;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// Soundtracks written so far, by trace, thread count and run number.
type Cache = Mutex<BTreeMap<(String, usize, usize), Arc<Vec<u8>>>>;

/// The soundtrack's bytes for `trace` at `--threads threads`, written by the real binary (cached per run).
#[allow(clippy::expect_used)]
fn wav_bytes(trace: &str, threads: usize, run: usize) -> Arc<Vec<u8>> {
    static CACHE: OnceLock<Cache> = OnceLock::new();
    let cache = CACHE.get_or_init(|| Mutex::new(BTreeMap::new()));
    let key = (trace.to_string(), threads, run);
    let mut map = cache.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    if let Some(b) = map.get(&key) {
        return Arc::clone(b);
    }
    let dir = std::env::temp_dir().join(format!("scanline-racer-audio-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp folder");
    let out = dir.join(format!("{trace}-{threads}-{run}.wav"));
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .current_dir(root())
        .args(["replay", &format!("assets/replays/{trace}.trace"), "--headless", "--threads", &threads.to_string()])
        .arg("--audio")
        .arg(&out)
        .status()
        .expect("runs the binary");
    assert!(status.success(), "replay --audio failed for {trace}");
    let bytes = Arc::new(std::fs::read(&out).expect("the WAV was written"));
    let _ = std::fs::remove_file(&out);
    map.insert(key, Arc::clone(&bytes));
    bytes
}

/// Interleaved stereo samples in [-1, 1] from a 16-bit 48 kHz stereo WAV (its header checked).
fn samples(bytes: &[u8]) -> Vec<f32> {
    let u32_at = |i: usize| u32::from_le_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    assert_eq!(&bytes[0..4], b"RIFF");
    assert_eq!(&bytes[8..16], b"WAVEfmt ");
    assert_eq!(u32_at(24), 48_000, "sample rate");
    assert_eq!(u16::from_le_bytes([bytes[22], bytes[23]]), 2, "channels");
    assert_eq!(u16::from_le_bytes([bytes[34], bytes[35]]), 16, "bits");
    assert_eq!(u32_at(40) as usize, bytes.len() - 44, "data size");
    bytes[44..].chunks_exact(2).map(|c| f32::from(i16::from_le_bytes([c[0], c[1]])) / 32767.0).collect()
}

/// Every world of `trace` from the grid (tick 0) to its end.
#[allow(clippy::expect_used)]
fn worlds(trace: &str) -> Vec<World> {
    let text = std::fs::read_to_string(root().join("assets/track/circuit/centerline.json")).expect("centre line");
    let track = Arc::new(Track::from_json(&text).expect("track"));
    let mut r = Replay::open(&root().join(format!("assets/replays/{trace}.trace")), track).expect("trace");
    let mut v = vec![r.world.clone()];
    while r.advance().expect("replays") {
        v.push(r.world.clone());
    }
    v
}

/// The player's engine, tick by tick, as the engine-speed curve gives it.
fn notes(worlds: &[World]) -> Vec<EngineNote> {
    let mut e = Engine::new();
    worlds.iter().map(|w| e.update(&w.cars[0], &w.params[0])).collect()
}

/// Left plus right over two.
fn mono(s: &[f32]) -> Vec<f32> {
    s.chunks_exact(2).map(|f| 0.5 * (f[0] + f[1])).collect()
}

/// The strongest frequency (30-700 Hz) of `x` at 48 kHz.
fn pitch(x: &[f32]) -> f32 {
    // Averaging fours: 12 kHz is plenty below 700 Hz and makes the scan four times cheaper.
    let d: Vec<f32> = x.chunks_exact(4).map(|c| 0.25 * c.iter().sum::<f32>()).collect();
    let n = d.len() as f32;
    let w: Vec<f32> =
        d.iter().enumerate().map(|(i, v)| v * (0.5 - 0.5 * libm::cosf(std::f32::consts::TAU * i as f32 / n))).collect();
    let (mut best, mut best_p) = (0.0, 0.0);
    let mut f = 30.0f32;
    while f < 700.0 {
        let c = 2.0 * libm::cosf(std::f32::consts::TAU * f / 12_000.0);
        let (mut s1, mut s2) = (0.0f32, 0.0f32);
        for &v in &w {
            let s0 = v + c * s1 - s2;
            s2 = s1;
            s1 = s0;
        }
        let p = s1 * s1 + s2 * s2 - c * s1 * s2;
        if p > best_p {
            (best, best_p) = (f, p);
        }
        f *= 1.004;
    }
    best
}

/// The mono samples of ticks `from..to`.
fn ticks(m: &[f32], from: usize, to: usize) -> &[f32] {
    &m[from * TICK..(to * TICK).min(m.len())]
}

fn max_jump(x: &[f32]) -> f32 {
    x.windows(2).map(|w| (w[1] - w[0]).abs()).fold(0.0, f32::max)
}

#[test]
fn engine_pitch_follows_the_engine_speed_curve_across_shifts() {
    let w = worlds("demo-race");
    let notes = notes(&w);
    let m = mono(&samples(&wav_bytes("demo-race", 1, 0)));
    let (mut checked, mut within, mut gears) = (0, 0, std::collections::BTreeSet::new());
    for start in (0..w.len() - WINDOW_TICKS).step_by(WINDOW_TICKS) {
        let hz: Vec<f32> = notes[start..start + WINDOW_TICKS].iter().map(EngineNote::hz).collect();
        let (lo, hi) = hz.iter().fold((f32::MAX, 0.0f32), |(a, b), &h| (a.min(h), b.max(h)));
        if hi > 1.03 * lo {
            continue; // a shift or a hard acceleration inside the window: no single pitch to find
        }
        let want = 0.5 * (lo + hi);
        let got = pitch(ticks(&m, start, start + WINDOW_TICKS));
        checked += 1;
        if (got / want - 1.0).abs() <= 0.05 {
            within += 1;
            gears.insert(notes[start].gear);
        } else {
            eprintln!("tick {start}: engine {want:.1} Hz, loudest {got:.1} Hz");
        }
    }
    eprintln!("{within} of {checked} steady windows within 5%, in gears {gears:?}");
    assert!(checked >= 60, "only {checked} steady windows");
    assert!(within * 10 >= checked * 9, "{within} of {checked} windows within 5%");
    assert!(gears.len() >= 4, "matched in gears {gears:?} only");
}

#[test]
fn engines_idle_on_the_grid_then_rev_at_the_start() {
    let w = worlds("demo-race");
    let start = w.iter().position(|w| w.race.phase == Phase::Racing).expect("the race starts");
    let m = mono(&samples(&wav_bytes("demo-race", 1, 0)));
    let idle = firing_hz(IDLE_RPM);
    for from in [30, 150, 270] {
        let got = pitch(ticks(&m, from, from + WINDOW_TICKS));
        assert!((got / idle - 1.0).abs() < 0.05, "grid at tick {from}: {got} Hz, idle is {idle} Hz");
    }
    let revving = pitch(ticks(&m, start + 60, start + 60 + WINDOW_TICKS));
    assert!(revving > 1.8 * idle, "0.5-1 s after the start: {revving} Hz against idle {idle} Hz");
}

/// Energy of the squeal band (1.9-3.1 kHz) in each tick's block, by Goertzel at 100 Hz steps.
fn squeal_band(m: &[f32]) -> Vec<f32> {
    m.chunks(TICK)
        .map(|b| {
            (19..=31)
                .map(|k| {
                    let c = 2.0 * libm::cosf(std::f32::consts::TAU * (k * 100) as f32 / 48_000.0);
                    let (mut s1, mut s2) = (0.0f32, 0.0f32);
                    for &v in b {
                        let s0 = v + c * s1 - s2;
                        s2 = s1;
                        s1 = s0;
                    }
                    s1 * s1 + s2 * s2 - c * s1 * s2
                })
                .sum()
        })
        .collect()
}

fn slip(c: &scanline_racer::game::car::Car) -> f32 {
    let f = c.forward();
    c.vel.dot(glam::Vec2::new(-f.y, f.x)).abs()
}

#[test]
fn tyre_squeal_rises_in_the_scuffle_slides() {
    let w = worlds("scuffle");
    let band = squeal_band(&mono(&samples(&wav_bytes("scuffle", 0, 0))));
    let (mut slide, mut grip) = (vec![], vec![]);
    for (t, world) in w.iter().enumerate().skip(1) {
        if slip(&world.cars[0]) > 4.0 {
            slide.push(band[t]);
        } else if world.cars.iter().all(|c| slip(c) < 1.0) && world.race.phase == Phase::Racing {
            grip.push(band[t]);
        }
    }
    let mean = |v: &[f32]| v.iter().sum::<f32>() / v.len().max(1) as f32;
    eprintln!(
        "{} sliding ticks: {:.3e}; {} gripping ticks: {:.3e}",
        slide.len(),
        mean(&slide),
        grip.len(),
        mean(&grip)
    );
    assert!(slide.len() >= 60 && grip.len() >= 60, "{} sliding, {} gripping ticks", slide.len(), grip.len());
    assert!(mean(&slide) > 10.0 * mean(&grip), "squeal band {} sliding vs {} gripping", mean(&slide), mean(&grip));
}

/// Ticks at which the player's car hits a barrier or a car at more than 3 m/s, after 100 ms without one.
fn player_contacts(w: &[World]) -> Vec<(usize, f32)> {
    let mut out: Vec<(usize, f32)> = vec![];
    for t in 1..w.len() {
        let (a, b) = (&w[t].cars[0], &w[t - 1].cars[0]);
        let mut speed = 0.0f32;
        let side = usize::from(a.loc.lateral > 0.0);
        if a.loc.lateral.abs() >= a.loc.barrier[side] - BODY_HALF_WIDTH - 1e-3 {
            let (_, dir) = w[t].track.point_at(a.loc.s, 0.0);
            let out = glam::Vec2::new(-dir.y, dir.x) * a.loc.lateral.signum();
            speed = speed.max(b.vel.dot(out) - a.vel.dot(out));
        }
        for j in 1..w[t].cars.len() {
            let d = w[t].cars[j].pos - a.pos;
            if d.length() <= 2.0 * w[t].params[0].radius + 0.02 {
                speed = speed.max(-(w[t - 1].cars[j].vel - b.vel).dot(d.normalize_or_zero()));
            }
        }
        if speed > 3.0 && out.last().is_none_or(|&(last, _)| t > last + 12) {
            out.push((t, speed));
        }
    }
    out
}

#[test]
fn an_impact_transient_at_each_contact_tick() {
    let w = worlds("scuffle");
    let m = mono(&samples(&wav_bytes("scuffle", 0, 0)));
    let hf = |x: &[f32]| x.windows(2).map(|p| (p[1] - p[0]) * (p[1] - p[0])).sum::<f32>();
    let hits = player_contacts(&w);
    assert!(hits.len() >= 2, "the scuffle has contacts: {hits:?}");
    for &(t, speed) in &hits {
        let before = hf(&m[t * TICK - 1440..t * TICK]);
        let after = hf(&m[t * TICK..t * TICK + 1440]);
        eprintln!("tick {t}: {speed:.1} m/s, high-band energy x{:.1}", after / before.max(1e-12));
        assert!(after > 3.0 * before, "tick {t} ({speed:.1} m/s): {after} after vs {before} before");
    }
}

#[test]
fn no_clipping() {
    for trace in ["demo-race", "scuffle"] {
        let s = samples(&wav_bytes(trace, if trace == "scuffle" { 0 } else { 1 }, 0));
        let peak = s.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        eprintln!("{trace}: peak {peak:.3} of full scale");
        assert!(peak < 0.99, "{trace}: peak {peak}");
        assert!(peak > 0.1, "{trace}: nearly silent ({peak})");
    }
}

#[test]
fn no_clicks_at_gear_changes_and_voice_starts() {
    // A click is a jump between two samples steeper than the sound around it. At every gear change and
    // every voice start (beeps, impacts, the finish), the steepest jump in the first 2 ms from the event may
    // exceed neither CLICK_BOUND nor 1.5 times the steepest jump of the sound around it (the 50 ms before
    // and the 10-60 ms after, once the voice has started) plus 0.005.
    for trace in ["demo-race", "scuffle"] {
        let w = worlds(trace);
        let s = samples(&wav_bytes(trace, if trace == "scuffle" { 0 } else { 1 }, 0));
        let (left, right): (Vec<f32>, Vec<f32>) = s.chunks_exact(2).map(|f| (f[0], f[1])).unzip();
        let notes = notes(&w);
        let mut events: Vec<usize> = (0..w.len()).filter(|&t| notes[t].shifted).collect();
        let shifts = events.len();
        events.extend([0, 120, 240, 360]);
        events.extend(player_contacts(&w).iter().map(|h| h.0));
        events.extend(
            (1..w.len()).filter(|&t| {
                w[t].race.standings[0].finished.is_some() && w[t - 1].race.standings[0].finished.is_none()
            }),
        );
        let mut worst = 0.0f32;
        for &t in &events {
            for ch in [&left, &right] {
                let at = t * TICK;
                let jump = max_jump(&ch[at.saturating_sub(1)..at + 96]);
                let around = max_jump(&ch[at.saturating_sub(2400)..at.max(1)]).max(max_jump(&ch[at + 480..at + 2880]));
                worst = worst.max(jump);
                assert!(
                    jump <= CLICK_BOUND && jump <= 1.5 * around + 0.005,
                    "{trace} tick {t}: jump {jump}, around it {around}"
                );
            }
        }
        eprintln!("{trace}: {shifts} gear changes, {} events, steepest jump {worst:.4}", events.len());
        assert!(shifts >= 5 || trace == "scuffle", "{trace}: only {shifts} gear changes");
    }
}

#[test]
fn every_sound_ends_cleanly() {
    for trace in ["demo-race", "scuffle"] {
        let s = samples(&wav_bytes(trace, if trace == "scuffle" { 0 } else { 1 }, 0));
        let ticks = worlds(trace).len();
        assert!(s.len() >= 2 * ticks * TICK, "{trace}: a block for every tick");
        let tail = &s[2 * ticks * TICK..];
        assert!(
            tail.len() <= 2 * 48_000 / 2,
            "{trace}: the ending takes at most 0.5 s, took {} frames",
            tail.len() / 2
        );
        assert!(s[s.len() - 2 * 2 * TICK..].iter().all(|&x| x == 0.0), "{trace}: ends in digital silence");
        assert!(max_jump(&s[2 * (ticks - 6) * TICK..]) <= CLICK_BOUND, "{trace}: the fade clicks");
    }
}

#[test]
fn the_soundtrack_is_bit_identical_across_runs_and_thread_counts() {
    assert!(*wav_bytes("demo-race", 1, 0) == *wav_bytes("demo-race", 3, 0), "--threads 1 and 3 differ");
    assert!(*wav_bytes("scuffle", 0, 0) == *wav_bytes("scuffle", 0, 1), "two runs differ");
}

/// Set (by `scripts/test`, hence CI) to make a missing PulseAudio a failure instead of a plainly reported skip.
const REQUIRE_AUDIO: &str = "SCANLINE_RACER_REQUIRE_AUDIO";
/// The same for Xvfb.
const REQUIRE_XVFB: &str = "SCANLINE_RACER_REQUIRE_XVFB";
/// Most seconds the window's sound is recorded for, from the game's start, waiting for its sound to begin and
/// run through [`STRETCH`]: a cold, busy host can take seconds to open the window and the device.
const RECORD_DEADLINE: f32 = 45.0;
/// The stretch of the recording compared (seconds from its steady sound): the start and the first gears.
const STRETCH: (f32, f32) = (1.5, 9.0);
/// Least RMS of every 50 ms block of a second for the sound to count as steady from that second's start:
/// the engines idle well above it, while a device that plays a few blocks and then stalls (the game busy
/// opening its window) falls below it.
const STEADY_FLOOR: f32 = 0.002;
/// Least RMS (full scale 1) of the loudest second of the recording: the engines at this level are plainly
/// audible; a null sink that got nothing records digital zero.
const RMS_FLOOR: f32 = 0.01;
/// Most race time (seconds) whose sound the window may not play at its start: the device opens at the first
/// frame and pulls its first period within tens of milliseconds, so the countdown's first beep (race time 0)
/// is heard.
const START_LAG: f32 = 0.3;

/// Child processes killed (and reaped) when dropped: on every path out of the test, a panic included.
struct Children(Vec<(&'static str, std::process::Child)>);

impl Children {
    fn find(&mut self, name: &str) -> Option<&mut std::process::Child> {
        self.0.iter_mut().find(|(n, _)| *n == name).map(|(_, c)| c)
    }

    /// Ends the child `name` (SIGKILL) and reaps it.
    fn end(&mut self, name: &str) {
        if let Some(c) = self.find(name) {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

impl Drop for Children {
    fn drop(&mut self) {
        for (_, c) in self.0.iter_mut().rev() {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

/// Runs `program` with `args`; `None` when it cannot be started at all (not installed).
fn spawn(program: &str, args: &[&str], env: &[(&str, &std::path::Path)]) -> Option<std::process::Child> {
    let mut cmd = std::process::Command::new(program);
    cmd.args(args).stdin(std::process::Stdio::null()).stdout(std::process::Stdio::null());
    cmd.stderr(std::process::Stdio::null());
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.spawn().ok()
}

/// Waits up to 10 s for a Unix socket at `path` to accept a connection.
fn wait_for_socket(path: &std::path::Path) -> bool {
    let t = std::time::Instant::now();
    while t.elapsed() < std::time::Duration::from_secs(10) {
        if std::os::unix::net::UnixStream::connect(path).is_ok() {
            return true;
        }
        std::thread::sleep(std::time::Duration::from_millis(50));
    }
    false
}

/// Starts Xvfb on a free display into `children`; its display (`:N`), or `None` when it is not installed
/// and not required.
#[allow(clippy::panic)]
fn start_xvfb(children: &mut Children) -> Option<String> {
    for k in 0..40 {
        let num = 300 + (std::process::id() as usize * 13 + k * 7) % 600;
        if std::path::Path::new(&format!("/tmp/.X{num}-lock")).exists() {
            continue;
        }
        let display = format!(":{num}");
        let Some(child) = spawn("Xvfb", &[&display, "-screen", "0", "640x480x24", "-nolisten", "tcp", "-noreset"], &[])
        else {
            if std::env::var_os(REQUIRE_XVFB).is_some() {
                panic!("cannot start Xvfb and {REQUIRE_XVFB} is set: install it (apt-get install xvfb)");
            }
            eprintln!("NOT RUN: the window's sound needs Xvfb, which is not installed; scripts/test installs it");
            return None;
        };
        children.0.push(("Xvfb", child));
        if wait_for_socket(std::path::Path::new(&format!("/tmp/.X11-unix/X{num}"))) {
            std::thread::sleep(std::time::Duration::from_millis(100));
            if let Some(Ok(None)) = children.find("Xvfb").map(std::process::Child::try_wait) {
                return Some(display);
            }
        }
        children.end("Xvfb");
        children.0.retain(|(n, _)| *n != "Xvfb");
    }
    panic!("no Xvfb display came up");
}

/// The samples of a WAV file `parec` wrote, as mono in [-1, 1], and its rate: the data chunk's size is not
/// trusted (a recorder that is killed never writes it).
#[allow(clippy::expect_used)]
fn recorded_mono(bytes: &[u8]) -> (Vec<f32>, u32) {
    let u16_at = |i: usize| u16::from_le_bytes([bytes[i], bytes[i + 1]]);
    assert_eq!(&bytes[0..4], b"RIFF", "a WAV file");
    let channels = usize::from(u16_at(22));
    let rate = u32::from_le_bytes([bytes[24], bytes[25], bytes[26], bytes[27]]);
    assert_eq!((u16_at(20), u16_at(34)), (1, 16), "16-bit PCM");
    let data = bytes.windows(4).position(|w| w == b"data").expect("a data chunk") + 8;
    let s: Vec<f32> =
        bytes[data..].chunks_exact(2).map(|c| f32::from(i16::from_le_bytes([c[0], c[1]])) / 32767.0).collect();
    let mono = s.chunks_exact(channels).map(|f| f.iter().sum::<f32>() / channels as f32).collect();
    (mono, rate)
}

/// Where the sound of `x` (48 kHz) becomes steady: the start of the first 50 ms block that begins a second
/// of blocks all above [`STEADY_FLOOR`] RMS; `None` before there is such a second.
fn steady_start(x: &[f32]) -> Option<usize> {
    let block = 2_400;
    let loud: Vec<bool> = x.chunks_exact(block).map(|b| rms(b) > STEADY_FLOOR).collect();
    loud.windows(20).position(|w| w.iter().all(|&l| l)).map(|b| b * block)
}

/// `x` (at `rate`) resampled to 48 kHz by linear interpolation.
fn to_48k(x: &[f32], rate: u32) -> Vec<f32> {
    if rate == 48_000 {
        return x.to_vec();
    }
    let step = rate as f64 / 48_000.0;
    let n = ((x.len() - 1) as f64 / step) as usize;
    (0..n)
        .map(|i| {
            let p = i as f64 * step;
            let (k, f) = (p as usize, (p - p.floor()) as f32);
            x[k] + (x[k + 1] - x[k]) * f
        })
        .collect()
}

fn rms(x: &[f32]) -> f32 {
    libm::sqrtf(x.iter().map(|v| v * v).sum::<f32>() / x.len().max(1) as f32)
}

/// The real device path: a private PulseAudio server with a null sink, the game replaying the demo race in
/// a window under Xvfb with its sound on the server's default device, and the sink's monitor recorded
/// with `parec` until its steady sound has run through [`STRETCH`] (at most [`RECORD_DEADLINE`]). The
/// recording must not be silent (its loudest second above [`RMS_FLOOR`]), and its engine pitch over the
/// stretch of the race (the grid's idle, the start, the first gears), in 0.5 s windows every 0.5 s, must match the headless WAV's pitch of the same
/// stretch: with the recording aligned to the WAV by the lag (searched from -0.5 s to +6 s in 50 ms steps)
/// at which most windows agree, at least 80% of the windows within 5%; and that lag within [`START_LAG`] of
/// 0 (the race's sound from its first tick: a device slow to start pulling would lose it, since the race's
/// sound meanwhile is dropped, not queued).
#[test]
#[allow(clippy::expect_used, clippy::panic)]
fn the_window_plays_the_race_on_a_real_audio_server() {
    let required = std::env::var_os(REQUIRE_AUDIO).is_some();
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("audio-server-{}", std::process::id()));
    let (run, home) = (dir.join("run"), dir.join("home"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&run).expect("runtime folder");
    std::fs::create_dir_all(&home).expect("home folder");
    // The server's own runtime folder and home, so it meets no other server and no other test's.
    let env: [(&str, &std::path::Path); 2] = [("XDG_RUNTIME_DIR", &run), ("HOME", &home)];
    let mut children = Children(vec![]);
    let sink = "module-null-sink sink_name=test rate=48000";
    let args = ["--exit-idle-time=-1", "-n", "--load", sink, "--load", "module-native-protocol-unix"];
    match spawn("pulseaudio", &args, &env) {
        Some(c) => children.0.push(("pulseaudio", c)),
        None if required => panic!("cannot start pulseaudio and {REQUIRE_AUDIO} is set: run scripts/test"),
        None => {
            eprintln!("NOT RUN: this test needs PulseAudio (pulseaudio, pulseaudio-utils); scripts/test installs it");
            return;
        }
    }
    assert!(wait_for_socket(&run.join("pulse/native")), "the PulseAudio server did not come up");
    let status = std::process::Command::new("pactl")
        .args(["set-default-sink", "test"])
        .envs(env)
        .status()
        .expect("pactl runs (pulseaudio-utils)");
    assert!(status.success(), "pactl set-default-sink");
    let Some(display) = start_xvfb(&mut children) else { return };
    let recording = dir.join("window.wav");
    // A null sink renders in blocks of the shortest latency its streams ask for; `parec`'s default asks for
    // 2 s, and a stream that joins then waits for the block under way to end (up to 2 s of the race unheard).
    let rec_args = [
        "--latency-msec=20",
        "-d",
        "test.monitor",
        "--rate=48000",
        "--channels=2",
        "--format=s16le",
        "--file-format=wav",
    ];
    let parec = spawn("parec", &[&rec_args[..], &[&*recording.to_string_lossy()]].concat(), &env)
        .expect("parec runs (pulseaudio-utils)");
    children.0.push(("parec", parec));
    // The game starts once the recorder is recording (the monitor's silence is flowing into the file).
    let t = std::time::Instant::now();
    while std::fs::metadata(&recording).map_or(0, |m| m.len()) < 48_000 && t.elapsed().as_secs() < 10 {
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let game = std::process::Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .current_dir(root())
        .args(["replay", "assets/replays/demo-race.trace", "--width", "320", "--height", "180"])
        .envs(env)
        .env("DISPLAY", &display)
        .env_remove("WAYLAND_DISPLAY")
        .env("SCANLINE_RACER_SETTINGS", dir.join("no-settings.json"))
        .env("SCANLINE_RACER_RECORDS", std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("records.json"))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("the game starts");
    children.0.push(("game", game));
    // Recorded until the steady sound has run through the stretch and a second beyond, or the deadline.
    let (t, need) = (std::time::Instant::now(), (STRETCH.1 + 1.0) * 48_000.0);
    let mut early = None;
    while t.elapsed().as_secs_f32() < RECORD_DEADLINE {
        std::thread::sleep(std::time::Duration::from_millis(250));
        early = children.find("game").and_then(|g| g.try_wait().ok().flatten());
        let bytes = std::fs::read(&recording).unwrap_or_default();
        let ready = bytes.len() > 44 && {
            let (rec, rate) = recorded_mono(&bytes);
            let got = to_48k(&rec, rate);
            steady_start(&got).is_some_and(|s| got.len() >= s + need as usize)
        };
        if early.is_some() || ready {
            break;
        }
    }
    children.end("game");
    std::thread::sleep(std::time::Duration::from_millis(300));
    children.end("parec");
    let mut said = String::new();
    if let Some(err) = children.find("game").and_then(|g| g.stderr.as_mut()) {
        let _ = std::io::Read::read_to_string(err, &mut said);
    }
    assert!(early.is_none(), "the game exited early ({early:?}): {said}");
    assert!(!said.contains("no audio"), "the game found no audio device: {said}");
    let (rec, rate) = recorded_mono(&std::fs::read(&recording).expect("parec wrote the recording"));
    let got = to_48k(&rec, rate);
    let loudest = got.chunks(48_000).map(rms).fold(0.0f32, f32::max);
    let heard = got.iter().position(|x| x.abs() > 1e-3).unwrap_or(got.len());
    let start = steady_start(&got).unwrap_or(got.len());
    eprintln!(
        "recorded {:.1} s at {rate} Hz; sound from {:.2} s, steady from {:.2} s; loudest second RMS {loudest:.4}",
        rec.len() as f32 / rate as f32,
        heard as f32 / 48_000.0,
        start as f32 / 48_000.0
    );
    assert!(loudest > RMS_FLOOR, "the window's sound is silent: loudest second RMS {loudest} (floor {RMS_FLOOR})");
    let want = mono(&samples(&wav_bytes("demo-race", 1, 0)));
    let window = 24_000;
    let at = |s: f32| (s * 48_000.0) as usize;
    let mut ours = vec![];
    let mut t = STRETCH.0;
    while t + 0.5 <= STRETCH.1 {
        let from = start + at(t);
        assert!(from + window <= got.len(), "the recording ends before {t} s of the steady sound");
        ours.push((t, pitch(&got[from..from + window])));
        t += 0.5;
    }
    // The WAV's pitch on a 50 ms grid over the stretch and the lags searched, then the lag at which most
    // windows agree.
    let step = 0.05f32;
    let first = ((STRETCH.0 - 0.5) / step) as usize;
    let grid: Vec<f32> = (first..=((STRETCH.1 + 6.5) / step) as usize)
        .map(|i| pitch(&want[at(i as f32 * step)..at(i as f32 * step) + window]))
        .collect();
    let headless = |t: f32, lag: i32| grid[(((t / step).round() as i32 + lag) as usize) - first];
    let (mut best, mut best_lag) = (0, 0);
    for lag in -10..=120 {
        let agree = ours.iter().filter(|(t, p)| (p / headless(*t, lag) - 1.0).abs() <= 0.05).count();
        if agree > best {
            (best, best_lag) = (agree, lag);
        }
    }
    for (t, p) in &ours {
        eprintln!("  {t:4.1} s: window {p:6.1} Hz, headless {:6.1} Hz", headless(*t, best_lag));
    }
    let best_lag = best_lag as f32 * step;
    eprintln!("{best} of {} windows within 5% at a lag of {best_lag:+.2} s", ours.len());
    assert!(best * 10 >= ours.len() * 8, "{best} of {} windows within 5% (best lag {best_lag} s)", ours.len());
    assert!(
        (-START_LAG..=START_LAG).contains(&best_lag),
        "the window's steady sound starts {best_lag:+.2} s into the race: its start was not played"
    );
}
