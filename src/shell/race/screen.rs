//! What the race shows and how its frames are drawn: the two parts of the session that several of its
//! concerns share.
//!
//! The keys, the pad and the menus move between screens, Settings edits the drawing options and the view,
//! and the HUD shows them. Kept here, below every concern, each concern takes the parts it needs as
//! arguments instead of reaching back into the whole race (`Race` in `race/mod.rs`, which holds them).

use std::time::Instant;

use crate::render::{Antialias, Filter, MipMode, Quality, RenderOptions, Renderer};
use crate::shell::auto_quality::AutoQuality;
use crate::shell::debug_overlay::DebugOverlay;
use crate::shell::race_scene::View;
use crate::shell::settings::Settings;

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
    /// The `auto` quality controller, when the picture follows the frame time.
    pub(super) auto: Option<AutoQuality>,
    /// The picture the player fixed (what the settings file keeps while `auto` changes the options).
    pub(super) fixed: Picture,
    /// The frame period `auto` budgets against (ms), from the window's pacing.
    pub(super) period_ms: f64,
    /// When the last frame was drawn (for `auto`'s durations).
    pub(super) last_frame: Option<Instant>,
}

/// The picture choices the settings file keeps: anti-aliasing, texture filter, mip levels, and whether
/// `auto` picks them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Picture {
    /// Anti-aliasing.
    pub(super) antialias: Antialias,
    /// Texture filter.
    pub(super) filter: Filter,
    /// Mip levels.
    pub(super) mip: MipMode,
    /// Level-of-detail cross-fades.
    pub(super) lod_fade: bool,
    /// Level-of-detail bias.
    pub(super) lod_bias: f32,
    /// Mip bias.
    pub(super) mip_bias: f32,
    /// Whether `auto` quality is on.
    pub(super) auto: bool,
}

impl Picture {
    /// `settings` with this picture in it.
    pub(super) fn into_settings(self, settings: Settings) -> Settings {
        Settings {
            antialias: self.antialias,
            filter: self.filter,
            mip: self.mip,
            lod_fade: self.lod_fade,
            lod_bias: self.lod_bias,
            mip_bias: self.mip_bias,
            auto_quality: self.auto,
            ..settings
        }
    }
}

/// The step `auto` starts at: the second from the top, from which a machine with room reaches the top in
/// a few seconds and one without steps down within one.
pub(super) const AUTO_START: Quality = Quality::High;

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
            auto: None,
            fixed: Picture {
                antialias: options.antialias,
                filter: options.filter,
                mip: options.mip,
                lod_fade: options.lod_fade,
                lod_bias: options.lod_bias,
                mip_bias: options.mip_bias,
                auto: false,
            },
            period_ms: crate::shell::pacing::Pacing::Uncapped.budget_period_ms(),
            last_frame: None,
        }
    }

    /// Turns `auto` quality on (starting at [`AUTO_START`]) or off (keeping the step in use, which becomes
    /// the fixed picture).
    pub(super) fn set_auto(&mut self, on: bool) {
        match (on, self.auto.is_some()) {
            (true, false) => {
                self.fixed = Picture { auto: false, ..self.picture() };
                self.auto = Some(AutoQuality::new(AUTO_START));
                self.options = AUTO_START.apply(self.options);
            }
            (false, true) => self.auto = None,
            _ => {}
        }
    }

    /// The picture to save: the options' own when fixed, the player's fixed one under `auto`.
    pub(super) fn picture(&self) -> Picture {
        match self.auto {
            Some(_) => Picture { auto: true, ..self.fixed },
            None => Picture {
                antialias: self.options.antialias,
                filter: self.options.filter,
                mip: self.options.mip,
                lod_fade: self.options.lod_fade,
                lod_bias: self.options.lod_bias,
                mip_bias: self.options.mip_bias,
                auto: false,
            },
        }
    }

    /// Takes a frame that took `ms` to draw: under `auto`, the step it calls for goes into the options.
    pub(super) fn frame_drawn(&mut self, ms: f64) {
        let now = Instant::now();
        let seconds = self.last_frame.map_or(0.0, |t| now.duration_since(t).as_secs_f64());
        self.last_frame = Some(now);
        if let Some(step) = self.auto.as_mut().and_then(|a| a.frame(ms, seconds, self.period_ms)) {
            self.options = step.apply(self.options);
        }
    }

    /// The quality in use as the HUD and F3 say it: `high (auto)`, `medium`, or `custom`.
    pub(super) fn quality_label(&self) -> String {
        match (&self.auto, Quality::of(&self.options)) {
            (Some(a), _) => format!("{} (auto)", a.step()),
            (None, Some(q)) => q.name().to_string(),
            (None, None) => "custom".to_string(),
        }
    }
}
