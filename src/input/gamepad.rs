//! Gamepads through gilrs: analog steering, throttle and brake with a radial deadzone and a response curve,
//! buttons for the menus, hot-plug, and a signal when the active pad is unplugged (the race pauses).
//!
//! No gamepad, or no permission to read input devices, is not an error: `Gamepads::new` then has no
//! backend and everything is driven from the keyboard. SDL game-controller mappings are honoured (gilrs
//! reads `SDL_GAMECONTROLLERCONFIG`). gilrs's own filters are off; the deadzone here is radial (the stick's
//! distance from centre, not each axis on its own) and configurable.

use gilrs::{Axis, Button, EventType, GamepadId, Gilrs, GilrsBuilder};

use crate::game::Controls;

/// The default radial deadzone, about what gilrs itself uses.
pub const DEFAULT_DEADZONE: f32 = 0.1;
/// The default response-curve exponent for steering (1 = linear; larger is finer near the centre).
pub const DEFAULT_CURVE: f32 = 1.6;

/// Shapes a stick position: a radial deadzone rescaled so output starts at 0 at its edge and reaches 1 at
/// full travel, then a power curve on the magnitude. NaN input gives the centre.
#[must_use]
pub fn shape_stick(x: f32, y: f32, deadzone: f32, curve: f32) -> (f32, f32) {
    let r = (x * x + y * y).sqrt();
    if !r.is_finite() || r <= deadzone {
        return (0.0, 0.0);
    }
    let dz = deadzone.clamp(0.0, 0.95);
    let t = libm::powf(((r.min(1.0) - dz) / (1.0 - dz)).clamp(0.0, 1.0), curve.clamp(0.2, 5.0));
    (x / r * t, y / r * t)
}

/// A trigger value with a small deadzone, 0 to 1.
#[must_use]
pub fn shape_trigger(v: f32, deadzone: f32) -> f32 {
    if !v.is_finite() || v <= deadzone { 0.0 } else { ((v - deadzone) / (1.0 - deadzone)).clamp(0.0, 1.0) }
}

/// A button press the game reacts to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PadButton {
    /// Confirm / start (A, Cross).
    Confirm,
    /// Pause (Start).
    Pause,
    /// Change the view (Y, Triangle).
    View,
    /// Back (B, Circle).
    Back,
    /// Menu focus up (D-pad up).
    Up,
    /// Menu focus down (D-pad down).
    Down,
}

/// What happened to the gamepads since the last poll.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PadEvent {
    /// A pad was plugged in (it becomes active if none was).
    Connected {
        /// The pad's name, as its driver or SDL mapping gives it.
        name: String,
    },
    /// The active pad was unplugged.
    ActiveDisconnected,
    /// A button was pressed on the active pad.
    Pressed(PadButton),
}

/// The gamepads and the active pad's analog state.
pub struct Gamepads {
    gilrs: Option<Gilrs>,
    active: Option<GamepadId>,
    stick: (f32, f32),
    throttle: f32,
    brake: f32,
    /// Radial deadzone of the steering stick.
    pub deadzone: f32,
    /// Steering response-curve exponent.
    pub curve: f32,
}

impl Default for Gamepads {
    fn default() -> Self {
        Self::new()
    }
}

impl Gamepads {
    /// Opens the gamepad backend; without one (no devices, no permission) the game is keyboard-only.
    #[must_use]
    pub fn new() -> Self {
        let gilrs = GilrsBuilder::new().with_default_filters(false).build().ok();
        let active = gilrs.as_ref().and_then(|g| g.gamepads().next().map(|(id, _)| id));
        Self {
            gilrs,
            active,
            stick: (0.0, 0.0),
            throttle: 0.0,
            brake: 0.0,
            deadzone: DEFAULT_DEADZONE,
            curve: DEFAULT_CURVE,
        }
    }

    /// True when a pad is connected and active.
    #[must_use]
    pub fn active(&self) -> bool {
        self.active.is_some()
    }

    /// How the active pad's maker labels its buttons (the Xbox names without an active pad).
    #[must_use]
    pub fn style(&self) -> super::pad_names::PadStyle {
        let vendor = match (&self.gilrs, self.active) {
            (Some(g), Some(id)) => g.connected_gamepad(id).and_then(|pad| pad.vendor_id()),
            _ => None,
        };
        super::pad_names::PadStyle::of_vendor(vendor)
    }

    /// True when the backend could not be opened (the UI says so: keyboard only).
    #[must_use]
    pub fn unavailable(&self) -> bool {
        self.gilrs.is_none()
    }

    /// Reads pending events: connections, the active pad's axes and button presses.
    pub fn poll(&mut self) -> Vec<PadEvent> {
        let mut out = vec![];
        let Some(g) = self.gilrs.as_mut() else {
            return out;
        };
        while let Some(ev) = g.next_event() {
            match ev.event {
                EventType::Connected => {
                    let name = g.gamepad(ev.id).name().to_string();
                    if self.active.is_none() {
                        self.active = Some(ev.id);
                    }
                    out.push(PadEvent::Connected { name });
                }
                EventType::Disconnected if self.active == Some(ev.id) => {
                    self.active = g.gamepads().map(|(id, _)| id).find(|&id| id != ev.id);
                    self.stick = (0.0, 0.0);
                    self.throttle = 0.0;
                    self.brake = 0.0;
                    out.push(PadEvent::ActiveDisconnected);
                }
                _ if self.active != Some(ev.id) => {}
                EventType::AxisChanged(Axis::LeftStickX, v, _) => self.stick.0 = v,
                EventType::AxisChanged(Axis::LeftStickY, v, _) => self.stick.1 = v,
                EventType::ButtonChanged(Button::RightTrigger2, v, _) => self.throttle = v,
                EventType::ButtonChanged(Button::LeftTrigger2, v, _) => self.brake = v,
                EventType::ButtonPressed(b, _) => {
                    let mapped = match b {
                        Button::South => Some(PadButton::Confirm),
                        Button::Start => Some(PadButton::Pause),
                        Button::North => Some(PadButton::View),
                        Button::East => Some(PadButton::Back),
                        Button::DPadUp => Some(PadButton::Up),
                        Button::DPadDown => Some(PadButton::Down),
                        _ => None,
                    };
                    out.extend(mapped.map(PadEvent::Pressed));
                }
                _ => {}
            }
        }
        out
    }

    /// The active pad's controls (left stick steers, right trigger accelerates, left trigger brakes), or
    /// `None` without an active pad.
    #[must_use]
    pub fn controls(&self) -> Option<Controls> {
        self.active?;
        let (steer, _) = shape_stick(self.stick.0, self.stick.1, self.deadzone, self.curve);
        Some(Controls { steer, throttle: shape_trigger(self.throttle, 0.05), brake: shape_trigger(self.brake, 0.05) })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radial_deadzone_and_curve() {
        assert_eq!(shape_stick(0.09, 0.0, 0.1, 1.0), (0.0, 0.0));
        assert_eq!(shape_stick(0.07, 0.07, 0.1, 1.0), (0.0, 0.0), "radial: inside the circle on a diagonal");
        let (x, _) = shape_stick(1.0, 0.0, 0.1, 1.0);
        assert!((x - 1.0).abs() < 1e-6);
        let (x, _) = shape_stick(0.55, 0.0, 0.1, 1.0);
        assert!((x - 0.5).abs() < 1e-6, "rescaled from the deadzone edge: {x}");
        let (lin, _) = shape_stick(0.55, 0.0, 0.1, 1.0);
        let (curved, _) = shape_stick(0.55, 0.0, 0.1, 2.0);
        assert!(curved < lin, "the curve is finer near the centre");
        assert_eq!(shape_stick(f32::NAN, 0.5, 0.1, 1.0), (0.0, 0.0));
        let (x, y) = shape_stick(-3.0, 0.0, 0.25, 1.6);
        assert!((x + 1.0).abs() < 1e-6 && y == 0.0, "past full travel is full lock");
        assert_eq!(shape_trigger(0.03, 0.05), 0.0);
        assert_eq!(shape_trigger(1.0, 0.05), 1.0);
        assert_eq!(shape_trigger(f32::NAN, 0.05), 0.0);
    }

    #[test]
    fn no_backend_means_keyboard_only() {
        // Whatever this machine has, construction never fails and an absent pad gives no controls.
        let pads = Gamepads::new();
        if !pads.active() {
            assert_eq!(pads.controls(), None);
        }
    }
}
