//! Geometry (Quake's `r_*` half): per object, the level of detail, culling, the vertex transform and
//! polygon set-up, once per frame, into batches (`core::batch`) the ordering and fill stages read.
//!
//! Stages, each in its file: [`lod`] (seed 003's model choice), [`cull`](mod@cull), `vertex` and
//! `transform` (with its AVX2 child), [`clip`], `setup` (gather or clip, snap, cull back faces, split
//! non-monotone polygons with [`monotone`]) and `small_setup` (small triangles set up for the fast fill).
//!
//! An object of many polygons is set up in pieces on the worker pool, each piece into its own batch. The
//! painter's orders append the pieces' polygons to the main batch in order and sort them later; the
//! z-buffer, which draws in submission order, leaves them in their pieces, each binned by the thread that
//! set it up, and stretches (`Stretch`) say in which order to draw the main batch and the pieces. Either way
//! the result is that of one pass, for any thread count.

pub mod clip;
pub mod cull;
pub mod lod;
pub mod monotone;
pub(crate) mod setup;
pub(crate) mod small_setup;
pub(crate) mod transform;
#[cfg(target_arch = "x86_64")]
mod transform_avx2;
pub(crate) mod vertex;

use std::time::Instant;

use glam::{Mat4, Vec3};
use rayon::iter::{IndexedParallelIterator, IntoParallelRefMutIterator, ParallelIterator};
use rayon::slice::{ParallelSlice, ParallelSliceMut};

use self::clip::ClipVolume;
use self::cull::{Frustum, world_sphere};
use self::lod::LodState;
use self::setup::{ObjectSetup, SetupScratch};
use self::vertex::{SetupVertex, VertexTransform};
use crate::render::core::band::{FrameLayout, bin};
use crate::render::core::batch::{Batch, Stretch};
use crate::render::core::camera::Camera;
use crate::render::core::draw_list::{DrawList, Instance};
use crate::render::core::mesh::Mesh;
use crate::render::core::options::{Method, MipMode, RenderOptions, TextureMode};
use crate::render::core::polygon::FastPathRule;
use crate::render::core::stats::{Stats, ms_since};
use crate::render::order::view_lists::stored_order;

/// Objects with at least this many polygons are set up in pieces on several threads (below it, handing out
/// the pieces costs more than it saves).
const PARALLEL_POLYGONS: usize = 1024;

/// Objects with at least this many vertices are transformed on several threads.
const PARALLEL_VERTICES: usize = 4096;

/// The geometry stage's output and scratch, kept from frame to frame so that frames after the first
/// allocate nothing per polygon.
#[derive(Debug, Default)]
pub(crate) struct Geometry {
    /// The current object's vertices after the transform.
    vertices: Vec<SetupVertex>,
    /// The frame's polygons (for the painter's orders all of them; for the z-buffer those of objects set up
    /// in one piece).
    pub(crate) main: Batch,
    main_scratch: SetupScratch,
    /// The pieces of objects set up on several threads.
    pub(crate) batches: Vec<Batch>,
    scratch: Vec<SetupScratch>,
    /// The z-buffer's drawing order (the submission order) as stretches of the main batch and of `batches`;
    /// empty for the painter's orders, which order `main.polys`.
    pub(crate) stretches: Vec<Stretch>,
    /// The level of detail each instance was drawn at last frame.
    pub(crate) lod: LodState,
}

/// What the whole frame shares while its objects are set up one by one.
struct FrameView<'a> {
    camera: &'a Camera,
    clip_from_world: Mat4,
    frustum: Frustum,
    volume: ClipVolume,
    /// Projected diameter in pixels of a unit radius at unit depth: the projection's y scale times the height.
    y_scale_px: f32,
    /// The eye's position and view direction in world space.
    eye: Vec3,
    forward: Vec3,
    layout: FrameLayout,
    list: &'a DrawList<'a>,
    options: &'a RenderOptions,
}

/// Where the z-buffer's current stretch of the main batch starts, and how many set-up batches are in use.
#[derive(Default)]
struct Cursor {
    main_start: u32,
    batches_used: usize,
}

impl Geometry {
    /// Cull, transform, clip, project, snap and back-face cull every instance of `list`: fills `self.main`
    /// (and `self.batches`, with `self.stretches` saying the z-buffer's order).
    pub(crate) fn run(
        &mut self,
        layout: FrameLayout,
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
        stats: &mut Stats,
    ) {
        self.main.clear();
        self.stretches.clear();
        let clip_from_view = camera.clip_from_view(layout.width, layout.height);
        let clip_from_world = clip_from_view * camera.view;
        let world_from_view = camera.view.inverse();
        let view = FrameView {
            eye: world_from_view.w_axis.truncate(),
            forward: -world_from_view.z_axis.truncate(),
            camera,
            clip_from_world,
            frustum: Frustum::new(&clip_from_world, camera.has_far_plane()),
            volume: ClipVolume::new(layout.width, layout.height, camera.has_far_plane()),
            y_scale_px: clip_from_view.y_axis.y * layout.height as f32,
            layout,
            list,
            options,
        };
        let mut cursor = Cursor::default();
        for (index, inst) in list.instances.iter().enumerate() {
            self.object(&view, index, inst, &mut cursor, stats);
        }
        let end = self.main.polys.len() as u32;
        if options.method == Method::ZBuffer && cursor.main_start < end {
            self.stretches.push(Stretch::Main(cursor.main_start..end));
        }
        self.main.counts.add_to(stats);
    }

    /// How many polygons (or pieces of split ones) the last frame handed to the fill.
    pub(crate) fn pieces(&self) -> u64 {
        let in_batches = self.stretches.iter().filter_map(|s| match s {
            Stretch::Batch(k) => self.batches.get(*k).map(|b| b.polys.len() as u64),
            Stretch::Main(_) => None,
        });
        self.main.polys.len() as u64 + in_batches.sum::<u64>()
    }

    /// The mesh each instance of `list` would draw (after the LOD choice, which updates the LOD history as
    /// a frame does), or `None` for an instance culled by the view frustum or naming no mesh.
    pub(crate) fn frame_meshes(
        &mut self,
        (width, height): (usize, usize),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Vec<Option<usize>> {
        let mut stats = Stats::default();
        let clip_from_view = camera.clip_from_view(width, height);
        let frustum = Frustum::new(&(clip_from_view * camera.view), camera.has_far_plane());
        let y_scale_px = clip_from_view.y_axis.y * height as f32;
        let lod = &mut self.lod;
        let pick = |(index, inst): (usize, &Instance)| {
            let m = lod.pick(index, inst, list, (camera, y_scale_px), options, &mut stats)?;
            let (_, culled) = cull(list.meshes.get(m)?, inst, &frustum);
            (!culled).then_some(m)
        };
        list.instances.iter().enumerate().map(pick).collect()
    }

    /// One instance: its model, culled or transformed and set up.
    fn object(&mut self, view: &FrameView<'_>, index: usize, inst: &Instance, cursor: &mut Cursor, stats: &mut Stats) {
        let (list, options) = (view.list, view.options);
        stats.objects_in += 1;
        let mesh_index = self.lod.pick(index, inst, list, (view.camera, view.y_scale_px), options, stats);
        let Some(mesh) = mesh_index.and_then(|m| list.meshes.get(m)) else {
            stats.objects_culled += 1;
            return;
        };
        // `view-lists`: the mesh with its split pieces, drawn in the stored order for this view.
        let lists = mesh_index
            .filter(|_| options.method == Method::ViewLists)
            .and_then(|m| list.view_lists.and_then(|v| v.get(m)));
        // The extended mesh begins with the original polygons, so it also serves per-polygon ordering.
        let own_polygons = mesh.polygons().len();
        let mesh = lists.map_or(mesh, |l| &l.mesh);
        let npoly = mesh.polygons().len() as u64;
        stats.polygons_in += npoly;
        let t_transform = Instant::now();
        let ((center, radius), culled) = cull(mesh, inst, &view.frustum);
        if culled {
            stats.objects_culled += 1;
            stats.polygons_in_culled_objects += npoly;
            stats.ms_transform += ms_since(t_transform);
            return;
        }
        let transform = VertexTransform {
            clip_from_model: view.clip_from_world * inst.model,
            depth_row: (view.camera.view * inst.model).row(2),
            volume: view.volume,
            size: (view.layout.width as f32, view.layout.height as f32),
            perspective: view.camera.is_perspective(),
        };
        self.transform(&transform, mesh, view.layout.threads);
        stats.ms_transform += ms_since(t_transform);
        let t_clip = Instant::now();
        let stored =
            lists.and_then(|l| stored_order(l, &inst.model, (center, radius), view.camera, (view.eye, view.forward)));
        let count = stored.map_or(own_polygons, |(order, _)| order.len());
        let object = ObjectSetup {
            mesh,
            stored: stored.map(|(order, _)| order),
            vertices: &self.vertices,
            transform: &transform,
            key: options.key,
            ordered: options.method != Method::ZBuffer,
            perspective_attrs: options.texture_mode != TextureMode::Affine,
            object_key: stored.map(|(_, key)| key),
            textures: list.textures.len(),
            mip_textures: if options.mip == MipMode::Polygon { list.textures } else { &[] },
            see_through: inst.see_through,
            fast_path: FastPathRule { filter: options.filter, mode: options.texture_mode, mip: options.mip },
            antialiased: options.antialias.coverage_samples().is_some(),
            width: view.layout.width as i32,
        };
        if view.layout.threads > 1 && count >= PARALLEL_POLYGONS {
            set_up_in_pieces(
                &object,
                count,
                view.layout,
                (&mut self.main, &mut self.batches, &mut self.scratch, &mut self.stretches),
                cursor,
            );
        } else {
            object.run(0..count, &mut self.main, &mut self.main_scratch);
        }
        stats.ms_clip += ms_since(t_clip);
    }

    /// Transforms `mesh`'s vertices into `self.vertices`, on several threads for a big mesh.
    fn transform(&mut self, transform: &VertexTransform, mesh: &Mesh, threads: usize) {
        let n = mesh.vertices().len();
        // Every slot is overwritten, so a longer buffer is only shortened.
        if self.vertices.len() < n {
            self.vertices.resize(n, SetupVertex::default());
        }
        self.vertices.truncate(n);
        if threads > 1 && n >= PARALLEL_VERTICES {
            // In place, a slice per worker (collecting from a parallel iterator would build per-thread lists
            // and copy them once more).
            let chunk = n.div_ceil(threads * 4);
            self.vertices
                .par_chunks_mut(chunk)
                .zip(mesh.vertices().par_chunks(chunk))
                .for_each(|(out, vs)| transform.run(out, vs));
        } else {
            transform.run(&mut self.vertices, mesh.vertices());
        }
    }
}

/// The world bounding sphere of `mesh` placed by `inst`, and whether the frustum excludes it.
fn cull(mesh: &Mesh, inst: &Instance, frustum: &Frustum) -> ((Vec3, f32), bool) {
    let (center, radius) = world_sphere(mesh.bounds(), &inst.model);
    let culled = center.is_finite() && radius.is_finite() && frustum.excludes(center, radius);
    ((center, radius), culled)
}

/// Sets up `count` polygons of `object` in pieces on the current pool. For the painter's orders the pieces'
/// polygons are appended to the main batch in order; for the z-buffer they stay in their batches, binned by
/// the thread that set them up while still in its cache, and the stretches record the order.
fn set_up_in_pieces(
    object: &ObjectSetup<'_>,
    count: usize,
    layout: FrameLayout,
    (main, batches, scratch, stretches): (&mut Batch, &mut Vec<Batch>, &mut Vec<SetupScratch>, &mut Vec<Stretch>),
    cursor: &mut Cursor,
) {
    let pieces = layout.threads * 4;
    let first = cursor.batches_used;
    cursor.batches_used += pieces;
    let used = cursor.batches_used;
    if batches.len() < used {
        batches.resize_with(used, Batch::default);
        scratch.resize_with(used, SetupScratch::default);
    }
    let ordered = object.ordered;
    let bands = (layout.height, layout.rows_per_band);
    batches[first..used].par_iter_mut().zip(scratch[first..used].par_iter_mut()).enumerate().for_each(|(i, (b, s))| {
        b.clear();
        b.tag = (first + i + 1) as u32;
        object.run(count * i / pieces..count * (i + 1) / pieces, b, s);
        if !ordered {
            bin(&b.polys, 0..b.polys.len() as u32, bands, &mut b.bins);
        }
    });
    if ordered {
        main.adopt_polygons(&batches[first..used]);
        return;
    }
    // The z-buffer draws them from where they are: appending them to the main batch would be a serial copy,
    // and binning them again in the fill would redo what each piece's thread did with them in its cache.
    main.adopt_counts(&batches[first..used]);
    let end = main.polys.len() as u32;
    if cursor.main_start < end {
        stretches.push(Stretch::Main(cursor.main_start..end));
    }
    cursor.main_start = end;
    stretches.extend((first..used).map(Stretch::Batch));
}
