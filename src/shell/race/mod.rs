//! The race in the window: the simulation fed at a fixed tick from the real clock.
//!
//! [`Race`] is the session: the world, the screen shown, and the clock that turns real time into ticks.
//! Each concern around it has its own file and owns its part of the state:
//! - `control`: where the player's controls come from (keyboard and gamepad, the autopilot, or a trace
//!   being replayed: the one seam where the source changes), and the keys and buttons that drive menus;
//! - `menus`: the main menu, the pause menu and the results table;
//! - `prefs`: the settings as the race holds them, the Settings window, and saving them to the file;
//! - `hud`: what is drawn over the race, and the title bar's status line;
//! - `record`: recording races to a trace;
//! - `ghost`: the ghost car and the lap it drives.

use winit::keyboard::KeyCode;

mod control;
mod ghost;
mod hud;
mod menus;
mod prefs;
mod record;

use super::debug_overlay::DebugOverlay;
use super::race_scene::{FIELD, RaceScene, View};
use super::window::{Content, ShellError};
use crate::game::rules::{Phase, format_ticks};
use crate::game::{DT, TICK_HZ, World};
use crate::input::recording::Recording;
use crate::input::replay::{lap_mm, step_recorded};
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

/// How real time becomes simulation ticks.
#[derive(Debug)]
struct Clock {
    /// Real time not yet simulated, in seconds.
    accumulator: f64,
    /// Replay speed (1 = real time).
    speed: f64,
    /// Ticks to run while paused (single-step).
    steps: u32,
    /// A replay freezes when the world reaches this tick.
    stop_at: Option<u64>,
}

/// How frames are drawn.
struct Drawing {
    renderer: Renderer,
    options: RenderOptions,
    view: View,
    /// The frame time, smoothed, for the HUD.
    frame_ms: f64,
    /// The F3 window.
    debug: DebugOverlay,
    /// Whether menus and HUD are drawn over the race.
    hud: bool,
}

/// The race.
pub struct Race {
    scene: RaceScene,
    world: World,
    /// Laps of the race on the grid (the main menu's slider, or the replayed trace's).
    laps: u32,
    screen: Screen,
    /// Why the replay or recording stopped, or what changed, shown in the menus and the HUD.
    notice: Option<String>,
    clock: Clock,
    drawing: Drawing,
    /// Where the player's controls come from.
    control: control::Control,
    /// The menus' own state.
    menu: menus::MenuState,
    /// The settings and where they are saved.
    prefs: prefs::Prefs,
    /// Recording races to a trace.
    recording: record::Recorder,
    /// The ghost car.
    ghost: ghost::Ghost,
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
            laps,
            screen: if menu { Screen::Menu } else { Screen::Race },
            notice: None,
            clock: Clock { accumulator: 0.0, speed: 1.0, steps: 0, stop_at: None },
            drawing: Drawing {
                renderer: Renderer::new(),
                options,
                view: View::ChaseNear,
                frame_ms: 0.0,
                debug: DebugOverlay::default(),
                hud: true,
            },
            control: control::Control::default(),
            menu: menus::MenuState::default(),
            prefs: prefs::Prefs::default(),
            recording: record::Recorder::default(),
            ghost: ghost::Ghost::default(),
        }
    }

    /// Freezes the replay when the world reaches `tick` (and prints one line saying so), and hides the HUD
    /// when `hud` is false: for comparing the window with headless frames.
    #[must_use]
    pub fn stopping_at(mut self, tick: Option<u64>, hud: bool) -> Self {
        self.clock.stop_at = tick;
        self.drawing.hud = hud;
        self
    }

    /// Lets the AI drive the player's car (the controls it chooses are recorded like a player's).
    #[must_use]
    pub fn autopilot(mut self, on: bool) -> Self {
        self.control.autopilot = on;
        self
    }

    /// The world being raced.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// One simulation tick with the player's controls from their source, recorded if asked; then the laps
    /// and the ghost are brought up to date.
    fn tick(&mut self) {
        let Some(c) = self.player_controls() else { return };
        if let Err(e) = step_recorded(
            &mut self.world,
            c,
            self.recording.recorder.as_mut().and_then(Recording::writer),
            CHECKSUM_EVERY,
        ) {
            self.end_recording(&format!("recording stopped: {e}"));
        }
        self.take_pending_ghost();
        if self.ghost.laps.observe(&self.world)
            && let Some(best) = &self.ghost.laps.best
            && self.ghost.lap.as_ref().is_none_or(|g| best.ticks() < g.ticks())
        {
            self.notice = Some(format!("best lap {}: the ghost drives it now", format_ticks(best.ticks())));
            self.ghost.lap = Some(best.clone());
        }
    }

    /// Leaves the main menu for the race, recording it first when the menu's toggle asks for it.
    fn start_race(&mut self) {
        self.start_recording();
        self.screen = Screen::Race;
    }

    /// Pauses a race being raced, resumes a paused one; any other screen stays as it is.
    fn toggle_pause(&mut self) {
        self.screen = match self.screen {
            Screen::Race => Screen::Paused,
            Screen::Paused => Screen::Race,
            other => other,
        };
    }

    /// A fresh start on the grid with the current number of laps.
    fn restart(&mut self) {
        self.world = World::with_laps(self.scene.track.clone(), FIELD, self.laps);
        self.clock.accumulator = 0.0;
        self.control.keys = control::Keys::default();
        self.drawing.renderer.reset_lod();
        self.ghost.laps.restart();
        if self.recording.recorder.is_some() {
            self.end_recording("recording ended at the restart");
        }
    }
}

impl Content for Race {
    fn update(&mut self, dt: f64) {
        self.gamepad_events();
        self.ghost_search_reports();
        while self.clock.steps > 0 {
            self.clock.steps -= 1;
            self.tick();
        }
        if self.screen != Screen::Race {
            return;
        }
        let clock = &mut self.clock;
        clock.accumulator = (clock.accumulator + dt * clock.speed).min(MAX_CATCH_UP * clock.speed.max(1.0));
        while self.clock.accumulator >= f64::from(DT) && self.screen == Screen::Race {
            if self.clock.stop_at.is_some_and(|t| self.world.tick >= t) {
                self.screen = Screen::Frozen;
                eprintln!("replay stopped at tick {}", self.world.tick);
                break;
            }
            self.clock.accumulator -= f64::from(DT);
            self.tick();
        }
    }

    fn key(&mut self, code: KeyCode, down: bool) -> bool {
        self.key_event(code, down)
    }

    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError> {
        let t = std::time::Instant::now();
        let ghost = self.ghost_pose();
        let d = &mut self.drawing;
        let stats = self.scene.render_with_ghost(
            &mut d.renderer,
            &self.world,
            d.view,
            &d.options,
            (frame, width, height),
            ghost,
        )?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        d.frame_ms = 0.9 * d.frame_ms + 0.1 * ms;
        let occupancy = if d.debug.visible { d.renderer.bucket_occupancy() } else { Vec::new() };
        d.debug.record(ms, &stats, occupancy);
        Ok(format!(
            "{}{} — {:?} — {} {:.1} ms, {} polygons",
            if self.screen == Screen::Paused { "PAUSED — " } else { "" },
            self.status(),
            self.drawing.view,
            self.drawing.options.method,
            ms,
            stats.polygons_drawn
        ))
    }

    fn ui_events(&mut self) -> Vec<egui::Event> {
        std::mem::take(&mut self.control.pad_ui)
    }

    fn scale(&mut self, current: u32) -> u32 {
        let wanted = self.prefs.scale.1.take().unwrap_or(current);
        self.prefs.scale.0 = wanted;
        wanted
    }

    fn ui(&mut self, ctx: &egui::Context) -> bool {
        if !self.drawing.hud || self.screen == Screen::Frozen {
            return false;
        }
        let mut quit = match self.screen {
            Screen::Menu => self.main_menu(ctx),
            Screen::Paused => self.pause_menu(ctx),
            Screen::Race | Screen::Frozen => false,
        };
        if self.prefs.open && self.screen != Screen::Race {
            self.settings_window(ctx);
        } else {
            self.prefs.rebinding = None;
        }
        self.save_settings();
        self.drawing.debug.show(ctx);
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
    use crate::shell::settings::SettingsFile;

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
        race.prefs.show_ghost = false;
        race.save_settings();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "{\n  \"ghost\": false,\n  \"scale\": 2\n}\n");
        std::fs::write(&p, "{\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n").unwrap();
        race.control.pads.deadzone = 0.25;
        race.save_settings();
        let want = "{\n  \"deadzone\": 0.25,\n  \"ghost\": false,\n  \"scale\": 2,\n  \"theme\": \"dark\"\n}\n";
        assert_eq!(std::fs::read_to_string(&p).unwrap(), want);
        assert_eq!(race.notice, None);
        // Broken by hand: not written, said once.
        std::fs::write(&p, "{\"theme\": ").unwrap();
        race.control.pads.curve = 2.0;
        race.save_settings();
        let said = race.notice.take().unwrap_or_default();
        assert!(said.ends_with("the file is left as it is and changes will not be saved"), "{said}");
        race.control.pads.curve = 2.5;
        race.save_settings();
        assert_eq!((race.notice.as_deref(), std::fs::read_to_string(&p).unwrap().as_str()), (None, "{\"theme\": "));
    }

    /// P, the pad's Start button and Esc toggle between racing and the pause menu through one function,
    /// which leaves the other screens alone.
    #[test]
    fn the_pause_toggle_switches_only_between_racing_and_paused() {
        let mut race = race_on_the_menu();
        for (from, to) in [
            (Screen::Race, Screen::Paused),
            (Screen::Paused, Screen::Race),
            (Screen::Menu, Screen::Menu),
            (Screen::Frozen, Screen::Frozen),
        ] {
            race.screen = from;
            race.toggle_pause();
            assert_eq!(race.screen, to, "{from:?}");
        }
    }
}
