//! The debug overlay (F3): frame-time plot, time per render stage, polygons in and drawn, LOD counts and
//! ordering-table bucket occupancy.

use std::collections::VecDeque;

use crate::render::Stats;

/// When this environment variable names a file, every frame's render time in milliseconds, its polygons
/// drawn, the quality it was drawn at (`high(auto)`, `low`, `custom`, `-` for none) and the seconds since
/// the first frame, then the milliseconds of its stages (transform, clip and set-up, order, fill) are
/// written to it, a line each (`ms polygons quality seconds transform clip order fill`): F3's numbers for
/// a whole run, for measuring a course's frame times in the window (created anew; written as frames are
/// drawn).
pub const FRAME_TIMES_ENV: &str = "SCANLINE_RACER_FRAME_TIMES";

/// Frames kept for the plot.
const HISTORY: usize = 240;
/// Buckets are summed into this many bars.
const BARS: usize = 48;

/// What the overlay shows, gathered frame by frame.
#[derive(Debug, Default)]
pub struct DebugOverlay {
    /// Shown or hidden.
    pub visible: bool,
    frame_ms: VecDeque<f32>,
    stats: Stats,
    occupancy: Vec<u32>,
    /// The frame-time log ([`FRAME_TIMES_ENV`]): `None` before the first frame, then the file if any.
    log: Option<Option<std::io::BufWriter<std::fs::File>>>,
    /// How the window times its frames, once it says.
    pub pacing: Option<super::window::Pacing>,
    /// The picture quality in use (`high (auto)`, `low`, `custom`), when the content has one.
    pub quality: Option<String>,
    /// When the first frame was logged (the log's last column counts from it).
    started: Option<std::time::Instant>,
}

impl DebugOverlay {
    /// Records one frame: its render time, statistics and bucket occupancy.
    pub fn record(&mut self, ms: f64, stats: &Stats, occupancy: Vec<u32>) {
        if self.frame_ms.len() == HISTORY {
            self.frame_ms.pop_front();
        }
        self.frame_ms.push_back(ms as f32);
        self.stats = stats.clone();
        self.occupancy = occupancy;
        let log = self.log.get_or_insert_with(|| {
            let path = std::env::var_os(FRAME_TIMES_ENV).filter(|p| !p.is_empty())?;
            std::fs::File::create(path).ok().map(std::io::BufWriter::new)
        });
        if let Some(w) = log {
            use std::io::Write;
            // A failed write ends the log (a full disk must not stop the game).
            let quality = self.quality.as_deref().unwrap_or("-").replace(' ', "");
            let t = self.started.get_or_insert_with(std::time::Instant::now).elapsed().as_secs_f64();
            // Flushed each frame, so a reader follows the run as it goes (60 small writes a second).
            let s = stats;
            let stages = format!("{:.4} {:.4} {:.4} {:.4}", s.ms_transform, s.ms_clip, s.ms_order, s.ms_fill);
            let line = writeln!(w, "{ms:.4} {} {quality} {t:.3} {stages}", s.polygons_drawn);
            if line.and_then(|()| w.flush()).is_err() {
                self.log = Some(None);
            }
        }
    }

    /// Draws the overlay in a corner window.
    pub fn show(&self, ctx: &egui::Context) {
        if !self.visible {
            return;
        }
        let s = &self.stats;
        egui::Window::new("Debug (F3)").anchor(egui::Align2::RIGHT_TOP, [-8.0, 8.0]).resizable(false).show(ctx, |ui| {
            let max = self.frame_ms.iter().copied().fold(1.0f32, f32::max);
            ui.label(format!(
                "frame: {:.2} ms (max {:.2} over {} frames)",
                self.frame_ms.back().unwrap_or(&0.0),
                max,
                self.frame_ms.len()
            ));
            plot(ui, self.frame_ms.iter().copied(), max, egui::Color32::from_rgb(120, 220, 120));
            if let Some(pacing) = self.pacing {
                ui.label(format!("frames: {pacing}"));
            }
            if let Some(quality) = &self.quality {
                ui.label(format!("quality: {quality}"));
            }
            ui.label(format!(
                "transform {:.2}  clip {:.2}  order {:.2}  fill {:.2} ms",
                s.ms_transform, s.ms_clip, s.ms_order, s.ms_fill
            ));
            ui.label(format!(
                "polygons in {}  drawn {}  (culled objects {}, back faces {}, outside {}, clipped {})",
                s.polygons_in,
                s.polygons_drawn,
                s.polygons_in_culled_objects,
                s.polygons_backface,
                s.polygons_outside,
                s.polygons_clipped
            ));
            ui.label(format!(
                "LOD close {}  mid {}  long {}  (saved {} polygons)",
                s.lod_close, s.lod_mid, s.lod_long, s.polygons_saved_by_lod
            ));
            ui.label(format!(
                "pixels written {}  shaded {}  rejected {}",
                s.pixels_written, s.pixels_shaded, s.pixels_rejected
            ));
            if self.occupancy.is_empty() {
                ui.label("bucket occupancy: (z-buffer or sort: no ordering table)");
            } else {
                let per = self.occupancy.len().div_ceil(BARS);
                let bars: Vec<f32> = self.occupancy.chunks(per).map(|c| c.iter().sum::<u32>() as f32).collect();
                let top = bars.iter().copied().fold(1.0f32, f32::max);
                let used = self.occupancy.iter().filter(|&&n| n > 0).count();
                ui.label(format!(
                    "bucket occupancy, near to far: {} of {} buckets used, fullest bar {}",
                    used,
                    self.occupancy.len(),
                    top
                ));
                bars_plot(ui, &bars, top);
            }
        });
    }
}

fn plot(ui: &mut egui::Ui, values: impl Iterator<Item = f32>, max: f32, color: egui::Color32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(300.0, 60.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_black_alpha(140));
    let pts: Vec<egui::Pos2> = values
        .enumerate()
        .map(|(i, v)| {
            let x = rect.left() + rect.width() * i as f32 / (HISTORY - 1) as f32;
            egui::pos2(x, rect.bottom() - rect.height() * (v / max).clamp(0.0, 1.0))
        })
        .collect();
    painter.add(egui::Shape::line(pts, egui::Stroke::new(1.5, color)));
}

fn bars_plot(ui: &mut egui::Ui, bars: &[f32], top: f32) {
    let (rect, _) = ui.allocate_exact_size(egui::vec2(300.0, 50.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 2.0, egui::Color32::from_black_alpha(140));
    let w = rect.width() / bars.len().max(1) as f32;
    for (i, b) in bars.iter().enumerate() {
        let h = rect.height() * (b / top).clamp(0.0, 1.0);
        let r = egui::Rect::from_min_max(
            egui::pos2(rect.left() + i as f32 * w, rect.bottom() - h),
            egui::pos2(rect.left() + (i + 1) as f32 * w - 1.0, rect.bottom()),
        );
        painter.rect_filled(r, 0.0, egui::Color32::from_rgb(230, 180, 60));
    }
}
