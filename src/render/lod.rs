//! Level of detail (seed 003, Namco): choosing a close, middle or long-shot model per object per frame.
//!
//! The seed picks the model by distance; here the choice is by projected size in pixels, which also accounts
//! for the field of view and the resolution: a car 100 pixels tall gets the same model whether that comes
//! from being near, from a narrow lens or from a large frame. Each [`LodSet`] says below which projected
//! height (in pixels) its middle and long models take over. A choice only changes when the size moves
//! [`HYSTERESIS`] past a threshold, so an object hovering at one does not flicker between models.

use std::fmt;
use std::str::FromStr;

/// One of the three models of a set.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// The close-up model (about 200-300 polygons for a car).
    Close = 0,
    /// The middle-range model (about 20-30).
    Mid = 1,
    /// The long-shot model (6: a hexahedron).
    Long = 2,
}

impl Level {
    /// All levels, finest first.
    pub const ALL: [Level; 3] = [Level::Close, Level::Mid, Level::Long];

    /// The name used on the command line and in statistics.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Level::Close => "close",
            Level::Mid => "mid",
            Level::Long => "long",
        }
    }

    fn from_index(i: u8) -> Option<Level> {
        Level::ALL.get(usize::from(i)).copied()
    }
}

impl fmt::Display for Level {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// How levels are chosen for a frame.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum LodMode {
    /// By projected size, with hysteresis (the default).
    #[default]
    Auto,
    /// The same level for every set (for comparisons and the chart).
    Force(Level),
}

impl FromStr for LodMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "auto" => Ok(LodMode::Auto),
            "close" => Ok(LodMode::Force(Level::Close)),
            "mid" => Ok(LodMode::Force(Level::Mid)),
            "long" => Ok(LodMode::Force(Level::Long)),
            _ => Err(format!("unknown level of detail '{s}' (expected auto, close, mid or long)")),
        }
    }
}

/// Relative margin around each threshold: switching to a finer model needs the size to exceed the threshold
/// by this much, switching to a coarser one to fall this much below it.
pub const HYSTERESIS: f32 = 0.15;

/// The three models of one object and where they switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodSet {
    /// Mesh indices (into the draw list's meshes) of the close, middle and long models.
    pub meshes: [usize; 3],
    /// Projected heights in pixels: below `switch_px[0]` the middle model is used, below `switch_px[1]` the
    /// long one.
    pub switch_px: [f32; 2],
}

/// The level for a projected height, given the level used last frame (if any).
#[must_use]
pub fn choose(size_px: f32, switch_px: [f32; 2], previous: Option<Level>) -> Level {
    let plain = |margin: [f32; 2]| {
        if size_px >= switch_px[0] * margin[0] {
            Level::Close
        } else if size_px >= switch_px[1] * margin[1] {
            Level::Mid
        } else {
            Level::Long
        }
    };
    if !size_px.is_finite() {
        return previous.unwrap_or(Level::Long);
    }
    let Some(prev) = previous else {
        return plain([1.0, 1.0]);
    };
    let (up, down) = (1.0 + HYSTERESIS, 1.0 - HYSTERESIS);
    // The thresholds next to the current level are moved away from it, so it takes a clear change to leave.
    let margins = match prev {
        Level::Close => [down, down],
        Level::Mid => [up, down],
        Level::Long => [up, up],
    };
    plain(margins)
}

/// Per-instance memory of the level last drawn, kept by the renderer from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct LodState {
    levels: Vec<u8>,
}

const NO_LEVEL: u8 = u8::MAX;

impl LodState {
    /// The level instance `i` was drawn at last frame.
    #[must_use]
    pub fn previous(&self, i: usize) -> Option<Level> {
        self.levels.get(i).and_then(|&l| Level::from_index(l))
    }

    /// Records the level of instance `i`.
    pub fn set(&mut self, i: usize, level: Level) {
        if self.levels.len() <= i {
            self.levels.resize(i + 1, NO_LEVEL);
        }
        self.levels[i] = level as u8;
    }

    /// Forgets every level (for a new scene or a camera cut).
    pub fn clear(&mut self) {
        self.levels.clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_without_history() {
        let s = [120.0, 24.0];
        assert_eq!(choose(500.0, s, None), Level::Close);
        assert_eq!(choose(120.0, s, None), Level::Close);
        assert_eq!(choose(119.0, s, None), Level::Mid);
        assert_eq!(choose(24.0, s, None), Level::Mid);
        assert_eq!(choose(23.9, s, None), Level::Long);
        assert_eq!(choose(f32::NAN, s, None), Level::Long);
    }

    #[test]
    fn hysteresis_keeps_the_current_level_near_a_threshold() {
        let s = [120.0, 24.0];
        assert_eq!(choose(110.0, s, Some(Level::Close)), Level::Close);
        assert_eq!(choose(103.0, s, Some(Level::Close)), Level::Close);
        assert_eq!(choose(101.0, s, Some(Level::Close)), Level::Mid);
        assert_eq!(choose(101.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(130.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(139.0, s, Some(Level::Mid)), Level::Close);
        assert_eq!(choose(21.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(20.0, s, Some(Level::Mid)), Level::Long);
        assert_eq!(choose(26.0, s, Some(Level::Long)), Level::Long);
        assert_eq!(choose(28.0, s, Some(Level::Long)), Level::Mid);
        assert_eq!(choose(1000.0, s, Some(Level::Long)), Level::Close);
    }

    #[test]
    fn a_slow_approach_and_retreat_switch_once_each_way() {
        let s = [120.0, 24.0];
        let mut level = None;
        let mut switches = vec![];
        // Size oscillates by ±5% around a slow ramp up and then down through both thresholds.
        let sizes: Vec<f32> = (0..2000)
            .map(|i| {
                let t = if i < 1000 { i as f32 / 1000.0 } else { (2000 - i) as f32 / 1000.0 };
                let base = 10.0 * libm::powf(20.0f32, t);
                base * (1.0 + 0.05 * libm::sinf((i as f32) * 0.7))
            })
            .collect();
        for size in sizes {
            let l = choose(size, s, level);
            if level.is_some_and(|p| p != l) {
                switches.push(l);
            }
            level = Some(l);
        }
        assert_eq!(switches, [Level::Mid, Level::Close, Level::Mid, Level::Long]);
    }

    #[test]
    fn state_remembers_per_instance() {
        let mut st = LodState::default();
        assert_eq!(st.previous(3), None);
        st.set(3, Level::Mid);
        assert_eq!(st.previous(3), Some(Level::Mid));
        assert_eq!(st.previous(0), None);
        st.clear();
        assert_eq!(st.previous(3), None);
    }
}
