//! The race's menus-side drawing: settings window, HUD (position, lap, times, countdown, speed, replay
//! notices) and the results table.

use super::{Race, Screen};
use crate::game::rules::{Phase, format_ticks};
use crate::input::bindings::{Action, Bindings};
use crate::render::{Method, TextureMode};
use crate::shell::race_scene::View;
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

impl Race {
    /// Rendering and view settings (from the main and pause menus).
    pub(super) fn settings(&mut self, ctx: &egui::Context) {
        let mut open = true;
        egui::Window::new("Settings").open(&mut open).resizable(false).show(ctx, |ui| {
            egui::ComboBox::from_label("visibility method").selected_text(self.options.method.name()).show_ui(
                ui,
                |ui| {
                    for m in Method::ALL {
                        ui.selectable_value(&mut self.options.method, m, m.name());
                    }
                },
            );
            ui.add(egui::Slider::new(&mut self.options.buckets, 8..=65536).logarithmic(true).text("buckets"));
            ui.add(egui::Slider::new(&mut self.options.lod_bias, -3.0..=3.0).text("LOD bias"));
            egui::ComboBox::from_label("texture mapping")
                .selected_text(format!("{:?}", self.options.texture_mode))
                .show_ui(ui, |ui| {
                    for m in [TextureMode::Perspective, TextureMode::Subdivided, TextureMode::Affine] {
                        ui.selectable_value(&mut self.options.texture_mode, m, format!("{m:?}"));
                    }
                });
            egui::ComboBox::from_label("view").selected_text(format!("{:?}", self.view)).show_ui(ui, |ui| {
                for v in View::ALL {
                    ui.selectable_value(&mut self.view, v, format!("{v:?}"));
                }
            });
            ui.checkbox(&mut self.debug.visible, "debug overlay (F3)");
            let ghost = match &self.ghost {
                Some(g) => format!("ghost car (best lap {})", format_ticks(g.ticks())),
                None => "ghost car (after your first lap)".to_string(),
            };
            ui.checkbox(&mut self.show_ghost, ghost);
            ui.separator();
            if self.pads.unavailable() || !self.pads.active() {
                ui.label("No gamepad found: keyboard only (a pad plugged in later is picked up).");
            }
            ui.add(egui::Slider::new(&mut self.pads.deadzone, 0.0..=0.3).text("stick deadzone"));
            ui.add(egui::Slider::new(&mut self.pads.curve, 1.0..=3.0).text("steering curve"));
            ui.separator();
            ui.label("Keys (click, then press the new key; Esc cancels):");
            egui::Grid::new("keys").show(ui, |ui| {
                for action in Action::ALL {
                    ui.label(action.label());
                    let text = if self.rebinding == Some(action) {
                        "press a key...".to_string()
                    } else {
                        self.bindings.keys(action).join(", ")
                    };
                    if ui.button(text).clicked() {
                        self.rebinding = Some(action);
                    }
                    ui.end_row();
                }
            });
            if ui.button("Default keys").clicked() {
                self.bindings = Bindings::default();
            }
            match &self.settings_file {
                Some(f) if f.writable() => ui.label(format!("Saved to {}", f.path().display())),
                Some(f) => ui.label(format!("Not saved: {} could not be read", f.path().display())),
                None => ui.label("Not saved: no settings file"),
            };
            let mut scale = self.scale.0;
            if ui
                .add(
                    egui::Slider::new(&mut scale, MIN_SCALE..=MAX_SCALE)
                        .text("window pixels per rendered pixel ('-' '=')"),
                )
                .changed()
            {
                self.scale.1 = Some(scale);
            }
        });
        self.settings_open = open;
    }

    /// Speed, position, lap, times and the countdown.
    pub(super) fn hud(&self, ctx: &egui::Context) {
        let race = &self.world.race;
        let me = &race.standings[0];
        let big = |t: String, size: f32| egui::RichText::new(t).size(size).strong().color(egui::Color32::WHITE);
        egui::Area::new(egui::Id::unique("hud-left")).anchor(egui::Align2::LEFT_TOP, [16.0, 12.0]).show(ctx, |ui| {
            ui.label(big(format!("P{} / {}", race.position(0), race.standings.len()), 30.0));
            ui.label(big(format!("LAP {} / {}", (me.laps + 1).min(race.laps), race.laps), 18.0));
            let now = if race.holding() { 0 } else { self.world.tick.saturating_sub(me.lap_start) };
            ui.label(big(format!("TIME {}", format_ticks(now)), 16.0));
            ui.label(big(format!("BEST {}", me.best_lap.map_or_else(|| "-:--.---".into(), format_ticks)), 16.0));
        });
        let since_green = self.world.tick.saturating_sub(race.start_tick);
        let banner = match race.phase {
            Phase::Countdown(left) => Some(format!("{}", left.div_ceil(u64::from(crate::game::TICK_HZ)))),
            Phase::Racing if since_green < u64::from(crate::game::TICK_HZ) => Some("GO!".to_string()),
            _ => None,
        };
        if let Some(text) = banner {
            egui::Area::new(egui::Id::unique("hud-countdown")).anchor(egui::Align2::CENTER_TOP, [0.0, 60.0]).show(
                ctx,
                |ui| {
                    ui.label(big(text, 64.0));
                },
            );
        }
        if self.source.is_some() || self.notice.is_some() {
            let text = match &self.notice {
                Some(n) => n.clone(),
                None => format!("REPLAY {}x — P pause, N step, [ ] speed, R restart", self.speed),
            };
            egui::Area::new(egui::Id::unique("hud-notice")).anchor(egui::Align2::CENTER_BOTTOM, [0.0, -40.0]).show(
                ctx,
                |ui| {
                    ui.label(big(text, 16.0));
                },
            );
        }
        let car = &self.world.cars[0];
        egui::Area::new(egui::Id::unique("hud-speed")).anchor(egui::Align2::RIGHT_BOTTOM, [-16.0, -12.0]).show(
            ctx,
            |ui| {
                ui.label(big(format!("{:.0} km/h", car.speed().abs() * 3.6), 28.0));
                ui.add(
                    egui::ProgressBar::new((car.speed().abs() / self.world.params.top_speed).clamp(0.0, 1.0))
                        .desired_width(180.0),
                );
            },
        );
        egui::Area::new(egui::Id::unique("hud-debug")).anchor(egui::Align2::LEFT_BOTTOM, [12.0, -8.0]).show(
            ctx,
            |ui| {
                ui.label(
                    egui::RichText::new(format!(
                        "{:?} view — {} — {:.1} ms/frame",
                        self.view, self.options.method, self.frame_ms
                    ))
                    .size(12.0)
                    .color(egui::Color32::from_gray(230)),
                );
            },
        );
    }

    /// The results table; returns true to quit.
    pub(super) fn results(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        let race = self.world.race.clone();
        egui::Window::new("Results")
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
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
