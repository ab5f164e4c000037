//! The fill stage across threads: the frame is cut into horizontal bands, the ordered polygons are binned
//! once by the bands they touch, and every band clears its own buffers and draws its bin, in order, on its
//! own rows. Because edge positions are exact integers and attributes are evaluated per row from the
//! polygon's vertices, a row's pixels do not depend on which band drew it.

use super::antialias::{self, Target};
use super::coarse_depth::{BandTest, Behind, CoarseDepth};
use super::polygon_spans::{PolygonSpans, walk_rows};
use super::row::{BandPixels, FLAT, RowRun, Run, SpanCounts, Visibility};
use super::samples::SampleStore;
use super::scanline::Span;
use super::small::{self, NextFlat};
use super::span::{Prepared, Shading, draw_prepared};
use super::span_lanes::{Fill, Paint, Source, dispatch, walk};
use crate::render::core::band::{Band, BandResolve};
use crate::render::core::batch::Screens;
use crate::render::core::draw_list::DrawList;
use crate::render::core::filter::Filter;
use crate::render::core::mip::TexGradients;
use crate::render::core::options::{MipMode, RenderOptions};
use crate::render::core::polygon::DrawPolygon;
use crate::render::core::samples::{ROW_SHIFTS, SamplePattern};
use crate::render::core::small::{SmallTriangle, TexPlanes};
use crate::render::core::vertex::{ATTRS, ScreenVertex, Winding};
use crate::render::simd::{self, Avx2};
use std::sync::atomic::AtomicU8;

/// A thread's depth and coverage rows for the band it is drawing, and a polygon's short spans there.
#[derive(Default)]
struct Scratch {
    /// A resolved frame's band's colour rows.
    color: Vec<u32>,
    runs: Vec<RowRun>,
    depth: Vec<f32>,
    coverage: Vec<u64>,
    samples: SampleStore,
    coarse: CoarseDepth,
}

thread_local! {
    /// Depth and coverage exist only a band at a time, per thread, reused band after band: they stay in the
    /// core's cache and never travel to memory (a frame-sized depth buffer at 1920x1080 is 8 MB written and
    /// read back every frame).
    static SCRATCH: std::cell::RefCell<Scratch> = std::cell::RefCell::new(Scratch::default());
}

/// A stretch of the drawing order: its polygons, and for each band the indices (into `polys`) of those
/// touching it, in order.
///
/// The z-buffer's order is the submission order, so a big object's set-up pieces bin their own polygons
/// as they finish, on the set-up's threads, and the fill reads the polygons where set-up left them; the
/// painter's orders bin pieces of their sorted order over the frame's polygon list.
#[derive(Clone, Copy)]
pub(crate) struct BinnedRun<'a> {
    pub(crate) polys: &'a [DrawPolygon],
    pub(crate) bins: &'a [Vec<u32>],
}

/// The polygons of one band's bin in every run, in turn.
///
/// A hand-written state machine: the fill's group loops peek it after every small triangle, so its step is
/// paid per triangle, and nested iterator adaptors over the runs make that step dearer.
struct BinIter<'a> {
    /// The runs still to visit.
    runs: &'a [BinnedRun<'a>],
    band: usize,
    /// The current run's polygons, and what is left of its bin for the band.
    polys: &'a [DrawPolygon],
    indices: std::slice::Iter<'a, u32>,
    /// Where small triangles' set-ups are, to read ahead.
    screens: Screens<'a>,
}

/// How many polygons of a bin ahead of the one drawn [`BinIter`] prefetches the record of, and half as many
/// the small triangle's set-up: on a scene of many small triangles their records do not stay in cache, and
/// a band visits one in every few (those binned to it), so the hardware does not prefetch them; each would
/// otherwise be a wait on memory, two in a row (the polygon, then its set-up).
const READ_AHEAD: usize = 8;

impl<'a> Iterator for BinIter<'a> {
    type Item = &'a DrawPolygon;

    #[inline(always)]
    fn next(&mut self) -> Option<&'a DrawPolygon> {
        loop {
            if let Some(&pi) = self.indices.next() {
                let ahead = self.indices.as_slice();
                if let Some(q) = ahead.get(READ_AHEAD - 1).and_then(|&i| self.polys.get(i as usize)) {
                    simd::prefetch(q);
                }
                let near = ahead.get(READ_AHEAD / 2 - 1).and_then(|&i| self.polys.get(i as usize));
                if let Some((t, _)) = near.and_then(|q| self.screens.small(q)) {
                    simd::prefetch(t);
                }
                match self.polys.get(pi as usize) {
                    Some(p) => return Some(p),
                    None => continue,
                }
            }
            let (run, rest) = self.runs.split_first()?;
            self.runs = rest;
            self.polys = run.polys;
            self.indices = run.bins.get(self.band).map_or(&[][..], Vec::as_slice).iter();
        }
    }
}

/// Read-only state shared by the fill workers.
pub(crate) struct FillContext<'a> {
    /// The drawing order: its runs in turn.
    pub(crate) runs: &'a [BinnedRun<'a>],
    pub(crate) background: Option<u32>,
    pub(crate) screens: Screens<'a>,
    pub(crate) list: &'a DrawList<'a>,
    pub(crate) options: &'a RenderOptions,
    pub(crate) visibility: Visibility,
    pub(crate) width: usize,
    pub(crate) words: usize,
    /// The coverage samples when anti-aliased.
    pub(crate) pattern: Option<SamplePattern>,
    /// Whether the frame is a rotated-grid frame drawn four rows a pixel: each row's samples are shifted by
    /// [`ROW_SHIFTS`], its screen doors take the ranks of a frame of twice the size
    /// ([`Door::in_tall_frame`](crate::render::core::door::Door::in_tall_frame)), and its textures are
    /// sampled as in such a frame.
    pub(crate) tall: bool,
    /// How a band's rows come from and go back to its rows of the picture, when the frame is resolved into
    /// one ([`Resolve`](crate::render::core::band::Resolve)).
    pub(crate) resolve: Option<BandResolve>,
    /// What each band remembers of the coarse depth test from the frames before
    /// ([`BandTest`](super::coarse_depth::BandTest)).
    pub(crate) coarse_depth: &'a [AtomicU8],
}

impl<'a> FillContext<'a> {
    /// Clears a band's buffers and draws its bin, band `index` of each run in turn; returns the pixel counts.
    /// A band of a resolved frame is drawn into the thread's own rows (spread from its rows of the picture
    /// first, when there is no background), which are then filtered into its rows of the picture.
    pub(crate) fn fill_band(&self, band: Band<'_>, index: usize) -> SpanCounts {
        SCRATCH.with_borrow_mut(|scratch| {
            let (y0, rows, out, resolve) = match (band, self.resolve) {
                (Band { y0, rows, out: Some(out), .. }, Some(resolve)) => (y0, rows, out, resolve),
                (band, _) => return self.fill_band_with(band, index, scratch),
            };
            let mut color = std::mem::take(&mut scratch.color);
            color.resize(rows * self.width, 0);
            if let Some(spread) = resolve.spread {
                spread(out, resolve.width, &mut color);
            }
            let counts = self.fill_band_with(Band { y0, rows, color: &mut color, out: None }, index, scratch);
            (resolve.run)(&color, out, resolve.width);
            scratch.color = color;
            counts
        })
    }

    /// How polygon `p`'s pixels are shaded: its paint, the frame's filter, mip choice and visibility, the
    /// polygon's level of detail or planes for the mip choice (every fill that shades a pixel by
    /// [`shade_surface`](super::span::shade_surface) takes its [`Shading`] from here).
    pub(crate) fn shading(&self, p: &DrawPolygon) -> Shading<'_> {
        let texture = p.texture().and_then(|t| self.list.textures.get(t as usize));
        let mip = self.options.mip.with_filter(self.options.filter);
        let measured = matches!(mip, MipMode::Span | MipMode::Pixel);
        let filter = self.options.filter.for_surface(p.lod(), p.alpha_cutoff().is_some());
        // The planes a pixel's level of detail is measured by, from the polygon's corners (the same in every
        // band that draws it).
        let gradients = match self.screens.of(p) {
            Some(v) if (measured || filter == Filter::Area) && texture.is_some() => TexGradients::of(v),
            _ => TexGradients::default(),
        };
        // A rotated-grid frame samples like a frame of twice the width and height: its texel footprints
        // are half as wide and, its rows being a quarter of a pixel, twice as tall (scaling the planes by
        // powers of two is exact). Its polygons' levels are already one finer: a level per polygon comes
        // from the polygon's area, four times larger in a frame of four rows a pixel.
        let gradients = if self.tall { gradients.in_tall_frame() } else { gradients };
        // The mip bias moves a polygon's level of detail, or scales the footprints a pixel's level is
        // measured from by its power of two (a footprint twice as long is one level coarser).
        let bias = Some(self.options.mip_bias).filter(|b| b.is_finite() && *b != 0.0);
        let (lod, gradients) = match bias {
            Some(b) if measured => (p.lod(), gradients.biased(b)),
            // `area` on a magnified polygon keeps level 0 and measures its box from the planes: a coarser bias
            // widens the box by its power of two (towards bilinear); a finer one changes nothing there (no
            // level is finer than 0, and a box narrower than the footprint would alias).
            Some(b) if filter == Filter::Area && b > 0.0 => ((p.lod() + b).max(0.0), gradients.biased(b)),
            Some(b) => ((p.lod() + b).max(0.0), gradients),
            None => (p.lod(), gradients),
        };
        Shading {
            texture,
            sampler: p.sampler,
            // `min-bilinear` by the polygon's own level (a bias moves which level it samples, not whether its
            // texture is minified).
            filter,
            mip,
            lod,
            gradients,
            mode: self.options.texture_mode,
            alpha_cutoff: p.alpha_cutoff(),
            constant_color: p.constant_color(),
            visibility: self.visibility,
            door: p.door().in_tall_frame(self.tall),
        }
    }

    fn fill_band_with(&self, band: Band<'_>, index: usize, scratch: &mut Scratch) -> SpanCounts {
        let Band { y0, rows: height, color, .. } = band;
        let Scratch { runs, depth, coverage, samples, coarse, .. } = scratch;
        let (w, words) = (self.width, self.words);
        if let Some(bg) = self.background {
            color.fill(bg);
        }
        let depth = cleared(depth, self.visibility == Visibility::DepthTest, height * w, f32::NEG_INFINITY);
        let coverage = cleared(coverage, self.visibility == Visibility::Coverage, height * words, 0);
        let mut rows = BandPixels { y0, width: w, words, color, depth, coverage };
        let mut total = SpanCounts::default();
        let mut add = |c: SpanCounts| total += c;
        let band_rows = (y0 as i32, (y0 + height) as i32);
        let bin = || BinIter { runs: self.runs, band: index, polys: &[], indices: [].iter(), screens: self.screens };
        if let Some(pattern) = &self.pattern {
            samples.begin(height * w, height, pattern);
            let mut target = Target { pixels: &mut rows, store: samples, pattern, band: band_rows };
            // The pattern comes from `SamplePattern::standard`, which makes only these three counts.
            debug_assert!(matches!(pattern.count, 4 | 8 | 16), "a pattern of {} samples", pattern.count);
            return match pattern.count {
                4 => self.fill_band_antialiased::<4>(bin(), &mut target),
                8 => self.fill_band_antialiased::<8>(bin(), &mut target),
                _ => self.fill_band_antialiased::<16>(bin(), &mut target),
            };
        }
        if self.visibility != Visibility::DepthTest {
            // Painter's orders visit the polygons in depth order, at random places in memory: reading one
            // corner of each first, with nothing waiting on the loads, lets their cache misses overlap,
            // where the drawing loop below would wait for them one at a time.
            let mut touched = 0i32;
            for p in bin() {
                if let Some((t, _)) = self.screens.small(p) {
                    touched ^= t.rows().0;
                } else if let Some(v) = self.screens.of(p) {
                    touched ^= v.first().map_or(0, |v| v.y.0);
                }
            }
            std::hint::black_box(touched);
        }
        let tested = self.visibility == Visibility::DepthTest && self.options.coarse_depth;
        let mut occlusion = BandTest::begin(coarse, self.coarse_depth.get(index), tested, band_rows, w);
        // Every floor first, from the whole bin's solid polygons: one is skipped behind a polygon drawn after
        // it as well as before.
        let solid = |p: &&DrawPolygon| p.alpha_cutoff().is_none() && p.door().is_none();
        occlusion.cover_all(bin().filter(solid).filter_map(|p| self.screens.of(p)));
        let mut polys = bin().peekable();
        while let Some(p) = polys.next() {
            // A polygon drawn from its corners may be hidden whole (small triangles have none: not tried).
            // Drawn on the band's rows, less those at its top and bottom where every tile under it hides it.
            let (mut drawn_rows, mut behind) = (band_rows, None);
            if occlusion.on()
                && let Some(v) = self.screens.of(p)
            {
                let Some(r) = occlusion.rows(v) else { continue };
                (drawn_rows, behind) = r;
            }
            let shading = self.shading(p);
            let prepared = shading.prepare();
            if let Some(tri) = self.screens.small(p) {
                // Set up only for polygons with a fast path (`FastPathRule`, which a test holds to `prepare`).
                debug_assert!(prepared.fast().is_some(), "a small triangle without a fast path");
                if let Some((source, alpha)) = prepared.fast() {
                    let group =
                        SmallGroup { first: (p, tri), rest: &mut polys, ctx: self, band: band_rows, rows: &mut rows };
                    add(dispatch(source, alpha, self.visibility, group));
                }
                continue;
            }
            let Some(verts) = self.screens.of(p) else { continue };
            let c = self.fill_corners(
                (verts, p.winding()),
                (&shading, &prepared),
                (drawn_rows, behind),
                (&mut rows, &mut *runs),
            );
            add(c);
        }
        occlusion.end();
        total
    }

    /// Draws a polygon with corners `verts` on the band's rows `band_rows`, skipping what the coarse depth's
    /// floors it may lie behind hide (`behind`): a fast path from the polygon's own level by one loop chosen
    /// for all its spans, any other a span at a time.
    fn fill_corners(
        &self,
        (verts, winding): (&[ScreenVertex], Winding),
        (shading, prepared): (&Shading<'_>, &Prepared<'_>),
        (band_rows, behind): ((i32, i32), Option<Behind<'_>>),
        (rows, runs): (&mut BandPixels<'_>, &mut Vec<RowRun>),
    ) -> SpanCounts {
        let width = self.width as i32;
        let tall = self.tall.then_some(ROW_SHIFTS);
        if let Some((source, alpha)) = prepared.fast().filter(|_| shading.mip != MipMode::Span) {
            let spans = PolygonSpans { verts, winding, band: band_rows, width, tall, rows, runs, behind };
            return dispatch(source, alpha, self.visibility, spans);
        }
        let mut total = SpanCounts::default();
        let draw = |span: &Span| {
            let hidden =
                behind.is_some_and(|b| b.columns(span.y, (span.x0.max(0) as usize, span.x1.max(0) as usize)).is_none());
            if !hidden {
                total += draw_prepared(span, shading, prepared, &mut rows.row(span.y));
            }
        };
        match prepared.fast() {
            None => walk_rows::<ATTRS>((verts, winding), band_rows, width, tall, draw),
            // Each attribute is interpolated on its own, so fewer of them change none of the others' bits.
            Some((Source::Flat(_), _)) => walk_rows::<1>((verts, winding), band_rows, width, tall, draw),
            Some(_) => walk_rows::<4>((verts, winding), band_rows, width, tall, draw),
        }
        total
    }

    /// Draws a band's polygons `bin` anti-aliased with a pattern of `N` samples, then resolves the band.
    fn fill_band_antialiased<const N: usize>(
        &self,
        bin: impl Iterator<Item = &'a DrawPolygon>,
        target: &mut Target<'_, '_>,
    ) -> SpanCounts {
        let mut total = SpanCounts::default();
        let mut pending = antialias::Pending::EMPTY;
        for p in bin {
            // Set-up makes no small triangles when the frame is anti-aliased: every polygon has corners.
            let Some(verts) = self.screens.of(p) else { continue };
            let shading = self.shading(p);
            total += antialias::fill_polygon::<N>(verts, &shading, &shading.prepare(), target, &mut pending);
        }
        antialias::resolve::<N>(target, self.visibility);
        total
    }
}

/// The band's `n` depths or coverage words, all `value`, when the frame's visibility `uses` them, else none.
fn cleared<T: Clone>(v: &mut Vec<T>, uses: bool, n: usize, value: T) -> &mut [T] {
    if !uses {
        return &mut [];
    }
    v.clear();
    v.resize(n, value);
    v
}

/// [`small::fill_flat_run`] for `VIS` (depth-tested, each pixel once, or overwriting), with AVX2
/// when `avx2` (from [`simd::avx2`]).
#[inline(always)]
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_variables))]
fn fill_flat_run<'t, const VIS: u8>(
    start: (&'t SmallTriangle, u32),
    next: &mut impl NextFlat<'t>,
    band: (i32, i32),
    px: &mut BandPixels<'_>,
    avx2: Option<Avx2>,
) -> ((u64, u64), Option<(&'t SmallTriangle, u32)>) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = avx2 {
        return crate::render::fill::small_avx2::fill_flat_run::<VIS>(avx2, start, next, band, px);
    }
    small::fill_flat_run(start, next, band, px, small::fill_flat_narrow::<VIS>)
}

/// Small triangles that follow one another in a bin and paint alike (flat colours, or one texture with one
/// tint and cutoff), drawn by one monomorphised loop: the shading, its fast path and the dispatch are
/// chosen once for the group rather than per triangle.
struct SmallGroup<'g, 'c, 'r, 'b, I: Iterator> {
    /// The group's first polygon and its set-up.
    first: (&'c DrawPolygon, SmallSetUp<'c>),
    /// The rest of the bin; the group takes polygons from it while they paint like the first.
    rest: &'g mut std::iter::Peekable<I>,
    ctx: &'c FillContext<'c>,
    /// The band's rows, `band.0..band.1`.
    band: (i32, i32),
    rows: &'r mut BandPixels<'b>,
}

/// A small triangle's set-up and its texture planes.
type SmallSetUp<'c> = (&'c SmallTriangle, &'c TexPlanes);

/// The set-up of the bin's next polygon (from `rest`) if it is a small triangle that paints like `first`
/// with the loop for source `SRC` (any flat colour, or the same texture, sampler, colour and cutoff).
#[inline(always)]
fn next_alike<'c, const SRC: u8>(
    rest: &mut std::iter::Peekable<impl Iterator<Item = &'c DrawPolygon>>,
    ctx: &'c FillContext<'c>,
    first: &DrawPolygon,
) -> Option<(&'c DrawPolygon, SmallSetUp<'c>)> {
    let q: &'c DrawPolygon = rest.peek()?;
    let alike = if SRC == FLAT { q.texture().is_none() } else { q.paints_like(first) };
    // A small triangle is set up only for a fast path, so with no texture it is flat.
    let t = ctx.screens.small(q).filter(|_| alike)?;
    rest.next();
    Some((q, t))
}

impl<'c, I: Iterator<Item = &'c DrawPolygon>> SmallGroup<'_, 'c, '_, '_, I> {
    /// Draws a group of flat small triangles (any visibility): runs of narrow ones by
    /// [`small::fill_flat_run`] (with AVX2 where the CPU has it), the others a run at a time.
    fn fill_flat<const VIS: u8>(self, paint: &Paint<'_>) -> SpanCounts {
        if self.ctx.tall {
            return self.fill_flat_shifted::<VIS>(paint);
        }
        let SmallGroup { first: (first, (tri, _)), rest, ctx, band, rows } = self;
        let mut total = SpanCounts::default();
        // Asked once per group: even the detection's cached answer is a cost the fill notices when asked per
        // triangle.
        let avx2 = simd::avx2();
        let mut next = AlikeFlat { rest, ctx, first };
        let mut current = Some((tri, paint.flat()));
        while let Some(start) = current {
            // A fresh view of the band's buffers for the run: its fields stay in registers through the
            // narrow fill's loop rather than being read back through `rows` after every store.
            let mut px = rows.reborrow();
            let ((written, rejected), wide) = fill_flat_run::<VIS>(start, &mut next, band, &mut px, avx2);
            total += SpanCounts { shaded: written, written, rejected };
            let Some((t, color)) = wide else { break };
            let paint = paint.with_flat(color);
            t.for_each_run::<1>(&TexPlanes::NONE, band, None, |y, run: &Run| {
                total += walk::<VIS, FLAT>(run, &paint, &mut rows.row(y))
            });
            current = next.next_flat();
        }
        total
    }

    /// [`Self::fill_flat`] in a frame of four rows a pixel: every triangle a run at a time, each row's
    /// samples shifted ([`ROW_SHIFTS`]; the narrow fill's four lanes sample the centres).
    fn fill_flat_shifted<const VIS: u8>(self, paint: &Paint<'_>) -> SpanCounts {
        let SmallGroup { first: (first, (tri, _)), rest, ctx, band, rows } = self;
        let mut total = SpanCounts::default();
        let mut next = AlikeFlat { rest, ctx, first };
        let mut current = Some((tri, paint.flat()));
        while let Some((t, color)) = current {
            let paint = paint.with_flat(color);
            t.for_each_run::<1>(&TexPlanes::NONE, band, Some(&ROW_SHIFTS), |y, run: &Run| {
                total += walk::<VIS, FLAT>(run, &paint, &mut rows.row(y))
            });
            current = next.next_flat();
        }
        total
    }
}

/// The flat small triangles that follow `first` in a bin (see [`next_alike`]), with their colours.
struct AlikeFlat<'g, 'c, I: Iterator> {
    rest: &'g mut std::iter::Peekable<I>,
    ctx: &'c FillContext<'c>,
    first: &'c DrawPolygon,
}

impl<'c, I: Iterator<Item = &'c DrawPolygon>> NextFlat<'c> for AlikeFlat<'_, 'c, I> {
    #[inline(always)]
    fn next_flat(&mut self) -> Option<(&'c SmallTriangle, u32)> {
        next_alike::<FLAT>(self.rest, self.ctx, self.first).map(|(q, (t, _))| (t, q.flat_rgb()))
    }
}

impl<'c, I: Iterator<Item = &'c DrawPolygon>> Fill for SmallGroup<'_, 'c, '_, '_, I> {
    fn fill<const VIS: u8, const SRC: u8>(self, paint: &Paint<'_>) -> SpanCounts {
        if SRC == FLAT {
            return self.fill_flat::<VIS>(paint);
        }
        // The frame's kind chosen once for the group, so the plain frame's loop has no shifts to look at.
        if self.ctx.tall { self.fill_runs::<VIS, SRC, true>(paint) } else { self.fill_runs::<VIS, SRC, false>(paint) }
    }
}

impl<'c, I: Iterator<Item = &'c DrawPolygon>> SmallGroup<'_, 'c, '_, '_, I> {
    /// Draws the group's triangles a run at a time, each row's samples shifted ([`ROW_SHIFTS`]) when `TALL`.
    fn fill_runs<const VIS: u8, const SRC: u8, const TALL: bool>(self, paint: &Paint<'_>) -> SpanCounts {
        let shifts = if TALL { Some(&ROW_SHIFTS) } else { None };
        let mut total = SpanCounts::default();
        let SmallGroup { first: (first, (mut tri, mut planes)), rest, ctx, band, rows } = self;
        // Set-up gave a textureless small triangle only the depth plane, which is all a flat colour reads.
        debug_assert_eq!(SRC == FLAT, first.texture().is_none());
        let mut paint = *paint;
        loop {
            let draw = |y, run: &Run| total += walk::<VIS, SRC>(run, &paint, &mut rows.row(y));
            // A flat colour needs only the depth.
            if SRC == FLAT {
                tri.for_each_run::<1>(planes, band, shifts, draw)
            } else {
                tri.for_each_run::<4>(planes, band, shifts, draw)
            }
            let Some((q, (t, p))) = next_alike::<SRC>(rest, ctx, first) else { break };
            if SRC == FLAT {
                paint = paint.with_flat(q.flat_rgb());
            }
            (tri, planes) = (t, p);
        }
        total
    }
}
