//! What the race shows and how its frames are drawn: the two parts of the session that several of its
//! concerns share.
//!
//! The keys, the pad and the menus move between screens, Settings edits the drawing options and the view,
//! and the HUD shows them. Kept here, below every concern, each concern takes the parts it needs as
//! arguments instead of reaching back into the whole race (`Race` in `race/mod.rs`, which holds them).

use crate::render::{RenderOptions, Renderer};
use crate::shell::debug_overlay::DebugOverlay;
use crate::shell::race_scene::View;

/// Which screen the race shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Screen {
    /// The main menu over the grid (nothing moves).
    Menu,
    /// Racing.
    Race,
    /// The pause menu (nothing moves).
    Paused,
    /// A replay stopped at its `--stop-at` tick: the frame stays, nothing moves, no menu.
    Frozen,
    /// The car select: the chosen car turning on its own, drawn at its close model, with its figures.
    Garage,
}

/// How frames are drawn.
pub(super) struct Drawing {
    /// The renderer, which keeps its level-of-detail choices between frames.
    pub(super) renderer: Renderer,
    /// The renderer's options (Settings and the 1-5 keys change them).
    pub(super) options: RenderOptions,
    /// The camera the race is seen from.
    pub(super) view: View,
    /// The frame time, smoothed, for the HUD.
    pub(super) frame_ms: f64,
    /// The F3 window.
    pub(super) debug: DebugOverlay,
    /// Whether menus and HUD are drawn over the race.
    pub(super) hud: bool,
}

impl Drawing {
    /// How a race's frames are drawn at first: with `options`, from close behind the player's car, with
    /// the menus and HUD over it and the debug overlay hidden.
    pub(super) fn new(options: RenderOptions) -> Self {
        Self {
            renderer: Renderer::new(),
            options,
            view: View::ChaseNear,
            frame_ms: 0.0,
            debug: DebugOverlay::default(),
            hud: true,
        }
    }
}
