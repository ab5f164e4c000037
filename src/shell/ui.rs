//! egui in the window: input from winit, layout by egui, and its meshes drawn by our own rasterizer
//! (`render::overlay`) over the upscaled frame at the window's full resolution, so text stays sharp.

use std::collections::BTreeMap;

use egui::epaint::{ImageData, Primitive};
use egui::{TextureId, ViewportId};
use winit::event::WindowEvent;
use winit::window::Window;

use crate::render::Texture;
use crate::render::overlay::{OverlayVertex, draw_triangles};

/// egui's state for one window and the textures it asked for.
pub struct Ui {
    ctx: egui::Context,
    state: egui_winit::State,
    textures: BTreeMap<TextureId, Texture>,
    shapes: Vec<egui::epaint::ClippedPrimitive>,
    pixels_per_point: f32,
    /// Where the text on screen is written when it changes (`$SCANLINE_RACER_UI_TEXT`), and what was written.
    text_out: Option<(std::path::PathBuf, String)>,
}

/// The environment variable naming a file that receives the text the menus show.
///
/// A line each: `X Y text`, the text's top-left corner in window pixels. For tests and tools that read the screen as a user does
/// (which key names Settings shows, where a button is to click), without OCR.
pub const UI_TEXT_ENV: &str = "SCANLINE_RACER_UI_TEXT";

impl Ui {
    /// egui for `window`.
    #[must_use]
    pub fn new(window: &Window) -> Self {
        let ctx = egui::Context::default();
        let state = egui_winit::State::new(ctx.clone(), ViewportId::ROOT, window, None, None, Some(4096));
        let text_out = std::env::var_os(UI_TEXT_ENV).map(|p| (std::path::PathBuf::from(p), String::new()));
        Self { ctx, state, textures: BTreeMap::new(), shapes: vec![], pixels_per_point: 1.0, text_out }
    }

    /// Passes a window event to egui; true when egui used it (a click on a button, typing in a field).
    pub fn on_event(&mut self, window: &Window, event: &WindowEvent) -> bool {
        self.state.on_window_event(window, event).consumed
    }

    /// Adds input events (beyond the window's own) to the next pass.
    pub fn push_events(&mut self, events: Vec<egui::Event>) {
        self.state.egui_input_mut().events.extend(events);
    }

    /// True while egui wants the keyboard (a text field has focus).
    #[must_use]
    pub fn wants_keyboard(&self) -> bool {
        self.ctx.egui_wants_keyboard_input()
    }

    /// Runs one egui pass with `build`, applies texture changes and keeps the tessellated meshes.
    pub fn run(&mut self, window: &Window, build: impl FnMut(&egui::Context)) {
        let input = self.state.take_egui_input(window);
        let mut out = self.ctx.run_pass(input, build);
        self.state.handle_platform_output(window, std::mem::take(&mut out.platform_output));
        for (id, deltas) in std::mem::take(&mut out.textures_delta.set) {
            for delta in deltas {
                self.apply(id, &delta);
            }
        }
        for id in std::mem::take(&mut out.textures_delta.free) {
            self.textures.remove(&id);
        }
        self.pixels_per_point = out.pixels_per_point;
        if let Some((path, last)) = &mut self.text_out {
            let mut lines = String::new();
            for clipped in &out.shapes {
                texts(&clipped.shape, out.pixels_per_point, &mut lines);
            }
            // Written only when it changes, whole (a reader never sees half a file); a failure is no reason
            // to stop the game.
            if lines != *last && crate::userfile::replace_atomically(path, lines.as_bytes()).is_ok() {
                *last = lines;
            }
        }
        self.shapes = self.ctx.tessellate(std::mem::take(&mut out.shapes), out.pixels_per_point);
    }

    fn apply(&mut self, id: TextureId, delta: &egui::epaint::ImageDelta) {
        let ImageData::Color(image) = &delta.image;
        let [w, h] = image.size;
        let texels: Vec<u32> = image
            .pixels
            .iter()
            .map(|c| {
                let [r, g, b, a] = c.to_array();
                u32::from_be_bytes([a, r, g, b])
            })
            .collect();
        let (Ok(w), Ok(h)) = (u32::try_from(w), u32::try_from(h)) else {
            return;
        };
        match delta.pos {
            Some([x, y]) => {
                if let (Some(tex), Ok(x), Ok(y)) = (self.textures.get_mut(&id), u32::try_from(x), u32::try_from(y)) {
                    tex.patch(x, y, w, h, &texels);
                }
            }
            None => {
                if let Ok(t) = Texture::new(w, h, texels) {
                    self.textures.insert(id, t);
                }
            }
        }
    }

    /// Draws the last pass's meshes into a `width` x `height` buffer; returns the pixels written.
    pub fn paint(&self, buffer: &mut [u32], width: usize, height: usize) -> u64 {
        let ppp = self.pixels_per_point;
        let mut written = 0;
        let mut verts = Vec::new();
        for prim in &self.shapes {
            let Primitive::Mesh(mesh) = &prim.primitive else {
                continue;
            };
            verts.clear();
            verts.extend(mesh.vertices.iter().map(|v| OverlayVertex {
                pos: [v.pos.x * ppp, v.pos.y * ppp],
                uv: [v.uv.x, v.uv.y],
                color: v.color.to_array(),
            }));
            let r = prim.clip_rect;
            let clip = [r.min.x * ppp, r.min.y * ppp, r.max.x * ppp, r.max.y * ppp];
            written +=
                draw_triangles(buffer, width, height, &verts, &mesh.indices, self.textures.get(&mesh.texture_id), clip);
        }
        written
    }
}

/// Appends a line `X Y text` for every text in `shape` (and the shapes it holds), in window pixels.
fn texts(shape: &egui::Shape, pixels_per_point: f32, out: &mut String) {
    match shape {
        egui::Shape::Text(t) => {
            let text = t.galley.text().replace('\n', " ");
            let (x, y) = (t.pos.x * pixels_per_point, t.pos.y * pixels_per_point);
            out.push_str(&format!("{} {} {text}\n", x.round(), y.round()));
        }
        egui::Shape::Vec(shapes) => shapes.iter().for_each(|s| texts(s, pixels_per_point, out)),
        _ => {}
    }
}
