//! Level of detail (seed 003, Namco): choosing a close, middle or long-shot model per object per frame.
//!
//! The seed picks the model by distance; here the choice is by projected size in pixels, which also accounts
//! for the field of view and the resolution: a car 100 pixels tall gets the same model whether that comes
//! from being near, from a narrow lens or from a large frame. Each
//! [`LodSet`](crate::render::core::draw_list::LodSet) says below which projected height (in pixels) its
//! middle and long models take over. A choice only changes when the size moves [`HYSTERESIS`] past a
//! threshold, so an object hovering at one does not flicker between models.

use crate::render::core::camera::Camera;
use crate::render::core::door::Door;
use crate::render::core::draw_list::{DrawList, Instance};
use crate::render::core::options::{Level, LodMode, RenderOptions};
use crate::render::core::stats::Stats;

use crate::render::geometry::cull::{model_scale, world_sphere_scaled};

/// Relative margin around each threshold: switching to a finer model needs the size to exceed the threshold
/// by this much, switching to a coarser one to fall this much below it.
pub const HYSTERESIS: f32 = 0.15;

/// How far [`HYSTERESIS`]'s band moves up when changes of model are cross-faded: a fade draws both models
/// for [`FADE_FRAMES`] frames, and stepping down 5% sooner and up 5% later draws fewer polygons over a race
/// than those frames add (`examples/lod_polygons.rs` at 640x480: 0.52-1.25% fewer than swapping on the demo
/// races, where the unmoved band drew 0.07-0.28% more). Frames without history keep the plain thresholds.
pub const FADE_SHIFT: f32 = 0.05;

/// The level for a projected height, given the level used last frame (if any). An infinite height (the eye
/// inside the object's bounding sphere, as the bumper camera is in the player's car) is the close model; a
/// NaN height keeps the previous level (the long one without history).
#[must_use]
pub fn choose(size_px: f32, switch_px: [f32; 2], previous: Option<Level>) -> Level {
    choose_shifted(size_px, switch_px, previous, 0.0)
}

/// [`choose`] with the hysteresis band moved up by `shift` (relative, at most [`HYSTERESIS`]): a model
/// steps down that much sooner and up that much later. Without history the thresholds are unmoved.
#[must_use]
pub fn choose_shifted(size_px: f32, switch_px: [f32; 2], previous: Option<Level>, shift: f32) -> Level {
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
    let (up, down) = (1.0 + HYSTERESIS + shift, 1.0 - HYSTERESIS + shift);
    // The thresholds next to the current level are moved away from it, so it takes a clear change to leave.
    let margins = match prev {
        Level::Close => [down, down],
        Level::Mid => [up, down],
        Level::Long => [up, up],
    };
    plain(margins)
}

/// Frames a cross-fade lasts ([`RenderOptions::lod_fade`]): the new model through a quarter of the pixels
/// for two frames, half for two, three quarters for two, then alone.
pub const FADE_FRAMES: u8 = 6;

/// Per-instance memory of the level last drawn and of a cross-fade under way, kept by the renderer from
/// frame to frame: a byte each, the level in bits 0-1, the level fading out in bits 2-3 and the frames the
/// fade has left in bits 4-6 (0: none); `NO_LEVEL` without history.
#[derive(Clone, Debug, Default)]
pub struct LodState {
    levels: Vec<u8>,
}

const NO_LEVEL: u8 = u8::MAX;

/// The level a slot holds.
fn slot_level(slot: u8) -> Option<Level> {
    if slot == NO_LEVEL { None } else { Level::from_index(slot & 3) }
}

/// The fade a slot holds: the level fading out and the frames left (this one included).
fn slot_fade(slot: u8) -> Option<(Level, u8)> {
    let left = (slot >> 4) & 7;
    if slot == NO_LEVEL || left == 0 { None } else { Some((Level::from_index((slot >> 2) & 3)?, left)) }
}

/// A slot holding `level` and `fade`.
fn slot_of(level: Level, fade: Option<(Level, u8)>) -> u8 {
    let (from, left) = fade.map_or((0, 0), |(l, n)| (l as u8, n.min(7)));
    level as u8 | from << 2 | left << 4
}

impl LodState {
    /// The level instance `i` was drawn at last frame.
    #[must_use]
    pub fn previous(&self, i: usize) -> Option<Level> {
        self.levels.get(i).and_then(|&l| slot_level(l))
    }

    /// Records the level of instance `i` (with no fade under way).
    pub fn set(&mut self, i: usize, level: Level) {
        if self.levels.len() <= i {
            self.levels.resize(i + 1, NO_LEVEL);
        }
        self.levels[i] = slot_of(level, None);
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
    ) -> Option<Picked> {
        let slot = self.slots(index + 1).last_mut()?;
        pick_level(slot, (inst, model_scale(&inst.model)), list, view, options, stats)
    }
}

/// The mesh an instance draws this frame, and during a cross-fade the mesh fading out with the doors the
/// two are drawn through (each pixel through exactly one of them).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Picked {
    /// The mesh chosen (an index into the draw list's meshes).
    pub(crate) mesh: usize,
    /// The door the chosen mesh is drawn through (none outside a fade).
    pub(crate) door: Door,
    /// During a fade: the mesh fading out and its door (the inverse of `door`).
    pub(crate) fading: Option<(usize, Door)>,
}

/// Picks the mesh an instance draws this frame: its own, or the level of its LOD set for its projected size
/// (seed 003's rule), remembered in `slot` (the level drawn last frame) for the next frame's hysteresis;
/// with [`RenderOptions::lod_fade`], a change of level starts a cross-fade of [`FADE_FRAMES`] frames from
/// the old model to the new (not for a see-through instance, whose pixels are a door already). `None` when
/// it names a set or a close model that does not exist. `y_scale_px` is the projected diameter in pixels of
/// a unit radius at unit depth.
pub(crate) fn pick_level(
    slot: &mut u8,
    (inst, scale): (&Instance, f32),
    list: &DrawList<'_>,
    (camera, y_scale_px): (&Camera, f32),
    options: &RenderOptions,
    stats: &mut Stats,
) -> Option<Picked> {
    let Some(set) = inst.lod.map(|s| list.lod_sets.get(s)) else {
        return Some(Picked { mesh: inst.mesh, door: Door::NONE, fading: None });
    };
    let set = set?;
    let close = list.meshes.get(set.meshes[0])?;
    let previous = slot_level(*slot);
    // Fades draw both models for a few frames: they move the hysteresis band (`FADE_SHIFT`) and, below, go
    // on from frame to frame.
    let fades = options.lod_fade && options.lod == LodMode::Auto && !inst.see_through;
    let level = match options.lod {
        LodMode::Force(level) => level,
        LodMode::Auto => {
            let (center, radius) = world_sphere_scaled(close.bounds(), &inst.model, scale);
            // `exp2f(0)` is exactly 1: the default bias needs no call of it for each of thousands of instances.
            let bias = if options.lod_bias == 0.0 { 1.0 } else { libm::exp2f(options.lod_bias) };
            let size = projected_size((center, radius), camera, y_scale_px) * bias;
            let shift = if fades { FADE_SHIFT } else { 0.0 };
            choose_shifted(if size.is_nan() { 0.0 } else { size }, set.switch_px, previous, shift)
        }
    };
    // A fade under way goes on a frame; a change of level starts a new one from the level drawn last frame.
    let mut fade = slot_fade(*slot).and_then(|(from, left)| (left > 1 && fades).then_some((from, left - 1)));
    if let Some(before) = previous.filter(|p| *p != level && fades) {
        fade = Some((before, FADE_FRAMES));
    }
    *slot = slot_of(level, fade);
    let chosen = set.meshes[level as usize];
    match level {
        Level::Close => stats.lod_close += 1,
        Level::Mid => stats.lod_mid += 1,
        Level::Long => stats.lod_long += 1,
    }
    let used = list.meshes.get(chosen).map_or(0, |m| m.polygons().len());
    stats.polygons_saved_by_lod += close.polygons().len().saturating_sub(used) as u64;
    let Some((from, left)) = fade else { return Some(Picked { mesh: chosen, door: Door::NONE, fading: None }) };
    // Frames left 6 and 5: a quarter of the pixels are the new model's; 4 and 3: half; 2 and 1: three quarters.
    let quarters = 4 - left.div_ceil(2);
    let (door, old_door) = (Door::quarters(quarters, false)?, Door::quarters(quarters, true)?);
    Some(Picked { mesh: chosen, door, fading: Some((set.meshes[from as usize], old_door)) })
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
    fn a_shifted_band_steps_down_sooner_and_up_later() {
        let s = [120.0, 24.0];
        let shifted = |size: f32, previous: Option<Level>| choose_shifted(size, s, previous, FADE_SHIFT);
        // Close -> Mid below 120 * 0.90 = 108 instead of 102.
        assert_eq!(choose(107.0, s, Some(Level::Close)), Level::Close);
        assert_eq!(shifted(107.0, Some(Level::Close)), Level::Mid);
        assert_eq!(shifted(108.5, Some(Level::Close)), Level::Close);
        // Mid -> Close from 120 * 1.20 = 144 instead of 138.
        assert_eq!(choose(140.0, s, Some(Level::Mid)), Level::Close);
        assert_eq!(shifted(140.0, Some(Level::Mid)), Level::Mid);
        assert_eq!(shifted(144.5, Some(Level::Mid)), Level::Close);
        // Mid -> Long below 24 * 0.90 = 21.6; Long -> Mid from 24 * 1.20 = 28.8.
        assert_eq!(shifted(21.5, Some(Level::Mid)), Level::Long);
        assert_eq!(shifted(28.0, Some(Level::Long)), Level::Long);
        assert_eq!(shifted(29.0, Some(Level::Long)), Level::Mid);
        // Without history the thresholds are the plain ones, so no first frame is followed by a change.
        for size in [23.9, 24.0, 119.0, 120.0] {
            assert_eq!(shifted(size, None), choose(size, s, None));
            let first = choose(size, s, None);
            assert_eq!(shifted(size, Some(first)), first, "size {size}");
        }
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

    #[test]
    fn a_change_of_level_starts_a_fade_that_runs_six_frames_and_then_draws_the_new_model_alone() {
        use crate::render::core::draw_list::LodSet;
        use crate::render::core::mesh::MeshBuilder;
        let mut b = MeshBuilder::new();
        let m = b.material(crate::render::core::mesh::Material::default());
        let corners = [glam::Vec3::ZERO, glam::Vec3::X, glam::Vec3::Y]
            .map(|p| b.vertex(crate::render::core::mesh::Vertex::new(p, glam::Vec2::ZERO)));
        b.polygon(&corners, m);
        let mesh = b.build().unwrap();
        let meshes = [mesh.clone(), mesh.clone(), mesh];
        let sets = [LodSet { meshes: [0, 1, 2], switch_px: [120.0, 24.0] }];
        let camera = Camera::look_at(glam::Vec3::new(0.0, 0.0, 5.0), glam::Vec3::ZERO, 1.0, 0.1, None);
        let mut slot = NO_LEVEL;
        let fade = RenderOptions { lod_fade: true, ..RenderOptions::default() };
        let mut pick = |scale: f32, options: &RenderOptions| {
            let inst = Instance::of_lod_set(0, glam::Mat4::from_scale(glam::Vec3::splat(scale)));
            let list =
                DrawList { meshes: &meshes, textures: &[], instances: &[inst], lod_sets: &sets, view_lists: None };
            pick_level(
                &mut slot,
                (&inst, model_scale(&inst.model)),
                &list,
                (&camera, 400.0),
                options,
                &mut Stats::default(),
            )
            .unwrap()
        };
        // Near (close model), then far enough for the middle one: six frames of fade, quarters 1, 1, 2, 2, 3, 3.
        assert_eq!(pick(4.0, &fade).fading, None);
        let frames: Vec<Picked> = (0..8).map(|_| pick(0.5, &fade)).collect();
        assert!(frames.iter().all(|p| p.mesh == 1));
        for (k, q) in [1, 1, 2, 2, 3, 3].into_iter().enumerate() {
            assert_eq!(frames[k].door, Door::quarters(q, false).unwrap(), "frame {k}");
            assert_eq!(frames[k].fading, Some((0, Door::quarters(q, true).unwrap())), "frame {k}");
        }
        assert_eq!((frames[6].door, frames[6].fading, frames[7].fading), (Door::NONE, None, None));
        // Without the option the change is a swap; a forced level never fades.
        assert_eq!(pick(4.0, &RenderOptions::default()).fading, None);
        let forced = RenderOptions { lod: LodMode::Force(Level::Long), ..fade };
        assert_eq!(pick(4.0, &forced), Picked { mesh: 2, door: Door::NONE, fading: None });
    }
}
