//! Where the player's controls come from: the keyboard and a gamepad together, the AI (autopilot), or a
//! trace being replayed, chosen in one place ([`Race::player_controls`]); and the keys and pad buttons
//! that pause, change the view, drive the menus and steer a replay.

use std::path::{Path, PathBuf};

use winit::keyboard::KeyCode;

use super::{Race, Screen};
use crate::game::ai::{Driver, drive};
use crate::game::rules::Phase;
use crate::game::{Controls, DT};
use crate::input::bindings::Action;
use crate::input::gamepad::{Gamepads, PadButton, PadEvent};
use crate::input::replay::{ReplayError, TraceSource};
use crate::render::RenderOptions;
use crate::shell::race_scene::{FIELD, RaceScene};
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

impl Control {
    /// Whether the player's controls come from a trace.
    pub(super) fn replaying(&self) -> bool {
        self.replay.is_some()
    }
}

impl Race {
    /// A replay of the trace at `path`: the trace drives the player's car; P pauses, N steps a tick, `[`
    /// and `]` halve and double the speed (1/4x to 16x), R restarts.
    pub fn replaying(scene: RaceScene, options: RenderOptions, path: &Path) -> Result<Self, ReplayError> {
        let mut race = Self::new(scene, options, 3, false);
        race.start_replay(path)?;
        Ok(race)
    }

    /// Switches to replaying the trace at `path` from its start; refuses a file that is not a trace of
    /// this track and field.
    pub(super) fn start_replay(&mut self, path: &Path) -> Result<(), ReplayError> {
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
        self.control.replay = Some(Replaying { source, path: path.to_path_buf() });
        self.screen = Screen::Race;
        Ok(())
    }

    /// The player's controls for the next tick (the seam between live play and a replay): from the trace
    /// when replaying, else from the AI with the autopilot on, else the keyboard and pad together. `None`
    /// when the replay has ended or failed: the race is then paused and the notice says why.
    pub(super) fn player_controls(&mut self) -> Option<Controls> {
        let control = &mut self.control;
        match control.replay.as_mut() {
            None if control.autopilot => {
                let w = &self.world;
                Some(drive(&Driver::field(FIELD), 0, &w.cars, &w.track, &w.params))
            }
            None => {
                // Keyboard and pad together: steering adds, pedals take the larger.
                let k = control.keys.controls();
                Some(match control.pads.controls() {
                    Some(p) => Controls {
                        steer: (k.steer + p.steer).clamp(-1.0, 1.0),
                        throttle: k.throttle.max(p.throttle),
                        brake: k.brake.max(p.brake),
                    },
                    None => k,
                })
            }
            Some(Replaying { source, .. }) => match source.next_controls(&self.world) {
                Ok(Some(c)) => Some(c),
                Ok(None) => {
                    self.notice = Some(format!(
                        "end of replay at tick {} ({} checksums verified)",
                        self.world.tick, source.verified
                    ));
                    self.screen = Screen::Paused;
                    None
                }
                Err(e) => {
                    self.notice = Some(e.to_string());
                    self.screen = Screen::Paused;
                    None
                }
            },
        }
    }

    /// Reacts to gamepad buttons and hot-plug: unplugging the active pad mid-race pauses the race.
    pub(super) fn gamepad_events(&mut self) {
        for ev in self.control.pads.poll() {
            match ev {
                PadEvent::Connected { name } => self.notice = Some(format!("gamepad connected: {name}")),
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
                    self.pad_menu_key(b);
                }
                PadEvent::Pressed(PadButton::Pause) => self.toggle_pause(),
                PadEvent::Pressed(PadButton::Back) if self.screen == Screen::Paused => self.screen = Screen::Race,
                PadEvent::Pressed(PadButton::View) => self.drawing.view = self.drawing.view.next(),
                PadEvent::Pressed(_) => {}
            }
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
            self.control.pad_ui.push(egui::Event::Key { key, physical_key: None, pressed, repeat: false, modifiers });
        }
    }

    /// A key went down or up: a key Settings waits for is bound; otherwise Esc and the bound keys drive,
    /// pause and change the view, F3 shows the debug overlay, R N `[` `]` steer a replay and 1-5 pick the
    /// visibility method. Returns true to quit (Esc in the main menu or on a frozen replay).
    pub(super) fn key_event(&mut self, code: KeyCode, down: bool) -> bool {
        let name = crate::shell::keys::key_name(code);
        if let Some(action) = self.prefs.rebinding
            && down
        {
            self.rebind(action, code, &name);
            return false;
        }
        let keys = &mut self.control.keys;
        match (code, self.prefs.bindings.action(&name)) {
            (KeyCode::Escape, _) if down => match self.screen {
                Screen::Menu | Screen::Frozen => return true,
                Screen::Race | Screen::Paused => self.toggle_pause(),
            },
            (KeyCode::Enter, _) if down && self.screen == Screen::Menu => self.start_race(),
            (_, Some(Action::SteerLeft)) => keys.left = down,
            (_, Some(Action::SteerRight)) => keys.right = down,
            (_, Some(Action::Throttle)) => keys.throttle = down,
            (_, Some(Action::Brake)) => keys.brake = down,
            _ if !down => {}
            (_, Some(Action::ChangeView)) => self.drawing.view = self.drawing.view.next(),
            (_, Some(Action::Pause)) => self.toggle_pause(),
            (KeyCode::F3, _) => self.drawing.debug.visible = !self.drawing.debug.visible,
            (KeyCode::KeyR | KeyCode::KeyN | KeyCode::BracketLeft | KeyCode::BracketRight, _)
                if self.control.replaying() =>
            {
                self.replay_key(code);
            }
            _ => {
                if let Some(m) = method_key(code) {
                    self.drawing.options.method = m;
                }
            }
        }
        false
    }

    /// R restarts the replay, N steps one tick while paused, `[` and `]` halve and double its speed.
    fn replay_key(&mut self, code: KeyCode) {
        let clock = &mut self.clock;
        match code {
            KeyCode::KeyR => {
                if let Some(path) = self.control.replay.as_ref().map(|r| r.path.clone())
                    && let Err(e) = self.start_replay(&path)
                {
                    self.notice = Some(e.to_string());
                }
            }
            KeyCode::KeyN if self.screen == Screen::Paused => clock.steps += 1,
            KeyCode::BracketLeft => clock.speed = (clock.speed * 0.5).max(0.25),
            KeyCode::BracketRight => clock.speed = (clock.speed * 2.0).min(16.0),
            _ => {}
        }
    }
}
