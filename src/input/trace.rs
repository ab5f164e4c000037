//! Input traces: the controls of every tick of a race, so the race can be replayed exactly.
//!
//! The format is documented in `docs/trace-format.md`. In short, little-endian:
//! `b"SRTRACE\0"`, `u16` format version, `u32` header length, a JSON header (what decides the simulation),
//! then records: tag `1` + controls (`i16` steer, `u8` throttle, `u8` brake) for each tick in order, and
//! every [`Header::checksum_every`] ticks tag `2` + `u64` tick + `u64` state checksum. Records are written
//! as they happen and flushed with each checksum, so a killed process leaves a valid prefix.
//!
//! Controls are quantized to what the file can hold *before* the simulation sees them ([`quantize`]), in
//! play and in replay alike, so a trace holds exactly what the simulation saw.

use std::fs::File;
use std::io::{BufReader, BufWriter, Read, Write};
use std::path::Path;

use thiserror::Error;

use super::header::MAX_HEADER;
pub use super::header::{
    FIRST_COURSE, Header, HeaderProblem, MAX_COURSE_NAME, SAME_CARS_SIM_VERSION, SIM_VERSION, is_course_name,
};
use crate::game::Controls;

/// The file's first eight bytes.
pub const MAGIC: &[u8; 8] = b"SRTRACE\0";
/// The format version this build writes (version 2: the header names the course).
pub const FORMAT_VERSION: u16 = 2;
/// The oldest format version this build reads: a version 1 trace (from before there were several courses)
/// was raced on the circuit, and replays there.
pub const OLDEST_FORMAT_VERSION: u16 = 1;
/// Largest trace file read: 256 MiB, about 14 hours of racing at 120 ticks a second (a three-lap race is
/// under 200 KB). Reading stops there whatever the file does meanwhile.
pub const MAX_TRACE_BYTES: u64 = 256 * 1024 * 1024;

const TAG_CONTROLS: u8 = 1;
const TAG_CHECKSUM: u8 = 2;

/// One record of a trace.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Record {
    /// The player's controls for the next tick.
    Controls(Controls),
    /// The world checksum after `tick`.
    Checksum {
        /// The tick.
        tick: u64,
        /// `World::checksum()` after it.
        sum: u64,
    },
}

/// Why a trace could not be written or read.
#[derive(Debug, Error)]
pub enum TraceError {
    /// The path is not a regular file (a folder, a FIFO, a device), is too big, or cannot be opened.
    #[error(transparent)]
    File(#[from] crate::userfile::UserFileError),
    /// The file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Not a trace file.
    #[error("{path}: not a scanline-racer trace (wrong magic bytes)")]
    Magic {
        /// The file.
        path: String,
    },
    /// A trace of another format version.
    #[error(
        "{path}: trace format version {found}, but this build reads versions {OLDEST_FORMAT_VERSION} to {FORMAT_VERSION}"
    )]
    Version {
        /// The file.
        path: String,
        /// The version in the file.
        found: u16,
    },
    /// A trace of another simulation version.
    #[error(
        "{path}: recorded with simulation version {found}, but this build runs versions {SAME_CARS_SIM_VERSION} and {SIM_VERSION}"
    )]
    SimVersion {
        /// The file.
        path: String,
        /// The version in the file.
        found: u32,
    },
    /// The header is missing, too long, does not parse, or describes a race this build cannot run.
    #[error("{path}: bad header: {problem}")]
    Header {
        /// The file.
        path: String,
        /// What is wrong.
        #[source]
        problem: HeaderProblem,
    },
    /// A record with an unknown tag.
    #[error("{path}: corrupt record at byte {offset} (tag {tag})")]
    Corrupt {
        /// The file.
        path: String,
        /// Byte offset of the record.
        offset: u64,
        /// The tag found.
        tag: u8,
    },
    /// A checksum record for a tick at or before the previous checksum record's: checksum ticks only move
    /// forward, so a run of records for one tick (which a replay would otherwise read all within that tick)
    /// stops at its second record.
    #[error(
        "{path}: checksum record at byte {offset} for tick {tick}, not after the previous checksum's tick {previous}"
    )]
    ChecksumOrder {
        /// The file.
        path: String,
        /// Byte offset of the record.
        offset: u64,
        /// Tick in the record.
        tick: u64,
        /// Tick of the checksum record before it.
        previous: u64,
    },
}

/// Rounds controls to what a trace stores: steer in 1/32767 steps, throttle and brake in 1/255 steps.
#[must_use]
pub fn quantize(c: Controls) -> Controls {
    let (steer, throttle, brake) = encode(c);
    decode(steer, throttle, brake)
}

fn encode(c: Controls) -> (i16, u8, u8) {
    let c = c.sanitized();
    ((c.steer * 32767.0).round() as i16, (c.throttle * 255.0).round() as u8, (c.brake * 255.0).round() as u8)
}

fn decode(steer: i16, throttle: u8, brake: u8) -> Controls {
    Controls {
        steer: (f32::from(steer) / 32767.0).clamp(-1.0, 1.0),
        throttle: f32::from(throttle) / 255.0,
        brake: f32::from(brake) / 255.0,
    }
}

/// Writes a trace as the race runs.
pub struct TraceWriter {
    out: BufWriter<File>,
    path: String,
    ticks: u64,
}

impl TraceWriter {
    /// Creates (or truncates) `path` and writes the header: for the asset generator and tests, which own
    /// their output; the game records a user's race through [`super::recording::Recording`], which never
    /// truncates an existing file.
    pub fn create(path: &Path, header: &Header) -> Result<Self, TraceError> {
        let name = path.display().to_string();
        let file = File::create(path).map_err(|source| TraceError::Io { path: name.clone(), source })?;
        Self::new(file, &name, header)
    }

    /// Writes the header to `file`, an empty file opened for writing; `name` stands for it in messages.
    pub fn new(file: File, name: &str, header: &Header) -> Result<Self, TraceError> {
        let name = name.to_string();
        let io = |source: std::io::Error| TraceError::Io { path: name.clone(), source };
        let mut out = BufWriter::new(file);
        let json = serde_json::to_vec(header)
            .map_err(|e| TraceError::Header { path: name.clone(), problem: HeaderProblem::Json(e) })?;
        out.write_all(MAGIC).map_err(io)?;
        out.write_all(&FORMAT_VERSION.to_le_bytes()).map_err(io)?;
        out.write_all(&(json.len() as u32).to_le_bytes()).map_err(io)?;
        out.write_all(&json).map_err(io)?;
        out.flush().map_err(io)?;
        Ok(Self { out, path: name, ticks: 0 })
    }

    /// Ticks whose controls were written.
    #[must_use]
    pub fn ticks(&self) -> u64 {
        self.ticks
    }

    /// Appends one tick's controls (quantized).
    pub fn controls(&mut self, c: Controls) -> Result<(), TraceError> {
        let (s, t, b) = encode(c);
        let mut rec = [TAG_CONTROLS, 0, 0, t, b];
        rec[1..3].copy_from_slice(&s.to_le_bytes());
        self.write(&rec)?;
        self.ticks += 1;
        Ok(())
    }

    /// Appends a checksum and flushes, so everything up to here survives a crash.
    pub fn checksum(&mut self, tick: u64, sum: u64) -> Result<(), TraceError> {
        let mut rec = [0u8; 17];
        rec[0] = TAG_CHECKSUM;
        rec[1..9].copy_from_slice(&tick.to_le_bytes());
        rec[9..17].copy_from_slice(&sum.to_le_bytes());
        self.write(&rec)?;
        self.out.flush().map_err(|e| self.io(e))
    }

    /// Flushes what is buffered (dropping the writer does too, but cannot report an error).
    pub fn finish(&mut self) -> Result<(), TraceError> {
        self.out.flush().map_err(|e| self.io(e))
    }

    /// Flushes what is buffered and waits until the file is on disk (before it is renamed into place).
    pub fn sync(&mut self) -> Result<(), TraceError> {
        self.finish()?;
        self.out.get_ref().sync_all().map_err(|e| self.io(e))
    }

    fn write(&mut self, bytes: &[u8]) -> Result<(), TraceError> {
        self.out.write_all(bytes).map_err(|e| self.io(e))
    }

    /// An I/O error writing this trace.
    fn io(&self, source: std::io::Error) -> TraceError {
        TraceError::Io { path: self.path.clone(), source }
    }
}

/// Reads a trace record by record; a record cut short at the end of the file ends the trace quietly
/// (that is what a killed recording leaves).
pub struct TraceReader {
    input: BufReader<Box<dyn Read + Send>>,
    path: String,
    offset: u64,
    /// The tick of the last checksum record read.
    last_checksum: Option<u64>,
}

impl TraceReader {
    /// Opens `path` and reads and checks its header; only a regular file is opened (a folder, a FIFO or a
    /// device is refused at once, without blocking), and at most [`MAX_TRACE_BYTES`] of it are read.
    pub fn open(path: &Path) -> Result<(Header, Self), TraceError> {
        let file = crate::userfile::open_regular(path, MAX_TRACE_BYTES, "a trace")?;
        Self::from_reader(&path.display().to_string(), Box::new(file))
    }

    /// Reads and checks the header of a trace coming from `input`; `name` stands for it in messages. Nothing
    /// is allocated from a length in the input except the header, which is bounded (64 KiB).
    pub fn from_reader(name: &str, input: Box<dyn Read + Send>) -> Result<(Header, Self), TraceError> {
        let name = name.to_string();
        let mut input = BufReader::new(input);
        let mut head = [0u8; 14];
        let bad = |problem| TraceError::Header { path: name.clone(), problem };
        // The file ending inside the header is a problem of the header; any other failure to read is an I/O
        // error of its own.
        let read_failed = |e: std::io::Error| match e.kind() {
            std::io::ErrorKind::UnexpectedEof => bad(HeaderProblem::Cut),
            _ => TraceError::Io { path: name.clone(), source: e },
        };
        input.read_exact(&mut head).map_err(read_failed)?;
        if &head[..8] != MAGIC {
            return Err(TraceError::Magic { path: name });
        }
        let version = u16::from_le_bytes([head[8], head[9]]);
        if !(OLDEST_FORMAT_VERSION..=FORMAT_VERSION).contains(&version) {
            return Err(TraceError::Version { path: name, found: version });
        }
        let len = u32::from_le_bytes([head[10], head[11], head[12], head[13]]);
        if len > MAX_HEADER {
            return Err(bad(HeaderProblem::TooLong { length: len }));
        }
        let mut json = vec![0u8; len as usize];
        input.read_exact(&mut json).map_err(read_failed)?;
        let header: Header = serde_json::from_slice(&json).map_err(|e| bad(HeaderProblem::Json(e)))?;
        if header.sim_version != SIM_VERSION && header.sim_version != SAME_CARS_SIM_VERSION {
            return Err(TraceError::SimVersion { path: name, found: header.sim_version });
        }
        if let Some(problem) = header.problem() {
            return Err(bad(problem));
        }
        Ok((header, Self { input, path: name, offset: 14 + u64::from(len), last_checksum: None }))
    }

    /// The next record, `Ok(None)` at the end (including a record cut short by a crash); a checksum record
    /// whose tick is not after the previous checksum record's is an error naming its byte offset.
    pub fn next_record(&mut self) -> Result<Option<Record>, TraceError> {
        let mut tag = [0u8; 1];
        if self.input.read_exact(&mut tag).is_err() {
            return Ok(None);
        }
        let at = self.offset;
        match tag[0] {
            TAG_CONTROLS => {
                let mut b = [0u8; 4];
                if self.input.read_exact(&mut b).is_err() {
                    return Ok(None);
                }
                self.offset += 5;
                Ok(Some(Record::Controls(decode(i16::from_le_bytes([b[0], b[1]]), b[2], b[3]))))
            }
            TAG_CHECKSUM => {
                let mut b = [0u8; 16];
                if self.input.read_exact(&mut b).is_err() {
                    return Ok(None);
                }
                self.offset += 17;
                let tick = u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]);
                let sum = u64::from_le_bytes([b[8], b[9], b[10], b[11], b[12], b[13], b[14], b[15]]);
                if let Some(previous) = self.last_checksum.filter(|&p| tick <= p) {
                    return Err(TraceError::ChecksumOrder { path: self.path.clone(), offset: at, tick, previous });
                }
                self.last_checksum = Some(tick);
                Ok(Some(Record::Checksum { tick, sum }))
            }
            other => Err(TraceError::Corrupt { path: self.path.clone(), offset: at, tag: other }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantizing_is_idempotent_and_clamps() {
        let c = Controls { steer: 0.123_456, throttle: 0.5, brake: 2.0 };
        let q = quantize(c);
        assert_eq!(quantize(q), q);
        assert_eq!(q.brake, 1.0);
        assert!((q.steer - 0.123_456).abs() < 1.0 / 32767.0);
        let nan = quantize(Controls { steer: f32::NAN, throttle: f32::NAN, brake: f32::NAN });
        assert_eq!(nan, Controls::default());
    }
}
