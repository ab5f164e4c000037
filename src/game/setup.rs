//! What a race is before it starts: the mode, the laps, the player's car, the AI's difficulty, and whose
//! handling the cars have. Everything here decides the simulation, so a trace's header holds all of it.

use super::garage::CARS;

/// The kind of race.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Mode {
    /// Against the AI: the full field on the grid.
    #[default]
    Race,
    /// Alone on the course, against the ghost of the best lap.
    TimeTrial,
}

impl Mode {
    /// Every mode, in menu order.
    pub const ALL: [Mode; 2] = [Mode::Race, Mode::TimeTrial];

    /// The name the command line, the settings and trace headers use.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Mode::Race => "race",
            Mode::TimeTrial => "time-trial",
        }
    }

    /// The mode of a name, if it is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Mode> {
        Mode::ALL.into_iter().find(|m| m.name() == name)
    }

    /// What the menus call it.
    #[must_use]
    pub fn title(self) -> &'static str {
        match self {
            Mode::Race => "Race",
            Mode::TimeTrial => "Time Trial",
        }
    }
}

/// How fast the AI drives: its share of the grip it dares use in corners, never the grip itself.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord)]
pub enum Difficulty {
    /// Slower in every corner.
    Easy,
    /// The pace the AI has always had.
    #[default]
    Normal,
    /// Closer to the limit.
    Hard,
}

impl Difficulty {
    /// Every difficulty, in menu order.
    pub const ALL: [Difficulty; 3] = [Difficulty::Easy, Difficulty::Normal, Difficulty::Hard];

    /// The name the command line, the settings and trace headers use.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Difficulty::Easy => "easy",
            Difficulty::Normal => "normal",
            Difficulty::Hard => "hard",
        }
    }

    /// The difficulty of a name, if it is one.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Difficulty> {
        Difficulty::ALL.into_iter().find(|d| d.name() == name)
    }

    /// What the AI's pace (its share of the grip in corners) is multiplied by.
    #[must_use]
    pub fn pace(self) -> f32 {
        match self {
            Difficulty::Easy => 0.92,
            Difficulty::Normal => 1.0,
            Difficulty::Hard => 1.035,
        }
    }
}

/// A name that is none of a choice's names (a mode or a difficulty).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("unknown {kind} {name:?} (accepted: {accepted})")]
pub struct UnknownChoice {
    /// What was being chosen: "mode", "difficulty".
    pub kind: &'static str,
    /// The name given (its first 40 characters).
    pub name: String,
    /// The names accepted, as the message lists them.
    pub accepted: &'static str,
}

impl std::fmt::Display for Mode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Mode {
    type Err = UnknownChoice;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Mode::from_name(s).ok_or_else(|| UnknownChoice {
            kind: "mode",
            name: s.chars().take(40).collect(),
            accepted: "race or time-trial",
        })
    }
}

impl std::fmt::Display for Difficulty {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for Difficulty {
    type Err = UnknownChoice;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Difficulty::from_name(s).ok_or_else(|| UnknownChoice {
            kind: "difficulty",
            name: s.chars().take(40).collect(),
            accepted: "easy, normal or hard",
        })
    }
}

/// Whose handling the cars have.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Handling {
    /// Each car its own, from the garage's table.
    #[default]
    Garage,
    /// Every car car 1's: the rules of simulation version 2, before the cars differed, so that a trace of
    /// that version still replays.
    Same,
}

/// Everything that decides a race before its first tick.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RaceSetup {
    /// The kind of race (Time Trial races one car).
    pub mode: Mode,
    /// Laps, 1 to 99.
    pub laps: u32,
    /// The player's car: its index in the garage (0 is car 1).
    pub car: usize,
    /// The AI's pace.
    pub difficulty: Difficulty,
    /// Whose handling the cars have.
    pub handling: Handling,
    /// Cars on the grid in a race (Time Trial: always 1).
    pub field: usize,
}

impl Default for RaceSetup {
    fn default() -> Self {
        Self {
            mode: Mode::Race,
            laps: 3,
            car: 0,
            difficulty: Difficulty::Normal,
            handling: Handling::Garage,
            field: CARS,
        }
    }
}

impl RaceSetup {
    /// Cars in the race: the field in a race, one in Time Trial.
    #[must_use]
    pub fn cars(&self) -> usize {
        match self.mode {
            Mode::Race => self.field.max(1),
            Mode::TimeTrial => 1,
        }
    }

    /// The garage index of each car of the race, by its index in the world: the player's car first, then
    /// the other cars in garage order (the field's AI takes the cars the player did not).
    #[must_use]
    pub fn models(&self) -> Vec<usize> {
        let player = self.car % CARS;
        let others = (0..CARS).filter(|&m| m != player).cycle();
        std::iter::once(player).chain(others).take(self.cars()).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_the_field_takes_the_cars_the_player_did_not() {
        for m in Mode::ALL {
            assert_eq!(Mode::from_name(m.name()), Some(m));
        }
        for d in Difficulty::ALL {
            assert_eq!(Difficulty::from_name(d.name()), Some(d));
        }
        assert_eq!(Mode::from_name("Race"), None);
        let s = RaceSetup { car: 4, ..RaceSetup::default() };
        assert_eq!(s.models(), vec![4, 0, 1, 2, 3, 5, 6, 7]);
        assert_eq!(RaceSetup { mode: Mode::TimeTrial, ..s }.models(), vec![4]);
        assert_eq!(RaceSetup { field: 10, ..s }.models().len(), 10);
        assert!(
            Difficulty::Easy.pace() < Difficulty::Normal.pace() && Difficulty::Normal.pace() < Difficulty::Hard.pace()
        );
    }
}
