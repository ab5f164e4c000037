//! The race as the window shows it: its frame, its UI (the menus, Settings, the HUD) and carrying out what
//! the player chose in them.

use winit::keyboard::KeyCode;

use super::hud;
use super::menus::{self, Choice};
use super::screen::Screen;
use super::session::Race;
use crate::game::rules::Phase;
use crate::input::ghost::GhostLap;
use crate::shell::window::{Content, ShellError};

impl Race {
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
                Choice::Setup(setup) => {
                    self.setup = setup;
                    self.restart();
                }
                Choice::Course(name) => self.change_course(&name),
                Choice::Garage => self.screen = Screen::Garage,
                Choice::Back => self.screen = Screen::Menu,
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
        if self.screen == Screen::Garage {
            // A turn every 12 s.
            self.showroom = (self.showroom + dt as f32 * std::f32::consts::TAU / 12.0) % std::f32::consts::TAU;
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
        let stats = if self.screen == Screen::Garage {
            let car = self.setup.car;
            self.scene.render_showroom(&mut d.renderer, (car, self.showroom), &d.options, (frame, width, height))?
        } else {
            let size = (frame, width, height);
            self.scene.render_with_ghost(&mut d.renderer, &self.world, d.view, &d.options, size, ghost)?
        };
        let ms = t.elapsed().as_secs_f64() * 1e3;
        d.frame_ms = 0.9 * d.frame_ms + 0.1 * ms;
        d.debug.quality = Some(d.quality_label());
        // After the F3 record: the log's line names the step this frame was drawn at.
        let occupancy = if d.debug.visible { d.renderer.bucket_occupancy() } else { Vec::new() };
        d.debug.record(ms, &stats, occupancy);
        d.frame_drawn(ms);
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

    fn pacing(&mut self, pacing: crate::shell::window::Pacing) {
        self.drawing.debug.pacing = Some(pacing);
        self.drawing.period_ms = pacing.budget_period_ms();
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
        let top = self.trials.top(&self.scene.course);
        let chose = match self.screen {
            Screen::Menu => self.menu.main_menu(
                ctx,
                menus::Offer {
                    courses: self.courses.as_ref().map_or(&[][..], |(_, list)| list.as_slice()),
                    course: &self.scene.course,
                    setup: &self.setup,
                    top: &top,
                },
                &mut self.recording.to,
                self.notice.as_deref(),
                &self.prefs.bindings,
                self.control.pads.style(),
            ),
            Screen::Paused => menus::pause_menu(ctx),
            Screen::Garage => menus::garage(ctx, &self.setup),
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
        if !matches!(self.screen, Screen::Menu | Screen::Garage) {
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
        if self.world.race.phase == Phase::Finished
            && self.choose(menus::results(ctx, &self.world.race, &self.world.models))
        {
            quit = true;
        }
        quit
    }
}
