//! The race session: the world, the screen shown, the clock that turns real time into ticks, the race's
//! builders, the tick, and carrying out what the keys and the pad ask (see the module's doc in `mod.rs`).

use std::path::Path;

use winit::keyboard::KeyCode;

use super::control::{Command, Control, Keys, Replaying};
use super::ghost::Ghost;
use super::menus::MenuState;
use super::prefs::{Chosen, Prefs};
use super::record::{CHECKSUM_EVERY, Recorder};
use super::screen::{Drawing, Screen};
use super::sound::Sound;
use super::trial::Trials;
use crate::shell::course::CourseInfo;
use crate::shell::race_scene::{Assets, RaceScene};
use crate::shell::records::RecordsFile;
use crate::shell::settings::{Settings, SettingsFile};

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
pub(super) struct Clock {
    /// Real time not yet simulated, in seconds.
    pub(super) accumulator: f64,
    /// Replay speed (1 = real time).
    pub(super) speed: f64,
    /// Ticks to run while paused (single-step).
    pub(super) steps: u32,
    /// A replay freezes when the world reaches this tick.
    pub(super) stop_at: Option<u64>,
}

/// The race.
pub struct Race {
    pub(super) scene: RaceScene,
    pub(super) world: World,
    /// The race on the grid: its mode, laps (the main menu's slider), car and difficulty, or the replayed
    /// trace's.
    pub(super) setup: RaceSetup,
    pub(super) screen: Screen,
    /// Why the replay or recording stopped, or what changed, shown in the menus and the HUD.
    pub(super) notice: Option<String>,
    pub(super) clock: Clock,
    pub(super) drawing: Drawing,
    /// Where the player's controls come from.
    pub(super) control: Control,
    /// The menus' own state.
    pub(super) menu: MenuState,
    /// The settings and where they are saved.
    pub(super) prefs: Prefs,
    /// Recording races to a trace.
    pub(super) recording: Recorder,
    /// The ghost car.
    pub(super) ghost: Ghost,
    /// The sound and the device it plays on.
    pub(super) sound: Sound,
    /// The assets and the courses they hold, offered in the main menu (none: the course cannot change).
    pub(super) courses: Option<(Assets, Vec<CourseInfo>)>,
    /// The player's records and the time trial's ghost.
    pub(super) trials: Trials,
    /// How far the car in the car select has turned (radians).
    pub(super) showroom: f32,
    /// The player's course and race while a trace chosen in the menu replays (what the settings keep).
    pub(super) player_choice: Option<(String, RaceSetup)>,
}

impl Race {
    /// The race `setup` on the grid, the player last, behind the main menu (or racing at once).
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
            courses: None,
            trials: Trials::default(),
            showroom: 0.0,
            player_choice: None,
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

    /// Lets `auto` quality pick the picture from the frame time (the options' picture is then the fixed one
    /// the settings file keeps). Call before [`Race::with_settings`], which takes the picture as saved.
    #[must_use]
    pub fn with_auto_quality(mut self, on: bool) -> Self {
        self.drawing.set_auto(on);
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
        if self.player_choice.is_some() {
            // A replay: the race the settings keep is the player's, not the trace's.
            let setup = RaceSetup {
                mode: settings.mode,
                laps: settings.laps,
                car: (settings.car.saturating_sub(1)) as usize,
                difficulty: settings.difficulty,
                ..RaceSetup::default()
            };
            self.player_choice = Some((settings.course.clone(), setup));
        }
        let chosen = match &self.player_choice {
            Some((course, setup)) => Chosen { course, setup },
            None => Chosen { course: &self.scene.course, setup: &self.setup },
        };
        self.prefs.apply(settings, file, scale, (self.drawing.picture(), chosen), &mut self.control.pads);
        if note.is_some() {
            self.notice = note;
        }
        self
    }

    /// Keeps the player's records in `file` (and the time trial's ghosts beside it); a time trial on the grid
    /// now starts recording for its ghost.
    #[must_use]
    pub fn with_records(mut self, file: RecordsFile) -> Self {
        self.trials.file = Some(file);
        self.restart();
        self
    }

    /// Offers the courses `assets` hold in the main menu; choosing one loads it there.
    #[must_use]
    pub fn with_courses(mut self, assets: Assets) -> Self {
        let list = assets.courses();
        self.courses = Some((assets, list));
        self
    }

    /// Loads the course `name` in place of the one raced (a failure is shown in the notice, and the race
    /// stays where it was): a fresh start on its grid, recorded under its name, without the ghost of the
    /// course left.
    pub(super) fn change_course(&mut self, name: &str) {
        let Some((assets, _)) = &self.courses else { return };
        match RaceScene::open(assets, name) {
            Ok(scene) => {
                self.recording.course = name.to_string();
                self.recording.inputs.add_all(&scene.scene().files, "a file of the game's assets");
                self.scene = scene;
                self.ghost = Ghost::default();
                self.restart();
            }
            Err(e) => self.notice = Some(e.to_string()),
        }
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
        self.trials.end();
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
    pub(super) fn tick(&mut self) {
        let c = match self.control.player_controls(&self.world) {
            Ok(c) => c,
            Err(why) => {
                self.notice = Some(why.to_string());
                self.screen = Screen::Paused;
                return;
            }
        };
        // Quantized here, as the recording will be, so that the time trial's ghost gets the tick's controls
        // even when the recording's write fails.
        let c = crate::input::trace::quantize(c);
        if let Err(e) = step_recorded(
            &mut self.world,
            c,
            self.recording.recorder.as_mut().and_then(Recording::writer),
            CHECKSUM_EVERY,
        ) {
            self.recording.end(&format!("recording stopped: {e}"), &mut self.notice);
        }
        self.trials.tick(&self.world, c, &mut self.notice);
        let counts = !self.control.replaying() && !self.control.autopilot;
        self.trials.observe(&self.world, (&self.scene.course, &self.setup), counts, &mut self.notice);
        self.sound.world(&self.world);
        self.ghost.take_pending(&self.world, &mut self.notice);
        self.ghost.observe(&self.world, &mut self.notice);
    }

    /// Switches to replaying the trace at `path` from its start, on its course (loaded when it is not the
    /// one raced); refuses a file that is not a trace of a course there is. The player's own choice of race
    /// is what the settings keep meanwhile.
    pub(super) fn start_replay(&mut self, path: &Path) -> Result<(), ReplayError> {
        let replay = Replaying::open(path)?;
        if replay.course() != self.scene.course {
            self.change_course(replay.course());
        }
        replay.check_course(&self.scene.course)?;
        self.player_choice.get_or_insert_with(|| (self.scene.course.clone(), self.setup));
        self.setup = replay.setup();
        self.restart();
        self.trials.end();
        self.control.replay(replay, &self.world, &self.scene.course)?;
        self.screen = Screen::Race;
        Ok(())
    }

    /// Leaves the main menu for the race, recording it first when the menu's toggle asks for it.
    pub(super) fn start_race(&mut self) {
        self.recording.start(&self.world, self.control.replaying(), &mut self.notice);
        self.screen = Screen::Race;
    }

    /// Pauses a race being raced, resumes a paused one, leaves the car select for the main menu; any other
    /// screen stays as it is.
    pub(super) fn toggle_pause(&mut self) {
        self.screen = match self.screen {
            Screen::Race => Screen::Paused,
            Screen::Paused => Screen::Race,
            Screen::Garage => Screen::Menu,
            other => other,
        };
    }

    /// A fresh start on the grid of the race chosen (`setup`), the time trial's recording started anew.
    pub(super) fn restart(&mut self) {
        self.world = World::for_race(self.scene.track.clone(), &self.setup);
        self.clock.accumulator = 0.0;
        self.control.keys = Keys::default();
        self.drawing.renderer.reset_lod();
        self.ghost.laps.restart();
        self.recording.end("recording ended at the restart", &mut self.notice);
        self.sound.restart(self.prefs.sound);
        let replaying = self.control.replaying();
        let chosen = (self.scene.course.as_str(), &self.setup);
        if let Some(search) = self.trials.restart(&self.world, chosen, replaying, &mut self.notice) {
            self.ghost.search(search);
        }
    }

    /// Saves the settings if they changed since the last save (a failure is shown in the notice).
    pub(super) fn save_settings(&mut self) {
        let chosen = match &self.player_choice {
            Some((course, setup)) => Chosen { course, setup },
            None => Chosen { course: &self.scene.course, setup: &self.setup },
        };
        self.prefs.save(&self.control.pads, (self.drawing.picture(), chosen), &mut self.notice);
    }

    /// A key went down or up: a key Settings waits for is bound; any other is what the player's controls
    /// make of it. Returns true to quit (Esc in the main menu or on a frozen replay).
    pub(super) fn key_event(&mut self, code: KeyCode, down: bool) -> bool {
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
    pub(super) fn gamepad_events(&mut self) {
        for ev in self.control.pads.poll() {
            let finished = self.world.race.phase == Phase::Finished;
            if let Some(command) = self.control.pad_event(ev, self.screen, finished) {
                self.obey(command);
            }
        }
    }

    /// Carries out what a key or a pad button asked; true to quit.
    pub(super) fn obey(&mut self, command: Command) -> bool {
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
    pub(super) fn run_ticks(&mut self, dt: f64) {
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
}
