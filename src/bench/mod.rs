//! The speed-against-accuracy sweep behind `scanline-racer bench`: frames of a demo replay (and fixed views
//! on the circuit) drawn under every method and setting, each timed beside the z-buffer in the same run and
//! measured against the DESIGN reference image.
//!
//! Timing: every configuration's frames are drawn `repeats` times, interleaved with the z-buffer drawing
//! the same frame at the same size (so both see the same machine state); a frame's time is its best of the
//! repeats, and a configuration's time is the median over frames. Errors are means over frames: FLIP mean,
//! FLIP 99th percentile, wrong pixels and PSNR against the reference (32x32 samples a pixel, z-buffer, exact
//! perspective, close LOD), plus the *visibility error*: wrong pixels and FLIP against the z-buffer frame at
//! the same texture, filter and LOD settings, which isolates what the visibility method alone costs.
//!
//! Temporal stability (`stability`): every configuration also draws a sequence of consecutive frames on one
//! renderer that keeps its LOD history, measured for shimmer against the reference sequence; and every LOD
//! setting replays the whole trace to count its LOD pops per minute (`frames::lod_pops_per_min`).

pub mod chart;
pub mod configs;
pub mod frames;
pub mod labels;
pub mod stability;

use std::collections::BTreeMap;
use std::time::Instant;

use crate::measure::{flip, psnr, reference_frame, wrong_pixels};
use crate::render::{Camera, DrawList, LodMode, Method, RenderError, RenderOptions, Renderer};
pub use configs::{Config, configs};
use configs::{key_name, mode_name};
pub use frames::{BenchFrame, collect_frames, collect_sequence, lod_pops_per_min};
use stability::{SequenceReferences, measure_sequence};

/// What was measured for one configuration.
#[derive(Clone, Debug)]
pub struct Row {
    /// The configuration.
    pub config: Config,
    /// Median over frames of the best-of-repeats time (ms).
    pub ms: f64,
    /// The same for the z-buffer at the same size, measured interleaved with it.
    pub zbuffer_ms: f64,
    /// Mean polygons drawn per frame.
    pub polygons_drawn: f64,
    /// Mean FLIP against the reference.
    pub flip_mean: f64,
    /// Mean over frames of the 99th-percentile FLIP.
    pub flip_p99: f64,
    /// Mean share of wrong pixels against the reference, in percent.
    pub wrong_pct: f64,
    /// Mean PSNR against the reference (dB; identical frames count as 99 dB).
    pub psnr_db: f64,
    /// Mean share of pixels differing from the z-buffer at the same settings, in percent.
    pub vis_wrong_pct: f64,
    /// Mean FLIP against the z-buffer at the same settings.
    pub vis_flip_mean: f64,
    /// On the Pareto front of time against FLIP mean among the main-size configurations (no other point is
    /// both faster and more accurate).
    pub pareto: bool,
    /// On the Pareto front of time against visibility error among the visibility configurations.
    pub vis_pareto: bool,
    /// Mean FLIP against the reference over the stability sequence's frames (drawn with LOD history).
    pub seq_flip_mean: f64,
    /// Shimmer over the stability sequence: RMS (0-255) of the frame-to-frame change the reference does not
    /// have ([`crate::measure::Shimmer`]); 0 for a sequence of fewer than two frames.
    pub shimmer_rms: f64,
    /// Share of shimmering pixels (change beyond the reference's by more than 24/255 in a channel) over the
    /// sequence's frame pairs, in percent.
    pub shimmer_pct: f64,
    /// On the Pareto front of time against shimmer RMS among the main-size configurations.
    pub stability_pareto: bool,
    /// LOD pops per minute of race time over the whole trace (see [`lod_pops_per_min`]); 0 for a forced
    /// level, which never switches. Filled in by the caller after [`run`] (0 until then).
    pub lod_pops_per_min: f64,
}

/// Draws `frame` with `options` at `size` on a renderer with no LOD history (frames are not consecutive).
fn draw(
    renderer: &mut Renderer,
    list: &DrawList<'_>,
    camera: &Camera,
    options: &RenderOptions,
    size: (usize, usize),
    out: &mut Vec<u32>,
) -> Result<(f64, u64), RenderError> {
    out.resize(size.0 * size.1, 0);
    renderer.reset_lod();
    let t = Instant::now();
    let stats = renderer.render(out, size.0, size.1, camera, list, options)?;
    Ok((t.elapsed().as_secs_f64() * 1e3, stats.polygons_drawn))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() { 0.0 } else { v[v.len() / 2] }
}

/// Runs the sweep: every configuration over every frame, then over the stability `sequence` (consecutive
/// frames, LOD history kept). `threads` is the renderer's thread count for all of it; `progress(done,
/// total)` is called after each configuration.
// long: one loop over the configurations, timing, then accuracy, then stability, each a few lines.
pub fn run<'s>(
    frames: &'s [BenchFrame],
    sequence: &'s [BenchFrame],
    list_for: impl Fn(&'s BenchFrame, &Config) -> DrawList<'s>,
    configs: &[Config],
    repeats: usize,
    threads: usize,
    mut progress: impl FnMut(usize, usize, &str),
) -> Result<Vec<Row>, RenderError> {
    let mut renderer = Renderer::new();
    let mut references: BTreeMap<(usize, usize, usize), Vec<u32>> = BTreeMap::new();
    let mut rows = Vec::with_capacity(configs.len());
    let (mut img, mut zimg) = (Vec::new(), Vec::new());
    let mut sequence_references = SequenceReferences::default();
    for (ci, config) in configs.iter().enumerate() {
        let options = RenderOptions { threads, ..config.options };
        let zoptions = RenderOptions { method: Method::ZBuffer, ..options };
        let timing_z = RenderOptions { method: Method::ZBuffer, threads, ..RenderOptions::default() };
        let (w, h) = config.size;
        let (mut times, mut ztimes) = (vec![f64::INFINITY; frames.len()], vec![f64::INFINITY; frames.len()]);
        for _ in 0..repeats.max(1) {
            for (fi, f) in frames.iter().enumerate() {
                let list = list_for(f, config);
                let (t, _) = draw(&mut renderer, &list, &f.camera, &options, config.size, &mut img)?;
                times[fi] = times[fi].min(t);
                let (tz, _) = draw(&mut renderer, &list, &f.camera, &timing_z, config.size, &mut zimg)?;
                ztimes[fi] = ztimes[fi].min(tz);
            }
        }
        let mut acc = [0.0f64; 8];
        for (fi, f) in frames.iter().enumerate() {
            let list = list_for(f, config);
            let (_, n) = draw(&mut renderer, &list, &f.camera, &options, config.size, &mut img)?;
            draw(&mut renderer, &list, &f.camera, &zoptions, config.size, &mut zimg)?;
            let reference = match references.entry((fi, w, h)) {
                std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
                std::collections::btree_map::Entry::Vacant(e) => {
                    e.insert(reference_frame(&f.camera, &list, w, h, crate::render::SKY_BLUE)?)
                }
            };
            let fl = flip(reference, &img, w, h);
            let vis = flip(&zimg, &img, w, h);
            acc[0] += n as f64;
            acc[1] += fl.as_ref().map_or(0.0, |f| f64::from(f.mean));
            acc[2] += fl.as_ref().map_or(0.0, |f| f64::from(f.p99));
            acc[3] += wrong_pixels(reference, &img) * 100.0;
            acc[4] += psnr(reference, &img).min(99.0);
            acc[5] += wrong_pixels(&zimg, &img) * 100.0;
            acc[6] += vis.as_ref().map_or(0.0, |f| f64::from(f.mean));
        }
        let n = frames.len().max(1) as f64;
        let seq = measure_sequence(
            &mut renderer,
            sequence,
            |f| list_for(f, config),
            &options,
            config.size,
            &mut sequence_references,
        )?;
        rows.push(Row {
            config: config.clone(),
            ms: median(&mut times),
            zbuffer_ms: median(&mut ztimes),
            polygons_drawn: acc[0] / n,
            flip_mean: acc[1] / n,
            flip_p99: acc[2] / n,
            wrong_pct: acc[3] / n,
            psnr_db: acc[4] / n,
            vis_wrong_pct: acc[5] / n,
            vis_flip_mean: acc[6] / n,
            pareto: false,
            vis_pareto: false,
            seq_flip_mean: seq.flip_mean,
            shimmer_rms: seq.shimmer_rms,
            shimmer_pct: seq.shimmer_pct,
            stability_pareto: false,
            lod_pops_per_min: 0.0,
        });
        progress(ci + 1, configs.len(), &config.label);
    }
    let main = configs.first().map_or((0, 0), |c| c.size);
    let front = pareto(&rows, |r| (r.config.size == main).then_some((r.ms, r.flip_mean)));
    let vis_front = pareto(&rows, |r| (r.config.group == "visibility").then_some((r.ms, r.vis_wrong_pct)));
    let stability_front = pareto(&rows, |r| (r.config.size == main).then_some((r.ms, r.shimmer_rms)));
    for (((r, a), b), c) in rows.iter_mut().zip(front).zip(vis_front).zip(stability_front) {
        r.pareto = a;
        r.vis_pareto = b;
        r.stability_pareto = c;
    }
    Ok(rows)
}

/// Which rows no other row beats on both time and error; `point` gives a row's (time, error), or `None` to
/// leave it out. Ties count as not beaten.
pub fn pareto(rows: &[Row], point: impl Fn(&Row) -> Option<(f64, f64)>) -> Vec<bool> {
    let points: Vec<Option<(f64, f64)>> = rows.iter().map(point).collect();
    points
        .iter()
        .enumerate()
        .map(|(i, p)| {
            p.is_some_and(|(t, e)| {
                !points
                    .iter()
                    .enumerate()
                    .any(|(j, q)| q.is_some_and(|(tj, ej)| j != i && tj <= t && ej <= e && (tj < t || ej < e)))
            })
        })
        .collect()
}

/// The rows of each course (`(course, rows)`) as CSV, with a header line; the first column is the course.
/// Columns after `vis_pareto`: `seq_flip_mean` (FLIP mean over the
/// stability sequence), `shimmer_rms` and `shimmer_pct` (its shimmer), `stability_pareto` (on the front of
/// time against shimmer RMS), `lod_pops_per_min` (0 for forced levels: they never switch).
#[must_use]
pub fn csv(courses: &[(&str, &[Row])], threads: usize) -> String {
    let mut s = String::from(
        "course,group,label,method,buckets,key,texture,filter,mip,aa,lod,lod_bias,width,height,threads,ms_median,zbuffer_ms_median,ratio_to_zbuffer,polygons_drawn,flip_mean,flip_p99,wrong_pct,psnr_db,vis_wrong_pct,vis_flip_mean,pareto,vis_pareto,seq_flip_mean,shimmer_rms,shimmer_pct,stability_pareto,lod_pops_per_min,preset,mip_bias\n",
    );
    for (course, rows) in courses {
        let main = rows.first().map_or((0, 0), |r| r.config.size);
        for r in rows.iter() {
            s.push_str(&csv_row(course, r, threads, main));
        }
    }
    s
}

/// One row of [`csv`]: `r` of `course`, measured on `threads` threads, in a sweep whose main size is `main`.
fn csv_row(course: &str, r: &Row, threads: usize, main: (usize, usize)) -> String {
    let o = &r.config.options;
    let lod = match o.lod {
        LodMode::Auto => "auto",
        LodMode::Force(l) => l.name(),
    };
    format!(
        "{course},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.3},{:.3},{:.3},{:.0},{:.5},{:.5},{:.3},{:.2},{:.3},{:.5},{},{},{:.5},{:.3},{:.3},{},{:.1},{},{}\n",
        r.config.group,
        r.config.label,
        o.method,
        o.buckets,
        key_name(o.key),
        mode_name(o.texture_mode),
        o.filter.name(),
        o.mip,
        o.antialias,
        lod,
        o.lod_bias,
        r.config.size.0,
        r.config.size.1,
        threads,
        r.ms,
        r.zbuffer_ms,
        r.ms / r.zbuffer_ms.max(1e-9),
        r.polygons_drawn,
        r.flip_mean,
        r.flip_p99,
        r.wrong_pct,
        r.psnr_db,
        r.vis_wrong_pct,
        r.vis_flip_mean,
        r.pareto,
        r.vis_pareto,
        r.seq_flip_mean,
        r.shimmer_rms,
        r.shimmer_pct,
        r.stability_pareto,
        r.lod_pops_per_min,
        configs::preset_of(&r.config, main).map_or("", |q| q.name()),
        o.mip_bias
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Level;

    fn row(ms: f64, flip_mean: f64) -> Row {
        Row {
            config: Config {
                group: "g",
                label: String::new(),
                options: RenderOptions::default(),
                size: (1, 1),
                view_level: None,
            },
            ms,
            zbuffer_ms: 1.0,
            polygons_drawn: 0.0,
            flip_mean,
            flip_p99: 0.0,
            wrong_pct: 0.0,
            psnr_db: 0.0,
            vis_wrong_pct: 0.0,
            vis_flip_mean: 0.0,
            pareto: false,
            vis_pareto: false,
            seq_flip_mean: 0.0,
            shimmer_rms: 0.0,
            shimmer_pct: 0.0,
            stability_pareto: false,
            lod_pops_per_min: 0.0,
        }
    }

    #[test]
    fn pareto_front_keeps_only_undominated_points() {
        let rows = vec![row(1.0, 0.5), row(2.0, 0.1), row(2.5, 0.3), row(3.0, 0.1), row(0.5, 0.9), row(1.0, 0.5)];
        let front = pareto(&rows, |r| Some((r.ms, r.flip_mean)));
        assert_eq!(front, [true, true, false, false, true, true]);
        // Left-out rows are neither on the front nor able to beat others.
        let front = pareto(&rows, |r| (r.ms != 0.5).then_some((r.ms, r.flip_mean)));
        assert_eq!(front, [true, true, false, false, false, true]);
    }

    /// The bumper camera sits inside the player's car's bounding sphere. With no LOD history (as every bench
    /// frame is drawn, and the game's first frame after a restart) that car must still get its close model:
    /// it got the long-shot box, a fifth of the frame, which made `lod close` look far better than `auto`.
    #[test]
    fn a_fresh_renderer_draws_the_car_the_camera_is_in_with_its_close_model() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        let scene = crate::shell::race_scene::RaceScene::load(&dir, crate::shell::race_scene::DEFAULT_COURSE).unwrap();
        let frames = collect_frames(&scene, &dir.join("replays/demo-race.trace"), 2).unwrap();
        let bumper = frames.iter().find(|f| f.name.ends_with("Bumper")).unwrap();
        let list = scene.draw_list(&bumper.instances);
        let (w, h) = (160, 120);
        let mut renderer = Renderer::new();
        let auto = RenderOptions::default();
        let close = RenderOptions { lod: LodMode::Force(Level::Close), ..auto };
        // The player's car is the first of the eight cars after the circuit's instances.
        let player = bumper.instances.len() - crate::shell::race_scene::FIELD;
        let set = &list.lod_sets[bumper.instances[player].lod.unwrap()];
        let (mut a, mut c) = (vec![], vec![]);
        draw(&mut renderer, &list, &bumper.camera, &auto, (w, h), &mut a).unwrap();
        draw(&mut renderer, &list, &bumper.camera, &close, (w, h), &mut c).unwrap();
        // Only the far cars and track-side objects differ (0.1-0.4% of pixels in chase views); was 21%.
        let differ = a.iter().zip(&c).filter(|(p, q)| p != q).count();
        assert!(differ * 100 < 2 * w * h, "{differ} of {} pixels differ from all-close", w * h);
        renderer.reset_lod();
        assert_eq!(renderer.frame_lod(w, h, &bumper.camera, &list, &auto)[player], Some((set.meshes[0], false)));
    }

    #[test]
    fn csv_has_a_value_for_every_column_of_every_row() {
        let mut r = row(2.0, 0.05);
        (r.shimmer_rms, r.shimmer_pct, r.lod_pops_per_min, r.stability_pareto) = (11.6, 4.75, 12.5, true);
        r.config.label = "lod auto +1".into();
        let mut forced = row(1.0, 0.1);
        forced.config.label = "lod long".into();
        let rows = [r, forced];
        let text = csv(&[("circuit", &rows[..])], 1);
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap().split(',').collect();
        for name in ["seq_flip_mean", "shimmer_rms", "shimmer_pct", "stability_pareto", "lod_pops_per_min"] {
            assert!(header.contains(&name), "no column {name}");
        }
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        assert_eq!(rows.len(), 2);
        let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
        for r in &rows {
            assert_eq!(r.len(), header.len());
            assert!(r.iter().all(|v| !v.is_empty() && !v.eq_ignore_ascii_case("nan")), "{r:?}");
        }
        assert_eq!(rows[0][col("shimmer_rms")], "11.600");
        assert_eq!(rows[0][col("shimmer_pct")], "4.750");
        assert_eq!(rows[0][col("lod_pops_per_min")], "12.5");
        assert_eq!(rows[0][col("stability_pareto")], "true");
        assert_eq!(rows[1][col("lod_pops_per_min")], "0.0");
    }

    #[test]
    fn the_sweep_covers_every_method_key_texture_mode_lod_and_resolution() {
        use crate::render::Quality;
        let c = configs((640, 480), &[8, 1024, 65536], &[(320, 240), (640, 480), (1920, 1080)], Quality::Low);
        for m in Method::ALL {
            assert!(c.iter().any(|c| c.options.method == m), "{m}");
        }
        assert!(c.iter().any(|c| c.options.buckets == 8) && c.iter().any(|c| c.options.buckets == 65536));
        assert_eq!(c.iter().filter(|c| c.group == "texture").count(), 6);
        assert_eq!(c.iter().filter(|c| c.group == "resolution").count(), 4);
        assert!(c.iter().any(|c| c.options.lod == LodMode::Force(Level::Long)));
        // Every preset at the main size, whatever the base.
        for base in Quality::ALL {
            let c = configs((640, 480), &[8, 1024], &[(320, 240)], base);
            for q in Quality::ALL {
                let n = c.iter().filter(|c| configs::preset_of(c, (640, 480)) == Some(q)).count();
                assert!(n >= 1, "{q} with base {base}");
            }
        }
    }
}
