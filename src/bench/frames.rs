//! The frames the bench draws: ticks of a demo replay seen from the chase camera, and fixed views of the
//! same moments from the other cameras (far chase, bumper, trackside), as camera and instance lists.

use std::path::Path;

use crate::input::replay::{Replay, ReplayError};
use crate::render::{Camera, Instance};
use crate::shell::race_scene::{FIELD, RaceScene, View, camera_for};

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
    let mut replay = Replay::open(path, scene.track.clone(), FIELD)?;
    let mut worlds = vec![];
    while replay.advance()? {
        if !replay.world.race.holding() {
            worlds.push(replay.world.tick);
        }
    }
    let n = worlds.len();
    let count = count.max(1).min(n.max(1));
    let ticks: Vec<u64> = (0..count).filter_map(|i| worlds.get((2 * i + 1) * n / (2 * count)).copied()).collect();
    let mut replay = Replay::open(path, scene.track.clone(), FIELD)?;
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
