//! The frames the bench draws: ticks of a demo replay seen from the chase camera, and fixed views of the
//! same moments from the other cameras (far chase, bumper, trackside), as camera and instance lists; a run
//! of consecutive frames for the temporal-stability measure; and the LOD pops of a whole replay.

use std::path::Path;

use crate::input::replay::{Replay, ReplayError};
use crate::render::{Camera, Instance, LodMode, RenderOptions, Renderer};
use crate::shell::race_scene::{RaceScene, View, camera_for};

/// One frame to draw: where from, and what.
#[derive(Clone, Debug)]
pub struct BenchFrame {
    /// `tick N view`.
    pub name: String,
    /// The camera.
    pub camera: Camera,
    /// The circuit and the cars at that tick.
    pub instances: Vec<Instance>,
}

/// `count` chase-camera frames spread evenly over the racing part of the trace at `path`, plus the other
/// three views at every other one of those ticks.
pub fn collect_frames(scene: &RaceScene, path: &Path, count: usize) -> Result<Vec<BenchFrame>, ReplayError> {
    let mut replay = Replay::open(path, scene.track.clone())?;
    let mut worlds = vec![];
    while replay.advance()? {
        if !replay.world.race.holding() {
            worlds.push(replay.world.tick);
        }
    }
    let n = worlds.len();
    let count = count.max(1).min(n.max(1));
    let ticks: Vec<u64> = (0..count).filter_map(|i| worlds.get((2 * i + 1) * n / (2 * count)).copied()).collect();
    let mut replay = Replay::open(path, scene.track.clone())?;
    let mut frames = vec![];
    let mut k = 0;
    while replay.advance()? {
        let w = &replay.world;
        if ticks.contains(&w.tick) {
            let mut views = vec![View::ChaseNear];
            if k % 2 == 1 {
                views.extend([View::ChaseFar, View::Bumper, View::Trackside]);
            }
            for view in views {
                frames.push(BenchFrame {
                    name: format!("tick {} {view:?}", w.tick),
                    camera: camera_for(w, view),
                    instances: scene.instances(w, None),
                });
            }
            k += 1;
        }
    }
    Ok(frames)
}

/// The tick the stability sequence starts at on the demo race (the chase camera on a fast stretch).
pub const SEQUENCE_START: u64 = 3000;

/// Ticks between the stability sequence's frames: 60 frames per second of race time.
pub const SEQUENCE_STEP: u64 = 2;

/// `count` consecutive chase-camera frames for the temporal-stability measure: ticks [`SEQUENCE_START`] on,
/// every [`SEQUENCE_STEP`]th tick, moved back to fit in the racing part of the trace when it is shorter (and
/// cut to the racing part when that is shorter than the sequence).
pub fn collect_sequence(scene: &RaceScene, path: &Path, count: usize) -> Result<Vec<BenchFrame>, ReplayError> {
    let mut replay = Replay::open(path, scene.track.clone())?;
    let (mut first, mut last) = (None, 0);
    while replay.advance()? {
        if !replay.world.race.holding() {
            first = first.or(Some(replay.world.tick));
            last = replay.world.tick;
        }
    }
    let Some(first) = first else { return Ok(vec![]) };
    let span = SEQUENCE_STEP * count.saturating_sub(1) as u64;
    let start = SEQUENCE_START.min(last.saturating_sub(span)).max(first);
    let ticks = |t: u64| t >= start && t <= last && (t - start).is_multiple_of(SEQUENCE_STEP) && t - start <= span;
    let mut replay = Replay::open(path, scene.track.clone())?;
    let mut frames = vec![];
    while replay.advance()? {
        let w = &replay.world;
        if ticks(w.tick) {
            frames.push(BenchFrame {
                name: format!("tick {} {:?}", w.tick, View::ChaseNear),
                camera: camera_for(w, View::ChaseNear),
                instances: scene.instances(w, None),
            });
        }
    }
    Ok(frames)
}

/// LOD pops per minute of race time for each of `settings` (options and frame size): the whole trace at
/// `path` replayed at 60 frames per second (every [`SEQUENCE_STEP`]th tick, the countdown included) from the
/// chase camera, one renderer per distinct LOD bias, cross-fade choice and frame size keeping its LOD
/// history as the game does, counting the frames in which an instance seen in this frame and the one before
/// is drawn with another model than before, at once ([`pops`]; with `lod_fade` a change starts a cross-fade
/// instead, which is no pop). Forced levels never pop: 0 without replaying. Only the LOD choice and the
/// view culling run (no drawing).
pub fn lod_pops_per_min(
    scene: &RaceScene,
    path: &Path,
    settings: &[(RenderOptions, (usize, usize))],
) -> Result<Vec<f64>, ReplayError> {
    // One renderer per distinct LOD choice: only the bias and the frame size matter to it.
    let key = |(o, size): &(RenderOptions, (usize, usize))| {
        (o.lod == LodMode::Auto).then_some((o.lod_bias.to_bits(), o.lod_fade, *size))
    };
    let mut keys: Vec<(u32, bool, (usize, usize))> = settings.iter().filter_map(key).collect();
    keys.sort_unstable();
    keys.dedup();
    let mut pops = vec![0u64; keys.len()];
    let mut renderers: Vec<Renderer> = keys.iter().map(|_| Renderer::new()).collect();
    let mut previous: Vec<Vec<Option<(usize, bool)>>> = vec![vec![]; keys.len()];
    let mut frames = 0u64;
    let mut replay = Replay::open(path, scene.track.clone())?;
    while !keys.is_empty() && replay.advance()? {
        let w = &replay.world;
        if !w.tick.is_multiple_of(SEQUENCE_STEP) {
            continue;
        }
        frames += 1;
        let (camera, instances) = (camera_for(w, View::ChaseNear), scene.instances(w, None));
        let list = scene.draw_list(&instances);
        for (k, &(bias, lod_fade, (width, height))) in keys.iter().enumerate() {
            let lod_bias = f32::from_bits(bias);
            let options = RenderOptions { lod: LodMode::Auto, lod_bias, lod_fade, ..RenderOptions::default() };
            let now = renderers[k].frame_lod(width, height, &camera, &list, &options);
            pops[k] += self::pops(&previous[k], &now);
            previous[k] = now;
        }
    }
    let minutes = frames as f64 / (60.0 * 60.0);
    let per_min = |k: usize| if minutes > 0.0 { pops[k] as f64 / minutes } else { 0.0 };
    Ok(settings.iter().map(|s| key(s).and_then(|k| keys.binary_search(&k).ok()).map_or(0.0, per_min)).collect())
}

/// How many instances are drawn with another mesh in `now` than in `before` (from [`Renderer::frame_lod`])
/// at once, among those seen in both: one coming into view or leaving it is no pop, nor is a change that
/// starts a cross-fade (marked `true` in `now`).
#[must_use]
pub fn pops(before: &[Option<(usize, bool)>], now: &[Option<(usize, bool)>]) -> u64 {
    let popped = |a: &Option<(usize, bool)>, b: &Option<(usize, bool)>| match (a, b) {
        (Some((m, fading)), Some((was, _))) => m != was && !fading,
        _ => false,
    };
    now.iter().zip(before).filter(|(a, b)| popped(a, b)).count() as u64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Level;

    fn demo() -> (RaceScene, std::path::PathBuf) {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
        (RaceScene::load(&dir, crate::shell::race_scene::DEFAULT_COURSE).unwrap(), dir.join("replays/demo-race.trace"))
    }

    #[test]
    fn a_pop_is_another_mesh_for_an_instance_seen_in_both_frames() {
        let swap = |v: &[Option<usize>]| v.iter().map(|m| m.map(|m| (m, false))).collect::<Vec<_>>();
        let before = swap(&[Some(1), Some(2), None, Some(4), Some(5)]);
        assert_eq!(pops(&before, &swap(&[Some(1), Some(3), Some(7), None, Some(6)])), 2);
        assert_eq!(pops(&[], &swap(&[Some(1)])), 0);
        // A change that starts a cross-fade is no pop.
        assert_eq!(pops(&before, &[Some((1, false)), Some((3, true)), None, None, Some((6, false))]), 1);
    }

    #[test]
    fn the_sequence_is_consecutive_chase_frames_from_tick_3000() {
        let (scene, trace) = demo();
        let seq = collect_sequence(&scene, &trace, 20).unwrap();
        let names: Vec<&str> = seq.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names.len(), 20);
        assert_eq!((names[0], names[19]), ("tick 3000 ChaseNear", "tick 3038 ChaseNear"));
        assert_eq!(collect_sequence(&scene, &trace, 1).unwrap()[0].name, "tick 3000 ChaseNear");
    }

    #[test]
    fn only_the_automatic_choice_pops_and_one_setting_counts_the_same_every_time() {
        let (scene, trace) = demo();
        let auto = RenderOptions::default();
        let long = RenderOptions { lod: LodMode::Force(Level::Long), ..auto };
        let size = (160, 120);
        let p = lod_pops_per_min(&scene, &trace, &[(auto, size), (long, size), (auto, size)]).unwrap();
        assert!(p[0] > 0.0 && p[0].is_finite(), "{p:?}");
        assert_eq!((p[1], p[2]), (0.0, p[0]));
        assert_eq!(lod_pops_per_min(&scene, &trace, &[(long, size)]).unwrap(), [0.0]);
    }
}
