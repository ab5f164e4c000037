//! What the settings file holds: the settings, their defaults, and the ranges a value must be in.
//!
//! The record reading and saving share, below both: `read` fills it from the file field by field, `save`
//! writes the fields that changed.

use serde::{Deserialize, Serialize};

use crate::game::garage::CARS;
use crate::game::{Difficulty, Mode};
use crate::input::bindings::Bindings;
use crate::input::gamepad::{DEFAULT_CURVE, DEFAULT_DEADZONE};
use crate::render::{Antialias, Filter, MipMode, RenderOptions};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

/// The master volume a new settings file starts at: the mixer's full level, so that the window plays what
/// `replay --headless --audio` writes (the mix is limited below full scale either way).
pub const DEFAULT_VOLUME: f32 = 1.0;
/// The range both volumes must be in (0 silent, 1 the mixer's full level).
pub const VOLUME_RANGE: std::ops::RangeInclusive<f32> = 0.0..=1.0;
/// The range the gamepad deadzone must be in.
pub const DEADZONE_RANGE: std::ops::RangeInclusive<f32> = 0.0..=0.3;
/// The range the steering response exponent must be in (1 linear).
pub const CURVE_RANGE: std::ops::RangeInclusive<f32> = 1.0..=3.0;
/// The LOD bias the settings file keeps (Settings' slider).
pub const LOD_BIAS_RANGE: std::ops::RangeInclusive<f32> = -3.0..=3.0;
/// The mip biases the settings file and the Settings panel take (`--mip-bias`'s range).
pub const MIP_BIAS_RANGE: std::ops::RangeInclusive<f32> = -4.0..=4.0;

/// The laps a race chosen in the menu may have.
pub const LAPS_RANGE: std::ops::RangeInclusive<u32> = 1..=9;

/// A range as the warnings write it (`0-0.3`).
#[must_use]
pub fn shown_range(r: &std::ops::RangeInclusive<f32>) -> String {
    format!("{}-{}", r.start(), r.end())
}

/// Everything the settings file holds.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct Settings {
    /// Keyboard bindings.
    pub keys: Bindings,
    /// Gamepad stick deadzone (radial), 0 to 0.3.
    pub deadzone: f32,
    /// Gamepad steering response exponent, 1 (linear) to 3.
    pub curve: f32,
    /// Window pixels per rendered pixel, 1 to [`MAX_SCALE`].
    pub scale: u32,
    /// Whether the ghost car (the best lap) is drawn.
    pub ghost: bool,
    /// Master volume of the race's sound, 0 (silent) to 1 (full).
    pub volume: f32,
    /// Volume of the effects (tyres, surfaces, impacts, beeps, clicks) beside the engines, 0 to 1.
    pub effects_volume: f32,
    /// Whether the sound is muted (the M key); the volumes are kept for when it is not.
    pub muted: bool,
    /// The race's anti-aliasing, by its command-line name (`"4x"`).
    #[serde(with = "by_name")]
    pub antialias: Antialias,
    /// The race's texture filter, by its command-line name (`"trilinear"`).
    #[serde(with = "by_name")]
    pub filter: Filter,
    /// Where the race's mip levels are chosen, by its command-line name (`"pixel"`).
    #[serde(with = "by_name")]
    pub mip: MipMode,
    /// Whether the race's level-of-detail changes cross-fade (`--lod-fade`).
    pub lod_fade: bool,
    /// The race's level-of-detail bias, -3 to 3 (positive keeps finer models farther).
    pub lod_bias: f32,
    /// The race's mip bias, -4 to 4 (negative: finer texture levels; `--mip-bias`).
    pub mip_bias: f32,
    /// Whether the race's picture follows the frame time (`auto` quality); when false, the three choices
    /// above are the picture.
    pub auto_quality: bool,
    /// The course raced last (its folder under `track/`).
    pub course: String,
    /// The player's car, 1 to 8.
    pub car: u32,
    /// The mode: `race` or `time-trial`.
    #[serde(with = "by_name")]
    pub mode: Mode,
    /// The AI's pace: `easy`, `normal` or `hard`.
    #[serde(with = "by_name")]
    pub difficulty: Difficulty,
    /// Laps, 1 to 9.
    pub laps: u32,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            keys: Bindings::default(),
            deadzone: DEFAULT_DEADZONE,
            curve: DEFAULT_CURVE,
            scale: 1,
            ghost: true,
            volume: DEFAULT_VOLUME,
            effects_volume: 1.0,
            muted: false,
            antialias: RenderOptions::default().antialias,
            filter: RenderOptions::default().filter,
            mip: RenderOptions::default().mip,
            lod_fade: false,
            lod_bias: 0.0,
            mip_bias: 0.0,
            auto_quality: true,
            course: crate::shell::course::DEFAULT_COURSE.to_string(),
            car: 1,
            mode: Mode::Race,
            difficulty: Difficulty::Normal,
            laps: 3,
        }
    }
}

/// A picture choice in the file as the name the command line takes (`"ssaa"`, `"bilinear"`), so that a
/// hand edit uses the words of `--help` and the file does not change when a variant is renamed in code.
mod by_name {
    use std::fmt::Display;
    use std::str::FromStr;

    use serde::{Deserialize, Deserializer, Serializer};

    /// Writes the choice's name.
    pub(super) fn serialize<T: Display, S: Serializer>(value: &T, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(value)
    }

    /// Reads a name (an unknown one is an error naming the choices).
    pub(super) fn deserialize<'de, T, D>(d: D) -> Result<T, D::Error>
    where
        T: FromStr<Err: Display>,
        D: Deserializer<'de>,
    {
        let name = String::deserialize(d)?;
        name.parse().map_err(serde::de::Error::custom)
    }
}

impl Settings {
    /// The settings with every value in range (NaN and out-of-range numbers back to defaults or clamped)
    /// and the bindings repaired; the notes say what changed.
    #[must_use]
    pub fn sanitized(mut self) -> (Self, Vec<String>) {
        let d = Settings::default();
        let mut notes = vec![];
        for (name, value, default, range) in [
            ("deadzone", &mut self.deadzone, d.deadzone, DEADZONE_RANGE),
            ("curve", &mut self.curve, d.curve, CURVE_RANGE),
            ("volume", &mut self.volume, d.volume, VOLUME_RANGE),
            ("effects_volume", &mut self.effects_volume, d.effects_volume, VOLUME_RANGE),
            ("lod_bias", &mut self.lod_bias, d.lod_bias, LOD_BIAS_RANGE),
            ("mip_bias", &mut self.mip_bias, d.mip_bias, MIP_BIAS_RANGE),
        ] {
            if !value.is_finite() || !range.contains(value) {
                notes.push(format!("{name} {value} out of {}: {default} used", shown_range(&range)));
                *value = default;
            }
        }
        if !(1..=CARS as u32).contains(&self.car) {
            notes.push(format!("car {} out of 1-{CARS}: 1 used", self.car));
            self.car = 1;
        }
        if !LAPS_RANGE.contains(&self.laps) {
            notes.push(format!(
                "laps {} out of {}-{}: {} used",
                self.laps,
                LAPS_RANGE.start(),
                LAPS_RANGE.end(),
                d.laps
            ));
            self.laps = d.laps;
        }
        if !crate::shell::course::is_course_name(&self.course) {
            let shown: String = self.course.chars().take(40).collect();
            notes.push(format!("course {shown:?} is not a course name: {} used", d.course));
            self.course = d.course.clone();
        }
        if !(MIN_SCALE..=MAX_SCALE).contains(&self.scale) {
            notes.push(format!("scale {} out of {MIN_SCALE}-{MAX_SCALE}: {MIN_SCALE} used", self.scale));
            self.scale = MIN_SCALE;
        }
        let (keys, key_notes) = self.keys.repaired(crate::shell::keys::is_key_name);
        self.keys = keys;
        notes.extend(key_notes);
        (self, notes)
    }
}
