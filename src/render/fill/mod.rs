//! The fill (Quake's `d_*` half): the frame's polygons drawn, in order, band by band on the worker pool.
//!
//! The ordered polygons are binned once by the bands of about 32 rows they touch (in pieces, on the pool);
//! each band then clears its own rows and draws its bin (`bands`), the threads taking the bands from one
//! queue, costliest first (`schedule`). A polygon is drawn by the scanline walk
//! of seeds 001 and 002 ([`scanline`]) into spans, shaded by the general span ([`span`]) or a fast path's
//! pixel loop (`span_lanes`, with its AVX2 child), or, for a small triangle set up in advance, by `small`
//! (with its AVX2 child). An anti-aliased frame draws each polygon's coverage samples (`coverage`) into the
//! band's samples (`samples`, a pixel's samples as vector lanes in `sample_lanes`) by `antialias`,
//! resolving them at the end of the band. Edge positions are exact integers and attributes are evaluated
//! per row from the polygon's vertices, so a row's pixels do not depend on which band drew it: frames are
//! bit-identical for every thread count.

pub(crate) mod antialias;
pub(crate) mod bands;
mod coarse_depth;
pub(crate) mod coverage;
pub(crate) mod plane;
mod polygon_spans;
pub(crate) mod row;
pub(crate) mod sample_lanes;
pub(crate) mod samples;
pub mod scanline;
mod schedule;
pub(crate) mod small;
#[cfg(target_arch = "x86_64")]
mod small_avx2;
pub mod span;
#[cfg(target_arch = "x86_64")]
mod span_avx2;
pub(crate) mod span_lanes;
pub(crate) mod texel;

use std::ops::Range;
use std::sync::atomic::AtomicU8;

use rayon::iter::{IndexedParallelIterator, IntoParallelRefMutIterator, ParallelIterator};

use self::bands::{BinnedRun, FillContext};
use self::row::{SpanCounts, Visibility};
use self::schedule::BandCosts;
use crate::render::core::band::{FrameLayout, Resolve, bin, split_bands};
use crate::render::core::batch::{Batch, Screens, Stretch};
use crate::render::core::draw_list::DrawList;
use crate::render::core::options::{Method, RenderOptions};
use crate::render::core::samples::SamplePattern;

/// Orders of at least this many polygons are binned in pieces on several threads.
const PARALLEL_BINNING: usize = 1024;

/// The fill's binning scratch, kept from frame to frame.
#[derive(Debug, Default)]
pub(crate) struct Fill {
    /// The stretches of polygon indices binned here: pieces of the painter's order, or of the z-buffer's
    /// stretches of the main batch.
    jobs: Vec<Range<u32>>,
    /// The polygons of each band (inner), for each of `jobs` (outer).
    bins: Vec<Vec<Vec<u32>>>,
    /// Each band's time in the last frame drawn on several threads: the order bands are handed out in.
    costs: BandCosts,
    /// What each band remembers of the coarse depth test ([`coarse_depth`]), for a layout of as many bands.
    coarse_depth: Vec<AtomicU8>,
}

/// What the geometry and ordering stages left for the fill.
pub(crate) struct Polygons<'a> {
    /// The frame's polygons (all of them for the painter's orders).
    pub(crate) main: &'a Batch,
    /// Big objects' set-up pieces, and the z-buffer's order of the two.
    pub(crate) batches: &'a [Batch],
    pub(crate) stretches: &'a [Stretch],
    /// The painter's order (indices into `main.polys`); empty for the z-buffer.
    pub(crate) order: &'a [u32],
}

impl Fill {
    /// Clears the buffers the method needs and fills every polygon in order, band by band, across the
    /// current thread pool when `layout.threads` is more than 1 (the caller runs this inside the pool);
    /// with `resolve`, each band is then filtered into its rows of the picture by the thread that drew it.
    pub(crate) fn run(
        &mut self,
        frame: &mut [u32],
        layout: FrameLayout,
        polygons: &Polygons<'_>,
        list: &DrawList<'_>,
        (options, tall): (&RenderOptions, bool),
        resolve: Option<Resolve<'_>>,
    ) -> SpanCounts {
        let ordered = options.method != Method::ZBuffer;
        // Out of `self` while the runs below borrow its bins.
        let mut costs = std::mem::take(&mut self.costs);
        let chunk = self.bin(layout, polygons, ordered);
        let bands = layout.height.div_ceil(layout.rows_per_band.max(1));
        if self.coarse_depth.len() != bands {
            self.coarse_depth = (0..bands).map(|_| AtomicU8::new(0)).collect();
        }
        let runs = self.runs(polygons, ordered, chunk);
        let ctx = FillContext {
            runs: &runs,
            background: options.background,
            screens: Screens { main: polygons.main, batches: polygons.batches },
            list,
            options,
            visibility: match options.method {
                Method::ZBuffer => Visibility::DepthTest,
                Method::BucketNear => Visibility::Coverage,
                Method::Sort | Method::BucketFar | Method::ViewLists => Visibility::Overwrite,
            },
            width: layout.width,
            words: layout.width.div_ceil(64),
            pattern: options.antialias.coverage_samples().and_then(SamplePattern::standard),
            tall,
            resolve: resolve.as_ref().map(|r| r.band),
            coarse_depth: &self.coarse_depth,
        };
        let (out, shape) = match resolve {
            Some(Resolve { out, rows, band }) => (Some(out), (band.width, rows)),
            None => (None, (0, 1)),
        };
        let bands = split_bands(frame, (layout.width, layout.height), layout.rows_per_band, out, shape);
        let counts = if layout.threads == 1 {
            bands
                .into_iter()
                .enumerate()
                .map(|(i, band)| ctx.fill_band(band, i))
                .fold(SpanCounts::default(), |a, b| a + b)
        } else {
            // Bands are handed out one at a time from a queue, costliest first (`schedule`): the sky and the
            // horizon cost very different amounts, and a costly band drawn last by one thread left the other
            // idle.
            costs.draw(&ctx, bands, layout)
        };
        drop(runs);
        self.costs = costs;
        counts
    }

    /// Bins what the fill bins itself (the painter's order, or the z-buffer's stretches of the main batch) in
    /// pieces of at most the returned number of polygons, in parallel when there are many.
    fn bin(&mut self, layout: FrameLayout, p: &Polygons<'_>, ordered: bool) -> u32 {
        let to_bin = if ordered { p.order.len() } else { p.main.polys.len() };
        let pieces = if layout.threads > 1 && to_bin >= PARALLEL_BINNING { layout.threads * 2 } else { 1 };
        let chunk = to_bin.div_ceil(pieces).max(1) as u32;
        self.jobs.clear();
        let mut cut = |r: Range<u32>| {
            let mut a = r.start;
            while a < r.end {
                let b = r.end.min(a.saturating_add(chunk));
                self.jobs.push(a..b);
                a = b;
            }
        };
        if ordered {
            cut(0..p.order.len() as u32);
        } else {
            for s in p.stretches {
                if let Stretch::Main(r) = s {
                    cut(r.clone());
                }
            }
        }
        self.bins.resize_with(self.jobs.len(), Vec::new);
        self.bins.truncate(self.jobs.len());
        let (polys, order, bands) = (&p.main.polys, p.order, (layout.height, layout.rows_per_band));
        let bin_job = |(b, r): (&mut Vec<Vec<u32>>, &Range<u32>)| {
            if ordered {
                let order = order.get(r.start as usize..r.end as usize).unwrap_or_default();
                bin(polys, order.iter().copied(), bands, b);
            } else {
                bin(polys, r.clone(), bands, b);
            }
        };
        if self.jobs.len() <= 1 {
            self.bins.iter_mut().zip(&self.jobs).for_each(bin_job);
        } else {
            self.bins.par_iter_mut().zip(&self.jobs).for_each(bin_job);
        }
        chunk
    }

    /// The runs of the drawing order, in order: the binned pieces, and for the z-buffer the set-up
    /// batches (binned by their set-up) between the main batch's stretches.
    fn runs<'a>(&'a self, p: &Polygons<'a>, ordered: bool, chunk: u32) -> Vec<BinnedRun<'a>> {
        let polys = &p.main.polys;
        let mut own = self.bins.iter().map(|bins| BinnedRun { polys, bins });
        if ordered {
            return own.collect();
        }
        let mut runs = Vec::with_capacity(p.stretches.len() + self.bins.len());
        for s in p.stretches {
            match s {
                Stretch::Main(r) => {
                    // This stretch's pieces, in order.
                    let n = r.len().div_ceil(chunk as usize);
                    runs.extend(own.by_ref().take(n));
                }
                Stretch::Batch(k) => {
                    if let Some(b) = p.batches.get(*k) {
                        runs.push(BinnedRun { polys: &b.polys, bins: &b.bins });
                    }
                }
            }
        }
        debug_assert!(own.next().is_none(), "a binned piece of the main batch was not drawn");
        runs
    }
}
