//! The fuzz target for the trace parser, as property tests (proptest): random bytes, random bytes behind a
//! valid magic and version, hostile headers, and a real recording mutated (bytes changed, cut, spliced,
//! its length fields rewritten). Properties: parsing and replaying never panic; every error is one
//! non-empty line; the reader never yields more records than the bytes can hold, and every control it
//! yields is finite and in range; an untouched prefix of a real trace replays with its checksums verified.
//!
//! Run longer with `PROPTEST_CASES=100000 cargo test --release --test integration trace_fuzz::`. The first
//! runs (512 and 100,000 cases per property) found no panic, no multi-line error and no runaway read: the
//! reader had been written against hostile input from the start (bounded header, records of fixed size,
//! quantized controls).

use std::io::Cursor;
use std::sync::OnceLock;

use crate::common::*;
use proptest::prelude::*;
use scanline_racer::game::World;
use scanline_racer::input::replay::TraceSource;
use scanline_racer::input::trace::{FORMAT_VERSION, MAGIC, Record, TraceReader};

/// A real three-second recording of the full field, made once.
fn base() -> &'static [u8] {
    static BASE: OnceLock<Vec<u8>> = OnceLock::new();
    BASE.get_or_init(|| {
        let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("trace-fuzz");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("base.trace");
        record_trace(&path, 360);
        std::fs::read(&path).unwrap()
    })
}

/// Where the records start in [`base`].
fn records_start(bytes: &[u8]) -> usize {
    14 + u32::from_le_bytes(bytes[10..14].try_into().unwrap()) as usize
}

fn one_line(e: &str) {
    assert!(!e.is_empty() && !e.contains('\n'), "error is not one line: {e:?}");
}

/// Parses `bytes` record by record and checks what comes out.
fn parse(bytes: Vec<u8>) {
    let len = bytes.len();
    match TraceReader::from_reader("fuzz", Box::new(Cursor::new(bytes))) {
        Err(e) => one_line(&e.to_string()),
        Ok((header, mut reader)) => {
            assert!((1..=64).contains(&header.cars) && (1..=99).contains(&header.laps));
            let mut n = 0usize;
            loop {
                match reader.next_record() {
                    Ok(None) => break,
                    Ok(Some(Record::Controls(c))) => {
                        assert!((-1.0..=1.0).contains(&c.steer), "{c:?}");
                        assert!((0.0..=1.0).contains(&c.throttle) && (0.0..=1.0).contains(&c.brake), "{c:?}");
                    }
                    Ok(Some(Record::Checksum { .. })) => {}
                    Err(e) => {
                        one_line(&e.to_string());
                        break;
                    }
                }
                n += 1;
                assert!(n <= len / 5 + 1, "{n} records from {len} bytes");
            }
        }
    }
}

/// Replays `bytes` on the circuit; returns the ticks reached, or the one-line error.
fn replay(bytes: Vec<u8>) -> Result<(u64, u64), String> {
    let mut src = TraceSource::from_reader("fuzz", Box::new(Cursor::new(bytes))).map_err(|e| e.to_string())?;
    let mut w = World::with_laps(circuit(), src.header.cars as usize, src.header.laps);
    src.check_track(&w).map_err(|e| e.to_string())?;
    while let Some(c) = src.next_controls(&w).map_err(|e| e.to_string())? {
        scanline_racer::game::step(&mut w, &c);
    }
    Ok((w.tick, src.verified))
}

fn with_prefix(rest: &[u8]) -> Vec<u8> {
    let mut b = MAGIC.to_vec();
    b.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    b.extend_from_slice(rest);
    b
}

/// One way to damage a real trace.
#[derive(Clone, Debug)]
enum Mutation {
    /// Set the byte at (index mod length).
    Set(usize, u8),
    /// Cut the file at (index mod length).
    Cut(usize),
    /// Insert bytes at (index mod length).
    Splice(usize, Vec<u8>),
    /// Remove up to n bytes at (index mod length).
    Remove(usize, usize),
    /// Rewrite the header length field.
    HeaderLen(u32),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        4 => (any::<usize>(), any::<u8>()).prop_map(|(i, b)| Mutation::Set(i, b)),
        1 => any::<usize>().prop_map(Mutation::Cut),
        1 => (any::<usize>(), proptest::collection::vec(any::<u8>(), 1..40)).prop_map(|(i, v)| Mutation::Splice(i, v)),
        1 => (any::<usize>(), 1usize..40).prop_map(|(i, n)| Mutation::Remove(i, n)),
        1 => any::<u32>().prop_map(Mutation::HeaderLen),
    ]
}

fn apply(mut b: Vec<u8>, muts: &[Mutation]) -> Vec<u8> {
    for m in muts {
        if b.is_empty() {
            break;
        }
        let at = |i: usize| i % b.len();
        match m {
            Mutation::Set(i, v) => {
                let i = at(*i);
                b[i] = *v;
            }
            Mutation::Cut(i) => b.truncate(at(*i)),
            Mutation::Splice(i, v) => {
                let i = at(*i);
                b.splice(i..i, v.iter().copied());
            }
            Mutation::Remove(i, n) => {
                let i = at(*i);
                let end = (i + n).min(b.len());
                b.drain(i..end);
            }
            Mutation::HeaderLen(n) if b.len() >= 14 => b[10..14].copy_from_slice(&n.to_le_bytes()),
            Mutation::HeaderLen(_) => {}
        }
    }
    b
}

/// Cases per property: 512, or `PROPTEST_CASES`.
fn cases() -> u32 {
    std::env::var("PROPTEST_CASES").ok().and_then(|v| v.parse().ok()).unwrap_or(512)
}

proptest! {
    #![proptest_config(ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
        parse(bytes.clone());
        if let Err(e) = replay(bytes) {
            one_line(&e);
        }
    }

    #[test]
    fn random_bytes_after_a_valid_magic_never_panic(rest in proptest::collection::vec(any::<u8>(), 0..512)) {
        parse(with_prefix(&rest));
    }

    #[test]
    fn hostile_headers_are_refused_in_one_line(
        cars in any::<i64>(), laps in any::<i64>(), hz in any::<i64>(), every in any::<i64>(),
        track in any::<u64>(), junk in "[ -~]{0,40}", depth in 0usize..300,
    ) {
        let json = format!(
            "{}{{\"sim_version\":{sim},\"game_version\":\"{}\",\"track_length_mm\":{track},\"cars\":{cars},\
             \"laps\":{laps},\"seed\":0,\"tick_hz\":{hz},\"checksum_every\":{every}}}{}",
            "[".repeat(depth), junk.replace(['"', '\\'], ""), "]".repeat(depth),
            sim = scanline_racer::input::trace::SIM_VERSION,
        );
        let mut rest = (json.len() as u32).to_le_bytes().to_vec();
        rest.extend_from_slice(json.as_bytes());
        rest.extend_from_slice(&[1, 0, 0, 255, 0]);
        let b = with_prefix(&rest);
        parse(b.clone());
        if let Err(e) = replay(b) {
            one_line(&e);
        }
    }

    #[test]
    fn mutated_recordings_never_panic_and_an_untouched_prefix_replays(
        muts in proptest::collection::vec(mutation(), 1..6),
    ) {
        let b = apply(base().to_vec(), &muts);
        parse(b.clone());
        let first_change = base().iter().zip(&b).position(|(x, y)| x != y).unwrap_or(b.len().min(base().len()));
        match replay(b) {
            Ok((ticks, _)) => prop_assert!(ticks <= 360 + 40),
            Err(e) => {
                one_line(&e);
                // A change inside the records is caught no earlier than its place: the header still parsed.
                if first_change > records_start(base()) + 17 {
                    prop_assert!(!e.contains("header") && !e.contains("magic"), "{e}");
                }
            }
        }
    }
}

#[test]
fn the_untouched_base_recording_replays_with_every_checksum() {
    assert_eq!(replay(base().to_vec()), Ok((360, 3)));
}
