//! What the settings file holds: the settings, their defaults, and the ranges a value must be in.
//!
//! The record reading and saving share, below both: `read` fills it from the file field by field, `save`
//! writes the fields that changed.

use serde::{Deserialize, Serialize};

use crate::input::bindings::Bindings;
use crate::input::gamepad::{DEFAULT_CURVE, DEFAULT_DEADZONE};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

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
}

impl Default for Settings {
    fn default() -> Self {
        Self { keys: Bindings::default(), deadzone: DEFAULT_DEADZONE, curve: DEFAULT_CURVE, scale: 1, ghost: true }
    }
}

impl Settings {
    /// The settings with every value in range (NaN and out-of-range numbers back to defaults or clamped)
    /// and the bindings repaired; the notes say what changed.
    #[must_use]
    pub fn sanitized(mut self) -> (Self, Vec<String>) {
        let d = Settings::default();
        let mut notes = vec![];
        if !self.deadzone.is_finite() || !(0.0..=0.3).contains(&self.deadzone) {
            notes.push(format!("deadzone {} out of 0-0.3: {} used", self.deadzone, d.deadzone));
            self.deadzone = d.deadzone;
        }
        if !self.curve.is_finite() || !(1.0..=3.0).contains(&self.curve) {
            notes.push(format!("curve {} out of 1-3: {} used", self.curve, d.curve));
            self.curve = d.curve;
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
