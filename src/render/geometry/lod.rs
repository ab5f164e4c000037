//! Level of detail (seed 003, Namco): choosing a close, middle or long-shot model per object per frame.
//!
//! The seed picks the model by distance; here the choice is by projected size in pixels, which also accounts
//! for the field of view and the resolution: a car 100 pixels tall gets the same model whether that comes
//! from being near, from a narrow lens or from a large frame. Each
//! [`LodSet`](crate::render::core::draw_list::LodSet) says below which projected height (in pixels) its
//! middle and long models take over. A choice only changes when the size moves [`HYSTERESIS`] past a
//! threshold, so an object hovering at one does not flicker between models.

use crate::render::core::camera::Camera;
use crate::render::core::draw_list::{DrawList, Instance};
use crate::render::core::options::{Level, LodMode, RenderOptions};
use crate::render::core::stats::Stats;

use crate::render::geometry::cull::world_sphere;

/// Relative margin around each threshold: switching to a finer model needs the size to exceed the threshold
/// by this much, switching to a coarser one to fall this much below it.
pub const HYSTERESIS: f32 = 0.15;

/// The level for a projected height, given the level used last frame (if any). An infinite height (the eye
/// inside the object's bounding sphere, as the bumper camera is in the player's car) is the close model; a
/// NaN height keeps the previous level (the long one without history).
#[must_use]
pub fn choose(size_px: f32, switch_px: [f32; 2], previous: Option<Level>) -> Level {
    let plain = |margin: [f32; 2]| {
        if size_px >= switch_px[0] * margin[0] {
            Level::Close
        } else if size_px >= switch_px[1] * margin[1] {
            Level::Mid
        } else {
            Level::Long
        }
    };
    if size_px.is_nan() {
        return previous.unwrap_or(Level::Long);
    }
    let Some(prev) = previous else {
        return plain([1.0, 1.0]);
    };
    let (up, down) = (1.0 + HYSTERESIS, 1.0 - HYSTERESIS);
    // The thresholds next to the current level are moved away from it, so it takes a clear change to leave.
    let margins = match prev {
        Level::Close => [down, down],
        Level::Mid => [up, down],
        Level::Long => [up, up],
    };
    plain(margins)
}

/// Per-instance memory of the level last drawn, kept by the renderer from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct LodState {
    levels: Vec<u8>,
}

const NO_LEVEL: u8 = u8::MAX;

impl LodState {
    /// The level instance `i` was drawn at last frame.
    #[must_use]
    pub fn previous(&self, i: usize) -> Option<Level> {
        self.levels.get(i).and_then(|&l| Level::from_index(l))
    }

    /// Records the level of instance `i`.
    pub fn set(&mut self, i: usize, level: Level) {
        if self.levels.len() <= i {
            self.levels.resize(i + 1, NO_LEVEL);
        }
        self.levels[i] = level as u8;
    }

    /// Forgets every level (for a new scene or a camera cut).
    pub fn clear(&mut self) {
        self.levels.clear();
    }

    /// The level slots of instances `0..n` (a slot without history holds no level), for
    /// [`pick_level`] on each, possibly on several threads.
    pub(crate) fn slots(&mut self, n: usize) -> &mut [u8] {
        if self.levels.len() < n {
            self.levels.resize(n, NO_LEVEL);
        }
        &mut self.levels[..n]
    }

    /// Picks the mesh instance `index` draws this frame ([`pick_level`] on its slot).
    pub(crate) fn pick(
        &mut self,
        index: usize,
        inst: &Instance,
        list: &DrawList<'_>,
        view: (&Camera, f32),
        options: &RenderOptions,
        stats: &mut Stats,
    ) -> Option<usize> {
        let slot = self.slots(index + 1).last_mut()?;
        pick_level(slot, inst, list, view, options, stats)
    }
}

/// Picks the mesh an instance draws this frame: its own, or the level of its LOD set for its projected size
/// (seed 003's rule), remembered in `slot` (the level drawn last frame) for the next frame's hysteresis;
/// `None` when it names a set or a close model that does not exist. `y_scale_px` is the projected diameter
/// in pixels of a unit radius at unit depth.
pub(crate) fn pick_level(
    slot: &mut u8,
    inst: &Instance,
    list: &DrawList<'_>,
    (camera, y_scale_px): (&Camera, f32),
    options: &RenderOptions,
    stats: &mut Stats,
) -> Option<usize> {
    let Some(set) = inst.lod.map(|s| list.lod_sets.get(s)) else {
        return Some(inst.mesh);
    };
    let set = set?;
    let close = list.meshes.get(set.meshes[0])?;
    let level = match options.lod {
        LodMode::Force(level) => level,
        LodMode::Auto => {
            let (center, radius) = world_sphere(close.bounds(), &inst.model);
            let size = projected_size((center, radius), camera, y_scale_px) * libm::exp2f(options.lod_bias);
            choose(if size.is_nan() { 0.0 } else { size }, set.switch_px, Level::from_index(*slot))
        }
    };
    *slot = level as u8;
    let chosen = set.meshes[level as usize];
    match level {
        Level::Close => stats.lod_close += 1,
        Level::Mid => stats.lod_mid += 1,
        Level::Long => stats.lod_long += 1,
    }
    let used = list.meshes.get(chosen).map_or(0, |m| m.polygons().len());
    stats.polygons_saved_by_lod += close.polygons().len().saturating_sub(used) as u64;
    Some(chosen)
}

/// The projected height in pixels of a sphere (world `center`, `radius`) seen by `camera`: infinite when the
/// eye is inside it or it is behind the eye.
fn projected_size((center, radius): (glam::Vec3, f32), camera: &Camera, y_scale_px: f32) -> f32 {
    if !camera.is_perspective() {
        return radius * y_scale_px;
    }
    let depth = -(camera.view.transform_point3(center).z);
    if depth > radius { radius * y_scale_px / depth } else { f32::INFINITY }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thresholds_without_history() {
        let s = [120.0, 24.0];
        assert_eq!(choose(500.0, s, None), Level::Close);
        assert_eq!(choose(120.0, s, None), Level::Close);
        assert_eq!(choose(119.0, s, None), Level::Mid);
        assert_eq!(choose(24.0, s, None), Level::Mid);
        assert_eq!(choose(23.9, s, None), Level::Long);
        assert_eq!(choose(f32::NAN, s, None), Level::Long);
        assert_eq!(choose(f32::NAN, s, Some(Level::Mid)), Level::Mid);
        // The eye inside the bounding sphere: the close model, with or without history.
        assert_eq!(choose(f32::INFINITY, s, None), Level::Close);
        assert_eq!(choose(f32::INFINITY, s, Some(Level::Long)), Level::Close);
    }

    #[test]
    fn hysteresis_keeps_the_current_level_near_a_threshold() {
        let s = [120.0, 24.0];
        assert_eq!(choose(110.0, s, Some(Level::Close)), Level::Close);
        assert_eq!(choose(103.0, s, Some(Level::Close)), Level::Close);
        assert_eq!(choose(101.0, s, Some(Level::Close)), Level::Mid);
        assert_eq!(choose(101.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(130.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(139.0, s, Some(Level::Mid)), Level::Close);
        assert_eq!(choose(21.0, s, Some(Level::Mid)), Level::Mid);
        assert_eq!(choose(20.0, s, Some(Level::Mid)), Level::Long);
        assert_eq!(choose(26.0, s, Some(Level::Long)), Level::Long);
        assert_eq!(choose(28.0, s, Some(Level::Long)), Level::Mid);
        assert_eq!(choose(1000.0, s, Some(Level::Long)), Level::Close);
    }

    #[test]
    fn a_slow_approach_and_retreat_switch_once_each_way() {
        let s = [120.0, 24.0];
        let mut level = None;
        let mut switches = vec![];
        // Size oscillates by ±5% around a slow ramp up and then down through both thresholds.
        let sizes: Vec<f32> = (0..2000)
            .map(|i| {
                let t = if i < 1000 { i as f32 / 1000.0 } else { (2000 - i) as f32 / 1000.0 };
                let base = 10.0 * libm::powf(20.0f32, t);
                base * (1.0 + 0.05 * libm::sinf((i as f32) * 0.7))
            })
            .collect();
        for size in sizes {
            let l = choose(size, s, level);
            if level.is_some_and(|p| p != l) {
                switches.push(l);
            }
            level = Some(l);
        }
        assert_eq!(switches, [Level::Mid, Level::Close, Level::Mid, Level::Long]);
    }

    #[test]
    fn state_remembers_per_instance() {
        let mut st = LodState::default();
        assert_eq!(st.previous(3), None);
        st.set(3, Level::Mid);
        assert_eq!(st.previous(3), Some(Level::Mid));
        assert_eq!(st.previous(0), None);
        st.clear();
        assert_eq!(st.previous(3), None);
    }
}
