//! Where the player's controls come from: the keyboard and a gamepad together, the AI (autopilot), or a
//! trace being replayed, chosen in one place ([`Control::player_controls`]); and what the keys and pad
//! buttons that do not drive ask of the race ([`Command`]: pause, change the view, drive the menus, steer a
//! replay), which the race carries out.

use std::path::{Path, PathBuf};

use thiserror::Error;
use winit::keyboard::KeyCode;

use super::screen::Screen;
use crate::game::ai::{Driver, drive};
use crate::game::{Controls, DT, World};
use crate::input::bindings::Action;
use crate::input::gamepad::{Gamepads, PadButton, PadEvent};
use crate::input::replay::{ReplayError, TraceSource};
use crate::render::Method;
use crate::shell::race_scene::FIELD;
use crate::shell::window::method_key;

/// Keyboard state turned into smoothed controls.
#[derive(Debug, Default)]
pub(super) struct Keys {
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

/// Why a replay gives the race no more controls: what the paused race then shows.
#[derive(Debug, Error)]
pub(super) enum ReplayStop {
    /// The trace ended.
    #[error("end of replay at tick {tick} ({verified} checksums verified)")]
    Ended {
        /// The tick the race reached.
        tick: u64,
        /// Checksums verified on the way.
        verified: u64,
    },
    /// The trace could not be read on, or the race left the recording.
    #[error(transparent)]
    Failed(ReplayError),
}

/// A trace being replayed: the source of the player's controls, and its path for R (restart).
pub(super) struct Replaying {
    source: TraceSource,
    path: PathBuf,
}

/// The player's inputs.
#[derive(Default)]
pub(super) struct Control {
    /// The keyboard's driving keys.
    pub(super) keys: Keys,
    /// Gamepads (none is fine: keyboard only).
    pub(super) pads: Gamepads,
    /// Key presses for the UI from the gamepad (D-pad moves the focus, A presses the focused button).
    pub(super) pad_ui: Vec<egui::Event>,
    /// The player's car drives itself (attract mode); its controls are still recorded like a player's.
    pub(super) autopilot: bool,
    /// In a replay, the trace the player's controls come from.
    replay: Option<Replaying>,
}

/// What a key or a pad button asks of the race beyond driving (the driving keys [`Control`] takes itself),
/// for the race to carry out: most of it changes parts of the race that are not the player's inputs.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Command {
    /// Quit the game (Esc in the main menu or on a frozen replay).
    Quit,
    /// Pause a race being raced, resume a paused one.
    TogglePause,
    /// Mute the sound, or unmute it (M, on every screen).
    ToggleMute,
    /// Leave the pause menu for the race (the pad's Back button).
    Resume,
    /// Leave the main menu for the race (Enter).
    StartRace,
    /// Show the next camera view.
    NextView,
    /// Show or hide the debug overlay (F3).
    ToggleDebug,
    /// Draw with this visibility method (1-5).
    Method(Method),
    /// Replay the trace being replayed from its start (R).
    RestartReplay,
    /// Run one tick of a paused replay (N).
    Step,
    /// Halve the replay's speed, down to 1/4x (`[`).
    Slower,
    /// Double the replay's speed, up to 16x (`]`).
    Faster,
    /// Show this notice (a gamepad was plugged in).
    Notice(String),
    /// The active gamepad was unplugged: a race being raced pauses, and the notice says why.
    PadLost,
}

impl Replaying {
    /// Opens the trace at `path` to replay (its track is checked by [`Control::replay`], against the world
    /// set up for the trace's race).
    pub(super) fn open(path: &Path) -> Result<Self, ReplayError> {
        let source = TraceSource::open(path)?;
        Ok(Self { source, path: path.to_path_buf() })
    }

    /// The course the trace was raced on.
    pub(super) fn course(&self) -> &str {
        &self.source.header.course
    }

    /// Refuses the trace unless it was raced on `course`.
    pub(super) fn check_course(&self, course: &str) -> Result<(), ReplayError> {
        self.source.check_course(course)
    }

    /// The race the trace recorded: the race replaying it is set up as it.
    pub(super) fn setup(&self) -> crate::game::RaceSetup {
        self.source.header.setup()
    }
}

impl Control {
    /// Whether the player's controls come from a trace.
    pub(super) fn replaying(&self) -> bool {
        self.replay.is_some()
    }

    /// The file of the trace being replayed, for R to replay it again from its start.
    pub(super) fn replay_path(&self) -> Option<PathBuf> {
        self.replay.as_ref().map(|r| r.path.clone())
    }

    /// Takes the player's controls from `replay` from now on, once its course is `course` and its track that
    /// of `world` (the world on the grid, set up for the trace's race); on a refusal the controls come from
    /// where they came.
    pub(super) fn replay(&mut self, replay: Replaying, world: &World, course: &str) -> Result<(), ReplayError> {
        replay.source.check_course(course)?;
        replay.source.check_track(world)?;
        self.replay = Some(replay);
        Ok(())
    }

    /// The player's controls for the next tick of `world` (the seam between live play and a replay): from
    /// the trace when replaying, else from the AI with the autopilot on, else the keyboard and pad
    /// together. `Err` says why there are none when the replay has ended or failed: the race then pauses
    /// and shows it.
    pub(super) fn player_controls(&mut self, world: &World) -> Result<Controls, ReplayStop> {
        match self.replay.as_mut() {
            None if self.autopilot => Ok(drive(&Driver::field(FIELD), 0, &world.cars, &world.track, &world.params[0])),
            None => {
                // Keyboard and pad together: steering adds, pedals take the larger.
                let k = self.keys.controls();
                Ok(match self.pads.controls() {
                    Some(p) => Controls {
                        steer: (k.steer + p.steer).clamp(-1.0, 1.0),
                        throttle: k.throttle.max(p.throttle),
                        brake: k.brake.max(p.brake),
                    },
                    None => k,
                })
            }
            Some(Replaying { source, .. }) => match source.next_controls(world) {
                Ok(Some(c)) => Ok(c),
                Ok(None) => Err(ReplayStop::Ended { tick: world.tick, verified: source.verified }),
                Err(e) => Err(ReplayStop::Failed(e)),
            },
        }
    }

    /// What gamepad event `ev` asks of the race on `screen` (`finished`: the results are shown). In menus
    /// the pad works like the keyboard: its D-pad and A become key presses for the UI, taken here.
    pub(super) fn pad_event(&mut self, ev: PadEvent, screen: Screen, finished: bool) -> Option<Command> {
        match ev {
            PadEvent::Connected { name } => Some(Command::Notice(format!("gamepad connected: {name}"))),
            PadEvent::ActiveDisconnected => Some(Command::PadLost),
            PadEvent::Pressed(b @ (PadButton::Confirm | PadButton::Up | PadButton::Down))
                if matches!(screen, Screen::Menu | Screen::Paused | Screen::Garage) || finished =>
            {
                self.pad_menu_key(b);
                None
            }
            PadEvent::Pressed(PadButton::Pause) => Some(Command::TogglePause),
            PadEvent::Pressed(PadButton::Back) if screen == Screen::Paused => Some(Command::Resume),
            PadEvent::Pressed(PadButton::Back) if screen == Screen::Garage => Some(Command::TogglePause),
            PadEvent::Pressed(PadButton::View) => Some(Command::NextView),
            PadEvent::Pressed(_) => None,
        }
    }

    /// In menus the pad works like the keyboard: D-pad moves the focus, A presses the button.
    fn pad_menu_key(&mut self, b: PadButton) {
        let (key, modifiers) = match b {
            PadButton::Up => (egui::Key::Tab, egui::Modifiers::SHIFT),
            PadButton::Down => (egui::Key::Tab, egui::Modifiers::NONE),
            _ => (egui::Key::Enter, egui::Modifiers::NONE),
        };
        for pressed in [true, false] {
            self.pad_ui.push(egui::Event::Key { key, physical_key: None, pressed, repeat: false, modifiers });
        }
    }

    /// Key `code` went down or up on `screen`, bound to `action` if any: the driving keys are taken here;
    /// for the others, what they ask: Esc and the bound keys pause, mute and change the view, F3 shows the debug
    /// overlay, R N `[` `]` steer a replay, 1-5 pick the visibility method, and Esc quits in the main menu
    /// or on a frozen replay.
    pub(super) fn key(&mut self, code: KeyCode, down: bool, action: Option<Action>, screen: Screen) -> Option<Command> {
        match (code, action) {
            (KeyCode::Escape, _) if down => Some(match screen {
                Screen::Menu | Screen::Frozen => Command::Quit,
                // In the car select, Esc goes back to the main menu (as the pause toggle's way out of it).
                Screen::Race | Screen::Paused | Screen::Garage => Command::TogglePause,
            }),
            (KeyCode::Enter, _) if down && screen == Screen::Menu => Some(Command::StartRace),
            (_, Some(Action::SteerLeft)) => hold(&mut self.keys.left, down),
            (_, Some(Action::SteerRight)) => hold(&mut self.keys.right, down),
            (_, Some(Action::Throttle)) => hold(&mut self.keys.throttle, down),
            (_, Some(Action::Brake)) => hold(&mut self.keys.brake, down),
            _ if !down => None,
            (_, Some(Action::ChangeView)) => Some(Command::NextView),
            (_, Some(Action::Pause)) => Some(Command::TogglePause),
            (_, Some(Action::Mute)) => Some(Command::ToggleMute),
            (KeyCode::F3, _) => Some(Command::ToggleDebug),
            (KeyCode::KeyR | KeyCode::KeyN | KeyCode::BracketLeft | KeyCode::BracketRight, _) if self.replaying() => {
                replay_key(code, screen)
            }
            _ => method_key(code).map(Command::Method),
        }
    }
}

/// A driving key went down or up: it is held while down, and asks nothing more of the race.
fn hold(held: &mut bool, down: bool) -> Option<Command> {
    *held = down;
    None
}

/// In a replay: R restarts it, N steps one tick while paused, `[` and `]` halve and double its speed.
fn replay_key(code: KeyCode, screen: Screen) -> Option<Command> {
    match code {
        KeyCode::KeyR => Some(Command::RestartReplay),
        KeyCode::KeyN if screen == Screen::Paused => Some(Command::Step),
        KeyCode::BracketLeft => Some(Command::Slower),
        KeyCode::BracketRight => Some(Command::Faster),
        _ => None,
    }
}
