//! The settings as the race holds them (key bindings, the pixel scale, the ghost car shown; the gamepad's
//! deadzone and curve live in the gamepads themselves), the Settings window that edits them, and saving
//! them to the settings file when they change.

use winit::keyboard::KeyCode;

use super::Race;
use crate::game::rules::format_ticks;
use crate::input::bindings::{Action, Bindings};
use crate::render::{Method, TextureMode};
use crate::shell::race_scene::View;
use crate::shell::settings::{Settings, SettingsFile};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

/// The settings being edited and where they are saved.
pub(super) struct Prefs {
    /// Key bindings (from the settings file).
    pub(super) bindings: Bindings,
    /// The action waiting for a key press in Settings.
    pub(super) rebinding: Option<Action>,
    /// Window pixels per rendered pixel: shown in Settings, `Some` when changed there.
    pub(super) scale: (u32, Option<u32>),
    /// Whether the ghost car is drawn.
    pub(super) show_ghost: bool,
    /// Whether the Settings window is open.
    pub(super) open: bool,
    /// Where settings are saved (none: not saved), and what was saved or loaded last.
    file: Option<SettingsFile>,
}

impl Default for Prefs {
    fn default() -> Self {
        Self {
            bindings: Bindings::default(),
            rebinding: None,
            scale: (1, None),
            show_ghost: true,
            open: false,
            file: None,
        }
    }
}

impl Race {
    /// Applies `settings` (keys, gamepad deadzone and curve, scale unless `scale` overrides it) and saves
    /// changes made in Settings to `file`; `note` (a problem reading the file) is shown in the menu.
    #[must_use]
    pub fn with_settings(
        mut self,
        settings: Settings,
        file: Option<SettingsFile>,
        scale: Option<u32>,
        note: Option<String>,
    ) -> Self {
        self.prefs.bindings = settings.keys.clone();
        self.prefs.show_ghost = settings.ghost;
        self.control.pads.deadzone = settings.deadzone;
        self.control.pads.curve = settings.curve;
        // A scale from the command line is for this run: it is saved only with a change made in Settings.
        let scale = scale.unwrap_or(settings.scale);
        self.prefs.scale = (scale, Some(scale));
        self.prefs.file = file.map(|mut f| {
            f.assume_saved(Settings { scale, ..settings });
            f
        });
        if note.is_some() {
            self.notice = note;
        }
        self
    }

    /// The settings as they stand now.
    fn current_settings(&self) -> Settings {
        Settings {
            keys: self.prefs.bindings.clone(),
            deadzone: self.control.pads.deadzone,
            curve: self.control.pads.curve,
            scale: self.prefs.scale.0,
            ghost: self.prefs.show_ghost,
        }
    }

    /// Saves the settings if they changed since the last save; a failure is not fatal: it is shown in the
    /// menu and said in one warning line (once: a change that failed counts as saved, and a file that no
    /// longer parses is not written again).
    pub(super) fn save_settings(&mut self) {
        let now = self.current_settings();
        if let Some(file) = &mut self.prefs.file
            && let Err(e) = file.save(&now)
        {
            eprintln!("warning: {e}");
            self.notice = Some(e.to_string());
        }
    }

    /// Settings was waiting for a key for `action` and `code` (named `name`) went down: Escape cancels,
    /// anything else is bound (reserved keys refused, said in the notice).
    pub(super) fn rebind(&mut self, action: Action, code: KeyCode, name: &str) {
        self.prefs.rebinding = None;
        if code != KeyCode::Escape
            && let Err(e) = self.prefs.bindings.bind(action, name)
        {
            self.notice = Some(e.to_string());
        }
    }

    /// The Settings window (from the main and pause menus): rendering, view, ghost, gamepad, keys, scale.
    pub(super) fn settings_window(&mut self, ctx: &egui::Context) {
        let mut open = true;
        egui::Window::new("Settings").open(&mut open).resizable(false).show(ctx, |ui| {
            self.rendering_settings(ui);
            ui.checkbox(&mut self.drawing.debug.visible, "debug overlay (F3)");
            let ghost = match &self.ghost.lap {
                Some(g) => format!("ghost car (best lap {})", format_ticks(g.ticks())),
                None => "ghost car (after your first lap)".to_string(),
            };
            ui.checkbox(&mut self.prefs.show_ghost, ghost);
            ui.separator();
            let pads = &mut self.control.pads;
            if pads.unavailable() || !pads.active() {
                ui.label("No gamepad found: keyboard only (a pad plugged in later is picked up).");
            }
            ui.add(egui::Slider::new(&mut pads.deadzone, 0.0..=0.3).text("stick deadzone"));
            ui.add(egui::Slider::new(&mut pads.curve, 1.0..=3.0).text("steering curve"));
            ui.separator();
            self.key_settings(ui);
            match &self.prefs.file {
                Some(f) if f.writable() => ui.label(format!("Saved to {}", f.path().display())),
                Some(f) => ui.label(format!("Not saved: {} could not be read", f.path().display())),
                None => ui.label("Not saved: no settings file"),
            };
            let mut scale = self.prefs.scale.0;
            if ui
                .add(
                    egui::Slider::new(&mut scale, MIN_SCALE..=MAX_SCALE)
                        .text("window pixels per rendered pixel ('-' '=')"),
                )
                .changed()
            {
                self.prefs.scale.1 = Some(scale);
            }
        });
        self.prefs.open = open;
    }

    /// Settings' renderer choices (not saved): visibility method, buckets, LOD bias, texture mapping, view.
    fn rendering_settings(&mut self, ui: &mut egui::Ui) {
        let options = &mut self.drawing.options;
        egui::ComboBox::from_label("visibility method").selected_text(options.method.name()).show_ui(ui, |ui| {
            for m in Method::ALL {
                ui.selectable_value(&mut options.method, m, m.name());
            }
        });
        ui.add(egui::Slider::new(&mut options.buckets, 8..=65536).logarithmic(true).text("buckets"));
        ui.add(egui::Slider::new(&mut options.lod_bias, -3.0..=3.0).text("LOD bias"));
        egui::ComboBox::from_label("texture mapping").selected_text(format!("{:?}", options.texture_mode)).show_ui(
            ui,
            |ui| {
                for m in [TextureMode::Perspective, TextureMode::Subdivided, TextureMode::Affine] {
                    ui.selectable_value(&mut options.texture_mode, m, format!("{m:?}"));
                }
            },
        );
        let view = &mut self.drawing.view;
        egui::ComboBox::from_label("view").selected_text(format!("{view:?}")).show_ui(ui, |ui| {
            for v in View::ALL {
                ui.selectable_value(view, v, format!("{v:?}"));
            }
        });
    }

    /// Settings' key table: each action's keys, a click waits for a new key; and "Default keys".
    fn key_settings(&mut self, ui: &mut egui::Ui) {
        let prefs = &mut self.prefs;
        ui.label("Keys (click, then press the new key; Esc cancels):");
        egui::Grid::new("keys").show(ui, |ui| {
            for action in Action::ALL {
                ui.label(action.label());
                let text = if prefs.rebinding == Some(action) {
                    "press a key...".to_string()
                } else {
                    prefs.bindings.keys(action).join(", ")
                };
                if ui.button(text).clicked() {
                    prefs.rebinding = Some(action);
                }
                ui.end_row();
            }
        });
        if ui.button("Default keys").clicked() {
            prefs.bindings = Bindings::default();
        }
    }
}
