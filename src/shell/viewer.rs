//! The interactive window: draws a scene with the software renderer every frame and lets you fly around it.
//!
//! The race itself is not built yet; until it is, `play` opens this viewer on the built-in demo scene (or any
//! glTF file). It already does what the game's shell will do: a winit window, softbuffer presentation, an
//! internal resolution below the window's with nearest (integer) upscaling, resizing down to 0x0 and back,
//! fullscreen, and a one-line error when there is no display.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::Instant;

use glam::{Mat4, Vec3};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, KeyEvent, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Fullscreen, Window, WindowId};

use crate::asset::LoadedScene;
use crate::render::{Camera, Method, Projection, RenderOptions, Renderer};

/// The hint printed when no window can be opened.
pub const HEADLESS_HINT: &str = "for headless frames use: scanline-racer render SCENE.gltf --out frame.png";

/// Why the window could not run.
#[derive(Debug, thiserror::Error)]
pub enum ShellError {
    /// No X11 or Wayland display could be reached.
    #[error("no display available ({reason}); {HEADLESS_HINT}")]
    NoDisplay {
        /// What winit reported.
        reason: String,
    },
    /// The window or its presentation surface failed.
    #[error("window: {0}")]
    Window(String),
    /// A screenshot could not be written.
    #[error(transparent)]
    Png(#[from] super::png::PngError),
}

/// What the viewer shows and how.
#[derive(Debug)]
pub struct ViewerConfig {
    /// The scene.
    pub scene: LoadedScene,
    /// Initial window size in physical pixels.
    pub size: (u32, u32),
    /// Start in fullscreen.
    pub fullscreen: bool,
    /// Window pixels per rendered pixel along each axis (1 = native resolution).
    pub scale: u32,
    /// Renderer settings.
    pub options: RenderOptions,
    /// Quit after this many presented frames (for tests and screenshots).
    pub exit_after_frames: Option<u64>,
    /// Write the last rendered frame here on exit.
    pub screenshot: Option<PathBuf>,
}

/// Keys that move the camera, held or not.
#[derive(Debug, Default)]
struct Held {
    forward: bool,
    back: bool,
    left: bool,
    right: bool,
    up: bool,
    down: bool,
}

struct Viewer {
    config: ViewerConfig,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    renderer: Renderer,
    frame: Vec<u32>,
    frame_size: (usize, usize),
    position: Vec3,
    yaw: f32,
    pitch: f32,
    speed: f32,
    projection: Projection,
    held: Held,
    last: Instant,
    title_at: Instant,
    frames: u64,
    frame_ms: f64,
    error: Option<ShellError>,
}

/// Opens the window and runs until it is closed.
pub fn run(config: ViewerConfig) -> Result<(), ShellError> {
    let event_loop = EventLoop::new().map_err(|e| ShellError::NoDisplay { reason: plain_reason(&e.to_string()) })?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let aspect = config.size.0 as f32 / config.size.1.max(1) as f32;
    let start = config.scene.cameras.first().map_or_else(|| config.scene.framing_camera(aspect), |c| c.camera);
    let (position, yaw, pitch) = pose_of(&start);
    let radius = config.scene.bounds.map_or(10.0, |(lo, hi)| (hi - lo).length().max(1.0));
    let now = Instant::now();
    let mut viewer = Viewer {
        window: None,
        surface: None,
        renderer: Renderer::new(),
        frame: Vec::new(),
        frame_size: (0, 0),
        position,
        yaw,
        pitch,
        speed: radius * 0.3,
        projection: start.projection,
        held: Held::default(),
        last: now,
        title_at: now,
        frames: 0,
        frame_ms: 0.0,
        error: None,
        config,
    };
    // winit panics inside its X11 backend when the display connection breaks mid-run; report that as an
    // error like any other instead of a panic message (the default hook is restored right after).
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| event_loop.run_app(&mut viewer)));
    std::panic::set_hook(hook);
    match ran {
        Ok(result) => result.map_err(|e| ShellError::Window(e.to_string()))?,
        Err(_) => return Err(ShellError::Window("the display connection failed".into())),
    }
    match viewer.error.take() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

/// Eye position, yaw (radians, 0 = looking down -Z, positive turns right) and pitch of a camera.
fn pose_of(camera: &Camera) -> (Vec3, f32, f32) {
    let eye = camera.view.inverse();
    let forward = -eye.z_axis.truncate().normalize_or(Vec3::NEG_Z);
    (eye.w_axis.truncate(), forward.x.atan2(-forward.z), forward.y.clamp(-1.0, 1.0).asin())
}

/// The view matrix of an eye at `position` with `yaw` and `pitch`, no roll.
fn view_of(position: Vec3, yaw: f32, pitch: f32) -> Mat4 {
    let dir = Vec3::new(yaw.sin() * pitch.cos(), pitch.sin(), -yaw.cos() * pitch.cos());
    let view = glam::camera::rh::view::look_to_mat4(position, dir, Vec3::Y);
    if view.is_finite() { view } else { Mat4::IDENTITY }
}

/// winit's message without the source location it prefixes ("os error at path/file.rs:123: ...").
fn plain_reason(s: &str) -> String {
    let reason = match s.split_once(".rs:") {
        Some((_, rest)) => rest.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start_matches(':').trim(),
        None => s,
    };
    reason.trim_end_matches('.').to_string()
}

impl Viewer {
    fn camera(&self) -> Camera {
        Camera { view: view_of(self.position, self.yaw, self.pitch), projection: self.projection }
    }

    fn step_camera(&mut self, dt: f32) {
        let h = &self.held;
        let turn = 1.6 * dt;
        if h.left {
            self.yaw -= turn;
        }
        if h.right {
            self.yaw += turn;
        }
        let ahead = Vec3::new(self.yaw.sin(), 0.0, -self.yaw.cos());
        let mut motion = Vec3::ZERO;
        if h.forward {
            motion += ahead;
        }
        if h.back {
            motion -= ahead;
        }
        if h.up {
            motion += Vec3::Y;
        }
        if h.down {
            motion -= Vec3::Y;
        }
        self.position += motion * self.speed * dt;
    }

    fn fail(&mut self, event_loop: &ActiveEventLoop, e: ShellError) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = (now - self.last).as_secs_f32().min(0.1);
        self.last = now;
        self.step_camera(dt);
        let (Some(window), Some(mut surface)) = (self.window.clone(), self.surface.take()) else {
            return;
        };
        let result = self.draw(&window, &mut surface);
        self.surface = Some(surface);
        match result {
            Ok(true) => {}
            Ok(false) => return,
            Err(e) => return self.fail(event_loop, e),
        }
        if self.config.exit_after_frames.is_some_and(|n| self.frames >= n) {
            if let Some(path) = self.config.screenshot.clone() {
                let (fw, fh) = self.frame_size;
                if let Err(e) = super::png::write_png(&path, &self.frame, fw, fh) {
                    return self.fail(event_loop, e.into());
                }
            }
            event_loop.exit();
        }
    }

    /// Renders and presents one frame; `Ok(false)` when the window has no area.
    fn draw(
        &mut self,
        window: &Window,
        surface: &mut softbuffer::Surface<Rc<Window>, Rc<Window>>,
    ) -> Result<bool, ShellError> {
        let now = self.last;
        let size = window.inner_size();
        // Minimised or resized to nothing: draw nothing, keep running.
        let (Some(ww), Some(wh)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(false);
        };
        surface.resize(ww, wh).map_err(|e| ShellError::Window(e.to_string()))?;
        let scale = self.config.scale.max(1);
        let (fw, fh) = (size.width.div_ceil(scale) as usize, size.height.div_ceil(scale) as usize);
        if self.frame_size != (fw, fh) {
            self.frame = vec![0; fw * fh];
            self.frame_size = (fw, fh);
        }
        let camera = self.camera();
        let t = Instant::now();
        let stats = self
            .renderer
            .render(&mut self.frame, fw, fh, &camera, &self.config.scene.draw_list(), &self.config.options)
            .map_err(|e| ShellError::Window(e.to_string()))?;
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * t.elapsed().as_secs_f64() * 1e3;
        let mut buffer = surface.buffer_mut().map_err(|e| ShellError::Window(e.to_string()))?;
        let (bw, s) = (size.width as usize, scale as usize);
        for (y, row) in buffer.chunks_mut(bw).enumerate() {
            let src = &self.frame[(y / s) * fw..(y / s) * fw + fw];
            for (x, px) in row.iter_mut().enumerate() {
                *px = src[(x / s).min(fw - 1)];
            }
        }
        buffer.present().map_err(|e| ShellError::Window(e.to_string()))?;
        self.frames += 1;
        if now.duration_since(self.title_at).as_secs_f32() > 0.5 {
            self.title_at = now;
            window.set_title(&format!(
                "scanline-racer — {} — {:.1} ms/frame — {} of {} polygons — {fw}x{fh}",
                self.config.options.method, self.frame_ms, stats.polygons_drawn, stats.polygons_in
            ));
        }
        Ok(true)
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, event: &KeyEvent) {
        let PhysicalKey::Code(code) = event.physical_key else {
            return;
        };
        let down = event.state == ElementState::Pressed;
        match code {
            KeyCode::ArrowUp | KeyCode::KeyW => self.held.forward = down,
            KeyCode::ArrowDown | KeyCode::KeyS => self.held.back = down,
            KeyCode::ArrowLeft | KeyCode::KeyA => self.held.left = down,
            KeyCode::ArrowRight | KeyCode::KeyD => self.held.right = down,
            KeyCode::KeyE | KeyCode::PageUp => self.held.up = down,
            KeyCode::KeyQ | KeyCode::PageDown => self.held.down = down,
            _ if !down => {}
            KeyCode::Escape => event_loop.exit(),
            KeyCode::Digit1 => self.config.options.method = Method::ZBuffer,
            KeyCode::Digit2 => self.config.options.method = Method::Sort,
            KeyCode::Digit3 => self.config.options.method = Method::BucketFar,
            KeyCode::Digit4 => self.config.options.method = Method::BucketNear,
            KeyCode::Equal => self.config.scale = (self.config.scale + 1).min(8),
            KeyCode::Minus => self.config.scale = self.config.scale.saturating_sub(1).max(1),
            KeyCode::F11 | KeyCode::KeyF => {
                if let Some(w) = &self.window {
                    w.set_fullscreen(if w.fullscreen().is_some() { None } else { Some(Fullscreen::Borderless(None)) });
                }
            }
            _ => {}
        }
    }
}

impl ApplicationHandler for Viewer {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = self.config.size;
        let mut attrs =
            Window::default_attributes().with_title("scanline-racer").with_inner_size(PhysicalSize::new(w, h));
        if self.config.fullscreen {
            attrs = attrs.with_fullscreen(Some(Fullscreen::Borderless(None)));
        }
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Rc::new(w),
            Err(e) => return self.fail(event_loop, ShellError::Window(e.to_string())),
        };
        let surface =
            softbuffer::Context::new(window.clone()).and_then(|c| softbuffer::Surface::new(&c, window.clone()));
        match surface {
            Ok(s) => self.surface = Some(s),
            Err(e) => return self.fail(event_loop, ShellError::Window(e.to_string())),
        }
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. } => self.key(event_loop, &event),
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pose_round_trips_the_start_camera() {
        let start = Camera::look_at(Vec3::new(3.0, 3.0, 8.0), Vec3::new(0.0, 0.5, -3.0), 0.9, 0.1, None);
        let (position, yaw, pitch) = pose_of(&start);
        let view = view_of(position, yaw, pitch);
        eprintln!("{position} {yaw} {pitch}\n{view}\n{}", start.view);
        assert!((view - start.view).abs().to_cols_array().iter().all(|d| *d < 1e-4));
    }
}
