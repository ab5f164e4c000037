//! Geometry (Quake's `r_*` half): per object, the level of detail, culling, the vertex transform and
//! polygon set-up, once per frame, into batches (`core::batch`) the ordering and fill stages read.
//!
//! Stages, each in its file: [`lod`] (seed 003's model choice), [`cull`](mod@cull), `vertex` and
//! `transform` (with its AVX2 child), [`clip`], `setup` (gather or clip, snap, cull back faces, split
//! non-monotone polygons with [`monotone`]) and `small_setup` (small triangles set up for the fast fill).
//!
//! Per frame: the visibility pass (`visible`: model chosen, object culled) over every instance, then
//! `pieces`: the visible objects transformed and set up in submission order, on the worker pool in pieces.

pub mod clip;
pub mod cull;
pub mod lod;
pub mod monotone;
mod pieces;
pub(crate) mod setup;
pub(crate) mod small_setup;
#[cfg(target_arch = "x86_64")]
mod small_setup_avx2;
pub(crate) mod transform;
#[cfg(target_arch = "x86_64")]
mod transform_avx2;
pub(crate) mod vertex;
pub(crate) mod visible;

use std::time::Instant;

use self::clip::ClipVolume;
use self::cull::Frustum;
use self::lod::LodState;
use self::pieces::{FrameView, SetUp};
use self::visible::{PassView, Visible, cull, visible_objects};
use crate::render::core::band::FrameLayout;
use crate::render::core::batch::Stretch;
use crate::render::core::camera::Camera;
use crate::render::core::draw_list::{DrawList, Instance};
use crate::render::core::options::RenderOptions;
use crate::render::core::stats::{Stats, ms_since};
use glam::{Mat4, Vec3};

/// The geometry stage's output and scratch, kept from frame to frame so that frames after the first
/// allocate nothing per polygon.
#[derive(Debug, Default)]
pub(crate) struct Geometry {
    /// The set-up's output (the polygons the fill draws and their order) and scratch.
    pub(crate) set_up: SetUp,
    /// The level of detail each instance was drawn at last frame.
    pub(crate) lod: LodState,
    /// The instances the visibility pass kept this frame, in order, and its per-chunk lists.
    visible: Vec<Visible>,
    visible_chunks: Vec<Vec<Visible>>,
}

impl Geometry {
    /// Cull, transform, clip, project, snap and back-face cull every instance of `list`: fills
    /// `self.set_up` (the polygons and, for the z-buffer, the order of their batches).
    ///
    /// When `tall`, the frame is a rotated-grid frame drawn four rows a pixel: the camera's aspect and the
    /// models' projected sizes are those of a frame a quarter of `layout`'s height, and no small triangles
    /// are set up.
    pub(crate) fn run(
        &mut self,
        (layout, tall): (FrameLayout, bool),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
        stats: &mut Stats,
    ) {
        let rows = if tall { layout.height / 4 } else { layout.height };
        let clip_from_view = shifted_clip_from_view(camera, (layout.width, layout.height), rows, options);
        let clip_from_world = clip_from_view * camera.view;
        let world_from_view = camera.view.inverse();
        let t_visible = Instant::now();
        let frustum = Frustum::new(&clip_from_world, camera.has_far_plane());
        let y_scale_px = clip_from_view.y_axis.y * rows as f32;
        let pass = PassView { camera, y_scale_px, frustum: &frustum, list, options };
        let mut visible = std::mem::take(&mut self.visible);
        visible_objects(&pass, &mut self.lod, layout.threads, (&mut self.visible_chunks, &mut visible), stats);
        stats.ms_transform += ms_since(t_visible);
        let view = FrameView {
            camera,
            clip_from_world,
            volume: ClipVolume::new(layout.width, layout.height, camera.has_far_plane()),
            eye: world_from_view.w_axis.truncate(),
            forward: -world_from_view.z_axis.truncate(),
            layout,
            list,
            options,
            tall,
        };
        self.set_up.run(&view, &pass, &visible, stats);
        self.visible = visible;
    }

    /// How many polygons (or pieces of split ones) the last frame handed to the fill.
    pub(crate) fn pieces(&self) -> u64 {
        let s = &self.set_up;
        let in_batches = s.stretches.iter().filter_map(|st| match st {
            Stretch::Batch(k) => s.batches.get(*k).map(|b| b.polys.len() as u64),
            Stretch::Main(_) => None,
        });
        s.main.polys.len() as u64 + in_batches.sum::<u64>()
    }

    /// The mesh each instance of `list` would draw (after the LOD choice, which updates the LOD history as
    /// a frame does) and whether a cross-fade from another is under way, or `None` for an instance culled by
    /// the view frustum or naming no mesh.
    pub(crate) fn frame_lod(
        &mut self,
        (width, height): (usize, usize),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Vec<Option<(usize, bool)>> {
        let mut stats = Stats::default();
        let clip_from_view = shifted_clip_from_view(camera, (width, height), height, options);
        let frustum = Frustum::new(&(clip_from_view * camera.view), camera.has_far_plane());
        let y_scale_px = clip_from_view.y_axis.y * height as f32;
        let lod = &mut self.lod;
        let pick = |(index, inst): (usize, &Instance)| {
            let picked = lod.pick(index, inst, list, (camera, y_scale_px), options, &mut stats)?;
            let (_, culled) = cull(list.meshes.get(picked.mesh)?, inst, &frustum);
            (!culled).then_some((picked.mesh, picked.fading.is_some()))
        };
        list.instances.iter().enumerate().map(pick).collect()
    }
}

/// The camera's view-to-clip matrix for a frame of `width` x `height` pixels whose aspect is that of `width`
/// x `rows` (`rows` is a quarter of `height` in a frame of four rows a pixel), followed by the image shift
/// of `options.pixel_offset` in the frame's pixels (a translation in NDC, which moves every projected point
/// by the same number of pixels; none when the offset is not finite).
fn shifted_clip_from_view(
    camera: &Camera,
    (width, height): (usize, usize),
    rows: usize,
    options: &RenderOptions,
) -> Mat4 {
    let clip_from_view = camera.clip_from_view(width, rows);
    let [dx, dy] = options.pixel_offset;
    if (dx == 0.0 && dy == 0.0) || !dx.is_finite() || !dy.is_finite() || width == 0 || height == 0 {
        return clip_from_view;
    }
    // x_ndc' = x_ndc + 2 dx / width: in clip space, x' = x + (2 dx / width) w, which a translation does.
    Mat4::from_translation(Vec3::new(2.0 * dx / width as f32, -2.0 * dy / height as f32, 0.0)) * clip_from_view
}
