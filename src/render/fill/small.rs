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
                let x0 = x + first as usize;
                f(y, &Run { x0, from: x0, x1: x + end as usize, a0, da: dadx, in_range: false });
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
#[path = "small_tests.rs"]
mod tests;
