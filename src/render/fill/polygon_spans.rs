//! A polygon's spans in a band on a fast path: one loop chosen for the whole polygon, its short spans
//! drawn by one chunk loop across rows.
//!
//! On a course of many small polygons most spans are a few pixels long; choosing the loop for each span,
//! with the copies of the source it takes, cost more than drawing them, and so did a chunk loop a span,
//! whose exit the CPU mispredicts about once a span. So spans of one polygon in a band are sorted by length
//! as the walk emits them: spans up to [`SHORT`] pixels are collected and drawn by one chunk loop that runs
//! on from one row's last chunk to the next row's first (spans of 1-3 pixels too: there they cost no more
//! than the per-pixel loop the loop a span leaves them to, and those of 2-3 pixels less), and longer spans
//! take the chunk loop a span at once, whose set-up stays in registers. Rows are disjoint, so drawing them
//! out of order changes no pixel. A polygon partly behind the band's coarse depth skips its spans' pixels
//! in the tiles whose floors hide it ([`Behind`]): a span whole, or the chunks before and after (a short
//! span only after, as the loop across rows starts each span at its first pixel).

use super::coarse_depth::Behind;
use super::row::{BandPixels, FLAT, SpanCounts};
#[cfg(target_arch = "x86_64")]
use super::row::{LANES, OVERWRITE, RowRun, Setup, corners_in_range};
use super::scanline::{Span, fill_spans_wound};
use super::span_lanes::{Fill, Paint, span_run};
use crate::render::core::vertex::{ScreenVertex, Winding};
#[cfg(target_arch = "x86_64")]
use crate::render::simd;

/// The longest span (in pixels) drawn by the chunk loop across rows; longer ones take the loop a span
/// (routing every span across rows made the city's frames 14% slower, its set-up read from memory every
/// chunk).
#[cfg(target_arch = "x86_64")]
const SHORT: i32 = 2 * LANES as i32;

/// A polygon's spans in a band, drawn with the loop [`dispatch`](super::span_lanes::dispatch) chose for its
/// source and visibility.
pub(super) struct PolygonSpans<'v, 'r, 'b> {
    pub(super) verts: &'v [ScreenVertex],
    /// Which way its corners run, as set-up found.
    pub(super) winding: Winding,
    /// The band's rows, `band.0..band.1`.
    pub(super) band: (i32, i32),
    pub(super) width: i32,
    /// Each row's sample shifts, in a frame of four rows a pixel.
    pub(super) tall: Option<[i32; 4]>,
    pub(super) rows: &'r mut BandPixels<'b>,
    /// Where the short spans are collected (the thread's, reused polygon after polygon).
    pub(super) runs: &'r mut Vec<RowRun>,
    /// The coarse depth's floors the polygon may lie behind: its pixels in tiles that hide it are skipped.
    pub(super) behind: Option<Behind<'r>>,
}

impl Fill for PolygonSpans<'_, '_, '_> {
    fn fill<const VIS: u8, const SRC: u8>(self, paint: &Paint<'_>) -> SpanCounts {
        let PolygonSpans { verts, winding, band, width, tall, rows, runs, behind } = self;
        // The columns of a span not hidden by the floors, `None` when none is.
        let within = |span: &Span| match &behind {
            Some(b) => b.columns(span.y, (span.x0.max(0) as usize, span.x1.max(0) as usize)),
            None => Some((0, usize::MAX)),
        };
        #[cfg(not(target_arch = "x86_64"))]
        let _ = runs;
        let mut total = SpanCounts::default();
        let corners = (verts, winding);
        // One colour over everything is a plain fill a span (`span_run`); the rest sort their spans.
        #[cfg(target_arch = "x86_64")]
        if !(SRC == FLAT && VIS == OVERWRITE)
            && width >= LANES as i32
            && let Some(avx2) = simd::avx2()
        {
            let (tex, colors) = paint.parts();
            let size = tex.map_or((0.0, 0.0), |t| (t.texture.width() as f32, t.texture.height() as f32));
            // Once for the polygon, instead of two divisions a span (on courses of small polygons, most of a
            // span's set-up).
            let known = SRC != FLAT && corners_in_range(verts, size);
            runs.clear();
            walk_source::<SRC>(corners, band, width, tall, |span: &Span| {
                let Some(columns) = within(span) else { return };
                let n = span.x1 - span.x0;
                if n > SHORT {
                    total += span_run::<VIS, SRC>(span, paint, &mut rows.row(span.y), known, columns);
                    return;
                }
                // Spans from the walk lie inside the row (`x0 >= 0`), so their attributes are at `x0`; a short
                // one is cut at its end only.
                let setup = Setup::of_span(span, size);
                let (x0, x1) = (span.x0.max(0) as usize, (span.x1.max(0) as usize).min(columns.1));
                let in_range = SRC != FLAT && (known || setup.texels_in_range(x1.saturating_sub(x0 + 1)));
                runs.push(RowRun { y: span.y as usize, x0, x1, in_range, setup });
            });
            let across = super::span_avx2::rows::rows::<VIS, SRC>(avx2, runs, tex, colors, rows);
            return total + across.unpack();
        }
        walk_source::<SRC>(corners, band, width, tall, |span: &Span| {
            if let Some(columns) = within(span) {
                total += span_run::<VIS, SRC>(span, paint, &mut rows.row(span.y), false, columns);
            }
        });
        total
    }
}

/// [`walk_rows`] with the attributes source `SRC` needs: each attribute is interpolated on its own, so
/// fewer of them change none of the others' bits, and a flat colour needs only the depth.
#[inline(always)]
fn walk_source<const SRC: u8>(
    corners: (&[ScreenVertex], Winding),
    band: (i32, i32),
    width: i32,
    tall: Option<[i32; 4]>,
    draw: impl FnMut(&Span),
) {
    if SRC == FLAT {
        walk_rows::<1>(corners, band, width, tall, draw);
    } else {
        walk_rows::<4>(corners, band, width, tall, draw);
    }
}

/// A polygon's spans on rows `band`, given its corners and their winding, each row's samples shifted by
/// `tall` when given.
#[inline(always)]
pub(super) fn walk_rows<const N: usize>(
    (verts, winding): (&[ScreenVertex], Winding),
    band: (i32, i32),
    width: i32,
    tall: Option<[i32; 4]>,
    draw: impl FnMut(&Span),
) {
    fill_spans_wound::<N>(verts, winding, band, width, tall, draw);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::fixed::Fx28_4;
    use crate::render::core::mip::TexGradients;
    use crate::render::core::samples::ROW_SHIFTS;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::texture::{Filter, Sampler, Texture, Wrap};
    use crate::render::core::vertex::{ATTRS, slot};
    use crate::render::fill::coarse_depth::{TILE_COLUMNS, TILE_ROWS};
    use crate::render::fill::row::Visibility;
    use crate::render::fill::span_lanes::{Source, dispatch};
    use crate::render::fill::texel::Tex;
    use crate::render::simd::{force_portable, has_avx2};

    /// A band's buffers after drawing polygon `verts` through [`PolygonSpans`] (with AVX2, or the portable
    /// loops only), and the counts.
    fn draw(
        corners: (&[ScreenVertex], Winding),
        (source, alpha, vis): (Source<'_>, Option<(f32, f32)>, Visibility),
        start: (&[u32], &[f32], &[u64]),
        (band, width, tall): ((i32, i32), usize, Option<[i32; 4]>),
        (portable, behind): (bool, Option<Behind<'_>>),
    ) -> (Vec<u32>, Vec<u32>, Vec<u64>, SpanCounts) {
        let (mut color, mut depth, mut coverage) = (start.0.to_vec(), start.1.to_vec(), start.2.to_vec());
        let words = width.div_ceil(64);
        let mut rows = BandPixels {
            y0: band.0 as usize,
            width,
            color: &mut color,
            depth: &mut depth,
            coverage: &mut coverage,
            words,
        };
        let mut runs = Vec::new();
        let spans = PolygonSpans {
            verts: corners.0,
            winding: corners.1,
            band,
            width: width as i32,
            tall,
            rows: &mut rows,
            runs: &mut runs,
            behind,
        };
        force_portable(portable);
        let counts = dispatch(source, alpha, vis, spans);
        force_portable(false);
        (color, depth.iter().map(|d| d.to_bits()).collect(), coverage, counts)
    }

    /// A polygon of `n` (3 or 4) corners around `(cx, cy)`, about `size` pixels across: a corner in each
    /// quadrant in turn (a star-shaped outline), in either winding, with depth, `1/w`, `s/w` and `t/w`
    /// varying across it; with `hostile`, one attribute at one corner NaN, infinite or huge.
    fn random_polygon(rng: &mut Lcg, (cx, cy, size): (f32, f32, f32), n: usize, hostile: bool) -> Vec<ScreenVertex> {
        let unit = |rng: &mut Lcg| rng.next() as f32 / u32::MAX as f32;
        let quadrants = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
        let mut verts: Vec<ScreenVertex> = quadrants[..n]
            .iter()
            .map(|&(sx, sy)| {
                let (rx, ry) = (size * (0.3 + unit(rng)), size * (0.3 + unit(rng)));
                let mut attrs = [0.0; ATTRS];
                attrs[slot::DEPTH] = unit(rng);
                attrs[slot::Q] = 0.1 + unit(rng);
                attrs[slot::S] = unit(rng) * 3.0 - 1.0;
                attrs[slot::T] = unit(rng) * 3.0 - 1.0;
                let at = |v: f32| Fx28_4((v * 16.0) as i32);
                ScreenVertex { x: at(cx + sx * rx), y: at(cy + sy * ry), attrs }
            })
            .collect();
        if rng.below(2) == 0 {
            verts.reverse();
        }
        if hostile {
            let bad = [f32::NAN, f32::INFINITY, -f32::INFINITY, 3e9, -3e9][rng.below(5) as usize];
            verts[rng.below(n as u32) as usize].attrs[rng.below(4) as usize] = bad;
        }
        verts
    }

    #[test]
    fn polygons_drawn_across_rows_match_the_per_pixel_loop_bit_for_bit() {
        if !has_avx2() {
            eprintln!("no AVX2 on this CPU: only the per-pixel loop runs, nothing to compare");
            return;
        }
        let mut rng = Lcg(11);
        let unit = |rng: &mut Lcg| rng.next() as f32 / u32::MAX as f32;
        let (mut short_spans, mut cases) = (0, 0);
        for case in 0..1500 {
            let width = [8usize, 24, 64, 100][rng.below(4) as usize];
            let band = (rng.below(40) as i32, 0);
            let band = (band.0, band.0 + 1 + rng.below(32) as i32);
            let height = (band.1 - band.0) as usize;
            // A triangle or quad from 1 to about 40 pixels across, partly outside the band or the row at
            // times, with depth, `1/w`, `s/w` and `t/w` varying across it.
            let size = [2.0, 6.0, 14.0, 40.0][rng.below(4) as usize];
            let (cx, cy) = (unit(&mut rng) * width as f32, band.0 as f32 + unit(&mut rng) * height as f32);
            let n = 3 + rng.below(2) as usize;
            let verts = random_polygon(&mut rng, (cx, cy, size), n, case % 5 == 4);
            let Some(winding) = Winding::of(&verts) else { continue };
            // The rotated grid's rows, each sampled at its shift, half the time.
            let tall = (rng.below(2) == 0).then_some(ROW_SHIFTS);
            let (tw, th) = ([1u32, 4, 16, 64, 5][rng.below(5) as usize], [1u32, 8, 32, 3][rng.below(4) as usize]);
            let Ok(tex) = Texture::new(tw, th, (0..tw * th).map(|_| rng.next()).collect()) else { panic!("texture") };
            let wraps = [Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat];
            let sampler = Sampler { wrap_s: wraps[rng.below(3) as usize], wrap_t: wraps[rng.below(3) as usize] };
            let nearest = Tex::polygon(&tex, sampler, Filter::Nearest, 0.0);
            let g = TexGradients { dx: [0.01, 0.05, -0.03], dy: [0.002, 0.02, 0.04] };
            let per_pixel = Tex::per_pixel(&tex, sampler, Filter::Nearest, g);
            let filtered = Tex::polygon(&tex, sampler, Filter::Bilinear, 0.5);
            let tint = [rng.below(65537), rng.below(65537), rng.below(65537)];
            let alpha = (rng.below(2) == 0).then(|| (unit(&mut rng), unit(&mut rng) * 0.5));
            let pixels = width * height;
            let color: Vec<u32> = (0..pixels).map(|_| rng.next()).collect();
            let depth: Vec<f32> = (0..pixels).map(|_| unit(&mut rng)).collect();
            // Random words, and often whole words drawn (which the chunk loops skip at once).
            let coverage: Vec<u64> = (0..width.div_ceil(64) * height)
                .map(|_| match rng.below(3) {
                    0 => u64::MAX,
                    1 => u64::MAX << rng.below(64),
                    _ => u64::from(rng.next()) << 32 | u64::from(rng.next()),
                })
                .collect();
            let sources = [
                Source::Flat(rng.next()),
                Source::Texel(nearest),
                Source::Tinted(nearest, tint),
                Source::Tinted(per_pixel, tint),
                Source::Texel(filtered),
            ];
            fill_spans_wound::<4>(&verts, winding, band, width as i32, tall, |s| {
                short_spans += usize::from(s.x1 - s.x0 <= SHORT);
            });
            for source in sources {
                for vis in [Visibility::Overwrite, Visibility::DepthTest, Visibility::Coverage] {
                    let start = (&color[..], &depth[..], &coverage[..]);
                    let paint = (source, alpha, vis);
                    let fast = draw((&verts, winding), paint, start, (band, width, tall), (false, None));
                    let slow = draw((&verts, winding), paint, start, (band, width, tall), (true, None));
                    assert_eq!(fast, slow, "case {case}, {vis:?}, {verts:?} in rows {band:?} of {width}");
                    cases += 1;
                }
            }
        }
        assert!(short_spans > 5000 && cases > 10_000, "{short_spans} short spans, {cases} cases");
    }

    #[test]
    fn pixels_in_tiles_the_floors_hide_are_skipped_and_the_rest_drawn_as_without_them() {
        let mut rng = Lcg(29);
        let unit = |rng: &mut Lcg| rng.next() as f32 / u32::MAX as f32;
        // A band starting at no multiple of a tile's rows: its tiles count from its first row.
        let (width, band) = (100usize, (27, 59));
        let height = (band.1 - band.0) as usize;
        let Ok(tex) = Texture::new(16, 8, (0..128).map(|_| rng.next()).collect()) else { panic!("texture") };
        let nearest = Tex::polygon(&tex, Sampler::default(), Filter::Nearest, 0.0);
        let (mut skipped, mut drawn) = (0, 0);
        for case in 0..400 {
            let size = [6.0, 14.0, 40.0, 90.0][rng.below(4) as usize];
            let (cx, cy) = (unit(&mut rng) * width as f32, band.0 as f32 + unit(&mut rng) * height as f32);
            let n = 3 + rng.below(2) as usize;
            let verts = random_polygon(&mut rng, (cx, cy, size), n, false);
            let Some(winding) = Winding::of(&verts) else { continue };
            let tall = (rng.below(2) == 0).then_some(ROW_SHIFTS);
            // Floors of 4 rows of 7 tiles, some of them hiding the polygon (above its `z`), some at it.
            let z = 0.5;
            let floor: Vec<f32> = (0..28).map(|_| [0.75, z, f32::NEG_INFINITY][rng.below(3) as usize]).collect();
            let behind = Behind::of(&floor, 7, band.0, z);
            let (color, depth) =
                ((0..width * height).map(|_| rng.next()).collect::<Vec<_>>(), vec![-1.0; width * height]);
            let source = [Source::Flat(rng.next()), Source::Texel(nearest)][rng.below(2) as usize];
            let start = (&color[..], &depth[..], &[][..]);
            let paint = (source, None, Visibility::DepthTest);
            let whole = draw((&verts, winding), paint, start, (band, width, tall), (false, None));
            for portable in [false, true] {
                let cut = draw((&verts, winding), paint, start, (band, width, tall), (portable, Some(behind)));
                for i in 0..width * height {
                    let (x, y) = (i % width, i / width);
                    // Where a tile hides it, a pixel is left as it was, or (before a short span's first
                    // tile that does not) drawn as without the floors.
                    let hides = floor[y / TILE_ROWS * 7 + x / TILE_COLUMNS] > z;
                    let (was, now) = ((color[i], depth[i].to_bits()), (cut.0[i], cut.1[i]));
                    let ok = now == (whole.0[i], whole.1[i]) || hides && now == was;
                    assert!(ok, "case {case}, pixel ({x}, {y}): {now:?}, {was:?} before, {verts:?}");
                    (skipped, drawn) =
                        (skipped + usize::from(now == was && now != (whole.0[i], whole.1[i])), drawn + 1);
                }
            }
        }
        assert!(skipped > 1_000 && drawn > 10 * skipped, "{skipped} of {drawn} pixels skipped");
    }

    /// True when every span the walk gives `verts` on rows `0..rows` of a frame `width` wide passes its own
    /// range check for a texture of `size`.
    fn every_span_in_range(verts: &[ScreenVertex], (width, rows): (i32, i32), size: (f32, f32), tall: bool) -> usize {
        let Some(winding) = Winding::of(verts) else { return 0 };
        let mut spans = 0;
        fill_spans_wound::<4>(verts, winding, (0, rows), width, tall.then_some(ROW_SHIFTS), |s| {
            let setup = Setup::of_span(s, size);
            let last = (s.x1 - s.x0 - 1).max(0) as usize;
            assert!(setup.texels_in_range(last), "{s:?} of {verts:?}, texture {size:?}");
            spans += 1;
        });
        spans
    }

    #[test]
    fn a_polygon_whose_corners_are_in_range_has_every_span_in_range() {
        // The promise `corners_in_range` makes for all of a polygon's spans, held against the check a span
        // makes for itself, on polygons up to its limits: `1/w` varying eight-fold, texel coordinates at the
        // corners near `2^20`, a corner far out to the side (the clipper's guard band reaches 8,192 pixels)
        // with long edges crossing the frame, slivers, both windings and the rotated grid's shifted rows.
        let mut rng = Lcg(23);
        let unit = |rng: &mut Lcg| rng.unit();
        let (mut promised, mut refused, mut spans) = (0, 0, 0);
        let (width, rows) = (1024, 256);
        for case in 0..6_000 {
            let size = [0.5, 3.0, 20.0, 300.0][rng.below(4) as usize];
            let n = 3 + rng.below(2) as usize;
            let (cx, cy) = (unit(&mut rng) * width as f32, unit(&mut rng) * rows as f32);
            let mut verts = random_polygon(&mut rng, (cx, cy, size), n, false);
            // One corner out to the side a third of the time (within the promise's 4,096 pixels, or past it).
            if case % 3 == 0 {
                let far = &mut verts[rng.below(n as u32) as usize];
                let reach = [4000.0, 8000.0][rng.below(2) as usize];
                far.x = Fx28_4(((unit(&mut rng) * 2.0 - 1.0) * reach * 16.0) as i32);
                far.y = Fx28_4(((unit(&mut rng) * 2.0 - 1.0) * reach * 8.0) as i32);
            }
            let (tw, th) = ([1.0f32, 64.0, 4096.0][rng.below(3) as usize], [1.0f32, 256.0][rng.below(2) as usize]);
            let q_base = [1e-6f32, 0.01, 1.0, 300.0][rng.below(4) as usize];
            let spread = 1.0 + unit(&mut rng) * 15.0;
            // Now and then coordinates past `2^22` and a corner behind the eye, which a span's own check
            // refuses, so that a promise made for them would fail below.
            let reach = 1_048_576.0 * (0.5 + unit(&mut rng) * if case % 5 == 0 { 8.0 } else { 1.0 });
            let behind = if case % 7 == 0 { rng.below(n as u32) as usize } else { n };
            for (i, v) in verts.iter_mut().enumerate() {
                let q = q_base * (1.0 + unit(&mut rng) * (spread - 1.0)) * if i == behind { -0.5 } else { 1.0 };
                let (u, w) = ((unit(&mut rng) * 2.0 - 1.0) * reach / tw, (unit(&mut rng) * 2.0 - 1.0) * reach / th);
                v.attrs[slot::Q] = q;
                v.attrs[slot::S] = u * q;
                v.attrs[slot::T] = w * q;
            }
            if !corners_in_range(&verts, (tw, th)) {
                refused += 1;
                continue;
            }
            promised += 1;
            spans += every_span_in_range(&verts, (width, rows), (tw, th), case % 2 == 0);
        }
        assert!(
            promised > 1500 && refused > 1500 && spans > 50_000,
            "{promised} promised, {refused} refused, {spans} spans"
        );
        // A sliver of a triangle whose far corner is 8,184 pixels out (found in review): its float edge lands
        // 1/1024 pixel right of a sample the exact rule covers, a span 1/60 of a pixel wide extrapolates from
        // there, and with sixteen-fold `1/w` one span's texel coordinate comes to 2^24. It is refused.
        let corner = |x: i32, y: i32, q: f32, u: f32| {
            let mut attrs = [0.0; ATTRS];
            (attrs[slot::DEPTH], attrs[slot::Q], attrs[slot::S]) = (0.5, q, u * q);
            ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs }
        };
        let u = 1e6 / 256.0;
        let sliver =
            [corner(-130_951, -63_755, 1.0, u), corner(25_127, 10_027, 1.0, u), corner(16_488, 5_943, 16.0, -u)];
        assert!(!corners_in_range(&sliver, (256.0, 256.0)));
        let winding = Winding::of(&sliver).expect("a triangle");
        let mut out_of_range = 0;
        fill_spans_wound::<4>(&sliver, winding, (0, 720), 1280, None, |s| {
            let setup = Setup::of_span(s, (256.0, 256.0));
            out_of_range += usize::from(!setup.texels_in_range((s.x1 - s.x0 - 1).max(0) as usize));
        });
        assert!(out_of_range > 0, "the sliver's spans are all in range: the case no longer shows the hazard");
        // What it refuses besides: NaN, a corner at or behind the eye plane, `1/w` varying more than
        // eight-fold, and a coordinate past `2^20`.
        let c = |x: i32, q: f32, s: f32| {
            let mut attrs = [0.0; ATTRS];
            (attrs[slot::Q], attrs[slot::S]) = (q, s);
            ScreenVertex { x: Fx28_4(x), y: Fx28_4(0), attrs }
        };
        let size = (64.0, 64.0);
        assert!(corners_in_range(&[c(0, 1.0, 5.0), c(0, 0.5, 1.0)], size));
        assert!(!corners_in_range(&[c(0, 1.0, f32::NAN), c(0, 0.5, 1.0)], size));
        assert!(!corners_in_range(&[c(0, 1.0, 5.0), c(0, 0.0, 0.0)], size));
        assert!(!corners_in_range(&[c(0, 1.0, 5.0), c(0, 1.0 / 9.0, 0.0)], size));
        assert!(!corners_in_range(&[c(0, 1.0, 20_000.0), c(0, 0.5, 1.0)], size));
        assert!(!corners_in_range(&[c(4096 * 16, 1.0, 5.0), c(0, 0.5, 1.0)], size));
    }
}
