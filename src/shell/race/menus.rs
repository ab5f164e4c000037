//! The race's menus: the main menu over the grid (course, car, mode, difficulty, laps, recording, replaying a
//! file, the keys), the pause
//! menu, and the results table at the finish. Each is drawn from the parts of the race it shows and returns
//! the player's [`Choice`]s, which the race carries out (in the order they were made) once it is drawn.

use std::path::PathBuf;

use super::record::RecordTo;
use crate::game::garage::GARAGE;
use crate::game::rules::{RaceProgress, format_ticks};
use crate::game::{Difficulty, Mode, RaceSetup};
use crate::input::bindings::{Action, Bindings};
use crate::shell::course::CourseInfo;
use crate::shell::records::LapRecord;

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
    /// Race this race (another mode, laps, car or difficulty): a fresh start on the grid with it.
    Setup(RaceSetup),
    /// Race on this course (by name): it is loaded, and the race starts afresh on its grid.
    Course(String),
    /// Replay the trace at this path.
    Replay(PathBuf),
    /// Open the car select.
    Garage,
    /// Back from the car select to the main menu.
    Back,
    /// Open or close the Settings window.
    Settings,
    /// Quit the game.
    Quit,
}

/// A menu window in the middle of the screen.
fn centred(title: &str) -> egui::Window<'static> {
    egui::Window::new(title).anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0]).collapsible(false).resizable(false)
}

/// What the main menu offers to choose from, and what is chosen now.
pub(super) struct Offer<'a> {
    /// The courses there are (none: the course cannot change here).
    pub(super) courses: &'a [CourseInfo],
    /// The course raced now.
    pub(super) course: &'a str,
    /// The race on the grid now.
    pub(super) setup: &'a RaceSetup,
    /// The best laps on the course, fastest first.
    pub(super) top: &'a [LapRecord],
}

impl Offer<'_> {
    /// The course, car, mode, difficulty and laps pickers; what changed goes into `chose`.
    fn pickers(&self, ui: &mut egui::Ui, chose: &mut Vec<Choice>) {
        let mut s = *self.setup;
        let title = self.courses.iter().find(|c| c.name == self.course).map_or(self.course, |c| c.title.as_str());
        egui::Grid::new("race choices").num_columns(2).show(ui, |ui| {
            ui.label("Course");
            egui::ComboBox::from_id_salt("course").selected_text(title).show_ui(ui, |ui| {
                for c in self.courses {
                    let label = format!("{} ({:.2} km)", c.title, c.length_m / 1000.0);
                    if ui.selectable_label(c.name == self.course, label).on_hover_text(&c.about).clicked()
                        && c.name != self.course
                    {
                        chose.push(Choice::Course(c.name.clone()));
                    }
                }
            });
            ui.end_row();
            ui.label("Car");
            ui.horizontal(|ui| {
                car_picker(ui, &mut s);
                if ui.button("See it").clicked() {
                    chose.push(Choice::Garage);
                }
            });
            ui.end_row();
            ui.label("Mode");
            ui.horizontal(|ui| {
                for m in Mode::ALL {
                    ui.radio_value(&mut s.mode, m, m.title());
                }
            });
            ui.end_row();
            ui.label("AI");
            ui.horizontal(|ui| {
                for d in Difficulty::ALL {
                    ui.radio_value(&mut s.difficulty, d, d.name());
                }
            });
            ui.end_row();
            ui.label("Laps");
            // The menu offers 1-9; more laps from the command line stay as they are until the slider moves.
            ui.add(
                egui::Slider::new(&mut s.laps, crate::shell::settings::LAPS_RANGE)
                    .clamping(egui::SliderClamping::Edits),
            );
            ui.end_row();
        });
        ui.label(figures(s.car));
        if s != *self.setup {
            chose.push(Choice::Setup(s));
        }
        if !self.top.is_empty() {
            ui.label("Best laps here:");
            for (k, r) in self.top.iter().enumerate() {
                let car = GARAGE.get(r.key.car.saturating_sub(1) as usize).map_or("?", |c| c.name);
                let mode = Mode::from_name(&r.key.mode).map_or("?", Mode::title);
                ui.label(format!("{}. {}  {car}, {mode}, {}", k + 1, format_ticks(r.ticks), r.key.difficulty));
            }
        }
    }
}

impl MenuState {
    /// The main menu: the race's course, car, mode, difficulty and laps (`offer`), the recording switch `to`,
    /// Race / Settings / Quit, replaying a file, the `notice` and the keys as `bindings` has them.
    pub(super) fn main_menu(
        &mut self,
        ctx: &egui::Context,
        offer: Offer<'_>,
        to: &mut RecordTo,
        notice: Option<&str>,
        bindings: &Bindings,
        pad: crate::input::pad_names::PadStyle,
    ) -> Vec<Choice> {
        let mut chose = vec![];
        centred("scanline-racer").show(ctx, |ui| {
            offer.pickers(ui, &mut chose);
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

/// The car `car`'s figures in one line.
fn figures(car: usize) -> String {
    let c = &GARAGE[car % GARAGE.len()];
    format!(
        "{}: {:.0} km/h, 0-100 km/h in {:.1} s, braking {:.1} g, grip {:.2} g",
        c.name,
        c.top_speed * 3.6,
        c.zero_to_100(),
        c.brake / 9.81,
        c.grip / 9.81
    )
}

/// The previous and next buttons around the name of the car in `s`.
fn car_picker(ui: &mut egui::Ui, s: &mut RaceSetup) {
    let n = GARAGE.len();
    if ui.button("<").clicked() {
        s.car = (s.car + n - 1) % n;
    }
    ui.label(format!("{} {}", s.car + 1, GARAGE[s.car % n].name));
    if ui.button(">").clicked() {
        s.car = (s.car + 1) % n;
    }
}

/// The car select over the turning car: the previous and next cars, the figures, and Done (Esc) back to
/// the main menu.
pub(super) fn garage(ctx: &egui::Context, setup: &RaceSetup) -> Vec<Choice> {
    let mut chose = vec![];
    let mut s = *setup;
    egui::Window::new("Choose your car")
        .anchor(egui::Align2::CENTER_BOTTOM, [0.0, -24.0])
        .collapsible(false)
        .resizable(false)
        .show(ctx, |ui| {
            ui.horizontal(|ui| car_picker(ui, &mut s));
            ui.label(figures(s.car));
            if ui.button("Done").clicked() {
                chose.push(Choice::Back);
            }
        });
    if s != *setup {
        chose.push(Choice::Setup(s));
    }
    chose
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

/// The results table of `race` (each car named by its garage index in `models`), with Race again, Main menu
/// and Quit.
pub(super) fn results(ctx: &egui::Context, race: &RaceProgress, models: &[usize]) -> Vec<Choice> {
    let mut chose = vec![];
    centred("Results").show(ctx, |ui| {
        egui::Grid::new("results").striped(true).show(ui, |ui| {
            ui.strong("Pos");
            ui.strong("Driver");
            ui.strong("Best lap");
            ui.end_row();
            for (k, &car) in race.order().iter().enumerate() {
                ui.label(format!("{}", k + 1));
                let name = models.get(car).and_then(|&m| GARAGE.get(m)).map_or("", |c| c.name);
                ui.label(if car == 0 { format!("You ({name})") } else { name.to_string() });
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
