//! The settings as the race holds them (key bindings, the pixel scale, the ghost car shown, the sound's
//! volumes and mute; the picture choices live in the drawing options, and the gamepad's deadzone and curve
//! in the gamepads themselves), the Settings window that edits them, and saving them to the settings file
//! when they change. What the Settings window edits beyond these (the drawing,
//! the gamepads) and the race's notice, where a problem is said, are passed in.

use winit::keyboard::KeyCode;

use super::screen::{Drawing, Picture};
use crate::game::RaceSetup;
use crate::game::rules::format_ticks;
use crate::input::bindings::{Action, Bindings};
use crate::input::gamepad::Gamepads;
use crate::render::{Antialias, Filter, Method, MipMode, Quality, TextureMode};
use crate::shell::keys::key_label;
use crate::shell::race_scene::View;
use crate::shell::settings::{LAPS_RANGE, Settings, SettingsFile, VOLUME_RANGE};
use crate::shell::window::{MAX_SCALE, MIN_SCALE};

/// How loud the race's sound is: what the settings hold and the mixer is told each frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SoundLevels {
    /// Master volume, 0 to 1.
    pub(super) volume: f32,
    /// Effects volume beside the engines, 0 to 1.
    pub(super) effects: f32,
    /// Whether the sound is muted.
    pub(super) muted: bool,
}

impl Default for SoundLevels {
    fn default() -> Self {
        let d = Settings::default();
        Self { volume: d.volume, effects: d.effects_volume, muted: d.muted }
    }
}

/// The race chosen in the main menu (or on the command line): its course and setup, as the settings file
/// keeps them.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chosen<'a> {
    /// The course's name.
    pub(super) course: &'a str,
    /// Its mode, laps, car and difficulty.
    pub(super) setup: &'a RaceSetup,
}

impl Chosen<'_> {
    /// `settings` with the race's choices in it (laps beyond the menu's 9 saved as 9).
    fn into_settings(self, settings: Settings) -> Settings {
        Settings {
            course: self.course.to_string(),
            car: self.setup.car as u32 + 1,
            mode: self.setup.mode,
            difficulty: self.setup.difficulty,
            laps: self.setup.laps.clamp(1, *LAPS_RANGE.end()),
            ..settings
        }
    }
}

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
    /// The sound: master volume, effects volume (0 to 1 each) and mute.
    pub(super) sound: SoundLevels,
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
            sound: SoundLevels::default(),
            open: false,
            file: None,
        }
    }
}

impl Prefs {
    /// Takes `settings` (keys, the ghost, and into `pads` the deadzone and curve; the scale unless `scale`
    /// overrides it) and saves changes made in Settings to `file`; `options` are the race's drawing options
    /// as the caller chose them, whose picture (anti-aliasing, filter, mip levels) counts as saved, so that
    /// only a change made in Settings is written.
    /// The race on the grid (`chosen`: its course and setup, from the command line or the settings) counts
    /// as saved too.
    pub(super) fn apply(
        &mut self,
        settings: Settings,
        file: Option<SettingsFile>,
        scale: Option<u32>,
        (picture, chosen): (Picture, Chosen<'_>),
        pads: &mut Gamepads,
    ) {
        self.bindings = settings.keys.clone();
        self.show_ghost = settings.ghost;
        self.sound = SoundLevels { volume: settings.volume, effects: settings.effects_volume, muted: settings.muted };
        pads.deadzone = settings.deadzone;
        pads.curve = settings.curve;
        // A scale or picture choice from the command line is for this run: it is saved only with a change
        // made in Settings.
        let scale = scale.unwrap_or(settings.scale);
        self.scale = (scale, Some(scale));
        self.file = file.map(|mut f| {
            f.assume_saved(chosen.into_settings(picture.into_settings(Settings { scale, ..settings })));
            f
        });
    }

    /// The settings as they stand now, the gamepad's from `pads`, the picture choices from `options`, the
    /// race's from `chosen`.
    fn current(&self, pads: &Gamepads, picture: Picture, chosen: Chosen<'_>) -> Settings {
        chosen.into_settings(picture.into_settings(Settings {
            keys: self.bindings.clone(),
            deadzone: pads.deadzone,
            curve: pads.curve,
            scale: self.scale.0,
            ghost: self.show_ghost,
            volume: self.sound.volume,
            effects_volume: self.sound.effects,
            muted: self.sound.muted,
            ..Settings::default()
        }))
    }

    /// Saves the settings (the gamepad's from `pads`, the picture choices from `options`, the race's from
    /// `chosen`) if they changed since the last save; a failure is not fatal: it is shown in `notice` and
    /// said in one warning line (once: a change that failed counts as saved, and a file that no longer
    /// parses is not written again).
    pub(super) fn save(
        &mut self,
        pads: &Gamepads,
        (picture, chosen): (Picture, Chosen<'_>),
        notice: &mut Option<String>,
    ) {
        let now = self.current(pads, picture, chosen);
        if let Some(file) = &mut self.file
            && let Err(e) = file.save(&now)
        {
            // Not `eprintln!`, which panics when the terminal has gone.
            let _ = std::io::Write::write_fmt(&mut std::io::stderr(), format_args!("warning: {e}\n"));
            *notice = Some(e.to_string());
        }
    }

    /// Settings was waiting for a key for `action` and `code` (named `name`) went down: Escape cancels,
    /// anything else is bound (reserved keys refused, said in `notice`).
    pub(super) fn rebind(&mut self, action: Action, code: KeyCode, name: &str, notice: &mut Option<String>) {
        self.rebinding = None;
        if code != KeyCode::Escape
            && let Err(crate::input::bindings::BindError::Reserved { key }) = self.bindings.bind(action, name)
        {
            *notice = Some(format!("{} is reserved for menus and the window", key_label(&key)));
        }
    }

    /// The Settings window (from the main and pause menus): rendering and view (in `drawing`), ghost (its
    /// lap time `ghost_ticks`, when there is a lap), gamepad (`pads`), keys, scale.
    pub(super) fn window(
        &mut self,
        ctx: &egui::Context,
        drawing: &mut Drawing,
        pads: &mut Gamepads,
        ghost_ticks: Option<u64>,
    ) {
        let mut open = true;
        egui::Window::new("Settings").open(&mut open).resizable(false).show(ctx, |ui| {
            rendering_settings(ui, drawing);
            ui.checkbox(&mut drawing.debug.visible, "debug overlay (F3)");
            let ghost = match ghost_ticks {
                Some(ticks) => format!("ghost car (best lap {})", format_ticks(ticks)),
                None => "ghost car (after your first lap)".to_string(),
            };
            ui.checkbox(&mut self.show_ghost, ghost);
            ui.separator();
            self.sound_settings(ui);
            ui.separator();
            if pads.unavailable() || !pads.active() {
                ui.label("No gamepad found: keyboard only (a pad plugged in later is picked up).");
            }
            ui.add(egui::Slider::new(&mut pads.deadzone, 0.0..=0.3).text("stick deadzone"));
            ui.add(egui::Slider::new(&mut pads.curve, 1.0..=3.0).text("steering curve"));
            ui.separator();
            self.key_settings(ui);
            match &self.file {
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
        self.open = open;
    }

    /// Settings' sound: master volume, effects volume, mute (and its key).
    fn sound_settings(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.sound;
        ui.add(egui::Slider::new(&mut s.volume, VOLUME_RANGE).text("master volume"));
        ui.add(egui::Slider::new(&mut s.effects, VOLUME_RANGE).text("effects volume"));
        let key = self.bindings.keys(Action::Mute).first().map_or_else(String::new, |k| format!(" ({})", key_label(k)));
        ui.checkbox(&mut s.muted, format!("mute{key}"));
    }

    /// Settings' key table: each action's keys, a click waits for a new key; and "Default keys".
    fn key_settings(&mut self, ui: &mut egui::Ui) {
        ui.label("Keys (click, then press the new key; Esc cancels):");
        egui::Grid::new("keys").show(ui, |ui| {
            for action in Action::ALL {
                ui.label(action.label());
                let text = if self.rebinding == Some(action) {
                    "press a key...".to_string()
                } else {
                    crate::shell::keys::key_labels(self.bindings.keys(action), ", ")
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
    }
}

/// Settings' renderer choices in `drawing`: anti-aliasing, texture filter and mip levels (saved: the picture
/// the player chose), and visibility method, buckets, LOD bias, texture mapping and view (for this run:
/// choices for measuring, which a later race should not inherit unawares).
fn rendering_settings(ui: &mut egui::Ui, drawing: &mut Drawing) {
    quality_setting(ui, drawing);
    let before = drawing.options;
    let options = &mut drawing.options;
    egui::ComboBox::from_label("visibility method").selected_text(options.method.name()).show_ui(ui, |ui| {
        for m in Method::ALL {
            ui.selectable_value(&mut options.method, m, m.name());
        }
    });
    egui::ComboBox::from_label("anti-aliasing").selected_text(options.antialias.name()).show_ui(ui, |ui| {
        for a in Antialias::ALL {
            ui.selectable_value(&mut options.antialias, a, a.name());
        }
    });
    egui::ComboBox::from_label("texture filter").selected_text(options.filter.name()).show_ui(ui, |ui| {
        for f in Filter::ALL {
            ui.selectable_value(&mut options.filter, f, f.name());
        }
    });
    egui::ComboBox::from_label("mip levels").selected_text(options.mip.name()).show_ui(ui, |ui| {
        for m in MipMode::ALL {
            ui.selectable_value(&mut options.mip, m, m.name());
        }
    });
    ui.checkbox(&mut options.lod_fade, "LOD cross-fade");
    // Both biases on one row: the panel keeps its height (the key bindings below stay in view).
    ui.horizontal(|ui| {
        ui.add(egui::Slider::new(&mut options.lod_bias, -3.0..=3.0).text("LOD bias"));
        ui.add(egui::Slider::new(&mut options.mip_bias, -2.0..=2.0).step_by(0.25).text("mip bias"));
    });
    let picture = |o: &crate::render::RenderOptions| (o.antialias, o.filter, o.mip, o.lod_fade, o.lod_bias, o.mip_bias);
    if picture(options) != picture(&before) {
        // A picture fixed by hand: `auto` no longer picks it.
        drawing.set_auto(false);
    }
    let options = &mut drawing.options;
    ui.add(egui::Slider::new(&mut options.buckets, 8..=65536).logarithmic(true).text("buckets"));
    egui::ComboBox::from_label("texture mapping").selected_text(format!("{:?}", options.texture_mode)).show_ui(
        ui,
        |ui| {
            for m in [TextureMode::Perspective, TextureMode::Subdivided, TextureMode::Affine] {
                ui.selectable_value(&mut options.texture_mode, m, format!("{m:?}"));
            }
        },
    );
    let view = &mut drawing.view;
    egui::ComboBox::from_label("view").selected_text(format!("{view:?}")).show_ui(ui, |ui| {
        for v in View::ALL {
            ui.selectable_value(view, v, format!("{v:?}"));
        }
    });
}

/// The quality choice: `auto` or one of the presets (each sets anti-aliasing, filter and mip levels; a
/// picture set by hand shows as `custom`).
fn quality_setting(ui: &mut egui::Ui, drawing: &mut Drawing) {
    let shown = drawing.quality_label();
    let mut auto = drawing.auto.is_some();
    let mut preset = if auto { None } else { Quality::of(&drawing.options) };
    egui::ComboBox::from_label("quality").selected_text(shown).show_ui(ui, |ui| {
        if ui.selectable_label(auto, "auto").clicked() {
            auto = true;
        }
        for q in Quality::ALL {
            if ui.selectable_label(preset == Some(q), q.name()).clicked() {
                (auto, preset) = (false, Some(q));
            }
        }
    });
    drawing.set_auto(auto);
    if let (false, Some(q)) = (auto, preset) {
        drawing.options = q.apply(drawing.options);
    }
}
