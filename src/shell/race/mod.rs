//! The race in the window: the simulation fed at a fixed tick from the real clock.
//!
//! [`Race`] is the session: the world, the screen shown, and the clock that turns real time into ticks.
//! Each concern around it has its own file and owns its part of the state, and the race hands each the
//! parts it needs (records flow down: no concern imports the race):
//! - `screen`: the screen shown and how frames are drawn, the two parts several concerns share;
//! - `control`: where the player's controls come from (keyboard and gamepad, the autopilot, or a trace
//!   being replayed: the one seam where the source changes), and what the keys and buttons ask of the race;
//! - `menus`: the main menu, the pause menu and the results table, and what the player chose in them;
//! - `prefs`: the settings as the race holds them, the Settings window, and saving them to the file;
//! - `hud`: what is drawn over the race, and the title bar's status line;
//! - `record`: recording races to a trace, with the header and checksum interval every trace has;
//! - `ghost`: the ghost car and the lap it drives;
//! - `trial`: the player's records at the finish, and the time trial's recording kept as its ghost;
//! - `sound`: the race's sound, a mixer shown every world stepped to, played on the audio device.
//!
//! `session` ties them together: the race's builders, the tick, and carrying out what the keys and the pad
//! ask; `content` is the race as the window shows it (its frame and UI, and carrying out the menus'
//! choices).

mod content;
mod control;
mod ghost;
mod hud;
mod menus;
mod prefs;
mod record;
mod screen;
mod session;
mod sound;
mod trial;

pub use record::{CHECKSUM_EVERY, header_for};
pub use session::Race;

#[cfg(test)]
mod tests;
