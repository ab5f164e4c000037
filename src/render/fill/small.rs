//! Small triangles' fill: each band draws the rows of a small triangle set up in advance
//! ([`SmallTriangle`], set up by `geometry::small_setup`) from its edge functions and attribute plane.
//!
//! A row's covered centres are found by the three integer edge functions a row at a time and drawn in one
//! call of the pixel loop chosen for the polygon ([`super::span_lanes::dispatch`]). A flat triangle whose box
//! is at most [`NARROW`] columns wide is drawn a row's four columns at a time instead ([`fill_flat_narrow`],
//! and with AVX2 `small_avx2`). Attributes are evaluated at each row's first covered centre from the first
//! vertex rather than stepped from row to row, so a row's values do not depend on which band draws it.

use super::row::{BandPixels, COVERAGE, DEPTH_TEST, Run};
use crate::render::core::fixed::Fx28_4;
use crate::render::core::small::{EdgeFn, NARROW, SmallTriangle, TexPlanes};

/// The first `N` columns of the box (bit `k` for column `k`) whose centres are inside all three edges on the
/// current row. Past the box the values stay in range (at most
/// [`MAX_SIDE`](crate::render::core::small::MAX_SIDE) columns are evaluated).
#[inline(always)]
fn row_mask<const N: i32>(edges: &[EdgeFn; 3]) -> u32 {
    let mut m = 0u32;
    let [mut f0, mut f1, mut f2] = [edges[0].at_row, edges[1].at_row, edges[2].at_row];
    for k in 0..N {
        m |= u32::from((f0 > 0) & (f1 > 0) & (f2 > 0)) << k;
        f0 += edges[0].step_x;
        f1 += edges[1].step_x;
        f2 += edges[2].step_x;
    }
    m
}

impl SmallTriangle {
    /// Calls `f` with each row of `band` (`band.0..band.1`) and the run of pixels the triangle covers on it,
    /// top to bottom, with the first `N` attributes (the depth, then those of the texture planes `tex`).
    /// With `shifts` (a frame of four rows a pixel), row `y` samples its pixels `shifts[y % 4]` raw units
    /// right of their centres: the edge functions move by that many units along x, exactly (a change per
    /// pixel is sixteen times a change per unit), and the run's attributes are at its first sample.
    #[inline(always)]
    pub(crate) fn for_each_run<const N: usize>(
        &self,
        tex: &TexPlanes,
        band: (i32, i32),
        shifts: Option<&[i32; 4]>,
        mut f: impl FnMut(i32, &Run),
    ) {
        let (y_start, y_end) = (self.rows[0].max(band.0), self.rows[1].min(band.1));
        if y_start >= y_end {
            return;
        }
        let mut edges = self.edges;
        // Exact integers: a band starting inside the box gets the values the rows above it would have
        // stepped to.
        for e in &mut edges {
            e.at_row += e.step_y * (y_start - self.rows[0]).max(0);
        }
        let [d0, ddx, ddy] = self.depth;
        let a_start = [d0, tex.a0[0], tex.a0[1], tex.a0[2]];
        let dadx = [ddx, tex.dadx[0], tex.dadx[1], tex.dadx[2]];
        let dady = [ddy, tex.dady[0], tex.dady[1], tex.dady[2]];
        let (columns, column_mask, x) = (self.columns(), self.column_mask(), self.x_start());
        for y in y_start..y_end {
            // A triangle is convex: the covered centres of a row are one run of the box's columns.
            // A fixed number of columns (4, 8 or 16, masked to the box) unrolls without a branch per column.
            let (row_edges, shift) = match shifts {
                Some(s) => {
                    let s = s[(y & 3) as usize];
                    let moved = edges.map(|e| EdgeFn { at_row: e.at_row + e.step_x / Fx28_4::ONE * s, ..e });
                    (moved, s as f32 / Fx28_4::ONE as f32)
                }
                None => (edges, 0.0),
            };
            let m = match columns {
                ..=4 => row_mask::<4>(&row_edges),
                5..=8 => row_mask::<8>(&row_edges),
                _ => row_mask::<16>(&row_edges),
            } & column_mask;
            if m != 0 {
                let (first, end) = (m.trailing_zeros(), u32::BITS - m.leading_zeros());
                // Evaluated from the first vertex on every row (not stepped), so any band gives the same values.
                let k = if shifts.is_some() { first as f32 + shift } else { first as f32 };
                let dy = y as f32 + 0.5 - self.y0;
                let mut a0 = a_start;
                for ((a, dx), dy_) in a0.iter_mut().zip(&dadx).zip(&dady).take(N) {
                    *a += dy_ * dy + k * dx;
                }
                f(y, &Run { x0: x + first as usize, x1: x + end as usize, a0, da: dadx });
            }
            for e in &mut edges {
                e.at_row += e.step_y;
            }
        }
    }
}

impl SmallTriangle {
    /// The triangle's rows in `band` when its box is at most [`NARROW`] columns wide, the case drawn four
    /// columns at a time ([`fill_flat_narrow`]); `None` for a wider box or no rows in the band.
    #[inline(always)]
    pub(crate) fn narrow_rows(&self, band: (i32, i32)) -> Option<NarrowRows> {
        let (y_start, y_end) = (self.rows[0].max(band.0), self.rows[1].min(band.1));
        if self.columns() > NARROW as u32 || y_start >= y_end {
            return None;
        }
        let skip = (y_start - self.rows[0]).max(0);
        let e = &self.edges;
        Some(NarrowRows {
            at_row: [
                e[0].at_row + e[0].step_y * skip,
                e[1].at_row + e[1].step_y * skip,
                e[2].at_row + e[2].step_y * skip,
            ],
            step_x: [e[0].step_x, e[1].step_x, e[2].step_x],
            step_y: [e[0].step_y, e[1].step_y, e[2].step_y],
            column_mask: self.column_mask(),
            x_start: self.x_start(),
            rows: (y_start, y_end),
            depth: [self.depth[0], self.depth[1], self.depth[2], self.y0],
        })
    }
}

/// A narrow small triangle's rows in one band: its edge functions at the box's first column on the band's
/// first row, and its depth plane.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NarrowRows {
    /// The three edge functions at the centre of pixel `(x_start, rows.0)`, and their change per column
    /// and per row.
    pub(crate) at_row: [i32; 3],
    pub(crate) step_x: [i32; 3],
    pub(crate) step_y: [i32; 3],
    /// Bits of the box's columns (at most [`NARROW`]).
    pub(crate) column_mask: u32,
    /// First column of the box.
    pub(crate) x_start: usize,
    /// The rows to draw, `rows.0..rows.1`.
    pub(crate) rows: (i32, i32),
    /// Depth at column `x_start` on the line through the first vertex, its change per column and per
    /// row, and that vertex's y.
    depth: [f32; 4],
}

impl NarrowRows {
    /// The depth at the centre of column `first` (of the box) on row `y`, exactly as
    /// [`SmallTriangle::for_each_run`] gives a run starting there.
    #[inline(always)]
    pub(crate) fn run_depth(&self, y: i32, first: u32) -> f32 {
        let [a0, dadx, dady, y0] = self.depth;
        let dy = y as f32 + 0.5 - y0;
        a0 + (dady * dy + first as f32 * dadx)
    }

    /// The depth's change per column.
    #[inline(always)]
    pub(crate) fn depth_step(&self) -> f32 {
        self.depth[1]
    }
}

/// Draws a narrow triangle's rows in colour `color` with visibility `VIS` (depth-tested: strictly nearer
/// wins; each pixel once; or overwriting, as in [`crate::render::fill::span_lanes::walk`]); returns `(written,
/// rejected)`. The AVX2 version is [`crate::render::fill::small_avx2::fill_flat_narrow`], held to this one bit for bit.
///
/// Each row is its four box columns at once: coverage, depths, the test and the writes as four-lane
/// selects, where the per-pixel loop spends more on a run of 1-3 pixels (its set-up and a call per row) than
/// on the pixels. The depth of a pixel is computed as the per-pixel loop computes it, from the row's first
/// covered pixel, so the frame is bit for bit the same.
#[inline(always)]
pub(crate) fn fill_flat_narrow<const VIS: u8>(r: &NarrowRows, color: u32, px: &mut BandPixels<'_>) -> (u64, u64) {
    let (mut written, mut rejected) = (0u64, 0u64);
    let edge = |i: usize| EdgeFn { at_row: r.at_row[i], step_x: r.step_x[i], step_y: r.step_y[i] };
    let mut edges = [edge(0), edge(1), edge(2)];
    let dd = r.depth_step();
    for y in r.rows.0..r.rows.1 {
        let m = row_mask::<{ NARROW as i32 }>(&edges) & r.column_mask;
        for e in &mut edges {
            e.at_row += e.step_y;
        }
        if m == 0 {
            continue;
        }
        let first = m.trailing_zeros();
        let d0 = r.run_depth(y, first);
        let row = y as usize - px.y0;
        let at = row * px.width + r.x_start;
        let lanes = at + NARROW <= px.color.len() && (VIS != DEPTH_TEST || at + NARROW <= px.depth.len());
        if !lanes {
            let (w, j) = fill_row_pixels::<VIS>(m, d0, dd, (row, r.x_start), color, px);
            written += w;
            rejected += j;
            continue;
        }
        let mut pass = [false; NARROW];
        match VIS {
            DEPTH_TEST => {
                if let Some(d) = px.depth.get_mut(at..at + NARROW) {
                    for (k, (old, ok)) in d.iter_mut().zip(&mut pass).enumerate() {
                        // Lanes left of the run get a negative offset; they are not covered.
                        let z = d0 + (k as f32 - first as f32) * dd;
                        *ok = (m >> k) & 1 != 0 && z > *old;
                        *old = if *ok { z } else { *old };
                    }
                }
            }
            _ => {
                let bits = if VIS == COVERAGE { px.claim(row, r.x_start, m) } else { m };
                for (k, ok) in pass.iter_mut().enumerate() {
                    *ok = (bits >> k) & 1 != 0;
                }
            }
        }
        let mut n = 0;
        for (p, &ok) in px.color.get_mut(at..at + NARROW).unwrap_or(&mut []).iter_mut().zip(&pass) {
            *p = if ok { color } else { *p };
            n += u64::from(ok);
        }
        written += n;
        rejected += u64::from(m.count_ones()) - n;
    }
    (written, rejected)
}

/// Draws flat small triangles in turn, `first` and then those `next` gives, each with its colour, while
/// they are narrow, each with `draw` ([`fill_flat_narrow`] or its AVX2 version); returns `(written,
/// rejected)` and the first triangle that is not narrow, which the caller draws a run at a time.
///
/// One loop for the run of triangles (rather than a call per triangle) lets the AVX2 version keep its
/// constants in registers across triangles.
#[inline(always)]
pub(crate) fn fill_flat_run<'t>(
    first: (&'t SmallTriangle, u32),
    next: &mut impl NextFlat<'t>,
    band: (i32, i32),
    px: &mut BandPixels<'_>,
    mut draw: impl FnMut(&NarrowRows, u32, &mut BandPixels<'_>) -> (u64, u64),
) -> ((u64, u64), Option<(&'t SmallTriangle, u32)>) {
    let (mut written, mut rejected) = (0, 0);
    let mut current = Some(first);
    while let Some((t, color)) = current {
        if t.columns() > NARROW as u32 {
            return ((written, rejected), current);
        }
        if let Some(r) = t.narrow_rows(band) {
            let (w, j) = draw(&r, color, px);
            written += w;
            rejected += j;
        }
        current = next.next_flat();
    }
    ((written, rejected), None)
}

/// Where [`fill_flat_run`] takes its triangles from: the next flat small triangle of the group and its
/// colour, `None` at the group's end.
///
/// A trait rather than a closure so that its method can be marked `inline(always)`: a closure is not
/// inlined into the AVX2 function, which is large, so the group's iteration would be a call per triangle.
pub(crate) trait NextFlat<'t> {
    /// The next triangle and its colour.
    fn next_flat(&mut self) -> Option<(&'t SmallTriangle, u32)>;
}

/// One row of a narrow triangle a pixel at a time (the columns `m` covers on band row `row` from column
/// `x_start`, depth `d0` at the first), with visibility `VIS`: for a row whose four columns would run past
/// the end of the buffers (on a band's last row, near the right edge of the frame); returns `(written,
/// rejected)`.
#[inline(always)]
pub(crate) fn fill_row_pixels<const VIS: u8>(
    m: u32,
    d0: f32,
    dd: f32,
    (row, x_start): (usize, usize),
    color: u32,
    px: &mut BandPixels<'_>,
) -> (u64, u64) {
    let (mut written, mut rejected) = (0u64, 0u64);
    let first = m.trailing_zeros();
    let at = row * px.width + x_start;
    for k in first..u32::BITS - m.leading_zeros() {
        let z = d0 + (k - first) as f32 * dd;
        let i = at + k as usize;
        let pass = match VIS {
            DEPTH_TEST => px.depth.get(i).is_some_and(|&old| z > old),
            COVERAGE => px.claim(row, x_start + k as usize, 1) != 0,
            _ => true,
        };
        if !pass {
            rejected += 1;
            continue;
        }
        if let Some(p) = px.color.get_mut(i) {
            *p = color;
        }
        if let Some(p) = px.depth.get_mut(i).filter(|_| VIS == DEPTH_TEST) {
            *p = z;
        }
        written += 1;
    }
    (written, rejected)
}

#[cfg(test)]
mod tests {
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
                let mut px = BandPixels {
                    y0: band.0 as usize,
                    width,
                    color: &mut c2,
                    depth: &mut d2,
                    coverage: &mut w2,
                    words: 1,
                };
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
}
