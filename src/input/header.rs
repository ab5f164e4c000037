//! A trace's header: what decides the simulation, written before the records (see `docs/trace-format.md`),
//! the race it describes, and what can be wrong with it.
//!
//! Why a file of its own: the header grew with the courses, the cars, the modes and the difficulties, and
//! `trace` (the records, the writer and the reader) stays one purpose that way.

use thiserror::Error;

use crate::game::garage::CARS;
use crate::game::{Difficulty, Handling, Mode, RaceSetup};

/// The course a trace whose header names none was raced on.
pub const FIRST_COURSE: &str = "circuit";
/// Longest course name.
pub const MAX_COURSE_NAME: usize = 32;
/// Version of the simulation rules: bumped when `game::step` changes behaviour, so an old trace is refused
/// with a clear message instead of diverging (build details that do not change the simulation keep it).
/// Version 3: each car handles as the garage's table says.
pub const SIM_VERSION: u32 = 3;
/// The simulation version before the cars differed, still replayed: every car gets car 1's handling
/// ([`Handling::Same`]).
pub const SAME_CARS_SIM_VERSION: u32 = 2;
/// Largest header accepted.
pub(super) const MAX_HEADER: u32 = 64 * 1024;

/// What decides the simulation, written at the start of a trace.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Header {
    /// The simulation rules' version ([`SIM_VERSION`]).
    pub sim_version: u32,
    /// The program version that wrote the trace (informative).
    pub game_version: String,
    /// The course's name: its folder under `assets/track/` (absent before format version 2: the circuit).
    #[serde(default = "first_course")]
    pub course: String,
    /// The course's lap length in millimetres (checks that the course is the one the race was run on).
    pub track_length_mm: u64,
    /// Cars in the race.
    pub cars: u32,
    /// The player's car, 1 to 8 (absent before format version 2: car 1).
    #[serde(default = "first_car")]
    pub car: u32,
    /// The mode: `race` or `time-trial` (absent before format version 2: `race`).
    #[serde(default = "race_mode")]
    pub mode: String,
    /// The AI's difficulty: `easy`, `normal` or `hard` (absent before format version 2: `normal`).
    #[serde(default = "normal_difficulty")]
    pub difficulty: String,
    /// Laps.
    pub laps: u32,
    /// Seed of the race's random choices.
    pub seed: u64,
    /// Simulation ticks per second.
    pub tick_hz: u32,
    /// Ticks between state checksums.
    pub checksum_every: u32,
}

fn first_course() -> String {
    FIRST_COURSE.to_string()
}

fn first_car() -> u32 {
    1
}

fn race_mode() -> String {
    Mode::Race.name().to_string()
}

fn normal_difficulty() -> String {
    Difficulty::Normal.name().to_string()
}

impl Header {
    /// What is wrong with a header that parsed, if anything: a race this build cannot run.
    #[must_use]
    pub fn problem(&self) -> Option<HeaderProblem> {
        if self.tick_hz != crate::game::TICK_HZ {
            return Some(HeaderProblem::TickRate { found: self.tick_hz });
        }
        if !(1..=64).contains(&self.cars) {
            return Some(HeaderProblem::Cars { found: self.cars });
        }
        if !(1..=99).contains(&self.laps) {
            return Some(HeaderProblem::Laps { found: self.laps });
        }
        if self.checksum_every == 0 {
            return Some(HeaderProblem::ChecksumInterval);
        }
        if !(1..=CARS as u32).contains(&self.car) {
            return Some(HeaderProblem::Car { found: self.car });
        }
        let Some(mode) = Mode::from_name(&self.mode) else {
            return Some(HeaderProblem::Mode { found: self.mode.chars().take(40).collect() });
        };
        if mode == Mode::TimeTrial && self.cars != 1 {
            return Some(HeaderProblem::TrialCars { found: self.cars });
        }
        if Difficulty::from_name(&self.difficulty).is_none() {
            return Some(HeaderProblem::Difficulty { found: self.difficulty.chars().take(40).collect() });
        }
        if !is_course_name(&self.course) {
            return Some(HeaderProblem::Course { found: self.course.chars().take(40).collect() });
        }
        None
    }

    /// The race the header describes (a header read by [`super::trace::TraceReader`] names a mode and difficulty there
    /// are; others fall back to a race at normal difficulty).
    #[must_use]
    pub fn setup(&self) -> RaceSetup {
        RaceSetup {
            mode: Mode::from_name(&self.mode).unwrap_or_default(),
            laps: self.laps,
            car: (self.car.max(1) - 1) as usize,
            difficulty: Difficulty::from_name(&self.difficulty).unwrap_or_default(),
            handling: if self.sim_version == SAME_CARS_SIM_VERSION { Handling::Same } else { Handling::Garage },
            field: self.cars as usize,
        }
    }
}

/// Whether `name` can name a course: 1 to [`MAX_COURSE_NAME`] lower-case ASCII letters, digits, `-` and
/// `_`, so that it is one plain folder name on every system (no `..`, no separator, no hidden file).
#[must_use]
pub fn is_course_name(name: &str) -> bool {
    (1..=MAX_COURSE_NAME).contains(&name.len())
        && name.bytes().all(|b| b.is_ascii_lowercase() || b.is_ascii_digit() || b == b'-' || b == b'_')
        && !name.starts_with('-')
}

/// What is wrong with a trace's header.
#[derive(Debug, Error)]
pub enum HeaderProblem {
    /// The file ends before the header does.
    #[error("file ends inside the header")]
    Cut,
    /// The header's length is over `MAX_HEADER`.
    #[error("header of {length} bytes is over the limit of {MAX_HEADER}")]
    TooLong {
        /// The length the file declares.
        length: u32,
    },
    /// The header is not the JSON object a trace header is (or could not be written as one).
    #[error("{0}")]
    Json(#[source] serde_json::Error),
    /// Another simulation tick rate.
    #[error("tick rate {found} Hz differs from this build's {} Hz", crate::game::TICK_HZ)]
    TickRate {
        /// The rate in the header.
        found: u32,
    },
    /// A number of cars this build cannot race (1-64; a time trial races 1).
    #[error("{found} cars is out of range 1-64")]
    Cars {
        /// Cars in the header.
        found: u32,
    },
    /// A number of laps this build cannot race.
    #[error("{found} laps is out of range 1-99")]
    Laps {
        /// Laps in the header.
        found: u32,
    },
    /// No ticks between checksums.
    #[error("checksum interval 0 is out of range")]
    ChecksumInterval,
    /// A time trial of more than one car.
    #[error("a time trial races 1 car, this header has {found}")]
    TrialCars {
        /// Cars in the header.
        found: u32,
    },
    /// A car the garage does not have.
    #[error("car {found} is out of range 1-{CARS}")]
    Car {
        /// The car in the header.
        found: u32,
    },
    /// A mode this build does not have.
    #[error("mode {found:?} is not race or time-trial")]
    Mode {
        /// The mode in the header (its first 40 characters).
        found: String,
    },
    /// A difficulty this build does not have.
    #[error("difficulty {found:?} is not easy, normal or hard")]
    Difficulty {
        /// The difficulty in the header (its first 40 characters).
        found: String,
    },
    /// A course name that names no folder (see [`is_course_name`]).
    #[error("course {found:?} is not a course name (lower-case letters, digits, '-' and '_')")]
    Course {
        /// The name in the header (its first 40 characters).
        found: String,
    },
}
