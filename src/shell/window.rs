//! The window: winit events, softbuffer presentation, integer upscaling, resizing to 0x0 and back,
//! fullscreen, screenshots, and the one-line error when there is no display.
//!
//! What is shown comes from a [`Content`]: the free-flying scene viewer or the race. The window knows
//! nothing of either; it hands the content the real time that passed and a frame buffer to draw into.

use std::num::NonZeroU32;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::{Duration, Instant};

use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::error::{EventLoopError, OsError};
use winit::event::{ElementState, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{KeyCode, PhysicalKey};
use winit::window::{Fullscreen, Window, WindowId};

pub use super::pacing::{FALLBACK_HZ, Pacing};

/// The hint printed when no window can be opened: the headless commands for a race and for a scene.
pub const HEADLESS_HINT: &str = "without a window use: scanline-racer replay TRACE --headless --frames DIR \
     (a race, e.g. assets/replays/demo-race.trace) or scanline-racer render SCENE.gltf --out frame.png";

/// Why the window could not run.
#[derive(Debug, thiserror::Error)]
pub enum ShellError {
    /// No X11 or Wayland display could be reached.
    #[error("no display available ({}); {HEADLESS_HINT}", plain_reason(&.0.to_string()))]
    NoDisplay(#[source] EventLoopError),
    /// The event loop failed while the window ran.
    #[error("window: {0}")]
    EventLoop(#[source] EventLoopError),
    /// The display connection broke while the window ran (winit's X11 backend panics then).
    #[error("window: the display connection failed")]
    DisplayLost,
    /// The window could not be created.
    #[error("window: {0}")]
    Create(#[source] OsError),
    /// The window's presentation surface failed at `step`.
    #[error("window: {step}: {source}")]
    Surface {
        /// What was being done with the surface.
        step: SurfaceStep,
        /// What softbuffer reported.
        source: softbuffer::SoftBufferError,
    },
    /// Drawing failed.
    #[error("render: {0}")]
    Render(#[from] crate::render::RenderError),
    /// A screenshot could not be written.
    #[error(transparent)]
    Image(#[from] super::image_file::ImageFileError),
}

/// What the window was doing with its presentation surface when it failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceStep {
    /// Making the surface for a new window.
    Create,
    /// Resizing it to the window.
    Resize,
    /// Taking its buffer to draw a frame into.
    Buffer,
    /// Showing the frame.
    Present,
}

impl std::fmt::Display for SurfaceStep {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            SurfaceStep::Create => "creating the drawing surface",
            SurfaceStep::Resize => "resizing the drawing surface",
            SurfaceStep::Buffer => "getting the frame buffer",
            SurfaceStep::Present => "presenting the frame",
        })
    }
}

/// The window's surface failed at `step`.
fn surface_error(step: SurfaceStep) -> impl FnOnce(softbuffer::SoftBufferError) -> ShellError {
    move |source| ShellError::Surface { step, source }
}

/// What a window shows: it is told the time and the keys, and draws frames.
pub trait Content {
    /// Advances by `dt` seconds of real time.
    fn update(&mut self, dt: f64);
    /// A key went down (`true`) or up; returns true to quit.
    fn key(&mut self, code: KeyCode, down: bool) -> bool;
    /// Draws every pixel of a `width` x `height` frame (which holds whatever was there before: at scale 1
    /// it is the window's own buffer); returns a short status for the title bar.
    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError>;
    /// Lays out menus and HUD for this frame; returns true to quit.
    fn ui(&mut self, _ctx: &egui::Context) -> bool {
        false
    }
    /// Extra input for the UI (a gamepad's menu navigation, as key presses).
    fn ui_events(&mut self) -> Vec<egui::Event> {
        Vec::new()
    }
    /// How the window times its frames (told once the window is open).
    fn pacing(&mut self, _pacing: Pacing) {}
    /// The window pixels per rendered pixel the content wants, given the current one.
    fn scale(&mut self, current: u32) -> u32 {
        current
    }
}

/// The visibility method keys 1-4 select (z-buffer, sort, bucket-far, bucket-near), in every window.
#[must_use]
pub fn method_key(code: KeyCode) -> Option<crate::render::Method> {
    let i = [KeyCode::Digit1, KeyCode::Digit2, KeyCode::Digit3, KeyCode::Digit4, KeyCode::Digit5]
        .iter()
        .position(|&k| k == code)?;
    crate::render::Method::ALL.get(i).copied()
}

/// Fewest window pixels per rendered pixel (native resolution).
pub const MIN_SCALE: u32 = 1;
/// Most window pixels per rendered pixel: the one bound the `=` key, `play --scale`, Settings and the
/// settings file share (a 1280x720 window then renders 160x90).
pub const MAX_SCALE: u32 = 8;

/// How the window opens.
#[derive(Clone, Debug)]
pub struct WindowConfig {
    /// Initial size in physical pixels.
    pub size: (u32, u32),
    /// Start in fullscreen.
    pub fullscreen: bool,
    /// Window pixels per rendered pixel along each axis (1 = native resolution).
    pub scale: u32,
    /// Quit after this many presented frames (for tests and screenshots).
    pub exit_after_frames: Option<u64>,
    /// Write the last rendered frame here on exit.
    pub screenshot: Option<PathBuf>,
    /// Present one frame per refresh of the display (`true`), or as many as the CPU allows (for measuring).
    pub paced: bool,
    /// Frames a second to pace to instead of the display's rate (`--fps`), when paced.
    pub fps: Option<f64>,
}

/// How the window's run ended without an error.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// Closed, quit from a menu or a key, or after `exit_after_frames`.
    Closed,
    /// Stopped by a signal (see [`super::stop`]), as Quit would have.
    Signal(super::stop::StopSignal),
}

struct App<'c> {
    config: WindowConfig,
    /// The stop signals caught while the window runs (the caller's, kept until its recording is kept).
    signals: Option<&'c super::stop::StopSignals>,
    /// The stop signal that ended the run.
    stopped_by: Option<super::stop::StopSignal>,
    content: &'c mut dyn Content,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    ui: Option<super::ui::Ui>,
    quit: bool,
    frame: Vec<u32>,
    frame_size: (usize, usize),
    last: Instant,
    title_at: Instant,
    frames: u64,
    /// The time between frames when paced (from the display, once the window is open), and when the next
    /// frame is due.
    period: Option<Duration>,
    due: Instant,
    error: Option<ShellError>,
}

/// winit's message without the source location it prefixes ("os error at path/file.rs:123: ...").
fn plain_reason(s: &str) -> String {
    let reason = match s.split_once(".rs:") {
        Some((_, rest)) => rest.trim_start_matches(|c: char| c.is_ascii_digit()).trim_start_matches(':').trim(),
        None => s,
    };
    reason.trim_end_matches('.').to_string()
}

/// Opens the window and runs until it is closed or one of the stop signals `signals` catches arrives (it
/// ends the window as Quit does, screenshot included).
pub fn run(
    config: WindowConfig,
    content: &mut dyn Content,
    signals: Option<&super::stop::StopSignals>,
) -> Result<Ended, ShellError> {
    let event_loop = EventLoop::new().map_err(ShellError::NoDisplay)?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let now = Instant::now();
    let mut app = App {
        config,
        signals,
        stopped_by: None,
        content,
        window: None,
        surface: None,
        ui: None,
        quit: false,
        frame: Vec::new(),
        frame_size: (0, 0),
        last: now,
        title_at: now,
        frames: 0,
        period: None,
        due: now,
        error: None,
    };
    // winit panics inside its X11 backend when the display connection breaks mid-run; report that as an
    // error like any other instead of a panic message (the default hook is restored right after).
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let ran = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| event_loop.run_app(&mut app)));
    std::panic::set_hook(hook);
    match ran {
        Ok(result) => result.map_err(ShellError::EventLoop)?,
        Err(_) => return Err(ShellError::DisplayLost),
    }
    // A signal that came after the loop's last look still names the stop.
    let stopped_by = app.stopped_by.or_else(|| signals.and_then(super::stop::StopSignals::received));
    match (app.error.take(), stopped_by) {
        (Some(e), _) => Err(e),
        (None, Some(signal)) => Ok(Ended::Signal(signal)),
        (None, None) => Ok(Ended::Closed),
    }
}

impl App<'_> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, e: ShellError) {
        self.error = Some(e);
        event_loop.exit();
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) {
        let now = Instant::now();
        let dt = (now - self.last).as_secs_f64();
        self.last = now;
        self.content.update(dt);
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
        if self.quit || self.config.exit_after_frames.is_some_and(|n| self.frames >= n) {
            self.exit(event_loop);
        }
    }

    /// Ends the run as Quit does: the screenshot, if one was asked for, then the loop's exit.
    fn exit(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(path) = self.config.screenshot.take() {
            let (fw, fh) = self.frame_size;
            if let Err(e) = super::image_file::write_image(&path, &self.frame, fw, fh) {
                return self.fail(event_loop, e.into());
            }
        }
        event_loop.exit();
    }

    /// Renders and presents one frame; `Ok(false)` when the window has no area.
    fn draw(
        &mut self,
        window: &Window,
        surface: &mut softbuffer::Surface<Rc<Window>, Rc<Window>>,
    ) -> Result<bool, ShellError> {
        let size = window.inner_size();
        // Minimised or resized to nothing: draw nothing, keep running.
        let (Some(ww), Some(wh)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(false);
        };
        surface.resize(ww, wh).map_err(surface_error(SurfaceStep::Resize))?;
        self.config.scale = self.content.scale(self.config.scale).clamp(MIN_SCALE, MAX_SCALE);
        let scale = self.config.scale.max(1);
        let (fw, fh) = (size.width.div_ceil(scale) as usize, size.height.div_ceil(scale) as usize);
        let (bw, s) = (size.width as usize, scale as usize);
        // At scale 1 the frame is drawn straight into the window's buffer (every frame draws every pixel,
        // over its background), saving a copy of the whole frame (3.7 MB at 1280x720) a frame; a screenshot
        // at the end needs the frame without the UI, so then it is kept aside as at other scales.
        let direct = s == 1 && self.config.screenshot.is_none();
        let mut buffer;
        let status = if direct {
            buffer = surface.buffer_mut().map_err(surface_error(SurfaceStep::Buffer))?;
            self.content.draw(&mut buffer, fw, fh)?
        } else {
            if self.frame_size != (fw, fh) {
                self.frame = vec![0; fw * fh];
                self.frame_size = (fw, fh);
            }
            let status = self.content.draw(&mut self.frame, fw, fh)?;
            buffer = surface.buffer_mut().map_err(surface_error(SurfaceStep::Buffer))?;
            upscale(&self.frame, fw, &mut buffer, bw, s);
            status
        };
        if let Some(ui) = self.ui.as_mut() {
            let content = &mut *self.content;
            let mut quit = false;
            ui.push_events(content.ui_events());
            ui.run(window, |ctx| quit |= content.ui(ctx));
            self.quit |= quit;
            ui.paint(&mut buffer, bw, size.height as usize);
        }
        buffer.present().map_err(surface_error(SurfaceStep::Present))?;
        self.frames += 1;
        let now = Instant::now();
        if now.duration_since(self.title_at).as_secs_f32() > 0.5 {
            self.title_at = now;
            window.set_title(&format!("scanline-racer — {status} — {fw}x{fh}"));
        }
        Ok(true)
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, code: KeyCode, down: bool) {
        match code {
            KeyCode::Equal if down => self.config.scale = (self.config.scale + 1).min(MAX_SCALE),
            KeyCode::Minus if down => self.config.scale = self.config.scale.saturating_sub(1).max(MIN_SCALE),
            KeyCode::F11 if down => {
                if let Some(w) = &self.window {
                    w.set_fullscreen(if w.fullscreen().is_some() { None } else { Some(Fullscreen::Borderless(None)) });
                }
            }
            _ => {
                if self.content.key(code, down) {
                    event_loop.exit();
                }
            }
        }
    }
}

impl ApplicationHandler for App<'_> {
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
            Err(e) => return self.fail(event_loop, ShellError::Create(e)),
        };
        let surface =
            softbuffer::Context::new(window.clone()).and_then(|c| softbuffer::Surface::new(&c, window.clone()));
        match surface {
            Ok(s) => self.surface = Some(s),
            Err(e) => return self.fail(event_loop, surface_error(SurfaceStep::Create)(e)),
        }
        self.ui = Some(super::ui::Ui::new(&window));
        // On X11: a lost X server ends the loop with an error (and the race is kept) instead of Xlib's exit.
        super::x11_lost::keep_running(&window);
        let millihertz = window.current_monitor().and_then(|m| m.refresh_rate_millihertz());
        let pacing = Pacing::new(self.config.paced, self.config.fps, millihertz);
        self.period = pacing.period();
        self.content.pacing(pacing);
        self.window = Some(window);
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        let used_by_ui = match (self.ui.as_mut(), self.window.as_ref()) {
            (Some(ui), Some(w)) => ui.on_event(w, &event) || ui.wants_keyboard(),
            _ => false,
        };
        if used_by_ui && matches!(event, WindowEvent::KeyboardInput { .. }) {
            return;
        }
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::KeyboardInput { event, .. } => {
                if let PhysicalKey::Code(code) = event.physical_key {
                    self.key(event_loop, code, event.state == ElementState::Pressed);
                }
            }
            WindowEvent::RedrawRequested => self.redraw(event_loop),
            _ => {}
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        if let Some(signal) = self.signals.and_then(super::stop::StopSignals::received) {
            self.stopped_by = Some(signal);
            return self.exit(event_loop);
        }
        let Some(w) = &self.window else { return };
        let Some(period) = self.period else {
            event_loop.set_control_flow(ControlFlow::Poll);
            return w.request_redraw();
        };
        // Paced: a frame when one is due, then sleep until the next (input and signals wake the loop too).
        let now = Instant::now();
        if now >= self.due {
            w.request_redraw();
            self.due = Pacing::next_due(period, self.due, now);
        }
        event_loop.set_control_flow(ControlFlow::WaitUntil(self.due));
    }
}

/// Copies `frame` (`fw` pixels a row) into `window` (`ww` a row), each frame pixel filling `s` x `s` window
/// pixels, the last blocks cut at the window's edges: scale 1 copies whole rows (a division per pixel here
/// was a millisecond of the main thread a frame at 1280x720).
fn upscale(frame: &[u32], fw: usize, window: &mut [u32], ww: usize, s: usize) {
    if fw == 0 || ww == 0 || s == 0 {
        return;
    }
    for (y, row) in window.chunks_mut(ww).enumerate() {
        let Some(src) = frame.get((y / s) * fw..(y / s + 1) * fw) else { return };
        if s == 1 {
            let n = row.len().min(src.len());
            row[..n].copy_from_slice(&src[..n]);
        } else {
            for (block, &p) in row.chunks_mut(s).zip(src) {
                block.fill(p);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::upscale;

    #[test]
    fn each_frame_pixel_fills_its_block_and_the_edges_are_cut() {
        // A 3x2 frame at scale 3 in a 7x5 window: columns 0-2, 3-5 and 6 (cut); rows 0-2 and 3-4 (cut).
        let frame = [1, 2, 3, 4, 5, 6];
        let mut window = [0u32; 35];
        upscale(&frame, 3, &mut window, 7, 3);
        for (i, &p) in window.iter().enumerate() {
            let (x, y) = (i % 7, i / 7);
            assert_eq!(p, frame[(y / 3) * 3 + x / 3], "pixel ({x}, {y})");
        }
        // Scale 1 is a copy.
        let mut same = [0u32; 6];
        upscale(&frame, 3, &mut same, 3, 1);
        assert_eq!(same, frame);
        // A frame too small for the window leaves the rest untouched rather than panicking.
        let mut big = [9u32; 12];
        upscale(&frame, 3, &mut big, 3, 1);
        assert_eq!(big, [1, 2, 3, 4, 5, 6, 9, 9, 9, 9, 9, 9]);
    }
}
