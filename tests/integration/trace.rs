//! Traces: a recorded race replays exactly; truncated, corrupted, foreign and hostile files are refused in one
//! line or replay their valid prefix, never panic; headless replay frames are identical for any thread count.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::*;
use scanline_racer::game::World;
use scanline_racer::input::replay::TraceSource;

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("trace");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn record(path: &Path, ticks: u64) -> Vec<(u64, u64)> {
    record_trace(path, ticks)
}

/// Replays a trace in-process; returns the ticks reached or the error message.
fn replay(path: &Path) -> Result<u64, String> {
    let mut src = TraceSource::open(path).map_err(|e| e.to_string())?;
    let mut w = World::for_race(circuit(), &src.header.setup());
    src.check_track(&w).map_err(|e| e.to_string())?;
    while let Some(c) = src.next_controls(&w).map_err(|e| e.to_string())? {
        scanline_racer::game::step(&mut w, &c);
    }
    Ok(w.tick)
}

#[test]
fn a_recorded_race_replays_exactly_and_a_cut_trace_replays_its_prefix() {
    let path = tmp("race.trace");
    let sums = record(&path, 120 * 20);
    assert_eq!(sums.len(), 20);
    assert_eq!(replay(&path), Ok(120 * 20));
    let bytes = std::fs::read(&path).unwrap();
    // Cut anywhere after the header: the prefix replays, to the last whole record.
    let header_end = 14 + u32::from_le_bytes([bytes[10], bytes[11], bytes[12], bytes[13]]) as usize;
    for cut in [header_end, header_end + 1, header_end + 3, bytes.len() / 2, bytes.len() - 1] {
        let p = tmp("cut.trace");
        std::fs::write(&p, &bytes[..cut]).unwrap();
        let ticks = replay(&p).unwrap_or_else(|e| panic!("cut at {cut}: {e}"));
        assert!(ticks <= 120 * 20);
    }
    // Cut inside the header: one clear error.
    for cut in [0, 5, 12, header_end - 1] {
        let p = tmp("cut-header.trace");
        std::fs::write(&p, &bytes[..cut]).unwrap();
        let e = replay(&p).unwrap_err();
        assert!(e.contains("header") || e.contains("magic"), "cut at {cut}: {e}");
    }
}

#[test]
fn corruption_is_caught_at_the_first_checksum_after_it() {
    let path = tmp("corrupt.trace");
    record(&path, 120 * 10);
    let mut bytes = std::fs::read(&path).unwrap();
    let header_end = 14 + u32::from_le_bytes([bytes[10], bytes[11], bytes[12], bytes[13]]) as usize;
    // Controls records are 5 bytes, checksums 17 after every 120 controls: find tick 300's controls.
    let per_second = 120 * 5 + 17;
    // Tick 601's record (the first of the sixth second; the countdown holds the cars until tick 360).
    let at = header_end + 5 * per_second;
    assert_eq!(bytes[at], 1, "a controls record");
    bytes[at + 3] = bytes[at + 3].wrapping_add(200); // throttle
    bytes[at + 1] ^= 0x7f; // steer
    let p = tmp("corrupt2.trace");
    std::fs::write(&p, &bytes).unwrap();
    let e = replay(&p).unwrap_err();
    assert!(e.contains("diverges") && e.contains("tick 720"), "{e}");
    // A bad tag is named with its offset.
    bytes[at] = 9;
    std::fs::write(&p, &bytes).unwrap();
    let e = replay(&p).unwrap_err();
    assert!(e.contains(&format!("corrupt record at byte {at}")), "{e}");
}

#[test]
fn random_mutations_never_panic() {
    let path = tmp("fuzz-base.trace");
    record(&path, 120 * 3);
    let base = std::fs::read(&path).unwrap();
    let mut rng = Rng(0xf00d);
    let p = tmp("fuzz.trace");
    let (mut ok, mut err) = (0, 0);
    for _ in 0..600 {
        let mut b = base.clone();
        let n = 1 + rng.range(0, 8) as usize;
        for _ in 0..n {
            let i = rng.range(0, b.len() as i64) as usize;
            b[i] = rng.next_u64() as u8;
        }
        if rng.next_u64().is_multiple_of(4) {
            b.truncate(rng.range(0, b.len() as i64) as usize);
        }
        std::fs::write(&p, &b).unwrap();
        match replay(&p) {
            Ok(_) => ok += 1,
            Err(e) => {
                assert!(!e.is_empty() && !e.contains('\n'), "{e}");
                err += 1;
            }
        }
    }
    assert!(ok > 0 && err > 0, "mutations both pass (unchanged prefix) and fail: {ok} ok, {err} errors");
}

#[test]
fn foreign_versions_and_files_are_refused_with_both_versions_named() {
    let path = tmp("version.trace");
    record(&path, 120);
    let bytes = std::fs::read(&path).unwrap();
    let mut v3 = bytes.clone();
    v3[8] = 3;
    let p = tmp("v3.trace");
    std::fs::write(&p, &v3).unwrap();
    let e = replay(&p).unwrap_err();
    assert!(e.contains("trace format version 3, but this build reads versions 1 to 2"), "{e}");
    let mut v0 = bytes.clone();
    v0[8] = 0;
    std::fs::write(&p, &v0).unwrap();
    assert!(replay(&p).unwrap_err().contains("format version 0"));
    let mut sim7 = bytes.clone();
    let key = format!("\"sim_version\":{}", scanline_racer::input::trace::SIM_VERSION).into_bytes();
    let key = key.as_slice();
    let pos = sim7.windows(key.len()).position(|w| w == key).expect("sim_version in the header");
    sim7[pos + key.len() - 1] = b'7';
    std::fs::write(&p, &sim7).unwrap();
    let e = replay(&p).unwrap_err();
    assert!(e.contains("simulation version 7, but this build runs versions 2 and 3"), "{e}");
    std::fs::write(&p, b"PNG\x89 not a trace at all").unwrap();
    assert!(replay(&p).unwrap_err().contains("magic"));
    let mut huge = bytes.clone();
    huge[10..14].copy_from_slice(&u32::MAX.to_le_bytes());
    std::fs::write(&p, &huge).unwrap();
    assert!(replay(&p).unwrap_err().contains("over the limit"), "no huge allocation for an absurd header length");
}

#[test]
fn headless_replay_writes_identical_frames_for_any_thread_count() {
    let path = tmp("frames.trace");
    record(&path, 120 * 6);
    let mut outputs = vec![];
    for threads in ["1", "2"] {
        let dir = tmp(&format!("frames-{threads}"));
        let _ = std::fs::remove_dir_all(&dir);
        let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
            .args(["replay", path.to_str().unwrap(), "--headless", "--frames", dir.to_str().unwrap()])
            .args(["--every", "240", "--width", "160", "--height", "90", "--threads", threads])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{err}");
        assert!(
            err.contains("replayed 720 ticks") && err.contains("6 checksums verified") && err.contains("3 frames"),
            "{err}"
        );
        let mut names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
        names.sort();
        outputs.push(names.iter().map(|p| std::fs::read(p).unwrap()).collect::<Vec<_>>());
    }
    assert_eq!(outputs[0].len(), 3);
    assert!(outputs[0] == outputs[1], "frames differ between 1 and 2 threads");
    // A diverging trace stops the command with one line naming the tick.
    let mut bytes = std::fs::read(&path).unwrap();
    let header_end = 14 + u32::from_le_bytes([bytes[10], bytes[11], bytes[12], bytes[13]]) as usize;
    bytes[header_end + 3] = 255; // full throttle at tick 1, during the countdown: no effect on the state...
    bytes[header_end + (120 * 5 + 17) * 4 + 5 * 10 + 1] ^= 0x40; // ...but a steering change at tick 491 does.
    let p = tmp("diverge.trace");
    std::fs::write(&p, &bytes).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", p.to_str().unwrap(), "--headless"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("diverges from the recording at tick 600"), "{err}");
}

/// The ghost's lap search on a background thread finds the lap the search done at once finds, laps
/// arriving fastest last; dropped mid-trace, it stops at once instead of replaying the rest.
#[test]
fn the_background_ghost_search_finds_the_fastest_lap_and_stops_when_dropped() {
    use scanline_racer::input::ghost::{GhostFound, GhostSearch, best_lap_of_trace};
    use std::time::{Duration, Instant};
    let demo = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/replays/demo-race.trace");
    let at_once = best_lap_of_trace(&demo, circuit()).unwrap().expect("the demo race has a lap");
    let mut search = GhostSearch::start(&demo, circuit()).unwrap();
    let mut laps = vec![];
    let end = loop {
        match search.wait() {
            Some(GhostFound::Faster(lap)) => laps.push(lap),
            Some(other) => break other,
            None => panic!("the search ended without saying so"),
        }
    };
    assert!(matches!(end, GhostFound::End { laps: true }), "{end:?}");
    assert!(laps.windows(2).all(|w| w[1].ticks() < w[0].ticks()), "each lap reported is faster");
    assert_eq!(laps.last(), Some(&at_once));
    // Two million ticks (about 40 s to replay in a debug build): dropping the search stops its thread.
    let long = tmp("idle-long.trace");
    write_idle_trace(&long, 2_000_000);
    let search = GhostSearch::start(&long, circuit()).unwrap();
    std::thread::sleep(Duration::from_millis(200));
    let t = Instant::now();
    drop(search);
    assert!(t.elapsed() < Duration::from_secs(2), "dropping took {:?}", t.elapsed());
    let _ = std::fs::remove_file(&long);
}

/// A trace of the header and then millions of checksum records for tick 0 (all with the right sum): the
/// replay refuses the second record, naming its byte offset, instead of reading them all inside one tick;
/// and a ghost search on it, dropped at once, stops within a bound (it used to read the whole run first).
#[test]
fn a_repeated_checksum_record_is_refused_and_the_ghost_search_on_it_stops_at_once() {
    use scanline_racer::input::ghost::{GhostFound, GhostSearch};
    use scanline_racer::input::trace::TraceWriter;
    use scanline_racer::shell::race::header_for;
    use std::io::Write;
    use std::time::{Duration, Instant};
    let w = World::with_laps(circuit(), 8, 3);
    let p = tmp("same-tick.trace");
    TraceWriter::create(&p, &header_for(&w, "circuit")).unwrap().finish().unwrap();
    let header_end = std::fs::metadata(&p).unwrap().len();
    let mut rec = [0u8; 17];
    rec[0] = 2;
    rec[9..17].copy_from_slice(&w.checksum().to_le_bytes());
    // Ten million records: 170 MB, within the 256 MiB a trace may have.
    let run: Vec<u8> = rec.iter().copied().cycle().take(17 * 1_000_000).collect();
    let mut f = std::fs::OpenOptions::new().append(true).open(&p).unwrap();
    for _ in 0..10 {
        f.write_all(&run).unwrap();
    }
    let err = replay(&p).unwrap_err();
    let second = header_end + 17;
    assert!(err.contains(&format!("{}: checksum record at byte {second} for tick 0,", p.display())), "{err}");
    // The ghost search stops there too, and says so at once.
    let mut search = GhostSearch::start(&p, circuit()).unwrap();
    let t = Instant::now();
    match search.wait() {
        Some(GhostFound::Failed(e)) => assert_eq!(e.to_string(), err),
        other => panic!("{other:?}"),
    }
    assert!(t.elapsed() < Duration::from_secs(1), "the search took {:?} to fail", t.elapsed());
    assert!(search.wait().is_none(), "nothing after the failure");
    // Dropped at once, the search returns at once (reading the run took about half a second before).
    let search = GhostSearch::start(&p, circuit()).unwrap();
    let t = Instant::now();
    drop(search);
    assert!(t.elapsed() < Duration::from_millis(250), "dropping took {:?}", t.elapsed());
    let _ = std::fs::remove_file(&p);
}

/// The search keeps one lap for the race, the fastest not yet taken, not a queue of every faster lap: a race
/// that looks only after the search has ended gets that lap and the end, and nothing more.
#[test]
fn the_ghost_search_keeps_only_the_fastest_lap_for_a_race_that_does_not_look() {
    use scanline_racer::input::ghost::{GhostFound, GhostSearch, LapRecorder, best_lap_of_trace};
    use scanline_racer::input::replay::Replay;
    use std::time::{Duration, Instant};
    // Three laps by the AI: the first, from the standing start, is the slowest.
    let p = tmp("three-laps.trace");
    record(&p, 120 * 300);
    let mut replay = Replay::open(&p, circuit()).unwrap();
    let (mut laps, mut faster) = (LapRecorder::default(), 0);
    while replay.advance().unwrap() {
        faster += usize::from(laps.observe(&replay.world));
    }
    assert!(faster >= 2, "the trace has {faster} laps each faster than the one before: the test needs two");
    let at_once = best_lap_of_trace(&p, circuit()).unwrap().unwrap();
    let mut search = GhostSearch::start(&p, circuit()).unwrap();
    let t = Instant::now();
    while !search.done() {
        assert!(t.elapsed() < Duration::from_secs(60), "the search still runs");
        std::thread::sleep(Duration::from_millis(10));
    }
    match search.poll().as_slice() {
        [GhostFound::Faster(lap), GhostFound::End { laps: true }] => assert_eq!(lap, &at_once),
        other => panic!("{} reports: {other:?}", other.len()),
    }
    assert!(search.poll().is_empty());
    assert!(search.wait().is_none());
}

/// A trace of format version 1 (from before the courses, its header names none) still replays, on the
/// circuit, with every checksum verified: in-process and with the command line.
#[test]
fn a_trace_from_before_the_courses_replays_on_the_circuit() {
    let old = samples().join("scuffle-v1.trace");
    let bytes = std::fs::read(&old).unwrap();
    assert_eq!(u16::from_le_bytes([bytes[8], bytes[9]]), 1, "the sample is a version 1 trace");
    let src = TraceSource::open(&old).unwrap();
    assert_eq!(src.header.course, "circuit");
    assert_eq!(replay(&old), Ok(3600));
    let o = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
        .args(["replay", "--headless"])
        .arg(&old)
        .env("SCANLINE_RACER_ASSETS", Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && err.contains("replayed 3600 ticks (30.0 s), 30 checksums verified"), "{err}");
}

/// A header naming a course that is no plain folder name is refused in one line; one naming a course the
/// assets do not hold is refused naming the courses there are.
#[test]
fn a_trace_naming_a_course_that_is_not_there_is_refused_in_one_line() {
    let path = tmp("course.trace");
    record(&path, 120);
    let bytes = std::fs::read(&path).unwrap();
    let key = b"\"course\":\"circuit\"";
    let pos = bytes.windows(key.len()).position(|w| w == key).expect("course in the header");
    for (name, want) in [("../x/..", "is not a course name"), ("nowhere", "no course \"nowhere\"")] {
        let mut header = bytes[14..].to_vec();
        let replaced = format!("\"course\":\"{name}\"");
        header.splice(pos - 14..pos - 14 + key.len(), replaced.bytes());
        let len =
            u32::from_le_bytes([bytes[10], bytes[11], bytes[12], bytes[13]]) as usize + replaced.len() - key.len();
        let mut out = bytes[..10].to_vec();
        out.extend_from_slice(&(len as u32).to_le_bytes());
        out.extend_from_slice(&header);
        let p = tmp(&format!("course-{}.trace", name.len()));
        std::fs::write(&p, &out).unwrap();
        let o = Command::new(env!("CARGO_BIN_EXE_scanline-racer"))
            .args(["replay", "--headless"])
            .arg(&p)
            .env("SCANLINE_RACER_ASSETS", Path::new(env!("CARGO_MANIFEST_DIR")).join("assets"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{err}");
        assert!(err.contains(want), "{name}: {err}");
        if name == "nowhere" {
            assert!(err.contains("the courses: circuit, city"), "{err}");
        }
    }
}
