//! The renderer: ties the stages together for one frame and keeps their scratch buffers and worker pool
//! from frame to frame.
//!
//! A frame is [`geometry`](super::geometry) (once per frame, a big object's polygons set up in pieces on the
//! pool), then [`order`](super::order) (the painter's methods only), then [`fill`](super::fill) (band by
//! band on the pool). With more than one thread the whole frame runs on a rayon pool kept between frames, so
//! the geometry runs on a worker too and does not compete for a core with workers still spinning after the
//! previous frame's fill. The calling thread is the pool's first worker where it can be (`Pool`): it draws
//! its frame itself with the others, instead of waking one to draw it and sleeping until it is done.

use std::time::Instant;

use super::core::band::{BandResolve, FrameLayout, Resolve, RowFilter, RowSpread};
use super::core::camera::Camera;
use super::core::draw_list::DrawList;
use super::core::error::RenderError;
use super::core::options::{Antialias, RenderOptions};
use super::core::stats::{Stats, ms_since};
use super::fill::row::SpanCounts;
use super::fill::{Fill, Polygons};
use super::geometry::Geometry;
use super::order::Order;
use super::supersample;

/// The largest frame side: screen positions are [`Fx28_4`](super::core::fixed::Fx28_4) with room for the
/// guard band.
const MAX_SIDE: usize = 1 << 20;

/// How rows of a frame are spread over their rows of a big frame before drawing over them, how rows of the
/// big frame come back to their rows of the frame, and how many rows of the big frame make one of the
/// frame's.
type BigPasses = (RowSpread, RowFilter, usize);

/// A reusable renderer: holds scratch buffers so frames after the first allocate nothing per polygon or
/// per pixel (only the fill's short lists of bands and runs, a few dozen entries, are made each frame).
#[derive(Debug, Default)]
pub struct Renderer {
    geometry: Geometry,
    order: Order,
    fill: Fill,
    /// The worker pool and its thread count, kept while the count stays the same.
    pool: Option<Pool>,
    /// Whether the frame being drawn is a rotated-grid frame, four rows a pixel.
    tall: bool,
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
        self.render_into(frame, (width, height), (camera, list, options), None)
    }

    /// [`render`](Self::render), resolving the frame band by band into the picture `resolve` names when it
    /// names one (a big frame of 2x2 supersampling or the rotated grid, drawn a band at a time into each
    /// thread's own rows; `frame` is then empty).
    fn render_into(
        &mut self,
        frame: &mut [u32],
        (width, height): (usize, usize),
        (camera, list, options): (&Camera, &DrawList<'_>, &RenderOptions),
        resolve: Option<Resolve<'_>>,
    ) -> Result<Stats, RenderError> {
        let needed = width.saturating_mul(height);
        // A resolved frame has no buffer of its own (its bands draw into their threads' rows).
        let needed_here = if resolve.is_some() { 0 } else { needed };
        if frame.len() < needed_here {
            return Err(RenderError::FrameTooSmall { len: frame.len(), width, height, needed });
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return Err(RenderError::FrameTooLarge { width, height });
        }
        let mut stats = Stats::default();
        if needed == 0 {
            return Ok(stats);
        }
        if options.antialias == Antialias::Supersample2x2 {
            return self.supersampled(&mut frame[..needed], (width, height), camera, list, options);
        }
        if options.antialias == Antialias::RotatedGrid {
            return self.rotated_grid(&mut frame[..needed], (width, height), camera, list, options);
        }
        let threads = match options.threads {
            0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
            n => n,
        }
        .min(super::MAX_THREADS);
        let layout = FrameLayout::new(width, height, threads).grouped(resolve.as_ref().map_or(1, |r| r.rows));
        let pool = self.take_pool(layout.threads)?;
        let frame = &mut frame[..needed_here];
        let counts = match &pool {
            Some(p) => p.pool.install(|| self.frame(frame, layout, (camera, list, options), &mut stats, resolve)),
            None => self.frame(frame, layout, (camera, list, options), &mut stats, resolve),
        };
        self.pool = pool;
        stats.pixels_shaded = counts.shaded;
        stats.pixels_written = counts.written;
        stats.pixels_rejected = counts.rejected;
        stats.pieces_filled = self.geometry.pieces();
        Ok(stats)
    }

    /// Draws the frame at twice the width and height and box-filters it down (2x2 supersampling, the
    /// quality yardstick). The level of detail is chosen as for the frame's own size (a bias of -1 halves the
    /// doubled projected sizes), so supersampling changes the edges and textures, not the models.
    fn supersampled(
        &mut self,
        frame: &mut [u32],
        (width, height): (usize, usize),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Result<Stats, RenderError> {
        let [dx, dy] = options.pixel_offset;
        let inner = RenderOptions {
            antialias: Antialias::Off,
            lod_bias: options.lod_bias - 1.0,
            pixel_offset: [2.0 * dx, 2.0 * dy],
            ..*options
        };
        // Drawn over what is there, each pixel becomes its four; each 2x2 block comes back as one.
        let passes: BigPasses = (supersample::expand, supersample::box_filter, 2);
        self.big_frame(frame, (width, (width * 2, height * 2)), passes, (camera, list, &inner), false)
    }

    /// Draws the frame at four times its height, each row's samples shifted by its own fraction of a pixel
    /// (the fill's [`ROW_SHIFTS`](super::core::samples::ROW_SHIFTS)), and averages each column of four rows:
    /// four samples a pixel on four rows and four columns, a rotated grid. The geometry runs once, with the
    /// camera's aspect and the models of the frame's own size; the screen doors take the ranks of a frame
    /// of twice the size, and the textures are sampled as there.
    fn rotated_grid(
        &mut self,
        frame: &mut [u32],
        (width, height): (usize, usize),
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Result<Stats, RenderError> {
        let th =
            height.checked_mul(4).filter(|&h| h <= MAX_SIDE).ok_or(RenderError::FrameTooLarge { width, height })?;
        let [dx, dy] = options.pixel_offset;
        let inner = RenderOptions { antialias: Antialias::Off, pixel_offset: [dx, 4.0 * dy], ..*options };
        let passes: BigPasses = (supersample::expand_rows, supersample::mean_rows, 4);
        self.big_frame(frame, (width, (width, th)), passes, (camera, list, &inner), true)
    }

    /// Draws the scene as a big frame, `bw` x `bh` (twice the width and height for 2x2 supersampling, four
    /// times the height for the rotated grid, a tall frame when `tall`) with `inner`, and brings it back to
    /// `frame` (`width` a row) by the second of `passes`. The big frame is never whole: each band is drawn
    /// into the drawing thread's own rows (spread from its rows of `frame` by the first of `passes` when the
    /// options draw no background) and filtered into its rows of `frame` as soon as it is drawn.
    fn big_frame(
        &mut self,
        frame: &mut [u32],
        (width, (bw, bh)): (usize, (usize, usize)),
        (spread, run, rows): BigPasses,
        (camera, list, inner): (&Camera, &DrawList<'_>, &RenderOptions),
        tall: bool,
    ) -> Result<Stats, RenderError> {
        self.tall = tall;
        let band = BandResolve { run, spread: inner.background.is_none().then_some(spread), width };
        let into = Resolve { out: frame, rows, band };
        let stats = self.render_into(&mut [], (bw, bh), (camera, list, inner), Some(into));
        self.tall = false;
        stats
    }

    /// How many polygons each ordering-table bucket held in the last frame (nearest first); empty when the
    /// last frame did not use the ordering table.
    #[must_use]
    pub fn bucket_occupancy(&self) -> Vec<u32> {
        self.order.occupancy()
    }

    /// Forgets the levels of detail chosen in earlier frames (call on a new scene or a camera cut).
    pub fn reset_lod(&mut self) {
        self.geometry.lod.clear();
    }

    /// The mesh each instance of `list` would draw in a `width` x `height` frame (after the LOD choice, which
    /// updates this renderer's LOD history like a frame does) and whether it is in a level-of-detail
    /// cross-fade ([`RenderOptions::lod_fade`]: then it also draws the model fading out), or `None` for an
    /// instance culled by the view frustum or naming no mesh. For exporting exactly what a frame draws.
    pub fn frame_lod(
        &mut self,
        width: usize,
        height: usize,
        camera: &Camera,
        list: &DrawList<'_>,
        options: &RenderOptions,
    ) -> Vec<Option<(usize, bool)>> {
        self.geometry.frame_lod((width, height), camera, list, options)
    }

    /// The pool for `threads` workers: the one kept from the last frame when the count is the same (and, for
    /// a pool the calling thread belongs to, the caller is the same thread), none for one thread.
    fn take_pool(&mut self, threads: usize) -> Result<Option<Pool>, RenderError> {
        let here = std::thread::current().id();
        Ok(match self.pool.take() {
            Some(p) if p.threads == threads && p.caller.is_none_or(|c| c == here) => Some(p),
            _ if threads == 1 => None,
            _ => Some(Pool::new(threads)?),
        })
    }

    /// The frame's stages in turn (inside the pool, when there is one).
    fn frame(
        &mut self,
        frame: &mut [u32],
        layout: FrameLayout,
        (camera, list, options): (&Camera, &DrawList<'_>, &RenderOptions),
        stats: &mut Stats,
        resolve: Option<Resolve<'_>>,
    ) -> SpanCounts {
        let t = Instant::now();
        self.geometry.run((layout, self.tall), camera, list, options, stats);
        let t_order = Instant::now();
        let keys = &self.geometry.set_up.main.keys;
        debug_assert!(keys.is_empty() || keys.len() == self.geometry.set_up.main.polys.len());
        self.order.run(keys, options);
        stats.ms_order = ms_since(t_order);
        let t_fill = Instant::now();
        let polygons = Polygons {
            main: &self.geometry.set_up.main,
            batches: &self.geometry.set_up.batches,
            stretches: &self.geometry.set_up.stretches,
            order: &self.order.order,
        };
        let counts = self.fill.run(frame, layout, &polygons, list, (options, self.tall), resolve);
        stats.ms_fill = ms_since(t_fill);
        debug_assert!(stats.ms_transform + stats.ms_clip <= ms_since(t) + 1.0);
        counts
    }
}

/// The renderer's workers: a rayon pool of `threads` threads, the calling thread one of them when it can be.
#[derive(Debug)]
struct Pool {
    /// How many threads draw, the caller included when `caller` is set.
    threads: usize,
    /// The pool.
    pool: rayon::ThreadPool,
    /// The thread that is the pool's first worker, when it is one: a frame drawn from it runs on it and
    /// `threads - 1` workers, and one drawn from another thread would run without it, so the pool is built
    /// again there.
    caller: Option<std::thread::ThreadId>,
}

impl Pool {
    /// A pool of `threads` threads, the calling thread among them when it is in no other pool.
    ///
    /// The caller draws its own frame rather than waking a worker for it and sleeping until it is done:
    /// two wake-ups fewer a frame, and one thread fewer to be woken onto a busy core. A thread can be the
    /// first worker of one pool in its life (rayon keeps it registered when the pool is gone), so a second
    /// pool built on it, or one on a thread already a rayon worker, is a pool of its own threads as before.
    fn new(threads: usize) -> Result<Self, RenderError> {
        let builder = || rayon::ThreadPoolBuilder::new().num_threads(threads).thread_name(|i| format!("fill-{i}"));
        if let Ok(pool) = builder().use_current_thread().build() {
            return Ok(Self { threads, pool, caller: Some(std::thread::current().id()) });
        }
        let pool = builder().build().map_err(|_| RenderError::WorkerFailed)?;
        Ok(Self { threads, pool, caller: None })
    }
}

#[cfg(test)]
mod tests {
    use super::Pool;

    #[test]
    fn the_calling_thread_is_a_worker_of_its_first_pool_only() {
        std::thread::spawn(|| {
            let here = std::thread::current().id();
            let first = Pool::new(2).unwrap();
            assert_eq!(first.caller, Some(here), "a thread in no pool joins its first");
            assert_eq!(first.pool.current_num_threads(), 2);
            assert_eq!(first.pool.install(rayon::current_thread_index), Some(0), "install runs on the caller");
            // Already a worker: the second pool is all its own threads, and runs elsewhere.
            let second = Pool::new(3).unwrap();
            assert_eq!(second.caller, None);
            assert_eq!(second.pool.current_num_threads(), 3);
            assert_ne!(second.pool.install(|| std::thread::current().id()), here);
            drop(first);
            // Rayon keeps the thread registered when its pool is gone, so later pools are their own threads.
            assert_eq!(Pool::new(2).unwrap().caller, None);
        })
        .join()
        .unwrap();
    }
}
