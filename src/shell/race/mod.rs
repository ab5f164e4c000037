//! The race in the window: the simulation fed at a fixed tick from the real clock, with the player's
//! controls from the keyboard or, in a replay, from a trace (the one seam where the source changes),
//! optionally recorded to a trace; menus, HUD and the debug overlay.

use winit::keyboard::KeyCode;

mod ghost;
mod record;
mod ui;

use super::race_scene::{FIELD, RaceScene, View};
use super::settings::{Settings, SettingsFile};
use super::window::{Content, ShellError, method_key};
use crate::game::ai::{Driver, drive};
use crate::game::rules::{Phase, format_ticks};
use crate::game::{Controls, DT, TICK_HZ, World};
use crate::input::bindings::{Action, Bindings};
use crate::input::ghost::{GhostLap, GhostSearch, LapRecorder};
use crate::input::recording::Recording;
use crate::input::replay::{ReplayError, TraceSource, lap_mm, step_recorded};
use crate::input::trace::{Header, SIM_VERSION};
use crate::render::{RenderOptions, Renderer};

/// Most simulated time one frame may catch up after a stall (the game slows down instead of jumping).
const MAX_CATCH_UP: f64 = 0.25;

/// Which screen the race shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Screen {
    /// The main menu over the grid (nothing moves).
    Menu,
    /// Racing.
    Race,
    /// The pause menu (nothing moves).
    Paused,
    /// A replay stopped at its `--stop-at` tick: the frame stays, nothing moves, no menu.
    Frozen,
}

/// Keyboard state turned into smoothed controls.
#[derive(Debug, Default)]
struct Keys {
    left: bool,
    right: bool,
    throttle: bool,
    brake: bool,
    steer: f32,
}

impl Keys {
    /// One tick of controls: digital steering eased in and out so a tap is a correction, not a swerve.
    fn controls(&mut self) -> Controls {
        let target = f32::from(u8::from(self.right)) - f32::from(u8::from(self.left));
        let rate = if target == 0.0 || target.signum() != self.steer.signum() { 6.0 } else { 2.5 };
        let step = rate * DT;
        self.steer += (target - self.steer).clamp(-step, step);
        Controls {
            steer: self.steer,
            throttle: f32::from(u8::from(self.throttle)),
            brake: f32::from(u8::from(self.brake)),
        }
    }
}

/// The race.
pub struct Race {
    scene: RaceScene,
    world: World,
    renderer: Renderer,
    options: RenderOptions,
    keys: Keys,
    accumulator: f64,
    view: View,
    screen: Screen,
    laps: u32,
    frame_ms: f64,
    debug: super::debug_overlay::DebugOverlay,
    settings_open: bool,
    /// In a replay, where the player's controls come from.
    source: Option<TraceSource>,
    /// When recording, where the controls go (a file beside the target, renamed over it at the end).
    recorder: Option<Recording>,
    /// Replay speed (1 = real time).
    speed: f64,
    /// Ticks to run while paused (single-step).
    steps: u32,
    /// Why the replay or recording stopped, shown in the HUD.
    notice: Option<String>,
    /// The trace being replayed, for R (restart).
    replay_path: Option<std::path::PathBuf>,
    /// A replay freezes when the world reaches this tick.
    stop_at: Option<u64>,
    /// Whether menus and HUD are drawn over the race.
    hud: bool,
    /// The player's car drives itself (attract mode); its controls are still recorded like a player's.
    autopilot: bool,
    /// Gamepads (none is fine: keyboard only).
    pads: crate::input::gamepad::Gamepads,
    /// Key presses for the UI from the gamepad (D-pad moves the focus, A presses the focused button).
    pad_ui: Vec<egui::Event>,
    /// The trace path typed in the main menu.
    replay_input: String,
    /// The main menu's recording toggle and the file it records to.
    record_to: record::RecordTo,
    /// Whether a recorded race has replaced its target in this run.
    kept_a_race: bool,
    /// Window pixels per rendered pixel: shown in Settings, `Some` when changed there.
    scale: (u32, Option<u32>),
    /// Key bindings (from the settings file).
    bindings: Bindings,
    /// The action waiting for a key press in Settings.
    rebinding: Option<Action>,
    /// Where settings are saved (none: not saved), and what was saved or loaded last.
    settings_file: Option<SettingsFile>,
    /// The player's laps so far, the fastest kept for the ghost.
    laps_rec: LapRecorder,
    /// The lap the ghost car drives (from `--ghost FILE`, or the fastest lap of this session).
    ghost: Option<GhostLap>,
    /// The search for the fastest lap of `--ghost FILE`, while it runs.
    ghost_search: Option<GhostSearch>,
    /// A faster lap from the search, waiting for the player to cross the line (the ghost never jumps mid-lap).
    ghost_pending: Option<GhostLap>,
    /// Whether the ghost car is drawn.
    show_ghost: bool,
}

/// Ticks between checksums in recorded traces: one second.
pub const CHECKSUM_EVERY: u32 = TICK_HZ;

/// The trace header for a race of `world`.
#[must_use]
pub fn header_for(world: &World) -> Header {
    Header {
        sim_version: SIM_VERSION,
        game_version: env!("CARGO_PKG_VERSION").to_string(),
        track_length_mm: lap_mm(world),
        cars: world.cars.len() as u32,
        laps: world.race.laps,
        seed: 0,
        tick_hz: TICK_HZ,
        checksum_every: CHECKSUM_EVERY,
    }
}

impl Race {
    /// A race of `laps` laps on the grid, the player last, behind the main menu (or racing at once).
    #[must_use]
    pub fn new(scene: RaceScene, options: RenderOptions, laps: u32, menu: bool) -> Self {
        let world = World::with_laps(scene.track.clone(), FIELD, laps);
        Self {
            world,
            scene,
            renderer: Renderer::new(),
            options,
            keys: Keys::default(),
            accumulator: 0.0,
            view: View::ChaseNear,
            screen: if menu { Screen::Menu } else { Screen::Race },
            laps,
            frame_ms: 0.0,
            debug: super::debug_overlay::DebugOverlay::default(),
            settings_open: false,
            source: None,
            recorder: None,
            speed: 1.0,
            steps: 0,
            notice: None,
            replay_path: None,
            stop_at: None,
            hud: true,
            autopilot: false,
            pads: crate::input::gamepad::Gamepads::new(),
            pad_ui: Vec::new(),
            replay_input: String::new(),
            record_to: record::RecordTo::default(),
            kept_a_race: false,
            scale: (1, None),
            bindings: Bindings::default(),
            rebinding: None,
            settings_file: None,
            laps_rec: LapRecorder::default(),
            ghost: None,
            ghost_search: None,
            ghost_pending: None,
            show_ghost: true,
        }
    }

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
        self.bindings = settings.keys.clone();
        self.show_ghost = settings.ghost;
        self.pads.deadzone = settings.deadzone;
        self.pads.curve = settings.curve;
        // A scale from the command line is for this run: it is saved only with a change made in Settings.
        let scale = scale.unwrap_or(settings.scale);
        self.scale = (scale, Some(scale));
        self.settings_file = file.map(|mut f| {
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
            keys: self.bindings.clone(),
            deadzone: self.pads.deadzone,
            curve: self.pads.curve,
            scale: self.scale.0,
            ghost: self.show_ghost,
        }
    }

    /// Saves the settings if they changed since the last save; a failure is not fatal: it is shown in the
    /// menu and said in one warning line (once: a change that failed counts as saved, and a file that no
    /// longer parses is not written again).
    fn save_settings(&mut self) {
        let now = self.current_settings();
        if let Some(file) = &mut self.settings_file
            && let Err(e) = file.save(&now)
        {
            eprintln!("warning: {e}");
            self.notice = Some(e.to_string());
        }
    }

    /// Freezes the replay when the world reaches `tick` (and prints one line saying so), and hides the HUD
    /// when `hud` is false: for comparing the window with headless frames.
    #[must_use]
    pub fn stopping_at(mut self, tick: Option<u64>, hud: bool) -> Self {
        self.stop_at = tick;
        self.hud = hud;
        self
    }

    /// Lets the AI drive the player's car (the controls it chooses are recorded like a player's).
    #[must_use]
    pub fn autopilot(mut self, on: bool) -> Self {
        self.autopilot = on;
        self
    }

    /// The world being raced.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// A replay of `source`: the trace drives the player's car; P pauses, N steps a tick, `[` and `]` halve and
    /// double the speed (1/4x to 16x), R restarts.
    pub fn replaying(scene: RaceScene, options: RenderOptions, path: &std::path::Path) -> Result<Self, ReplayError> {
        let mut race = Self::new(scene, options, 3, false);
        race.start_replay(path)?;
        Ok(race)
    }

    /// Switches to replaying the trace at `path` from its start; refuses a file that is not a trace of
    /// this track and field.
    fn start_replay(&mut self, path: &std::path::Path) -> Result<(), ReplayError> {
        let source = TraceSource::open(path)?;
        if source.header.cars as usize != FIELD {
            return Err(ReplayError::Cars {
                path: path.display().to_string(),
                found: source.header.cars,
                expected: FIELD,
            });
        }
        self.laps = source.header.laps;
        self.restart();
        source.check_track(&self.world)?;
        self.source = Some(source);
        self.replay_path = Some(path.to_path_buf());
        self.screen = Screen::Race;
        Ok(())
    }

    /// One simulation tick with the controls from the keyboard or the trace (the seam), recorded if asked.
    fn tick(&mut self) {
        let c = match self.source.as_mut() {
            None if self.autopilot => {
                let w = &self.world;
                drive(&Driver::field(FIELD), 0, &w.cars, &w.track, &w.params)
            }
            None => {
                // Keyboard and pad together: steering adds, pedals take the larger.
                let k = self.keys.controls();
                match self.pads.controls() {
                    Some(p) => Controls {
                        steer: (k.steer + p.steer).clamp(-1.0, 1.0),
                        throttle: k.throttle.max(p.throttle),
                        brake: k.brake.max(p.brake),
                    },
                    None => k,
                }
            }
            Some(src) => match src.next_controls(&self.world) {
                Ok(Some(c)) => c,
                Ok(None) => {
                    self.notice = Some(format!(
                        "end of replay at tick {} ({} checksums verified)",
                        self.world.tick, src.verified
                    ));
                    self.screen = Screen::Paused;
                    return;
                }
                Err(e) => {
                    self.notice = Some(e.to_string());
                    self.screen = Screen::Paused;
                    return;
                }
            },
        };
        if let Err(e) =
            step_recorded(&mut self.world, c, self.recorder.as_mut().and_then(Recording::writer), CHECKSUM_EVERY)
        {
            self.end_recording(&format!("recording stopped: {e}"));
        }
        self.take_pending_ghost();
        if self.laps_rec.observe(&self.world)
            && let Some(best) = &self.laps_rec.best
            && self.ghost.as_ref().is_none_or(|g| best.ticks() < g.ticks())
        {
            self.notice = Some(format!("best lap {}: the ghost drives it now", format_ticks(best.ticks())));
            self.ghost = Some(best.clone());
        }
    }

    /// Reacts to gamepad buttons and hot-plug: unplugging the active pad mid-race pauses the race.
    fn gamepad_events(&mut self) {
        use crate::input::gamepad::{PadButton, PadEvent};
        for ev in self.pads.poll() {
            match ev {
                PadEvent::Connected(name) => self.notice = Some(format!("gamepad connected: {name}")),
                PadEvent::ActiveDisconnected => {
                    if self.screen == Screen::Race {
                        self.screen = Screen::Paused;
                    }
                    self.notice = Some("gamepad disconnected: race paused".into());
                }
                PadEvent::Pressed(b @ (PadButton::Confirm | PadButton::Up | PadButton::Down))
                    if matches!(self.screen, Screen::Menu | Screen::Paused)
                        || self.world.race.phase == Phase::Finished =>
                {
                    // In menus the pad works like the keyboard: D-pad moves the focus, A presses the button.
                    let (key, modifiers) = match b {
                        PadButton::Up => (egui::Key::Tab, egui::Modifiers::SHIFT),
                        PadButton::Down => (egui::Key::Tab, egui::Modifiers::NONE),
                        _ => (egui::Key::Enter, egui::Modifiers::NONE),
                    };
                    for pressed in [true, false] {
                        self.pad_ui.push(egui::Event::Key {
                            key,
                            physical_key: None,
                            pressed,
                            repeat: false,
                            modifiers,
                        });
                    }
                }
                PadEvent::Pressed(PadButton::Pause) => {
                    self.screen = match self.screen {
                        Screen::Race => Screen::Paused,
                        Screen::Paused => Screen::Race,
                        other => other,
                    };
                }
                PadEvent::Pressed(PadButton::Back) if self.screen == Screen::Paused => self.screen = Screen::Race,
                PadEvent::Pressed(PadButton::View) => self.view = self.view.next(),
                PadEvent::Pressed(_) => {}
            }
        }
    }

    /// Leaves the main menu for the race, recording it first when the menu's toggle asks for it.
    fn start_race(&mut self) {
        self.start_recording();
        self.screen = Screen::Race;
    }

    /// A fresh start on the grid with the current number of laps.
    fn restart(&mut self) {
        self.world = World::with_laps(self.scene.track.clone(), FIELD, self.laps);
        self.accumulator = 0.0;
        self.keys = Keys::default();
        self.renderer.reset_lod();
        self.laps_rec.restart();
        if self.recorder.is_some() {
            self.end_recording("recording ended at the restart");
        }
    }

    /// The race status for the title bar: countdown, lap, times, position, or the results.
    fn status(&self) -> String {
        let race = &self.world.race;
        let me = &race.standings[0];
        let pos = race.position(0);
        match race.phase {
            Phase::Countdown(left) => format!("{}...", left.div_ceil(u64::from(crate::game::TICK_HZ))),
            Phase::Racing => {
                let now = self.world.tick.saturating_sub(me.lap_start);
                let best = me.best_lap.map_or_else(|| "-".into(), format_ticks);
                format!(
                    "{:.0} km/h — P{pos}/{} — lap {}/{} {} (best {best})",
                    self.world.cars[0].speed().abs() * 3.6,
                    race.standings.len(),
                    (me.laps + 1).min(race.laps),
                    race.laps,
                    format_ticks(now)
                )
            }
            Phase::Finished => {
                let results: Vec<String> = race
                    .finish_order
                    .iter()
                    .enumerate()
                    .map(|(k, &car)| {
                        let who = if car == 0 { "you".to_string() } else { format!("car {}", car + 1) };
                        format!("{}. {who}", k + 1)
                    })
                    .collect();
                format!("FINISHED P{pos} — {}", results.join(", "))
            }
        }
    }
}

impl Content for Race {
    fn update(&mut self, dt: f64) {
        self.gamepad_events();
        self.ghost_search_reports();
        while self.steps > 0 {
            self.steps -= 1;
            self.tick();
        }
        if self.screen != Screen::Race {
            return;
        }
        self.accumulator = (self.accumulator + dt * self.speed).min(MAX_CATCH_UP * self.speed.max(1.0));
        while self.accumulator >= f64::from(DT) && self.screen == Screen::Race {
            if self.stop_at.is_some_and(|t| self.world.tick >= t) {
                self.screen = Screen::Frozen;
                eprintln!("replay stopped at tick {}", self.world.tick);
                break;
            }
            self.accumulator -= f64::from(DT);
            self.tick();
        }
    }

    fn key(&mut self, code: KeyCode, down: bool) -> bool {
        let name = super::keys::key_name(code);
        if let Some(action) = self.rebinding
            && down
        {
            // Settings is waiting for a key: Escape cancels, anything else is bound (reserved keys refused).
            self.rebinding = None;
            if code != KeyCode::Escape
                && let Err(e) = self.bindings.bind(action, &name)
            {
                self.notice = Some(e.to_string());
            }
            return false;
        }
        match (code, self.bindings.action(&name)) {
            (KeyCode::Escape, _) if down => match self.screen {
                Screen::Menu | Screen::Frozen => return true,
                Screen::Race => self.screen = Screen::Paused,
                Screen::Paused => self.screen = Screen::Race,
            },
            (KeyCode::Enter, _) if down && self.screen == Screen::Menu => self.start_race(),
            (_, Some(Action::SteerLeft)) => self.keys.left = down,
            (_, Some(Action::SteerRight)) => self.keys.right = down,
            (_, Some(Action::Throttle)) => self.keys.throttle = down,
            (_, Some(Action::Brake)) => self.keys.brake = down,
            _ if !down => {}
            (_, Some(Action::ChangeView)) => self.view = self.view.next(),
            (_, Some(Action::Pause)) => {
                self.screen = match self.screen {
                    Screen::Race => Screen::Paused,
                    Screen::Paused => Screen::Race,
                    other => other,
                };
            }
            (KeyCode::F3, _) => self.debug.visible = !self.debug.visible,
            (KeyCode::KeyR, _) if self.replay_path.is_some() => {
                if let Some(path) = self.replay_path.clone()
                    && let Err(e) = self.start_replay(&path)
                {
                    self.notice = Some(e.to_string());
                }
            }
            (KeyCode::KeyN, _) if self.source.is_some() && self.screen == Screen::Paused => self.steps += 1,
            (KeyCode::BracketLeft, _) if self.source.is_some() => self.speed = (self.speed * 0.5).max(0.25),
            (KeyCode::BracketRight, _) if self.source.is_some() => self.speed = (self.speed * 2.0).min(16.0),
            _ => {
                if let Some(m) = method_key(code) {
                    self.options.method = m;
                }
            }
        }
        false
    }

    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError> {
        let t = std::time::Instant::now();
        let ghost = self.ghost_pose();
        let stats = self.scene.render_with_ghost(
            &mut self.renderer,
            &self.world,
            self.view,
            &self.options,
            (frame, width, height),
            ghost,
        )?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * ms;
        let occupancy = if self.debug.visible { self.renderer.bucket_occupancy() } else { Vec::new() };
        self.debug.record(ms, &stats, occupancy);
        Ok(format!(
            "{}{} — {:?} — {} {:.1} ms, {} polygons",
            if self.screen == Screen::Paused { "PAUSED — " } else { "" },
            self.status(),
            self.view,
            self.options.method,
            ms,
            stats.polygons_drawn
        ))
    }

    fn ui_events(&mut self) -> Vec<egui::Event> {
        std::mem::take(&mut self.pad_ui)
    }

    fn scale(&mut self, current: u32) -> u32 {
        let wanted = self.scale.1.take().unwrap_or(current);
        self.scale.0 = wanted;
        wanted
    }

    fn ui(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        if !self.hud || self.screen == Screen::Frozen {
            return false;
        }
        match self.screen {
            Screen::Menu => {
                egui::Window::new("scanline-racer")
                    .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                    .collapsible(false)
                    .resizable(false)
                    .show(ctx, |ui| {
                        ui.label("Eight cars, 4.2 km, one bridge.");
                        let before = self.laps;
                        ui.add(egui::Slider::new(&mut self.laps, 1..=10).text("laps"));
                        if self.laps != before {
                            self.restart();
                        }
                        ui.horizontal(|ui| {
                            ui.checkbox(&mut self.record_to.on, "record the race to");
                            ui.add(egui::TextEdit::singleline(&mut self.record_to.text).desired_width(150.0));
                        });
                        ui.horizontal(|ui| {
                            if ui.button("Race").clicked() {
                                self.start_race();
                            }
                            if ui.button("Settings").clicked() {
                                self.settings_open = !self.settings_open;
                            }
                            if ui.button("Quit").clicked() {
                                quit = true;
                            }
                        });
                        ui.horizontal(|ui| {
                            ui.add(
                                egui::TextEdit::singleline(&mut self.replay_input)
                                    .hint_text("race.trace")
                                    .desired_width(180.0),
                            );
                            if ui.button("Replay a file").clicked() {
                                let path = std::path::PathBuf::from(self.replay_input.trim());
                                if let Err(e) = self.start_replay(&path) {
                                    self.notice = Some(e.to_string());
                                }
                            }
                        });
                        if let Some(n) = &self.notice {
                            ui.label(n.as_str());
                        }
                        let keys = |a: Action| self.bindings.keys(a).join("/");
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
            }
            Screen::Paused => {
                egui::Window::new("Paused")
                    .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
                    .collapsible(false)
                    .resizable(false)
                    .show(ctx, |ui| {
                        if ui.button("Resume").clicked() {
                            self.screen = Screen::Race;
                        }
                        if ui.button("Restart").clicked() {
                            self.restart();
                            self.screen = Screen::Race;
                        }
                        if ui.button("Settings").clicked() {
                            self.settings_open = !self.settings_open;
                        }
                        if ui.button("Main menu").clicked() {
                            self.restart();
                            self.screen = Screen::Menu;
                        }
                        if ui.button("Quit").clicked() {
                            quit = true;
                        }
                    });
            }
            Screen::Race | Screen::Frozen => {}
        }
        if self.settings_open && self.screen != Screen::Race {
            self.settings(ctx);
        } else {
            self.rebinding = None;
        }
        self.save_settings();
        self.debug.show(ctx);
        if self.screen != Screen::Menu {
            self.hud(ctx);
        }
        if self.world.race.phase == Phase::Finished && self.results(ctx) {
            quit = true;
        }
        quit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A race on the main menu with the shipped assets.
    pub(super) fn race_on_the_menu() -> Race {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        Race::new(RaceScene::load(&dir).unwrap(), RenderOptions::default(), 1, true)
    }

    /// Settings changed in the game are saved onto the file as it is at that moment: a key added by hand
    /// while the game runs stays, with both changes; a file broken by hand is then left alone, said once.
    #[test]
    fn settings_saved_by_the_game_keep_a_hand_edit_made_meanwhile() {
        let dir = std::env::temp_dir().join(format!("scanline-racer-race-settings-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("settings.json");
        std::fs::write(&p, "{\"scale\": 2}").unwrap();
        let (file, settings, note) = SettingsFile::load(&p);
        let mut race = race_on_the_menu().with_settings(settings, Some(file), None, note);
        race.show_ghost = false;
        race.save_settings();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"ghost\": false,\n  \"scale\": 2\n}\n");
        std::fs::write(&p, "{\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n").unwrap();
        race.pads.deadzone = 0.25;
        race.save_settings();
        let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
        assert_eq!(race.notice, None);
        // Broken by hand: not written, said once.
        std::fs::write(&p, "{\"theme\": ").unwrap();
        race.pads.curve = 2.0;
        race.save_settings();
        let said = race.notice.take().unwrap_or_default();
        assert!(said.ends_with("the file is left as it is and changes will not be saved"), "{said}");
        race.pads.curve = 2.5;
        race.save_settings();
        assert_eq!((race.notice.as_deref(), std::fs::read_to_string(&p).unwrap().as_str()), (None, "{\"theme\": "));
    }
}
