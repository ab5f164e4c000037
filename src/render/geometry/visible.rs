//! The visibility pass: every instance's model chosen ([`lod`](super::lod)) and culled by the view frustum
//! ([`cull`](mod@super::cull)) before any vertex is transformed, on the worker pool for a scene of many
//! objects.
//!
//! A course dressed with thousands of trees and rocks has ten times more instances than it draws, and
//! choosing and culling each is a few dozen nanoseconds: done one by one on one thread, interleaved with
//! the set-up, it was a tenth of a mountain frame. Each instance's choice depends only on itself and its
//! own slot of the LOD history, so the pass splits the instances into contiguous chunks and keeps the
//! survivors in instance order: the result is the same for any thread count.

use glam::Vec3;
use rayon::iter::{IndexedParallelIterator, IntoParallelRefMutIterator, ParallelIterator};
use rayon::slice::{ParallelSlice, ParallelSliceMut};

use super::cull::{Frustum, model_scale, world_sphere, world_sphere_scaled};
use super::lod::{LodState, pick_level};
use crate::render::core::camera::Camera;
use crate::render::core::door::Door;
use crate::render::core::draw_list::{DrawList, Instance};
use crate::render::core::mesh::Mesh;
use crate::render::core::options::{Method, RenderOptions};
use crate::render::core::stats::Stats;

/// Scenes with at least this many instances are chosen and culled on several threads.
const PARALLEL_INSTANCES: usize = 1024;

/// An instance that survived the pass: what its set-up needs.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Visible {
    /// The instance's index in the draw list.
    pub(crate) index: usize,
    /// The mesh chosen for it (an index into the draw list's meshes).
    pub(crate) mesh: usize,
    /// Its world bounding sphere (centre, radius).
    pub(crate) sphere: (Vec3, f32),
    /// The screen door it is drawn through: none, or one side of a level-of-detail cross-fade.
    pub(crate) door: Door,
}

/// What the pass reads of the frame.
pub(crate) struct PassView<'a> {
    /// The camera, for the projected size.
    pub(crate) camera: &'a Camera,
    /// Projected diameter in pixels of a unit radius at unit depth.
    pub(crate) y_scale_px: f32,
    /// The view frustum.
    pub(crate) frustum: &'a Frustum,
    /// The frame's objects.
    pub(crate) list: &'a DrawList<'a>,
    /// The frame's options (LOD rule, method).
    pub(crate) options: &'a RenderOptions,
}

impl<'a> PassView<'a> {
    /// The mesh the set-up draws for mesh index `m`: the mesh itself, or under `view-lists` its extended
    /// mesh (the original polygons followed by their split pieces).
    pub(crate) fn drawn_mesh(&self, m: usize) -> Option<&'a Mesh> {
        let mesh = self.list.meshes.get(m)?;
        let lists = (self.options.method == Method::ViewLists).then(|| self.list.view_lists.and_then(|v| v.get(m)));
        Some(lists.flatten().map_or(mesh, |l| &l.mesh))
    }

    /// Chooses instance `index`'s model (updating its LOD `slot`) and culls it; counts both in `stats`. During
    /// a level-of-detail cross-fade, the model fading out follows the chosen one, each through its door.
    fn classify(&self, index: usize, inst: &Instance, slot: &mut u8, stats: &mut Stats) -> [Option<Visible>; 2] {
        stats.objects_in += 1;
        let view = (self.camera, self.y_scale_px);
        let scale = model_scale(&inst.model);
        let Some(picked) = pick_level(slot, (inst, scale), self.list, view, self.options, stats) else {
            stats.objects_culled += 1;
            return [None, None];
        };
        let chosen = self.placed((index, inst, scale), (picked.mesh, picked.door), stats);
        // The model fading out is drawn only where the chosen one is (a culled object is culled whole).
        let fading = chosen.and(picked.fading).and_then(|m| self.placed((index, inst, scale), m, stats));
        [chosen, fading]
    }

    /// Instance `index` (of model scale `scale`) drawing mesh `m` through `door`, or `None` (counted in
    /// `stats`) when the mesh is not in the list or the frustum excludes it.
    fn placed(
        &self,
        (index, inst, scale): (usize, &Instance, f32),
        (m, door): (usize, Door),
        stats: &mut Stats,
    ) -> Option<Visible> {
        let Some(mesh) = self.drawn_mesh(m) else {
            stats.objects_culled += 1;
            return None;
        };
        let npoly = mesh.polygons().len() as u64;
        stats.polygons_in += npoly;
        let sphere = world_sphere_scaled(mesh.bounds(), &inst.model, scale);
        let culled = excluded(sphere, self.frustum);
        if culled {
            stats.objects_culled += 1;
            stats.polygons_in_culled_objects += npoly;
            return None;
        }
        Some(Visible { index, mesh: m, sphere, door })
    }
}

/// The world bounding sphere of `mesh` placed by `inst`, and whether the frustum excludes it.
pub(crate) fn cull(mesh: &Mesh, inst: &Instance, frustum: &Frustum) -> ((Vec3, f32), bool) {
    let sphere = world_sphere(mesh.bounds(), &inst.model);
    (sphere, excluded(sphere, frustum))
}

/// Whether the frustum excludes world sphere `(center, radius)`; a sphere that is not finite never is.
fn excluded((center, radius): (Vec3, f32), frustum: &Frustum) -> bool {
    center.is_finite() && radius.is_finite() && frustum.excludes(center, radius)
}

/// Chooses and culls every instance of the view's list into `out` (in instance order), on the current pool
/// when `threads > 1` and the list is long, each chunk into its own list of `chunks`; adds the counts to
/// `stats`.
pub(crate) fn visible_objects(
    view: &PassView<'_>,
    lod: &mut LodState,
    threads: usize,
    (chunks, out): (&mut Vec<Vec<Visible>>, &mut Vec<Visible>),
    stats: &mut Stats,
) {
    out.clear();
    let instances = view.list.instances;
    let slots = lod.slots(instances.len());
    if threads <= 1 || instances.len() < PARALLEL_INSTANCES {
        for ((index, inst), slot) in instances.iter().enumerate().zip(slots) {
            out.extend(view.classify(index, inst, slot, stats).into_iter().flatten());
        }
        return;
    }
    let size = instances.len().div_ceil(threads * 4);
    let count = instances.len().div_ceil(size);
    chunks.resize_with(count, Vec::new);
    let counts = chunks[..count]
        .par_iter_mut()
        .zip(instances.par_chunks(size).zip(slots.par_chunks_mut(size)))
        .enumerate()
        .map(|(k, (found, (insts, slots)))| {
            found.clear();
            let mut s = Stats::default();
            for (i, (inst, slot)) in insts.iter().zip(slots).enumerate() {
                found.extend(view.classify(k * size + i, inst, slot, &mut s).into_iter().flatten());
            }
            s
        })
        .reduce(Stats::default, add_counts);
    *stats = add_counts(std::mem::take(stats), counts);
    for found in &chunks[..count] {
        out.extend_from_slice(found);
    }
}

/// `a` with the pass's counts of `b` added (integers, so the order of the sums does not matter).
fn add_counts(mut a: Stats, b: Stats) -> Stats {
    a.objects_in += b.objects_in;
    a.objects_culled += b.objects_culled;
    a.polygons_in += b.polygons_in;
    a.polygons_in_culled_objects += b.polygons_in_culled_objects;
    a.lod_close += b.lod_close;
    a.lod_mid += b.lod_mid;
    a.lod_long += b.lod_long;
    a.polygons_saved_by_lod += b.polygons_saved_by_lod;
    a
}
