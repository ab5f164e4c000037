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
//! - `sound`: the race's sound, a mixer shown every world stepped to, played on the audio device.
//!
//! This file ties them together: the race's builders, the tick, and carrying out what the keys, the pad
//! and the menus ask.

use std::path::Path;

use winit::keyboard::KeyCode;

mod control;
mod ghost;
mod hud;
mod menus;
mod prefs;
mod record;
mod screen;
mod sound;

pub use record::{CHECKSUM_EVERY, header_for};

use self::control::{Command, Control, Keys, Replaying};
use self::ghost::Ghost;
use self::menus::{Choice, MenuState};
use self::prefs::Prefs;
use self::record::Recorder;
use self::screen::{Drawing, Screen};
use self::sound::Sound;
use super::race_scene::RaceScene;
use super::settings::{Settings, SettingsFile};
use super::window::{Content, ShellError};
use crate::game::rules::Phase;
use crate::game::{DT, RaceSetup, World};
use crate::input::ghost::{GhostLap, GhostSearch};
use crate::input::recording::{Kept, RecordError, Recording};
use crate::input::replay::{ReplayError, step_recorded};
use crate::render::RenderOptions;

/// Most simulated time one frame may catch up after a stall (the game slows down instead of jumping).
const MAX_CATCH_UP: f64 = 0.25;

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

/// The race.
pub struct Race {
    scene: RaceScene,
    world: World,
    /// The race on the grid: its mode, laps (the main menu's slider), car and difficulty, or the replayed
    /// trace's.
    setup: RaceSetup,
    screen: Screen,
    /// Why the replay or recording stopped, or what changed, shown in the menus and the HUD.
    notice: Option<String>,
    clock: Clock,
    drawing: Drawing,
    /// Where the player's controls come from.
    control: Control,
    /// The menus' own state.
    menu: MenuState,
    /// The settings and where they are saved.
    prefs: Prefs,
    /// Recording races to a trace.
    recording: Recorder,
    /// The ghost car.
    ghost: Ghost,
    /// The sound and the device it plays on.
    sound: Sound,
}

impl Race {
    /// A race of `laps` laps on the grid, the player last, behind the main menu (or racing at once).
    #[must_use]
    pub fn new(scene: RaceScene, options: RenderOptions, setup: RaceSetup, menu: bool) -> Self {
        let world = World::for_race(scene.track.clone(), &setup);
        let recording = Recorder::on(&scene.course);
        Self {
            world,
            scene,
            setup,
            screen: if menu { Screen::Menu } else { Screen::Race },
            notice: None,
            clock: Clock { accumulator: 0.0, speed: 1.0, steps: 0, stop_at: None },
            drawing: Drawing::new(options),
            control: Control::default(),
            menu: MenuState::default(),
            prefs: Prefs::default(),
            recording,
            ghost: Ghost::default(),
            sound: Sound::default(),
        }
    }

    /// A replay of the trace at `path`: the trace drives the player's car; P pauses, N steps a tick, `[`
    /// and `]` halve and double the speed (1/4x to 16x), R restarts.
    pub fn replaying(scene: RaceScene, options: RenderOptions, path: &Path) -> Result<Self, ReplayError> {
        let mut race = Self::new(scene, options, RaceSetup::default(), false);
        race.start_replay(path)?;
        Ok(race)
    }

    /// Freezes the replay when the world reaches `tick` (and prints one line saying so), and hides the HUD
    /// when `hud` is false: for comparing the window with headless frames.
    #[must_use]
    pub fn stopping_at(mut self, tick: Option<u64>, hud: bool) -> Self {
        self.clock.stop_at = tick;
        self.drawing.hud = hud;
        self
    }

    /// Plays the race's sound on the default audio device, opened when the window first draws (with none,
    /// one line says so and the race runs silent).
    #[must_use]
    pub fn with_sound(mut self) -> Self {
        self.sound.enable();
        self
    }

    /// Lets the AI drive the player's car (the controls it chooses are recorded like a player's).
    #[must_use]
    pub fn autopilot(mut self, on: bool) -> Self {
        self.control.autopilot = on;
        self
    }

    /// Applies `settings` (keys, gamepad deadzone and curve, scale unless `scale` overrides it) and saves
    /// changes made in Settings to `file`; `note` (a problem reading the file) is shown in the menu. The
    /// picture choices in `settings` are the caller's to put in the options given to [`Race::new`] (the
    /// command line may override them for the run); a change made to them in Settings is saved.
    #[must_use]
    pub fn with_settings(
        mut self,
        settings: Settings,
        file: Option<SettingsFile>,
        scale: Option<u32>,
        note: Option<String>,
    ) -> Self {
        self.prefs.apply(settings, file, scale, &self.drawing.options, &mut self.control.pads);
        if note.is_some() {
            self.notice = note;
        }
        self
    }

    /// Races against `lap` as a see-through ghost car from the start (a faster lap driven now replaces it).
    #[must_use]
    pub fn with_ghost(mut self, lap: GhostLap) -> Self {
        self.ghost.lap = Some(lap);
        self
    }

    /// Races against the fastest lap `search` finds in a trace: each faster lap it reports takes over
    /// before the green light or when the player crosses the line; the HUD says when the trace held none.
    #[must_use]
    pub fn with_ghost_search(mut self, search: GhostSearch) -> Self {
        self.ghost.search(search);
        self
    }

    /// Records races to `path`: at once when the race starts without the menu, else each race started from
    /// the main menu while its switch (now on, with this file) stays on. A path that cannot be recorded to
    /// (a folder, a missing folder) is refused now, before the window opens; `path` itself is not touched.
    pub fn record_to(mut self, path: &Path) -> Result<Self, RecordError> {
        self.recording.record_to(path, &self.world, self.screen == Screen::Race)?;
        Ok(self)
    }

    /// Names the files the run reads (the settings file, the assets): a name typed in the main menu's
    /// recording field that leads to one of them is refused there ("not recording: ...").
    #[must_use]
    pub fn reading(mut self, inputs: crate::userfile::Inputs) -> Self {
        self.recording.inputs = inputs;
        self
    }

    /// Ends the recording when the window has closed (by any path: Quit, Esc in the main menu, the window's
    /// close button, `--exit-after-frames`, an error): what was raced replaces the target. `None` when
    /// there was nothing to record to or a race was already kept; [`Kept::Nothing`] when the switch was on
    /// and no race was recorded in this run.
    pub fn finish_recording(&mut self) -> Result<Option<Kept>, RecordError> {
        self.recording.finish()
    }

    /// The world being raced.
    #[must_use]
    pub fn world(&self) -> &World {
        &self.world
    }

    /// One simulation tick with the player's controls from their source, recorded if asked; then the laps
    /// and the ghost are brought up to date. A replay that has ended or failed pauses the race instead,
    /// and the notice says why.
    fn tick(&mut self) {
        let c = match self.control.player_controls(&self.world) {
            Ok(c) => c,
            Err(why) => {
                self.notice = Some(why.to_string());
                self.screen = Screen::Paused;
                return;
            }
        };
        if let Err(e) = step_recorded(
            &mut self.world,
            c,
            self.recording.recorder.as_mut().and_then(Recording::writer),
            CHECKSUM_EVERY,
        ) {
            self.recording.end(&format!("recording stopped: {e}"), &mut self.notice);
        }
        self.sound.world(&self.world);
        self.ghost.take_pending(&self.world, &mut self.notice);
        self.ghost.observe(&self.world, &mut self.notice);
    }

    /// Switches to replaying the trace at `path` from its start; refuses a file that is not a trace of
    /// this track and field.
    fn start_replay(&mut self, path: &Path) -> Result<(), ReplayError> {
        let replay = Replaying::open(path)?;
        self.setup = replay.setup();
        self.restart();
        self.control.replay(replay, &self.world)?;
        self.screen = Screen::Race;
        Ok(())
    }

    /// Leaves the main menu for the race, recording it first when the menu's toggle asks for it.
    fn start_race(&mut self) {
        self.recording.start(&self.world, self.control.replaying(), &mut self.notice);
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
        self.world = World::for_race(self.scene.track.clone(), &self.setup);
        self.clock.accumulator = 0.0;
        self.control.keys = Keys::default();
        self.drawing.renderer.reset_lod();
        self.ghost.laps.restart();
        self.recording.end("recording ended at the restart", &mut self.notice);
        self.sound.restart(self.prefs.sound);
    }

    /// Saves the settings if they changed since the last save (a failure is shown in the notice).
    fn save_settings(&mut self) {
        self.prefs.save(&self.control.pads, &self.drawing.options, &mut self.notice);
    }

    /// A key went down or up: a key Settings waits for is bound; any other is what the player's controls
    /// make of it. Returns true to quit (Esc in the main menu or on a frozen replay).
    fn key_event(&mut self, code: KeyCode, down: bool) -> bool {
        let name = crate::shell::keys::key_name(code);
        if let Some(action) = self.prefs.rebinding
            && down
        {
            self.prefs.rebind(action, code, &name, &mut self.notice);
            return false;
        }
        let action = self.prefs.bindings.action(&name);
        self.control.key(code, down, action, self.screen).is_some_and(|command| self.obey(command))
    }

    /// Reacts to gamepad buttons and hot-plug, one event at a time (each sees the screen the last left).
    fn gamepad_events(&mut self) {
        for ev in self.control.pads.poll() {
            let finished = self.world.race.phase == Phase::Finished;
            if let Some(command) = self.control.pad_event(ev, self.screen, finished) {
                self.obey(command);
            }
        }
    }

    /// Carries out what a key or a pad button asked; true to quit.
    fn obey(&mut self, command: Command) -> bool {
        match command {
            Command::Quit => return true,
            Command::TogglePause => self.toggle_pause(),
            Command::ToggleMute => {
                let muted = !self.prefs.sound.muted;
                self.prefs.sound.muted = muted;
                self.notice = Some(if muted { "sound muted" } else { "sound on" }.to_string());
            }
            Command::Resume => self.screen = Screen::Race,
            Command::StartRace => self.start_race(),
            Command::NextView => self.drawing.view = self.drawing.view.next(),
            Command::ToggleDebug => self.drawing.debug.visible = !self.drawing.debug.visible,
            Command::Method(m) => self.drawing.options.method = m,
            Command::RestartReplay => {
                if let Some(path) = self.control.replay_path()
                    && let Err(e) = self.start_replay(&path)
                {
                    self.notice = Some(e.to_string());
                }
            }
            Command::Step => self.clock.steps += 1,
            Command::Slower => self.clock.speed = (self.clock.speed * 0.5).max(0.25),
            Command::Faster => self.clock.speed = (self.clock.speed * 2.0).min(16.0),
            Command::Notice(n) => self.notice = Some(n),
            Command::PadLost => {
                if self.screen == Screen::Race {
                    self.screen = Screen::Paused;
                }
                self.notice = Some("gamepad disconnected: race paused".into());
            }
        }
        false
    }

    /// Runs the ticks `dt` seconds of real time are worth at the replay's speed (a stall is caught up only
    /// so far); a replay freezes at its stop tick.
    fn run_ticks(&mut self, dt: f64) {
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

    /// Carries out the menus' choices in the order they were made; true when one was Quit.
    fn choose(&mut self, choices: Vec<Choice>) -> bool {
        if !choices.is_empty() {
            self.sound.click();
        }
        let mut quit = false;
        for choice in choices {
            match choice {
                Choice::Race => self.start_race(),
                Choice::Resume => self.screen = Screen::Race,
                Choice::Restart => {
                    self.restart();
                    self.screen = Screen::Race;
                }
                Choice::MainMenu => {
                    self.restart();
                    self.screen = Screen::Menu;
                }
                Choice::Laps(laps) => {
                    self.setup.laps = laps;
                    self.restart();
                }
                Choice::Replay(path) => {
                    if let Err(e) = self.start_replay(&path) {
                        self.notice = Some(e.to_string());
                    }
                }
                Choice::Settings => self.prefs.open = !self.prefs.open,
                Choice::Quit => quit = true,
            }
        }
        quit
    }
}

impl Content for Race {
    fn update(&mut self, dt: f64) {
        self.gamepad_events();
        self.ghost.search_reports(&self.world, &mut self.notice);
        while self.clock.steps > 0 {
            self.clock.steps -= 1;
            self.tick();
        }
        if self.screen == Screen::Race {
            // The grid is heard once before the first tick, as the headless soundtrack starts.
            self.sound.world(&self.world);
            self.run_ticks(dt);
        }
        self.sound.levels(self.prefs.sound);
        self.sound.frame(dt, self.screen == Screen::Race);
    }

    fn key(&mut self, code: KeyCode, down: bool) -> bool {
        self.key_event(code, down)
    }

    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError> {
        let t = std::time::Instant::now();
        let ghost = self.ghost.pose(&self.world, self.prefs.show_ghost);
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
            hud::status(&self.world),
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
        let chose = match self.screen {
            Screen::Menu => self.menu.main_menu(
                ctx,
                self.setup.laps,
                &mut self.recording.to,
                self.notice.as_deref(),
                &self.prefs.bindings,
                self.control.pads.style(),
            ),
            Screen::Paused => menus::pause_menu(ctx),
            Screen::Race | Screen::Frozen => Vec::new(),
        };
        let mut quit = self.choose(chose);
        if self.prefs.open && self.screen != Screen::Race {
            let ghost_ticks = self.ghost.lap.as_ref().map(GhostLap::ticks);
            self.prefs.window(ctx, &mut self.drawing, &mut self.control.pads, ghost_ticks);
        } else {
            self.prefs.rebinding = None;
        }
        self.save_settings();
        self.drawing.debug.show(ctx);
        if self.screen != Screen::Menu {
            let replay = self.control.replaying().then(|| {
                (
                    self.clock.speed,
                    crate::shell::keys::key_labels(
                        self.prefs.bindings.keys(crate::input::bindings::Action::Pause),
                        "/",
                    ),
                )
            });
            hud::hud(ctx, &self.world, self.notice.as_deref(), replay, &self.drawing);
        }
        if self.world.race.phase == Phase::Finished && self.choose(menus::results(ctx, &self.world.race)) {
            quit = true;
        }
        quit
    }
}

#[cfg(test)]
mod tests;
