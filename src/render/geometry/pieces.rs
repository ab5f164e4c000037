//! Setting up the visible objects in submission order: each one's vertices transformed and its polygons set
//! up, on one thread or in pieces on the worker pool.
//!
//! On the pool, a big object is set up in pieces of its polygons, and a run of consecutive small objects in
//! pieces of whole objects (a mountain frame draws a thousand trees and rocks of a few dozen polygons each,
//! which one thread would set up while the other waits). Each piece goes into its own batch. The painter's
//! orders append the pieces' polygons to the main batch in order and sort them later; the z-buffer, which
//! draws in submission order, leaves them in their pieces, each binned by the thread that set it up, and
//! stretches ([`Stretch`]) say in which order to draw the main batch and the pieces. Either way the result
//! is that of one pass, for any thread count.

use std::time::Instant;

use glam::{Mat4, Vec3};
use rayon::iter::{IndexedParallelIterator, IntoParallelRefMutIterator, ParallelIterator};
use rayon::slice::{ParallelSlice, ParallelSliceMut};

use super::clip::ClipVolume;
use super::setup::{ObjectSetup, SetupScratch};
use super::vertex::{SetupVertex, VertexTransform};
use super::visible::{PassView, Visible};
use crate::render::core::band::{FrameLayout, bin};
use crate::render::core::batch::{Batch, Stretch};
use crate::render::core::camera::Camera;
use crate::render::core::door::Door;
use crate::render::core::draw_list::DrawList;
use crate::render::core::mesh::Mesh;
use crate::render::core::options::{Method, MipMode, RenderOptions, TextureMode};
use crate::render::core::polygon::FastPathRule;
use crate::render::core::stats::Stats;
use crate::render::order::view_lists::stored_order;

/// Objects with at least this many polygons are set up in pieces of their polygons on several threads
/// (below it, handing out the pieces costs more than it saves).
const PARALLEL_POLYGONS: usize = 1024;

/// Runs of smaller objects with at least this many polygons in all are set up in pieces of whole objects.
const PARALLEL_RUN_POLYGONS: usize = 1024;

/// What setting up one small object costs beside its polygons, in polygons: a run is cut into pieces of
/// equal cost. Each piece of the mountain's frames timed on its own: an object took about 0.35 us beside
/// 0.10 us a polygon, so that cut by polygons alone, a piece of 1,954 trees took four times as long as one
/// of 7 larger objects with as many polygons, and the thread that drew it finished last.
const OBJECT_COST: usize = 3;

/// Objects with at least this many vertices are transformed on several threads.
const PARALLEL_VERTICES: usize = 4096;

/// What the whole frame shares while its objects are set up.
pub(crate) struct FrameView<'a> {
    /// The camera.
    pub(crate) camera: &'a Camera,
    /// World to clip space.
    pub(crate) clip_from_world: Mat4,
    /// The clip volume (guard band).
    pub(crate) volume: ClipVolume,
    /// The eye's position and view direction in world space.
    pub(crate) eye: Vec3,
    /// See `eye`.
    pub(crate) forward: Vec3,
    /// The frame's size, bands and threads.
    pub(crate) layout: FrameLayout,
    /// The frame's objects.
    pub(crate) list: &'a DrawList<'a>,
    /// The frame's options.
    pub(crate) options: &'a RenderOptions,
    /// Whether the frame is drawn four rows a pixel (a rotated-grid frame), whose rows sample shifted columns.
    pub(crate) tall: bool,
}

/// One visible object ready for its vertices: the mesh drawn, how many of its polygons are set up, the
/// stored order that applies (`view-lists`), its vertex transform and the screen door it is drawn through.
struct Prepared<'a> {
    mesh: &'a Mesh,
    count: usize,
    stored: Option<(&'a [u32], f32)>,
    transform: VertexTransform,
    door: Door,
}

impl<'a> FrameView<'a> {
    /// What setting up visible object `v` needs, or `None` when its instance or mesh is not in the list.
    fn prepare(&self, pass: &PassView<'a>, v: &Visible) -> Option<Prepared<'a>> {
        let (list, options) = (self.list, self.options);
        let inst = list.instances.get(v.index)?;
        let own = list.meshes.get(v.mesh)?;
        let own_polygons = own.polygons().len();
        let model = own.placed_model(&inst.model, self.eye);
        let mesh = pass.drawn_mesh(v.mesh)?;
        // `view-lists`: the mesh with its split pieces, drawn in the stored order for this view. The extended
        // mesh begins with the original polygons, so it also serves per-polygon ordering.
        let lists = (options.method == Method::ViewLists).then(|| list.view_lists.and_then(|l| l.get(v.mesh)));
        let stored =
            lists.flatten().and_then(|l| stored_order(l, &model, v.sphere, self.camera, (self.eye, self.forward)));
        let transform = VertexTransform {
            clip_from_model: self.clip_from_world * model,
            depth_row: (self.camera.view * model).row(2),
            volume: self.volume,
            size: (self.layout.width as f32, self.layout.height as f32),
            perspective: self.camera.is_perspective(),
        };
        let count = stored.map_or(own_polygons, |(order, _)| order.len());
        // A see-through instance keeps its checkerboard; otherwise the door of its level-of-detail fade.
        let door = if inst.see_through { Door::CHECKERBOARD } else { v.door };
        Some(Prepared { mesh, count, stored, transform, door })
    }

    /// How many polygons visible object `v`'s own mesh has (0 for a mesh not in the list): what a run of
    /// small objects is measured and cut into pieces by.
    fn polygons(&self, v: &Visible) -> usize {
        self.list.meshes.get(v.mesh).map_or(0, |m| m.polygons().len())
    }

    /// The set-up of a prepared object whose vertices are `vertices`.
    fn object_setup<'s>(&'s self, p: &'s Prepared<'a>, vertices: &'s [SetupVertex]) -> ObjectSetup<'s> {
        let (list, options) = (self.list, self.options);
        let mip = options.mip.with_filter(options.filter);
        ObjectSetup {
            mesh: p.mesh,
            stored: p.stored.map(|(order, _)| order),
            vertices,
            transform: &p.transform,
            key: options.key,
            ordered: options.method != Method::ZBuffer,
            perspective_attrs: options.texture_mode != TextureMode::Affine,
            object_key: p.stored.map(|(_, key)| key),
            textures: list.textures.len(),
            // The choice the filter makes (a polygon's level for `min-bilinear`, as the fill takes it).
            mip_textures: if mip == MipMode::Polygon { list.textures } else { &[] },
            door: p.door,
            fast_path: FastPathRule { filter: options.filter, mode: options.texture_mode, mip },
            antialiased: options.antialias.coverage_samples().is_some(),
            tall: self.tall,
            width: self.layout.width as i32,
        }
    }
}

/// The set-up's output and scratch, kept from frame to frame so that frames after the first allocate
/// nothing per polygon.
#[derive(Debug, Default)]
pub(crate) struct SetUp {
    /// The current object's vertices after the transform (on one thread).
    vertices: Vec<SetupVertex>,
    /// The frame's polygons (for the painter's orders all of them; for the z-buffer those of objects set up
    /// on one thread).
    pub(crate) main: Batch,
    main_scratch: SetupScratch,
    /// The pieces set up on several threads, each with its scratch and its objects' vertices.
    pub(crate) batches: Vec<Batch>,
    scratch: Vec<(SetupScratch, Vec<SetupVertex>)>,
    /// The z-buffer's drawing order (the submission order) as stretches of the main batch and of `batches`;
    /// empty for the painter's orders, which order `main.polys`.
    pub(crate) stretches: Vec<Stretch>,
    /// Where the z-buffer's current stretch of the main batch starts.
    main_start: u32,
    /// How many of `batches` this frame uses.
    batches_used: usize,
}

/// Of a run of small objects, the clock is read around every `TIMED`th object only: read around each of
/// a mountain frame's three thousand objects, it was 2% of the frame.
const TIMED: usize = 4;

/// The seconds spent transforming and setting up, as measured around the objects that were timed.
#[derive(Clone, Copy, Default)]
struct Times {
    transform: f64,
    set_up: f64,
}

impl Times {
    /// Adds the wall time of a run since `start` to `stats`, shared between the two stages in the
    /// proportion these times measured (half each when nothing was timed).
    fn charge(self, start: Instant, stats: &mut Stats) {
        let wall = start.elapsed().as_secs_f64() * 1e3;
        let measured = self.transform + self.set_up;
        let share = if measured > 0.0 { self.transform / measured } else { 0.5 };
        stats.ms_transform += wall * share;
        stats.ms_clip += wall * (1.0 - share);
    }
}

impl SetUp {
    /// Sets up the `visible` objects of a frame, in order: fills `main` (and `batches`, with `stretches`
    /// saying the z-buffer's order) and adds the time of each stage to `stats`.
    pub(crate) fn run(&mut self, view: &FrameView<'_>, pass: &PassView<'_>, visible: &[Visible], stats: &mut Stats) {
        self.main.clear();
        self.stretches.clear();
        (self.main_start, self.batches_used) = (0, 0);
        let threads = view.layout.threads;
        let polygons = |v: &Visible| view.polygons(v);
        let mut rest = visible;
        while !rest.is_empty() {
            // The run of small objects up to the next big one.
            let small = rest.iter().position(|v| polygons(v) >= PARALLEL_POLYGONS).unwrap_or(rest.len());
            let (run, after) = rest.split_at(small.max(1));
            if threads > 1 && small > 1 && run.iter().map(polygons).sum::<usize>() >= PARALLEL_RUN_POLYGONS {
                self.run_in_pieces(view, pass, run, stats);
            } else {
                let start = Instant::now();
                let mut times = Times::default();
                for (i, v) in run.iter().enumerate() {
                    self.object(view, pass, v, (i % TIMED == 0).then_some(&mut times));
                }
                times.charge(start, stats);
            }
            rest = after;
        }
        let end = self.main.polys.len() as u32;
        if view.options.method == Method::ZBuffer && self.main_start < end {
            self.stretches.push(Stretch::Main(self.main_start..end));
        }
        self.main.counts.add_to(stats);
    }

    /// One object on this thread (a big one in pieces of its polygons on the pool), timed into `times` when
    /// given.
    fn object(&mut self, view: &FrameView<'_>, pass: &PassView<'_>, v: &Visible, times: Option<&mut Times>) {
        let t_transform = times.is_some().then(Instant::now);
        let Some(p) = view.prepare(pass, v) else { return };
        self.transform(&p.transform, p.mesh, view.layout.threads);
        let t_setup = times.is_some().then(Instant::now);
        if view.layout.threads > 1 && p.count >= PARALLEL_POLYGONS {
            let pieces = view.layout.threads * 4;
            let first = self.take_batches(pieces);
            let object = view.object_setup(&p, &self.vertices);
            let ordered = object.ordered;
            let bands = (view.layout.height, view.layout.rows_per_band);
            let batches = &mut self.batches[first..first + pieces];
            batches.par_iter_mut().enumerate().zip(self.scratch[first..].par_iter_mut()).for_each(
                |((i, b), (s, _))| {
                    object.run(p.count * i / pieces..p.count * (i + 1) / pieces, b, s);
                    if !ordered {
                        bin(&b.polys, 0..b.polys.len() as u32, bands, &mut b.bins);
                    }
                },
            );
            self.adopt(first, ordered);
        } else {
            view.object_setup(&p, &self.vertices).run(0..p.count, &mut self.main, &mut self.main_scratch);
        }
        if let (Some(times), Some(t0), Some(t1)) = (times, t_transform, t_setup) {
            times.transform += (t1 - t0).as_secs_f64();
            times.set_up += t1.elapsed().as_secs_f64();
        }
    }

    /// A run of small objects in pieces of whole objects on the pool, each piece's objects transformed into
    /// its own vertices and set up into its own batch. The wall time is shared between the stages in the
    /// proportion the pieces measured.
    fn run_in_pieces(&mut self, view: &FrameView<'_>, pass: &PassView<'_>, run: &[Visible], stats: &mut Stats) {
        let start = Instant::now();
        let pieces = (view.layout.threads * 4).min(run.len());
        let first = self.take_batches(pieces);
        let ordered = view.options.method != Method::ZBuffer;
        let bands = (view.layout.height, view.layout.rows_per_band);
        // Pieces of about equal cost (the cut falls on the object where the running cost passes each share),
        // so the threads finish together.
        let cost = |v: &Visible| view.polygons(v) + OBJECT_COST;
        let total: usize = run.iter().map(cost).sum();
        let mut cuts = Vec::with_capacity(pieces + 1);
        let mut seen = 0usize;
        cuts.push(0);
        for (i, v) in run.iter().enumerate() {
            seen += cost(v);
            if seen * pieces >= total * cuts.len() && cuts.len() < pieces {
                cuts.push(i + 1);
            }
        }
        cuts.resize(pieces + 1, run.len());
        let times = self.batches[first..first + pieces]
            .par_iter_mut()
            .zip(self.scratch[first..first + pieces].par_iter_mut())
            .zip(cuts.par_windows(2))
            .map(|((b, (s, vertices)), cut)| {
                let mut times = Times::default();
                for (i, v) in run.get(cut[0]..cut[1]).unwrap_or(&[]).iter().enumerate() {
                    let timed = i % TIMED == 0;
                    let t = timed.then(Instant::now);
                    let Some(p) = view.prepare(pass, v) else { continue };
                    transform_into(vertices, &p.transform, p.mesh);
                    let t_setup = timed.then(Instant::now);
                    view.object_setup(&p, vertices).run(0..p.count, b, s);
                    if let (Some(t0), Some(t1)) = (t, t_setup) {
                        times.transform += (t1 - t0).as_secs_f64();
                        times.set_up += t1.elapsed().as_secs_f64();
                    }
                }
                if !ordered {
                    bin(&b.polys, 0..b.polys.len() as u32, bands, &mut b.bins);
                }
                times
            })
            .reduce(Times::default, |a, b| Times { transform: a.transform + b.transform, set_up: a.set_up + b.set_up });
        self.adopt(first, ordered);
        times.charge(start, stats);
    }

    /// The next `pieces` batches (cleared and tagged) with their scratch; returns the first's index.
    fn take_batches(&mut self, pieces: usize) -> usize {
        let first = self.batches_used;
        self.batches_used += pieces;
        let used = self.batches_used;
        if self.batches.len() < used {
            self.batches.resize_with(used, Batch::default);
            self.scratch.resize_with(used, Default::default);
        }
        for (i, b) in self.batches[first..used].iter_mut().enumerate() {
            b.clear();
            b.tag = (first + i + 1) as u32;
        }
        first
    }

    /// Hands the batches from `first` on (as far as used) to the drawing order: for the painter's orders
    /// (`ordered`) their polygons are appended to the main batch in order; for the z-buffer they stay where
    /// they are and the stretches record the order.
    fn adopt(&mut self, first: usize, ordered: bool) {
        let batches = &self.batches[first..self.batches_used];
        if ordered {
            self.main.adopt_polygons(batches);
            return;
        }
        // The z-buffer draws them from where they are: appending them to the main batch would be a serial
        // copy, and binning them again in the fill would redo what each piece's thread did in its cache.
        self.main.adopt_counts(batches);
        let end = self.main.polys.len() as u32;
        if self.main_start < end {
            self.stretches.push(Stretch::Main(self.main_start..end));
        }
        self.main_start = end;
        self.stretches.extend((first..self.batches_used).map(Stretch::Batch));
    }

    /// Transforms `mesh`'s vertices into `self.vertices`, on several threads for a big mesh.
    fn transform(&mut self, transform: &VertexTransform, mesh: &Mesh, threads: usize) {
        let n = mesh.vertices().len();
        if threads > 1 && n >= PARALLEL_VERTICES {
            size_for(&mut self.vertices, n);
            // In place, a slice per worker (collecting from a parallel iterator would build per-thread lists
            // and copy them once more).
            let chunk = n.div_ceil(threads * 4);
            self.vertices
                .par_chunks_mut(chunk)
                .zip(mesh.vertices().par_chunks(chunk))
                .for_each(|(out, vs)| transform.run(out, vs));
        } else {
            transform_into(&mut self.vertices, transform, mesh);
        }
    }
}

/// Makes `vertices` hold exactly `n` slots (every slot is overwritten, so a longer buffer is only shortened).
fn size_for(vertices: &mut Vec<SetupVertex>, n: usize) {
    if vertices.len() < n {
        vertices.resize(n, SetupVertex::default());
    }
    vertices.truncate(n);
}

/// Transforms `mesh`'s vertices into `vertices` on this thread.
fn transform_into(vertices: &mut Vec<SetupVertex>, transform: &VertexTransform, mesh: &Mesh) {
    size_for(vertices, mesh.vertices().len());
    transform.run(vertices, mesh.vertices());
}
