//! The race in the window: the simulation fed at a fixed tick from the real clock, the keyboard as the
//! player's controls, chase, bumper and trackside cameras, and the cars drawn at their levels of detail.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use winit::keyboard::KeyCode;

use super::window::{Content, ShellError, method_key};
use crate::asset::{AssetError, LoadedScene, load};
use crate::game::rules::{Phase, format_ticks};
use crate::game::{Controls, DT, Track, World, step};
use crate::render::{Camera, DrawList, Instance, Method, RenderOptions, Renderer, TextureMode};

/// Most simulated time one frame may catch up after a stall (the game slows down instead of jumping).
const MAX_CATCH_UP: f64 = 0.25;
/// Number of cars in a race.
pub const FIELD: usize = 8;

/// Where the shipped assets are: `$SCANLINE_RACER_ASSETS`, `./assets`, or beside the executable's build tree.
#[must_use]
pub fn find_assets() -> Option<PathBuf> {
    let mut candidates: Vec<PathBuf> =
        std::env::var_os("SCANLINE_RACER_ASSETS").map(PathBuf::from).into_iter().collect();
    candidates.push(PathBuf::from("assets"));
    if let Ok(exe) = std::env::current_exe() {
        // target/release/scanline-racer -> ../../assets
        if let Some(root) = exe.parent().and_then(Path::parent).and_then(Path::parent) {
            candidates.push(root.join("assets"));
        }
    }
    candidates.into_iter().find(|p| p.join("track/circuit.gltf").is_file())
}

/// The circuit and the cars, loaded and merged into one scene.
pub struct RaceScene {
    scene: LoadedScene,
    statics: usize,
    car_sets: Vec<usize>,
    track: Arc<Track>,
}

impl RaceScene {
    /// Loads `track/circuit.gltf`, `track/centerline.json` and `cars/car_N.gltf` from `dir`.
    pub fn load(dir: &Path) -> Result<Self, AssetError> {
        let mut scene = load(&dir.join("track/circuit.gltf"))?;
        let statics = scene.instances.len();
        let mut car_sets = vec![];
        for n in 1..=FIELD {
            let car = load(&dir.join(format!("cars/car_{n}.gltf")))?;
            let first = scene.append(LoadedScene { instances: vec![], cameras: vec![], ..car });
            car_sets.push(first);
        }
        let line = dir.join("track/centerline.json");
        let text = std::fs::read_to_string(&line)
            .map_err(|e| AssetError::Read { file: line.display().to_string(), reason: e.to_string() })?;
        let track = Track::from_json(&text)
            .map_err(|e| AssetError::Scene { file: line.display().to_string(), reason: e.to_string() })?;
        scene.instances.truncate(statics);
        Ok(Self { scene, statics, car_sets, track: Arc::new(track) })
    }
}

/// Camera placements, switched with C (as Virtua Racing's view buttons).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum View {
    ChaseNear,
    ChaseFar,
    Bumper,
    Trackside,
}

/// Which screen the race shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Screen {
    /// The main menu over the grid (nothing moves).
    Menu,
    /// Racing.
    Race,
    /// The pause menu (nothing moves).
    Paused,
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
        }
    }

    fn camera(&self) -> Camera {
        let car = &self.world.cars[0];
        let p = car.position3();
        let f = car.forward();
        let fwd = Vec3::new(f.x, 0.0, f.y);
        let (eye, target, yfov) = match self.view {
            View::ChaseNear => (p - fwd * 6.5 + Vec3::Y * 2.3, p + fwd * 6.0 + Vec3::Y * 0.8, 0.95),
            View::ChaseFar => (p - fwd * 12.0 + Vec3::Y * 4.0, p + fwd * 8.0 + Vec3::Y * 0.8, 0.85),
            View::Bumper => (p + fwd * 0.6 + Vec3::Y * 0.9, p + fwd * 20.0 + Vec3::Y * 0.7, 1.05),
            View::Trackside => {
                // The nearest of a camera every 150 m, just behind the right-hand barrier, 6 m up.
                let s = (car.loc.s / 150.0).round() * 150.0 + 60.0;
                let (pos, _) = self.world.track.point_at(s, car.loc.barrier[1] + 2.0);
                (pos + Vec3::Y * 6.0, p + Vec3::Y * 0.6, 0.5)
            }
        };
        Camera::look_at(eye, target, yfov, 0.3, None)
    }

    /// A fresh start on the grid with the current number of laps.
    fn restart(&mut self) {
        self.world = World::with_laps(self.scene.track.clone(), FIELD, self.laps);
        self.accumulator = 0.0;
        self.keys = Keys::default();
        self.renderer.reset_lod();
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
        if self.screen != Screen::Race {
            return;
        }
        self.accumulator = (self.accumulator + dt).min(MAX_CATCH_UP);
        while self.accumulator >= f64::from(DT) {
            self.accumulator -= f64::from(DT);
            let c = self.keys.controls();
            step(&mut self.world, &c);
        }
    }

    fn key(&mut self, code: KeyCode, down: bool) -> bool {
        match code {
            KeyCode::Escape if down => match self.screen {
                Screen::Menu => return true,
                Screen::Race => self.screen = Screen::Paused,
                Screen::Paused => self.screen = Screen::Race,
            },
            KeyCode::Enter if down && self.screen == Screen::Menu => self.screen = Screen::Race,
            KeyCode::ArrowLeft | KeyCode::KeyA => self.keys.left = down,
            KeyCode::ArrowRight | KeyCode::KeyD => self.keys.right = down,
            KeyCode::ArrowUp | KeyCode::KeyW => self.keys.throttle = down,
            KeyCode::ArrowDown | KeyCode::KeyS => self.keys.brake = down,
            _ if !down => {}
            KeyCode::KeyC => {
                self.view = match self.view {
                    View::ChaseNear => View::ChaseFar,
                    View::ChaseFar => View::Bumper,
                    View::Bumper => View::Trackside,
                    View::Trackside => View::ChaseNear,
                };
            }
            KeyCode::F3 => self.debug.visible = !self.debug.visible,
            KeyCode::KeyP => {
                self.screen = match self.screen {
                    Screen::Race => Screen::Paused,
                    Screen::Paused => Screen::Race,
                    Screen::Menu => Screen::Menu,
                };
            }
            _ => {
                if let Some(m) = method_key(code) {
                    self.options.method = m;
                }
            }
        }
        false
    }

    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError> {
        let mut instances: Vec<Instance> = self.scene.scene.instances[..self.scene.statics].to_vec();
        for (i, car) in self.world.cars.iter().enumerate() {
            let model = Mat4::from_translation(car.position3()) * Mat4::from_rotation_y(-car.yaw);
            instances.push(Instance::of_lod_set(self.scene.car_sets[i % self.scene.car_sets.len()], model));
        }
        let list = DrawList {
            meshes: &self.scene.scene.meshes,
            textures: &self.scene.scene.textures,
            instances: &instances,
            lod_sets: &self.scene.scene.lod_sets,
        };
        let t = std::time::Instant::now();
        let stats = self.renderer.render(frame, width, height, &self.camera(), &list, &self.options)?;
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

    fn ui(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
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
                            if ui.button("Race").clicked() {
                                self.screen = Screen::Race;
                            }
                            if ui.button("Settings").clicked() {
                                self.settings_open = !self.settings_open;
                            }
                            if ui.button("Quit").clicked() {
                                quit = true;
                            }
                        });
                        ui.label("Arrows steer, accelerate and brake; C changes the view; Esc pauses.");
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
            Screen::Race => {}
        }
        if self.settings_open && self.screen != Screen::Race {
            self.settings(ctx);
        }
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

impl Race {
    /// Rendering and view settings (from the main and pause menus).
    fn settings(&mut self, ctx: &egui::Context) {
        let mut open = true;
        egui::Window::new("Settings").open(&mut open).resizable(false).show(ctx, |ui| {
            egui::ComboBox::from_label("visibility method").selected_text(self.options.method.name()).show_ui(
                ui,
                |ui| {
                    for m in Method::ALL {
                        ui.selectable_value(&mut self.options.method, m, m.name());
                    }
                },
            );
            ui.add(egui::Slider::new(&mut self.options.buckets, 8..=65536).logarithmic(true).text("buckets"));
            ui.add(egui::Slider::new(&mut self.options.lod_bias, -3.0..=3.0).text("LOD bias"));
            egui::ComboBox::from_label("texture mapping")
                .selected_text(format!("{:?}", self.options.texture_mode))
                .show_ui(ui, |ui| {
                    for m in [TextureMode::Perspective, TextureMode::Subdivided, TextureMode::Affine] {
                        ui.selectable_value(&mut self.options.texture_mode, m, format!("{m:?}"));
                    }
                });
            egui::ComboBox::from_label("view").selected_text(format!("{:?}", self.view)).show_ui(ui, |ui| {
                for v in [View::ChaseNear, View::ChaseFar, View::Bumper, View::Trackside] {
                    ui.selectable_value(&mut self.view, v, format!("{v:?}"));
                }
            });
            ui.checkbox(&mut self.debug.visible, "debug overlay (F3)");
            ui.label("Internal resolution: '-' and '=' change the window pixels per rendered pixel.");
        });
        self.settings_open = open;
    }

    /// Speed, position, lap, times and the countdown.
    fn hud(&self, ctx: &egui::Context) {
        let race = &self.world.race;
        let me = &race.standings[0];
        let big = |t: String, size: f32| egui::RichText::new(t).size(size).strong().color(egui::Color32::WHITE);
        egui::Area::new(egui::Id::unique("hud-left")).anchor(egui::Align2::LEFT_TOP, [16.0, 12.0]).show(ctx, |ui| {
            ui.label(big(format!("P{} / {}", race.position(0), race.standings.len()), 30.0));
            ui.label(big(format!("LAP {} / {}", (me.laps + 1).min(race.laps), race.laps), 18.0));
            let now = if race.holding() { 0 } else { self.world.tick.saturating_sub(me.lap_start) };
            ui.label(big(format!("TIME {}", format_ticks(now)), 16.0));
            ui.label(big(format!("BEST {}", me.best_lap.map_or_else(|| "-:--.---".into(), format_ticks)), 16.0));
        });
        let since_green = self.world.tick.saturating_sub(race.start_tick);
        let banner = match race.phase {
            Phase::Countdown(left) => Some(format!("{}", left.div_ceil(u64::from(crate::game::TICK_HZ)))),
            Phase::Racing if since_green < u64::from(crate::game::TICK_HZ) => Some("GO!".to_string()),
            _ => None,
        };
        if let Some(text) = banner {
            egui::Area::new(egui::Id::unique("hud-countdown")).anchor(egui::Align2::CENTER_TOP, [0.0, 60.0]).show(
                ctx,
                |ui| {
                    ui.label(big(text, 64.0));
                },
            );
        }
        let car = &self.world.cars[0];
        egui::Area::new(egui::Id::unique("hud-speed")).anchor(egui::Align2::RIGHT_BOTTOM, [-16.0, -12.0]).show(
            ctx,
            |ui| {
                ui.label(big(format!("{:.0} km/h", car.speed().abs() * 3.6), 28.0));
                ui.add(
                    egui::ProgressBar::new((car.speed().abs() / self.world.params.top_speed).clamp(0.0, 1.0))
                        .desired_width(180.0),
                );
            },
        );
        egui::Area::new(egui::Id::unique("hud-debug")).anchor(egui::Align2::LEFT_BOTTOM, [12.0, -8.0]).show(
            ctx,
            |ui| {
                ui.label(
                    egui::RichText::new(format!(
                        "{:?} view — {} — {:.1} ms/frame",
                        self.view, self.options.method, self.frame_ms
                    ))
                    .size(12.0)
                    .color(egui::Color32::from_gray(230)),
                );
            },
        );
    }

    /// The results table; returns true to quit.
    fn results(&mut self, ctx: &egui::Context) -> bool {
        let mut quit = false;
        let race = self.world.race.clone();
        egui::Window::new("Results")
            .anchor(egui::Align2::CENTER_CENTER, [0.0, 0.0])
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
                egui::Grid::new("results").striped(true).show(ui, |ui| {
                    ui.strong("Pos");
                    ui.strong("Driver");
                    ui.strong("Best lap");
                    ui.end_row();
                    for (k, &car) in race.order().iter().enumerate() {
                        ui.label(format!("{}", k + 1));
                        ui.label(if car == 0 { "You".to_string() } else { format!("Car {}", car + 1) });
                        ui.label(race.standings[car].best_lap.map_or_else(|| "-".into(), format_ticks));
                        ui.end_row();
                    }
                });
                ui.horizontal(|ui| {
                    if ui.button("Race again").clicked() {
                        self.restart();
                        self.screen = Screen::Race;
                    }
                    if ui.button("Main menu").clicked() {
                        self.restart();
                        self.screen = Screen::Menu;
                    }
                    if ui.button("Quit").clicked() {
                        quit = true;
                    }
                });
            });
        quit
    }
}
