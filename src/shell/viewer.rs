//! The scene viewer: fly a camera around any glTF scene (`play --scene FILE`).

use glam::{Mat4, Vec3};
use winit::keyboard::KeyCode;

use super::window::{Content, ShellError, method_key};
use crate::asset::LoadedScene;
use crate::render::{Camera, Projection, RenderOptions, Renderer};

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

/// A free camera over a scene.
pub struct Viewer {
    scene: LoadedScene,
    options: RenderOptions,
    renderer: Renderer,
    position: Vec3,
    yaw: f32,
    pitch: f32,
    speed: f32,
    projection: Projection,
    held: Held,
    frame_ms: f64,
}

/// Eye position, yaw (radians, 0 = looking down -Z, positive turns right) and pitch of a camera.
fn pose_of(camera: &Camera) -> (Vec3, f32, f32) {
    let eye = camera.view.inverse();
    let forward = -eye.z_axis.truncate().normalize_or(Vec3::NEG_Z);
    (eye.w_axis.truncate(), libm::atan2f(forward.x, -forward.z), libm::asinf(forward.y.clamp(-1.0, 1.0)))
}

/// The view matrix of an eye at `position` with `yaw` and `pitch`, no roll.
fn view_of(position: Vec3, yaw: f32, pitch: f32) -> Mat4 {
    let dir = Vec3::new(libm::sinf(yaw) * libm::cosf(pitch), libm::sinf(pitch), -libm::cosf(yaw) * libm::cosf(pitch));
    let view = glam::camera::rh::view::look_to_mat4(position, dir, Vec3::Y);
    if view.is_finite() { view } else { Mat4::IDENTITY }
}

impl Viewer {
    /// A viewer starting at the scene's first camera (or one that frames it) for a window of `aspect`.
    #[must_use]
    pub fn new(scene: LoadedScene, options: RenderOptions, aspect: f32) -> Self {
        let start = scene.cameras.first().map_or_else(|| scene.framing_camera(aspect), |c| c.camera);
        let (position, yaw, pitch) = pose_of(&start);
        let radius = scene.bounds.map_or(10.0, |(lo, hi)| (hi - lo).length().max(1.0));
        Self {
            scene,
            options,
            renderer: Renderer::new(),
            position,
            yaw,
            pitch,
            speed: radius * 0.3,
            projection: start.projection,
            held: Held::default(),
            frame_ms: 0.0,
        }
    }

    fn camera(&self) -> Camera {
        Camera { view: view_of(self.position, self.yaw, self.pitch), projection: self.projection }
    }
}

impl Content for Viewer {
    fn update(&mut self, dt: f64) {
        let dt = dt.min(0.1) as f32;
        let h = &self.held;
        let turn = 1.6 * dt;
        if h.left {
            self.yaw -= turn;
        }
        if h.right {
            self.yaw += turn;
        }
        let ahead = Vec3::new(libm::sinf(self.yaw), 0.0, -libm::cosf(self.yaw));
        let mut motion = Vec3::ZERO;
        for (on, dir) in [(h.forward, ahead), (h.back, -ahead), (h.up, Vec3::Y), (h.down, Vec3::NEG_Y)] {
            if on {
                motion += dir;
            }
        }
        self.position += motion * self.speed * dt;
    }

    fn key(&mut self, code: KeyCode, down: bool) -> bool {
        match code {
            KeyCode::Escape if down => return true,
            KeyCode::ArrowUp | KeyCode::KeyW => self.held.forward = down,
            KeyCode::ArrowDown | KeyCode::KeyS => self.held.back = down,
            KeyCode::ArrowLeft | KeyCode::KeyA => self.held.left = down,
            KeyCode::ArrowRight | KeyCode::KeyD => self.held.right = down,
            KeyCode::KeyE | KeyCode::PageUp => self.held.up = down,
            KeyCode::KeyQ | KeyCode::PageDown => self.held.down = down,
            _ if !down => {}
            _ => {
                if let Some(m) = method_key(code) {
                    self.options.method = m;
                }
            }
        }
        false
    }

    fn draw(&mut self, frame: &mut [u32], width: usize, height: usize) -> Result<String, ShellError> {
        let camera = self.camera();
        let t = std::time::Instant::now();
        if self.options.method == crate::render::Method::ViewLists && self.scene.view_lists.is_none() {
            use crate::render::order::view_lists::{DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS};
            self.scene.prepare_view_lists(DEFAULT_LEVEL, DEFAULT_MAX_POLYGONS);
        }
        let stats = self.renderer.render(frame, width, height, &camera, &self.scene.draw_list(), &self.options)?;
        self.frame_ms = 0.9 * self.frame_ms + 0.1 * t.elapsed().as_secs_f64() * 1e3;
        Ok(format!(
            "{} — {:.1} ms/frame — {} of {} polygons",
            self.options.method, self.frame_ms, stats.polygons_drawn, stats.polygons_in
        ))
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
        assert!((view - start.view).abs().to_cols_array().iter().all(|d| *d < 1e-4));
    }
}
