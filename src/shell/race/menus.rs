//! The race's menus: the main menu over the grid (laps, recording, replaying a file, the keys), the pause
//! menu, and the results table at the finish. Each is drawn from the parts of the race it shows and returns
//! the player's [`Choice`]s, which the race carries out (in the order they were made) once it is drawn.

use std::path::PathBuf;

use super::record::RecordTo;
use crate::game::rules::{RaceProgress, format_ticks};
use crate::input::bindings::{Action, Bindings};

/// What the menus keep between frames.
#[derive(Debug, Default)]
pub(super) struct MenuState {
    /// The trace path typed in the main menu.
    replay_input: String,
}

/// What the player chose in a menu, for the race to do.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Choice {
    /// Leave the main menu for the race (recording it when the switch asks for it).
    Race,
    /// Back to the race from the pause menu.
    Resume,
    /// A fresh start on the grid, racing at once (Restart, Race again).
    Restart,
    /// A fresh start on the grid, behind the main menu.
    MainMenu,
    /// Race this many laps: a fresh start on the grid with them.
    Laps(u32),
    /// Replay the trace at this path.
    Replay(PathBuf),
    /// Open or close the Settings window.
    Settings,
    /// Quit the game.
    Quit,
}

/// A menu window in the middle of the screen.
fn centred(title: &str) -> egui::Window<'static> {
    egui::Window::new(title).anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0]).collapsible(false).resizable(false)
}

impl MenuState {
    /// The main menu: the race's `laps`, the recording switch `to`, Race / Settings / Quit, replaying a file,
    /// the `notice` and the keys as `bindings` has them.
    pub(super) fn main_menu(
        &mut self,
        ctx: &egui::Context,
        laps: u32,
        to: &mut RecordTo,
        notice: Option<&str>,
        bindings: &Bindings,
        pad: crate::input::pad_names::PadStyle,
    ) -> Vec<Choice> {
        let mut chose = vec![];
        centred("scanline-racer").show(ctx, |ui| {
            ui.label("Eight cars, 4.2 km, one bridge.");
            let mut wanted = laps;
            ui.add(egui::Slider::new(&mut wanted, 1..=10).text("laps"));
            if wanted != laps {
                chose.push(Choice::Laps(wanted));
            }
            ui.horizontal(|ui| {
                ui.checkbox(&mut to.on, "record the race to");
                ui.add(egui::TextEdit::singleline(&mut to.text).desired_width(150.0));
            });
            ui.horizontal(|ui| {
                if ui.button("Race").clicked() {
                    chose.push(Choice::Race);
                }
                if ui.button("Settings").clicked() {
                    chose.push(Choice::Settings);
                }
                if ui.button("Quit").clicked() {
                    chose.push(Choice::Quit);
                }
            });
            ui.horizontal(|ui| self.replay_a_file(ui, &mut chose));
            if let Some(n) = notice {
                ui.label(n);
            }
            let keys = |a: Action| crate::shell::keys::key_labels(bindings.keys(a), "/");
            ui.label(format!(
                "Keys: {} and {} steer, {} accelerates, {} brakes, {} changes the view, {} mutes, Esc pauses \
                 (Settings rebinds).",
                keys(Action::SteerLeft),
                keys(Action::SteerRight),
                keys(Action::Throttle),
                keys(Action::Brake),
                keys(Action::ChangeView),
                keys(Action::Mute)
            ));
            ui.label(pad.help());
        });
        chose
    }

    /// The main menu's field for a trace's path and its "Replay a file" button.
    fn replay_a_file(&mut self, ui: &mut egui::Ui, chose: &mut Vec<Choice>) {
        ui.add(egui::TextEdit::singleline(&mut self.replay_input).hint_text("race.trace").desired_width(180.0));
        if ui.button("Replay a file").clicked() {
            chose.push(Choice::Replay(PathBuf::from(self.replay_input.trim())));
        }
    }
}

/// The pause menu: Resume, Restart, Settings, Main menu, Quit.
pub(super) fn pause_menu(ctx: &egui::Context) -> Vec<Choice> {
    let mut chose = vec![];
    centred("Paused").show(ctx, |ui| {
        for (label, choice) in [
            ("Resume", Choice::Resume),
            ("Restart", Choice::Restart),
            ("Settings", Choice::Settings),
            ("Main menu", Choice::MainMenu),
            ("Quit", Choice::Quit),
        ] {
            if ui.button(label).clicked() {
                chose.push(choice);
            }
        }
    });
    chose
}

/// The results table of `race`, with Race again, Main menu and Quit.
pub(super) fn results(ctx: &egui::Context, race: &RaceProgress) -> Vec<Choice> {
    let mut chose = vec![];
    centred("Results").show(ctx, |ui| {
        egui::Grid::new("results").striped(true).show(ui, |ui| {
            ui.strong("Pos");
            ui.strong("Driver");
            ui.strong("Best lap");
            ui.end_row();
            for (k, &car) in race.order().iter().enumerate() {
                ui.label(format!("{}", k + 1));
                ui.label(if car == 0 { "You".to_string() } else { format!("Car {}", car + 1) });
                ui.label(race.standings[car].best_lap.map_or_else(|| "-".into(), format_ticks));
                ui.end_row();
            }
        });
        ui.horizontal(|ui| {
            for (label, choice) in
                [("Race again", Choice::Restart), ("Main menu", Choice::MainMenu), ("Quit", Choice::Quit)]
            {
                if ui.button(label).clicked() {
                    chose.push(choice);
                }
            }
        });
    });
    chose
}
