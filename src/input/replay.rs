//! Replaying a trace: the trace becomes the source of the player's controls, and every checksum in it is
//! checked against the world as the replay reaches its tick.

use std::path::Path;

use thiserror::Error;

use super::trace::{Header, Record, TraceError, TraceReader};
use crate::game::{Controls, World};

/// Why a replay stopped.
#[derive(Debug, Error)]
pub enum ReplayError {
    /// The file could not be read.
    #[error(transparent)]
    Trace(#[from] TraceError),
    /// The simulation no longer matches the recording.
    #[error("{path}: replay diverges from the recording at tick {tick} (state checksum differs)")]
    Diverged {
        /// The trace file.
        path: String,
        /// The first tick whose checksum differs.
        tick: u64,
    },
    /// A checksum record for a tick the replay is not at.
    #[error("{path}: checksum record for tick {found} where tick {expected} was expected")]
    Misplaced {
        /// The trace file.
        path: String,
        /// Tick in the record.
        found: u64,
        /// Tick of the world.
        expected: u64,
    },
    /// The trace was recorded on another course.
    #[error("{path}: recorded on the course {found}, this race is on {expected}")]
    Course {
        /// The trace file.
        path: String,
        /// The course in the header.
        found: String,
        /// The course of this race.
        expected: String,
    },
    /// The trace was recorded on another circuit.
    #[error("{path}: recorded on a track of {found} mm per lap, this track is {expected} mm")]
    Track {
        /// The trace file.
        path: String,
        /// Lap length in the header.
        found: u64,
        /// Lap length of the loaded track.
        expected: u64,
    },
}

/// A trace as a source of controls, checking checksums on the way.
pub struct TraceSource {
    /// The trace's header.
    pub header: Header,
    reader: TraceReader,
    path: String,
    /// Checksums verified so far.
    pub verified: u64,
}

impl TraceSource {
    /// Opens a trace.
    pub fn open(path: &Path) -> Result<Self, ReplayError> {
        let (header, reader) = TraceReader::open(path)?;
        Ok(Self { header, reader, path: path.display().to_string(), verified: 0 })
    }

    /// A trace read from `input` (a pipe, or bytes in memory); `name` stands for it in messages.
    pub fn from_reader(name: &str, input: Box<dyn std::io::Read + Send>) -> Result<Self, ReplayError> {
        let (header, reader) = TraceReader::from_reader(name, input)?;
        Ok(Self { header, reader, path: name.to_string(), verified: 0 })
    }

    /// Checks that the trace was recorded on the course named `course`.
    pub fn check_course(&self, course: &str) -> Result<(), ReplayError> {
        if self.header.course != course {
            return Err(ReplayError::Course {
                path: self.path.clone(),
                found: self.header.course.clone(),
                expected: course.to_string(),
            });
        }
        Ok(())
    }

    /// Checks that the trace was recorded on `world`'s track.
    pub fn check_track(&self, world: &World) -> Result<(), ReplayError> {
        let expected = lap_mm(world);
        if self.header.track_length_mm.abs_diff(expected) > 1 {
            return Err(ReplayError::Track { path: self.path.clone(), found: self.header.track_length_mm, expected });
        }
        Ok(())
    }

    /// The controls for the next tick of `world`, after checking any checksum recorded for its current tick;
    /// `Ok(None)` at the end of the trace.
    pub fn next_controls(&mut self, world: &World) -> Result<Option<Controls>, ReplayError> {
        loop {
            match self.reader.next_record()? {
                None => return Ok(None),
                Some(Record::Controls(c)) => return Ok(Some(c)),
                Some(Record::Checksum { tick, sum }) => {
                    if tick != world.tick {
                        return Err(ReplayError::Misplaced {
                            path: self.path.clone(),
                            found: tick,
                            expected: world.tick,
                        });
                    }
                    if sum != world.checksum() {
                        return Err(ReplayError::Diverged { path: self.path.clone(), tick });
                    }
                    self.verified += 1;
                }
            }
        }
    }
}

/// A recorded race being replayed without a window: the world and the trace that drives its player.
pub struct Replay {
    /// The world as of the last tick replayed.
    pub world: World,
    /// The trace.
    pub source: TraceSource,
}

impl Replay {
    /// Opens the trace at `path` for the race its header describes on `track`, refusing a trace of
    /// another track.
    pub fn open(path: &Path, track: std::sync::Arc<crate::game::Track>) -> Result<Self, ReplayError> {
        let source = TraceSource::open(path)?;
        let world = World::for_race(track, &source.header.setup());
        source.check_track(&world)?;
        Ok(Self { world, source })
    }

    /// Replays one tick; `Ok(false)` at the end of the trace.
    pub fn advance(&mut self) -> Result<bool, ReplayError> {
        match self.source.next_controls(&self.world)? {
            Some(c) => {
                crate::game::step(&mut self.world, &c);
                Ok(true)
            }
            None => Ok(false),
        }
    }
}

/// One tick of a recorded race: quantizes the controls as a trace stores them, steps the world, and appends
/// the controls (and every `checksum_every` ticks a checksum) to `recorder`. Play and scripted recordings
/// both go through here, so a trace holds exactly what the simulation saw.
pub fn step_recorded(
    world: &mut World,
    c: Controls,
    recorder: Option<&mut super::trace::TraceWriter>,
    checksum_every: u32,
) -> Result<Controls, TraceError> {
    let c = super::trace::quantize(c);
    crate::game::step(world, &c);
    if let Some(rec) = recorder {
        rec.controls(c)?;
        if world.tick.is_multiple_of(u64::from(checksum_every.max(1))) {
            rec.checksum(world.tick, world.checksum())?;
        }
    }
    Ok(c)
}

/// The world's lap length in millimetres, as trace headers store it.
#[must_use]
pub fn lap_mm(world: &World) -> u64 {
    (f64::from(world.track.length()) * 1000.0).round() as u64
}
