//! The race's menus: the main menu over the grid (laps, recording, replaying a file, the keys), the pause
//! menu, and the results table at the finish. Each returns true when the player chose Quit.

use super::{Race, Screen};
use crate::game::rules::format_ticks;
use crate::input::bindings::Action;

/// What the menus keep between frames.
#[derive(Debug, Default)]
pub(super) struct MenuState {
    /// The trace path typed in the main menu.
    replay_input: String,
}

/// A menu window in the middle of the screen.
fn centred(title: &str) -> egui::Window<'static> {
    egui::Window::new(title).anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0]).collapsible(false).resizable(false)
}

impl Race {
    /// The main menu: laps, the recording switch, Race / Settings / Quit, replaying a file, the keys.
    pub(super) fn main_menu(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        centred("scanline-racer").show(ctx, |ui| {
            ui.label("Eight cars, 4.2 km, one bridge.");
            let before = self.laps;
            ui.add(egui::Slider::new(&mut self.laps, 1..=10).text("laps"));
            if self.laps != before {
                self.restart();
            }
            ui.horizontal(|ui| {
                let to = &mut self.recording.to;
                ui.checkbox(&mut to.on, "record the race to");
                ui.add(egui::TextEdit::singleline(&mut to.text).desired_width(150.0));
            });
            ui.horizontal(|ui| {
                if ui.button("Race").clicked() {
                    self.start_race();
                }
                if ui.button("Settings").clicked() {
                    self.prefs.open = !self.prefs.open;
                }
                if ui.button("Quit").clicked() {
                    quit = true;
                }
            });
            ui.horizontal(|ui| self.replay_a_file(ui));
            if let Some(n) = &self.notice {
                ui.label(n.as_str());
            }
            let keys = |a: Action| self.prefs.bindings.keys(a).join("/");
            ui.label(format!(
                "Keys: {} and {} steer, {} accelerates, {} brakes, {} changes the view, Esc pauses (Settings rebinds).",
                keys(Action::SteerLeft),
                keys(Action::SteerRight),
                keys(Action::Throttle),
                keys(Action::Brake),
                keys(Action::ChangeView)
            ));
            ui.label("Gamepad: stick steers, triggers drive; D-pad and A in menus; Start pauses.");
        });
        quit
    }

    /// The main menu's field for a trace's path and its "Replay a file" button.
    fn replay_a_file(&mut self, ui: &mut egui::Ui) {
        ui.add(egui::TextEdit::singleline(&mut self.menu.replay_input).hint_text("race.trace").desired_width(180.0));
        if ui.button("Replay a file").clicked() {
            let path = std::path::PathBuf::from(self.menu.replay_input.trim());
            if let Err(e) = self.start_replay(&path) {
                self.notice = Some(e.to_string());
            }
        }
    }

    /// The pause menu: Resume, Restart, Settings, Main menu, Quit.
    pub(super) fn pause_menu(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        centred("Paused").show(ctx, |ui| {
            if ui.button("Resume").clicked() {
                self.screen = Screen::Race;
            }
            if ui.button("Restart").clicked() {
                self.restart();
                self.screen = Screen::Race;
            }
            if ui.button("Settings").clicked() {
                self.prefs.open = !self.prefs.open;
            }
            if ui.button("Main menu").clicked() {
                self.restart();
                self.screen = Screen::Menu;
            }
            if ui.button("Quit").clicked() {
                quit = true;
            }
        });
        quit
    }

    /// The results table, with Race again, Main menu and Quit.
    pub(super) fn results(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        let race = self.world.race.clone();
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
                if ui.button("Race again").clicked() {
                    self.restart();
                    self.screen = Screen::Race;
                }
                if ui.button("Main menu").clicked() {
                    self.restart();
                    self.screen = Screen::Menu;
                }
                if ui.button("Quit").clicked() {
                    quit = true;
                }
            });
        });
        quit
    }
}
