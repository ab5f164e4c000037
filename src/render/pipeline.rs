//! The frame pipeline: ties the stages together, owns the per-frame scratch buffers, and splits the fill
//! into horizontal bands drawn in parallel.
//!
//! With more than one thread the whole frame runs on a rayon pool kept between frames. Geometry (cull,
//! transform, clip, snap, order) runs once per frame, a big object's polygons set up in pieces across the
//! pool (`project.rs`). The fill then runs in bands of about 32 rows handed out by work stealing: the
//! ordered polygons are binned once by band, and each band draws only its bin on its own rows
//! ([`super::bands`]). The painter's orders append the set-up pieces' polygons in order and sort them; the
//! z-buffer, which draws in submission order, leaves them in their pieces, each binned by the thread that
//! set it up. Because edge positions are exact integers and attributes are evaluated per row from
//! the polygon's vertices, a row's pixels do not depend on which band drew it: frames are bit-identical for
//! every thread count.

use std::ops::Range;
use std::time::Instant;

use glam::Mat4;
use thiserror::Error;

use rayon::iter::{IndexedParallelIterator, IntoParallelIterator, IntoParallelRefMutIterator, ParallelIterator};
use rayon::slice::{ParallelSlice, ParallelSliceMut};

use super::bands::{BinnedRun, FillContext, bin, split_bands};
use super::clip::{CLIP_ATTRS, ClipVolume};
use super::cull::{Frustum, world_sphere};
use super::lod::{Level, LodMode, LodState, choose};
use super::mesh::DEPTH_BIAS_STEP;
use super::ordering_table::{Direction, OrderingTable};
use super::project::{Batch, ObjectSetup, Screens, SetupVertex};
use super::scanline::{ScreenVertex, slot};
use super::span::{FastPathRule, SpanCounts, TextureMode, Visibility, pack_rgb};
use super::texture::Sampler;
use super::transform::VertexTransform;
use super::view_lists::model_direction;
use super::{Camera, DrawList, Method, RenderOptions, Stats};

/// Why a frame could not be drawn.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum RenderError {
    /// The pixel slice is shorter than `width * height`.
    #[error("frame buffer holds {len} pixels, but {width}x{height} needs {needed}")]
    FrameTooSmall {
        /// Pixels supplied.
        len: usize,
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
        /// `width * height` (saturated).
        needed: usize,
    },
    /// The frame is too large for the fixed-point grid (more than 2^20 pixels on a side).
    #[error("frame of {width}x{height} is larger than the renderer supports (2^20 on a side)")]
    FrameTooLarge {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
    },
    /// The fill stage's worker threads could not be started.
    #[error("could not start the fill worker threads")]
    WorkerFailed,
}

/// A polygon (or a piece of one) ready for the fill stage.
///
/// Set-up writes one per polygon and the ordering, binning and fill stages read them back, so the record
/// is kept to 48 bytes (measured on the small-polygon scene: 16 more bytes cost 0.03 ms of 1.36): the
/// optional parts of its paint are values with flags, and ordering keys live beside the polygons
/// ([`super::project::Batch::keys`]), only for the methods that order by them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct DrawPolygon {
    /// Its first screen vertex in its batch, or for a small triangle its set-up's index there: in the batch's
    /// textured small triangles when it has a texture ([`HAS_TEXTURE`]), else in its flat ones.
    pub(super) first: u32,
    /// How many corners it has.
    pub(super) count: u32,
    /// The batch holding its screen vertices or small triangle (see [`Screens`]).
    pub(super) batch: u32,
    /// The rows whose centres it covers, `rows.0..rows.1` (before clipping to the frame).
    pub(super) rows: (i32, i32),
    /// The texture index when [`HAS_TEXTURE`] is set; otherwise, with [`HAS_COLOR`], the colour packed as
    /// `0x00RRGGBB` ([`pack_rgb`]), which the fill of flat small triangles takes per triangle.
    texture: u32,
    /// The alpha cutoff, when [`HAS_CUTOFF`] is set.
    cutoff: f32,
    /// The colour of every corner, when [`HAS_COLOR`] is set.
    color: [f32; 4],
    pub(super) sampler: Sampler,
    /// [`HAS_TEXTURE`], [`HAS_CUTOFF`], [`HAS_COLOR`], [`SCREEN_DOOR`], [`SMALL`].
    flags: u8,
}

const _: () = assert!(size_of::<DrawPolygon>() == 48);

/// [`DrawPolygon::flags`]: it has a texture.
const HAS_TEXTURE: u8 = 1;
/// It has an alpha cutoff.
const HAS_CUTOFF: u8 = 2;
/// All its corners have one colour.
const HAS_COLOR: u8 = 4;
/// It is drawn with the screen door (see-through).
const SCREEN_DOOR: u8 = 8;
/// It is a small triangle set up for the fast path: `first` indexes its batch's small triangles (textured or
/// flat, by [`HAS_TEXTURE`]) and it has no screen vertices.
const SMALL: u8 = 16;

/// How a polygon is painted: what [`DrawPolygon`] stores compactly.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct PolygonPaint {
    pub(super) texture: Option<u32>,
    pub(super) sampler: Sampler,
    pub(super) alpha_cutoff: Option<f32>,
    pub(super) constant_color: Option<[f32; 4]>,
    pub(super) screen_door: bool,
}

impl DrawPolygon {
    /// A polygon with corners `first..first + count` of batch `batch` (or small triangle `first` there, when
    /// `small`), covering `rows`, painted `paint`.
    #[inline]
    pub(super) fn new(first: u32, count: u32, batch: u32, rows: (i32, i32), small: bool, paint: &PolygonPaint) -> Self {
        let flag = |on: bool, f: u8| if on { f } else { 0 };
        let flags = flag(paint.texture.is_some(), HAS_TEXTURE)
            | flag(paint.alpha_cutoff.is_some(), HAS_CUTOFF)
            | flag(paint.constant_color.is_some(), HAS_COLOR)
            | flag(paint.screen_door, SCREEN_DOOR)
            | flag(small, SMALL);
        Self {
            first,
            count,
            batch,
            rows,
            texture: paint.texture.unwrap_or_else(|| paint.constant_color.map_or(0, pack_rgb)),
            cutoff: paint.alpha_cutoff.unwrap_or(0.0),
            color: paint.constant_color.unwrap_or([0.0; 4]),
            sampler: paint.sampler,
            flags,
        }
    }

    /// Its texture index.
    #[inline(always)]
    pub(super) fn texture(&self) -> Option<u32> {
        (self.flags & HAS_TEXTURE != 0).then_some(self.texture)
    }

    /// Its alpha cutoff.
    #[inline(always)]
    pub(super) fn alpha_cutoff(&self) -> Option<f32> {
        (self.flags & HAS_CUTOFF != 0).then_some(self.cutoff)
    }

    /// The colour of all its corners, if they share one.
    #[inline(always)]
    pub(super) fn constant_color(&self) -> Option<[f32; 4]> {
        (self.flags & HAS_COLOR != 0).then_some(self.color)
    }

    /// Its colour packed as `0x00RRGGBB`, for a polygon of one colour with no texture (0 otherwise).
    #[inline(always)]
    pub(super) fn flat_rgb(&self) -> u32 {
        if self.flags & (HAS_TEXTURE | HAS_COLOR) == HAS_COLOR { self.texture } else { 0 }
    }

    /// Whether it is drawn with the screen door.
    #[inline(always)]
    pub(super) fn screen_door(&self) -> bool {
        self.flags & SCREEN_DOOR != 0
    }

    /// Whether it is a small triangle set up for the fast path.
    #[inline(always)]
    pub(super) fn small(&self) -> bool {
        self.flags & SMALL != 0
    }

    /// Whether `other` is painted the same (texture, sampler, cutoff and colour; not the screen door).
    #[inline(always)]
    pub(super) fn paints_like(&self, other: &Self) -> bool {
        (self.texture(), self.sampler, self.alpha_cutoff(), self.constant_color())
            == (other.texture(), other.sampler, other.alpha_cutoff(), other.constant_color())
    }
}

/// Moves a decal's depth towards the viewer for the depth test by `steps` times (one pixel of the
/// polygon's steepest depth slope plus [`DEPTH_BIAS_STEP`] of its nearest depth), as GPUs' polygon offset
/// does: the slope term covers the depth error of snapping vertices to 1/16 pixel, which at a grazing angle
/// exceeds any constant offset; the constant covers surfaces seen face on. A constant added to `1/w` keeps
/// it affine in screen space, so interpolation stays exact.
pub(super) fn slope_scaled_bias(verts: &mut [ScreenVertex], steps: u8) {
    let d = |v: &ScreenVertex| (v.x.to_f32(), v.y.to_f32(), v.attrs[slot::DEPTH]);
    let mut slope = 0.0f32;
    let mut nearest = 0.0f32;
    if let Some(a) = verts.first().map(d) {
        for i in 1..verts.len().saturating_sub(1) {
            let (b, c) = (d(&verts[i]), d(&verts[i + 1]));
            let (e1, e2) = ((b.0 - a.0, b.1 - a.1, b.2 - a.2), (c.0 - a.0, c.1 - a.1, c.2 - a.2));
            let det = e1.0 * e2.1 - e2.0 * e1.1;
            if det.abs() > 1e-6 {
                let gx = (e1.2 * e2.1 - e2.2 * e1.1) / det;
                let gy = (e2.2 * e1.0 - e1.2 * e2.0) / det;
                slope = gx.abs().max(gy.abs());
                break;
            }
        }
    }
    for v in verts.iter() {
        nearest = nearest.max(v.attrs[slot::DEPTH].abs());
    }
    let offset = f32::from(steps) * (slope + nearest * DEPTH_BIAS_STEP);
    if offset.is_finite() {
        for v in verts.iter_mut() {
            v.attrs[slot::DEPTH] += offset;
        }
    }
}

/// A reusable renderer: holds scratch buffers so frames after the first allocate nothing per polygon or
/// per pixel (only the fill's short lists of bands and runs, a few dozen entries, are made each frame).
#[derive(Debug, Default)]
pub struct Renderer {
    setup_vertices: Vec<SetupVertex>,
    main: Batch,
    batches: Vec<Batch>,
    order: Vec<u32>,
    /// The z-buffer's drawing order (the submission order) as stretches of the main batch and set-up
    /// batches; empty for the painter's orders, which order `main.polys`.
    stretches: Vec<Stretch>,
    /// The stretches of polygon indices binned by the fill stage: pieces of `order`, or for the z-buffer of
    /// the main batch's stretches.
    bin_jobs: Vec<Range<u32>>,
    /// The polygons of each band (inner), for each of `bin_jobs` (outer).
    bins: Vec<Vec<Vec<u32>>>,
    pool: Option<(usize, rayon::ThreadPool)>,
    table: OrderingTable,
    used_table: bool,
    lod_state: LodState,
}

const MAX_SIDE: usize = 1 << 20;

/// Where a stretch of the z-buffer's drawing order is.
#[derive(Clone, Debug, PartialEq)]
enum Stretch {
    /// Polygons `range` of the main batch, binned by the fill stage.
    Main(Range<u32>),
    /// All the polygons of set-up batch `k`, binned by its set-up.
    Batch(usize),
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

impl Renderer {
    /// A renderer with empty scratch buffers.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Draws `list` seen by `camera` into `frame` (`width * height` pixels, `0x00RRGGBB`, rows from the top).
    ///
    /// Any geometry is accepted: NaN, infinite or huge coordinates drop the polygon (counted in
    /// [`Stats::polygons_invalid`]), a bad mesh index drops the instance, a bad texture index draws untextured.
    /// A 0x0 frame draws nothing.
    pub fn render(
        &mut self,
        frame: &mut [u32],
        width: usize,
        height: usize,
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Result<Stats, RenderError> {
        let needed = width.saturating_mul(height);
        if frame.len() < needed {
            return Err(RenderError::FrameTooSmall { len: frame.len(), width, height, needed });
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(RenderError::FrameTooLarge { width, height });
        }
        let mut stats = Stats::default();
        if needed == 0 {
            return Ok(stats);
        }
        let threads = match options.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n,
        }
        .clamp(1, height);
        // The whole frame runs on the pool, not just the fill: the geometry then runs on a worker too, so it
        // does not compete for a core with workers still spinning after the previous frame's fill.
        let pool = match self.pool.take() {
            Some((n, pool)) if n == threads => Some((n, pool)),
            _ if threads == 1 => None,
            _ => {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .thread_name(|i| format!("fill-{i}"))
                    .build()
                    .map_err(|_| RenderError::WorkerFailed)?;
                Some((threads, pool))
            }
        };
        // About BAND_ROWS rows a band, and (when the height divides well) a number of bands the threads
        // share evenly.
        let bands = height.div_ceil(BAND_ROWS).next_multiple_of(threads).max(1);
        let rows_per_band = height.div_ceil(bands).max(1);
        let mut frame_steps = |this: &mut Self| {
            let t = Instant::now();
            this.geometry((width, height, threads, rows_per_band), camera, list, options, &mut stats);
            let t_order = Instant::now();
            this.order(options);
            stats.ms_order = ms(t_order);
            let t_fill = Instant::now();
            let counts = this.fill(&mut frame[..needed], (width, height, threads, rows_per_band), list, options);
            stats.ms_fill = ms(t_fill);
            debug_assert!(stats.ms_transform + stats.ms_clip <= ms(t) + 1.0);
            counts
        };
        let counts = match &pool {
            Some((_, p)) => p.install(|| frame_steps(self)),
            None => frame_steps(self),
        };
        self.pool = pool;
        stats.pixels_shaded = counts.shaded;
        stats.pixels_written = counts.written;
        stats.pixels_rejected = counts.rejected;
        stats.pieces_filled = self.main.polys.len() as u64
            + self
                .stretches
                .iter()
                .filter_map(|s| match s {
                    Stretch::Batch(k) => self.batches.get(*k).map(|b| b.polys.len() as u64),
                    Stretch::Main(_) => None,
                })
                .sum::<u64>();
        Ok(stats)
    }

    /// How many polygons each ordering-table bucket held in the last frame (nearest first); empty when the
    /// last frame did not use the ordering table.
    #[must_use]
    pub fn bucket_occupancy(&self) -> Vec<u32> {
        if self.used_table { self.table.occupancy() } else { Vec::new() }
    }

    /// Forgets the levels of detail chosen in earlier frames (call on a new scene or a camera cut).
    pub fn reset_lod(&mut self) {
        self.lod_state.clear();
    }

    /// The mesh each instance of `list` would draw in a frame `height` pixels tall (after the LOD choice,
    /// which updates this renderer's LOD history like a frame does), or `None` for an instance culled by the
    /// view frustum or naming no mesh. For exporting exactly what a frame draws.
    pub fn frame_meshes(
        &mut self,
        width: usize,
        height: usize,
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Vec<Option<usize>> {
        let mut stats = Stats::default();
        let clip_from_world = camera.clip_from_view(width, height) * camera.view;
        let frustum = Frustum::new(&clip_from_world, camera.has_far_plane());
        let y_scale_px = camera.clip_from_view(width, height).y_axis.y * height as f32;
        list.instances
            .iter()
            .enumerate()
            .map(|(index, inst)| {
                let m = self.resolve_mesh(index, inst, list, (camera, y_scale_px), options, &mut stats)?;
                let mesh = list.meshes.get(m)?;
                let (center, radius) = world_sphere(mesh.bounds(), &inst.model);
                let culled = center.is_finite() && radius.is_finite() && frustum.excludes(center, radius);
                (!culled).then_some(m)
            })
            .collect()
    }

    /// Picks the mesh for an instance: its own, or the level of its LOD set for this frame.
    fn resolve_mesh(
        &mut self,
        index: usize,
        inst: &super::Instance,
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
                let size = if camera.is_perspective() {
                    let depth = -(camera.view.transform_point3(center).z);
                    if depth > radius { radius * y_scale_px / depth } else { f32::INFINITY }
                } else {
                    radius * y_scale_px
                };
                let size = size * libm::exp2f(options.lod_bias);
                choose(if size.is_nan() { 0.0 } else { size }, set.switch_px, self.lod_state.previous(index))
            }
        };
        self.lod_state.set(index, level);
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

    /// Cull, transform, clip, project, snap, back-face cull; fills `self.main.polys`, `self.main.screen` and
    /// `self.main.small` (big objects' corners stay in `self.batches`, and for the z-buffer their polygons
    /// too, binned by bands of `rows_per_band` rows, with `self.stretches` saying the order).
    fn geometry(
        &mut self,
        (width, height, threads, rows_per_band): (usize, usize, usize, usize),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
        stats: &mut Stats,
    ) {
        self.main.clear();
        self.stretches.clear();
        let ordered = options.method != Method::ZBuffer;
        // Where the main batch's current stretch of the z-buffer's order starts.
        let mut main_start = 0;
        // Set-up batches of big objects used so far this frame (their screen vertices stay in them).
        let mut batches_used = 0;
        let clip_from_world = camera.clip_from_view(width, height) * camera.view;
        let frustum = Frustum::new(&clip_from_world, camera.has_far_plane());
        let volume = ClipVolume::new(width, height, camera.has_far_plane());
        let perspective_attrs = options.texture_mode != TextureMode::Affine;
        let (wf, hf) = (width as f32, height as f32);
        // Projected diameter in pixels of a unit radius at unit depth: the projection's y scale times the height.
        let y_scale_px = camera.clip_from_view(width, height).y_axis.y * hf;
        let world_from_view = camera.view.inverse();
        let (eye, forward) = (world_from_view.w_axis.truncate(), -world_from_view.z_axis.truncate());
        for (index, inst) in list.instances.iter().enumerate() {
            stats.objects_in += 1;
            let mesh_index = self.resolve_mesh(index, inst, list, (camera, y_scale_px), options, stats);
            let Some(mesh) = mesh_index.and_then(|m| list.meshes.get(m)) else {
                stats.objects_culled += 1;
                continue;
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
            let (center, radius) = world_sphere(mesh.bounds(), &inst.model);
            if center.is_finite() && radius.is_finite() && frustum.excludes(center, radius) {
                stats.objects_culled += 1;
                stats.polygons_in_culled_objects += npoly;
                stats.ms_transform += ms(t_transform);
                continue;
            }
            let clip_from_model: Mat4 = clip_from_world * inst.model;
            let view_from_model: Mat4 = camera.view * inst.model;
            let transform = VertexTransform {
                clip_from_model,
                depth_row: view_from_model.row(2),
                volume,
                size: (wf, hf),
                perspective: camera.is_perspective(),
            };
            let n = mesh.vertices().len();
            // Every slot is overwritten below, so a longer buffer is only shortened.
            if self.setup_vertices.len() < n {
                self.setup_vertices.resize(n, SetupVertex::default());
            }
            self.setup_vertices.truncate(n);
            if threads > 1 && n >= PARALLEL_VERTICES {
                // In place, a slice per worker (collecting from a parallel iterator would build per-thread
                // lists and copy them once more).
                let chunk = n.div_ceil(threads * 4);
                self.setup_vertices
                    .par_chunks_mut(chunk)
                    .zip(mesh.vertices().par_chunks(chunk))
                    .for_each(|(out, vs)| transform.run(out, vs));
            } else {
                transform.run(&mut self.setup_vertices, mesh.vertices());
            }
            stats.ms_transform += ms(t_transform);
            let t_clip = Instant::now();
            // A stored order is for an object seen from outside: from at least twice its radius away. A mesh
            // the camera is in or near (a stretch of road, the terrain) is ordered per polygon instead. The
            // object is placed by the nearest depth of its bounding sphere, so it is drawn after the ground
            // polygons it stands on (measured: with its centre's depth, big road polygons near the camera
            // painted over the lower half of the player's car).
            let (stored, object_key) = match lists {
                Some(l) if (center - eye).length() > 2.0 * radius => {
                    let to_object = if camera.is_perspective() { Ok(eye) } else { Err(forward) };
                    match model_direction(&inst.model, center, to_object) {
                        Some(d) => (Some(l.nearest(d)), Some(-camera.view.transform_point3(center).z - radius)),
                        None => (None, None),
                    }
                }
                _ => (None, None),
            };
            let count = stored.map_or(own_polygons, <[u32]>::len);
            let object = ObjectSetup {
                mesh,
                stored,
                vertices: &self.setup_vertices,
                transform: &transform,
                key: options.key,
                ordered,
                perspective_attrs,
                object_key,
                textures: list.textures.len(),
                see_through: inst.see_through,
                fast_path: FastPathRule { filter: options.filter, mode: options.texture_mode },
                width: width as i32,
            };
            if threads > 1 && count >= PARALLEL_POLYGONS {
                // Pieces of the polygon list set up in parallel, then appended in order (the painter's
                // orders) or drawn from where they are in order (the z-buffer): the result is the same as
                // one pass, for any thread count.
                let pieces = threads * 4;
                let first = batches_used;
                batches_used += pieces;
                if self.batches.len() < batches_used {
                    self.batches.resize_with(batches_used, Batch::default);
                }
                self.batches[first..batches_used].par_iter_mut().enumerate().for_each(|(i, b)| {
                    b.clear();
                    b.tag = (first + i + 1) as u32;
                    object.run(count * i / pieces..count * (i + 1) / pieces, b);
                    if !ordered {
                        // While its polygons are still in this core's cache.
                        bin(&b.polys, 0..b.polys.len() as u32, (height, rows_per_band), &mut b.bins);
                    }
                });
                if ordered {
                    self.main.adopt_polygons(&self.batches[first..batches_used]);
                } else {
                    // The z-buffer draws them from where they are (measured on the small-polygon scene
                    // with 2 threads: appending them was a 0.026 ms serial copy, and binning them again in
                    // the fill 0.035 ms).
                    self.main.adopt_counts(&self.batches[first..batches_used]);
                    let end = self.main.polys.len() as u32;
                    if main_start < end {
                        self.stretches.push(Stretch::Main(main_start..end));
                    }
                    main_start = end;
                    self.stretches.extend((first..batches_used).map(Stretch::Batch));
                }
            } else {
                object.run(0..count, &mut self.main);
            }
            stats.ms_clip += ms(t_clip);
        }
        let end = self.main.polys.len() as u32;
        if !ordered && main_start < end {
            self.stretches.push(Stretch::Main(main_start..end));
        }
        self.main.counts.add_to(stats);
    }

    /// Fills `self.order` with polygon indices in drawing order.
    fn order(&mut self, options: &RenderOptions) {
        self.order.clear();
        self.used_table = matches!(options.method, Method::BucketFar | Method::BucketNear | Method::ViewLists);
        match options.method {
            // Drawn in the order of `self.stretches`.
            Method::ZBuffer => {}
            Method::Sort => {
                self.order.extend(0..self.main.polys.len() as u32);
                let keys = &self.main.keys;
                debug_assert_eq!(keys.len(), self.main.polys.len());
                // Stable: polygons with equal keys keep submission order. Far (large key) first.
                self.order.sort_by(|&a, &b| {
                    let key = |i: u32| keys.get(i as usize).copied().unwrap_or(0.0);
                    key(b).total_cmp(&key(a))
                });
            }
            Method::BucketFar | Method::BucketNear | Method::ViewLists => {
                let keys = &self.main.keys;
                debug_assert_eq!(keys.len(), self.main.polys.len());
                let (mut near, mut far) = (f32::INFINITY, f32::NEG_INFINITY);
                for &k in keys.iter().filter(|k| k.is_finite()) {
                    near = near.min(k);
                    far = far.max(k);
                }
                let direction =
                    if options.method == Method::BucketNear { Direction::NearToFar } else { Direction::FarToNear };
                self.table.reset(options.buckets, options.mapping, near, far, direction);
                // The order the linked buckets would give (on one thread: see `OrderingTable::sort`).
                self.table.sort(keys, &mut self.order);
            }
        }
    }

    /// Clears the buffers the method needs and fills every polygon in order, in bands of `rows_per_band`
    /// rows, across the current thread pool when `threads` is more than 1 (the caller runs this inside the
    /// pool).
    fn fill(
        &mut self,
        frame: &mut [u32],
        (width, height, threads, rows_per_band): (usize, usize, usize, usize),
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> SpanCounts {
        let visibility = match options.method {
            Method::ZBuffer => Visibility::DepthTest,
            Method::BucketNear => Visibility::Coverage,
            Method::Sort | Method::BucketFar | Method::ViewLists => Visibility::Overwrite,
        };
        let words = width.div_ceil(64);
        let ordered = options.method != Method::ZBuffer;
        // What is binned here, in parallel pieces: the painter's order, or the z-buffer's stretches of the
        // main batch.
        let to_bin = if ordered { self.order.len() } else { self.main.polys.len() };
        let pieces = if threads > 1 && to_bin >= PARALLEL_POLYGONS { threads * 2 } else { 1 };
        let chunk = to_bin.div_ceil(pieces).max(1) as u32;
        self.bin_jobs.clear();
        let mut cut = |r: Range<u32>| {
            let mut a = r.start;
            while a < r.end {
                let b = r.end.min(a.saturating_add(chunk));
                self.bin_jobs.push(a..b);
                a = b;
            }
        };
        if ordered {
            cut(0..self.order.len() as u32);
        } else {
            for s in &self.stretches {
                if let Stretch::Main(r) = s {
                    cut(r.clone());
                }
            }
        }
        self.bins.resize_with(self.bin_jobs.len(), Vec::new);
        self.bins.truncate(self.bin_jobs.len());
        let (polys, order, layout) = (&self.main.polys, &self.order, (height, rows_per_band));
        let bin_job = |(b, r): (&mut Vec<Vec<u32>>, &Range<u32>)| {
            if ordered {
                let order = order.get(r.start as usize..r.end as usize).unwrap_or_default();
                bin(polys, order.iter().copied(), layout, b);
            } else {
                bin(polys, r.clone(), layout, b);
            }
        };
        if self.bin_jobs.len() <= 1 {
            self.bins.iter_mut().zip(&self.bin_jobs).for_each(bin_job);
        } else {
            self.bins.par_iter_mut().zip(&self.bin_jobs).for_each(bin_job);
        }
        // The runs of the drawing order, in order.
        let mut own = self.bins.iter().map(|bins| BinnedRun { polys, bins });
        let runs: Vec<BinnedRun<'_>> = if ordered {
            own.collect()
        } else {
            let mut runs = Vec::with_capacity(self.stretches.len() + self.bins.len());
            for s in &self.stretches {
                match s {
                    Stretch::Main(r) => {
                        // This stretch's pieces, in order.
                        let n = r.len().div_ceil(chunk as usize);
                        runs.extend(own.by_ref().take(n));
                    }
                    Stretch::Batch(k) => {
                        if let Some(b) = self.batches.get(*k) {
                            runs.push(BinnedRun { polys: &b.polys, bins: &b.bins });
                        }
                    }
                }
            }
            debug_assert!(own.next().is_none(), "a binned piece of the main batch was not drawn");
            runs
        };
        let ctx = FillContext {
            runs: &runs,
            background: options.background,
            screens: Screens { main: &self.main, batches: &self.batches },
            list,
            options,
            visibility,
            width,
            words,
        };
        let bands = split_bands(frame, width, rows_per_band);
        let jobs = bands.into_iter().enumerate();
        if threads == 1 {
            return jobs.map(|(i, band)| ctx.fill_band(band, i)).fold(SpanCounts::default(), |a, b| a + b);
        }
        // Bands are handed out by work stealing, as the sky and the ground cost very different amounts.
        let jobs: Vec<_> = jobs.collect();
        jobs.into_par_iter().map(|(i, band)| ctx.fill_band(band, i)).reduce(SpanCounts::default, |a, b| a + b)
    }
}

/// Objects with at least this many polygons are set up in pieces on several threads (below it, handing out
/// the pieces costs more than it saves).
const PARALLEL_POLYGONS: usize = 1024;

/// Objects with at least this many vertices are transformed on several threads.
const PARALLEL_VERTICES: usize = 4096;

/// Rows per band, about: small enough that a band's colour and depth rows stay in the core's cache while it
/// is drawn and that bands balance across threads, large enough that few polygons are set up twice. The
/// band count is first rounded up to a multiple of the thread count, then the height is cut into bands of
/// equal rows, which gives that many bands when the height divides well (480 rows on 2 threads:
/// 16 bands of 30 rows, not 15 of 32, of which one thread drew 8: fill 0.286 -> 0.259 ms on the
/// small-polygon scene). The band layout never changes a pixel (a test renders with 1 to 400 threads).
const BAND_ROWS: usize = 32;

/// The clip attributes layout is shared with [`super::clip`]; keep them in step.
const _: () = assert!(CLIP_ATTRS == 7);
