//! Tests of the small-triangle fill: coverage and attributes against the scanline walker (centres and
//! shifted rows), and the narrow fill against the pixel loop.

use super::*;
use crate::render::core::fixed::Fx28_4;
use crate::render::core::samples::ROW_SHIFTS;
use crate::render::core::small::SmallFrame;
use crate::render::core::test_rng::Lcg;
use crate::render::core::vertex::ATTRS;
use crate::render::core::vertex::{ScreenVertex, signed_area2};
use crate::render::fill::row::OVERWRITE;
use crate::render::fill::scanline::{Span, fill_spans, fill_spans_shifted};

fn sv(x: i32, y: i32, a: f32) -> ScreenVertex {
    ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs: [a, 1.0, a * 2.0, -a, 0.5, 0.5, 0.5, 1.0] }
}

/// A run as `(y, x0, x1)` and the first four attributes at its first pixel.
type Runs = Vec<((i32, usize, usize), [f32; 4])>;

/// The runs the small path gives, `None` if it declines.
fn small_runs(v: &[ScreenVertex], rows: (i32, i32), width: i32) -> Option<Runs> {
    small_runs_shifted(v, rows, width, None)
}

/// [`small_runs`] in a frame whose rows sample shifted columns, when `shifts` is given.
fn small_runs_shifted(v: &[ScreenVertex], rows: (i32, i32), width: i32, shifts: Option<&[i32; 4]>) -> Option<Runs> {
    let frame = if shifts.is_some() { SmallFrame::tall(width) } else { SmallFrame::plain(width) };
    let (t, planes) = SmallTriangle::new::<4>(v, signed_area2(v), frame)?;
    let mut out = vec![];
    t.for_each_run::<4>(&planes, rows, shifts, |y, r| out.push(((y, r.x0, r.x1), r.a0)));
    Some(out)
}

fn walker_runs(v: &[ScreenVertex], rows: (i32, i32), width: i32) -> Runs {
    walker_runs_shifted(v, rows, width, None)
}

fn walker_runs_shifted(v: &[ScreenVertex], rows: (i32, i32), width: i32, shifts: Option<&[i32; 4]>) -> Runs {
    let mut out = vec![];
    let push = |s: &Span| out.push(((s.y, s.x0 as usize, s.x1 as usize), [s.a0[0], s.a0[1], s.a0[2], s.a0[3]]));
    match shifts {
        Some(&s) => fill_spans_shifted::<ATTRS>(v, rows, width, s, push),
        None => fill_spans(v, rows, width, push),
    }
    out
}

/// The plane `a = c0 x + c1 y + c2` (pixels) through corners `t` (raw units) carrying 0, 1 and 2.
fn exact_plane(t: &[(i32, i32); 3]) -> [f64; 3] {
    let p = t.map(|(x, y)| (f64::from(x) / 16.0, f64::from(y) / 16.0));
    let (e1, e2) = ((p[1].0 - p[0].0, p[1].1 - p[0].1), (p[2].0 - p[0].0, p[2].1 - p[0].1));
    let det = e1.0 * e2.1 - e2.0 * e1.1;
    let (c0, c1) = ((1.0 * e2.1 - 2.0 * e1.1) / det, (2.0 * e1.0 - 1.0 * e2.0) / det);
    [c0, c1, -(c0 * p[0].0 + c1 * p[0].1)]
}

#[test]
fn shifted_rows_cover_what_the_walker_covers_with_the_same_shifts() {
    let mut rng = Lcg(9);
    let (mut drawn, mut edge_columns, mut tall) = (0, 0, 0);
    for case in 0..20_000 {
        let step = [16, 8, 4, 1][case % 4];
        // Up to 42 rows tall: a frame of four rows a pixel takes boxes of up to 64 rows.
        let mut p = || (rng.range(-8, 40) * step / 4 + 100, rng.range(-8, 160) * step / 4 + 60);
        let t = [p(), p(), p()];
        let v: Vec<_> = t.iter().enumerate().map(|(i, &(x, y))| sv(x, y, i as f32)).collect();
        let (width, rows) = (14, (4, 50));
        let Some(small) = small_runs_shifted(&v, rows, width, Some(&ROW_SHIFTS)) else { continue };
        let (top, bottom) = (t.iter().map(|p| p.1).min().unwrap(), t.iter().map(|p| p.1).max().unwrap());
        tall += usize::from(bottom - top > 16 * 16);
        let walker = walker_runs_shifted(&v, rows, width, Some(&ROW_SHIFTS));
        let pixels = |r: &Runs| r.iter().map(|r| r.0).collect::<Vec<_>>();
        assert_eq!(pixels(&small), pixels(&walker), "triangle {t:?}");
        drawn += small.len();
        // Runs reaching a column whose centre is outside the corners' range: the widened box at work.
        let (lo, hi) = (t.iter().map(|p| p.0).min().unwrap(), t.iter().map(|p| p.0).max().unwrap());
        edge_columns +=
            small.iter().filter(|r| (r.0.1 as i32) * 16 + 8 < lo || (r.0.2 as i32 - 1) * 16 + 8 >= hi).count();
        // The attributes are the plane's at the run's first shifted sample (the walker's own, on a
        // span thinner than 1/64 of a pixel, are its left edge's, so the plane is the yardstick here).
        let plane = exact_plane(&t);
        for ((y, x0, _), a) in &small {
            let x = *x0 as f64 + 0.5 + f64::from(ROW_SHIFTS[(*y & 3) as usize]) / 16.0;
            let want = plane[0] * x + plane[1] * (f64::from(*y) + 0.5) + plane[2];
            assert!((f64::from(a[0]) - want).abs() < 1e-3, "{t:?} row {y}: {} vs {want}", a[0]);
        }
    }
    assert!(drawn > 10_000 && edge_columns > 100, "{drawn} runs compared, {edge_columns} past the centres");
    assert!(tall > 1_000, "only {tall} triangles taller than 16 rows");
}

#[test]
fn coverage_equals_the_scanline_walker_on_random_and_edge_aligned_triangles() {
    let mut rng = Lcg(7);
    let mut drawn = 0;
    for case in 0..20_000 {
        // Vertices on a coarse grid (whole, half and quarter pixels) make centres land on edges often.
        let step = [16, 8, 4, 1][case % 4];
        let mut p = || (rng.range(-8, 40) * step / 4 + 100, rng.range(-8, 40) * step / 4 + 60);
        let t = [p(), p(), p()];
        let v: Vec<_> = t.iter().enumerate().map(|(i, &(x, y))| sv(x, y, i as f32)).collect();
        let (width, rows) = (14, (4, 11));
        let Some(small) = small_runs(&v, rows, width) else { continue };
        let walker = walker_runs(&v, rows, width);
        let pixels = |r: &Runs| r.iter().map(|r| r.0).collect::<Vec<_>>();
        assert_eq!(pixels(&small), pixels(&walker), "triangle {t:?}");
        drawn += small.len();
        // The attributes agree with the walker's to rounding.
        for (a, b) in small.iter().zip(&walker) {
            for i in 0..4 {
                assert!((a.1[i] - b.1[i]).abs() < 1e-3, "{t:?} {:?} attr {i}: {} vs {}", a.0, a.1[i], b.1[i]);
            }
        }
    }
    assert!(drawn > 10_000, "only {drawn} runs compared");
}

#[test]
fn large_or_non_triangular_polygons_are_left_to_the_walker() {
    let big = [sv(0, 0, 0.0), sv(16 * 17, 0, 0.0), sv(0, 16 * 3, 0.0)];
    assert!(SmallTriangle::new::<4>(&big, signed_area2(&big), SmallFrame::plain(400)).is_none());
    let quad = [sv(0, 0, 0.0), sv(32, 0, 0.0), sv(32, 32, 0.0), sv(0, 32, 0.0)];
    assert!(SmallTriangle::new::<4>(&quad, signed_area2(&quad), SmallFrame::plain(400)).is_none());
    let flat = [sv(0, 0, 0.0), sv(32, 0, 0.0), sv(64, 0, 0.0)];
    assert_eq!(small_runs(&flat, (0, 100), 400), Some(vec![]));
}

#[test]
fn the_narrow_fill_draws_the_runs_as_the_pixel_loop_does_bit_for_bit() {
    let mut rng = Lcg(5);
    let (width, band) = (13usize, (2, 9));
    let n = (band.1 - band.0) as usize * width;
    let (mut narrow, mut pixels, mut past_end) = (0, 0, 0);
    for case in 0..5_000 {
        let (x, y) = (rng.range(-20, 13 * 16 + 20), rng.range(0, 11 * 16));
        let mut corner = || {
            let mut v = sv(x + rng.range(-70, 70), y + rng.range(-70, 70), 0.0);
            v.attrs[0] = if case % 4 == 0 { 0.5 } else { rng.unit() };
            v
        };
        let v = [corner(), corner(), corner()];
        let frame = SmallFrame::plain(width as i32);
        let Some((t, _)) = SmallTriangle::new::<1>(&v, signed_area2(&v), frame) else { continue };
        let Some(r) = t.narrow_rows(band) else { continue };
        let old: Vec<f32> = (0..n).map(|i| if i % 3 == 0 { 0.5 } else { rng.unit() }).collect();
        // 'Already drawn' bits, one word a row (13 pixels).
        let drawn: Vec<u64> = (0..n / width).map(|_| u64::from(rng.next() & 0x1fff)).collect();
        for vis in [DEPTH_TEST, OVERWRITE, COVERAGE] {
            // The reference: each run a pixel at a time, depth `a0 + k * da` (as `span_lanes::walk`).
            let (mut color, mut depth, mut cover) = (vec![0u32; n], old.clone(), drawn.clone());
            let mut counts = (0, 0);
            t.for_each_run::<1>(&TexPlanes::NONE, band, None, |y, run| {
                for x in run.x0..run.x1 {
                    let (row, bit) = ((y - band.0) as usize, 1u64 << x);
                    let i = row * width + x;
                    let z = run.a0[0] + (x - run.x0) as f32 * run.da[0];
                    let pass = match vis {
                        DEPTH_TEST => z.partial_cmp(&depth[i]) == Some(std::cmp::Ordering::Greater),
                        COVERAGE => cover[row] & bit == 0,
                        _ => true,
                    };
                    if !pass {
                        counts.1 += 1;
                        continue;
                    }
                    color[i] = 7;
                    if vis == DEPTH_TEST {
                        depth[i] = z;
                    }
                    cover[row] |= if vis == COVERAGE { bit } else { 0 };
                    counts.0 += 1;
                    // Drawn by the one-pixel fallback: four columns from the box's first would pass
                    // the end of the buffers.
                    past_end += usize::from(y == band.1 - 1 && r.x_start + NARROW > width);
                }
            });
            let (mut c2, mut d2, mut w2) = (vec![0u32; n], old.clone(), drawn.clone());
            let mut px =
                BandPixels { y0: band.0 as usize, width, color: &mut c2, depth: &mut d2, coverage: &mut w2, words: 1 };
            let got = match vis {
                DEPTH_TEST => fill_flat_narrow::<DEPTH_TEST>(&r, 7, &mut px),
                COVERAGE => fill_flat_narrow::<COVERAGE>(&r, 7, &mut px),
                _ => fill_flat_narrow::<OVERWRITE>(&r, 7, &mut px),
            };
            let bits = |d: &[f32]| d.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            let (mine, reference) = ((c2, bits(&d2), w2, got), (color, bits(&depth), cover, counts));
            assert_eq!(mine, reference, "case {case}, visibility {vis}: {v:?}");
            narrow += 1;
            pixels += counts.0;
        }
    }
    assert!(narrow > 2_000 && pixels > 5_000, "{narrow} triangles, {pixels} pixels");
    assert!(past_end > 100, "only {past_end} pixels drawn by the fallback");
}

#[test]
fn a_band_draws_the_same_rows_as_the_whole_frame() {
    let t = [sv(20, 20, 0.0), sv(200, 60, 1.0), sv(90, 230, 2.0)];
    let whole = small_runs(&t, (0, 100), 100);
    let mut banded = small_runs(&t, (0, 7), 100).unwrap_or_default();
    banded.extend(small_runs(&t, (7, 100), 100).unwrap_or_default());
    assert_eq!(whole.as_deref(), Some(&banded[..]));
    assert!(banded.len() >= 10);
}
