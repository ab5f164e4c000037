//! Scanline fill (seeds 001 and 002): walk a polygon's left and right edge chains at once and emit spans.
//!
//! The polygon must be y-monotone (every scan line cuts it in at most one span); the pipeline splits others
//! before they get here. No edge table and no sorting: the top vertex is found while reading the vertex list,
//! and the two chains are followed downwards from it, one edge at a time.
//!
//! **Sub-pixel and fill rules.** Vertices are in [`Fx28_4`] (1/16 pixel). Pixel `(x, y)` has its centre at
//! `(x + 0.5, y + 0.5)`. A row `y` is covered when `top <= y + 0.5 < bottom`, and within it a pixel `x` is
//! covered when `left <= x + 0.5 < right`: left and top edges are inclusive, right and bottom edges exclusive
//! (the top-left rule of OpenGL and Direct3D). Edge positions at row centres are computed exactly with a
//! quotient-and-remainder DDA on the fixed-point grid, starting from the exact intersection of the edge with
//! the first row centre (the prestep), so a centre on an edge shared by two polygons belongs to exactly one.
//! Attributes are evaluated at the exact sub-pixel row centre along each edge and then at each pixel centre
//! across the span, directly from the start values rather than by accumulated stepping, so a row comes out
//! bit-identical whichever band (thread) draws it.
//!
//! **Shifted rows** ([`fill_spans_shifted`]): in a frame drawn four rows a pixel for the rotated grid, row
//! `y` samples each pixel at `(x + 0.5 + shifts[y % 4] / 16, y + 0.5)` instead of its centre (each shift a
//! whole number of sixteenths below one pixel, so still on the vertices' grid), by the same rules: the
//! first covered pixel of an edge is the ceiling of `(x_edge - 0.5 - shift) / 1`, found from the DDA's
//! quotient and remainder exactly, and the span's attributes are at its first pixel's shifted sample.

use crate::render::core::fixed::Fx28_4;
use crate::render::core::vertex::{ATTRS, ScreenVertex, Winding};

/// A horizontal run of covered pixels `x0..x1` on row `y`, with attributes at the centre of `x0` and their
/// change per pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Row.
    pub y: i32,
    /// First pixel (inclusive, already clipped to the frame).
    pub x0: i32,
    /// End pixel (exclusive, already clipped to the frame).
    pub x1: i32,
    /// Attributes at the centre of pixel `x0`.
    pub a0: [f32; ATTRS],
    /// Change of the attributes per pixel.
    pub da: [f32; ATTRS],
}

/// One edge of a chain, from an upper vertex to a lower one, positioned at a row.
struct Edge {
    /// Raw y of the lower vertex: the edge covers row centres strictly above it.
    bottom: i32,
    /// Index of the lower vertex, where the chain continues.
    end: usize,
    // Exact position: first covered pixel = q + (r != 0), the ceiling of (x_at_centre - 0.5).
    q: i64,
    r: i64,
    sq: i64,
    sr: i64,
    d: i64,
    // Float values for attributes.
    x0: f32,
    y0: f32,
    dxdy: f32,
    a0: [f32; ATTRS],
    dady: [f32; ATTRS],
}

impl Edge {
    /// The edge from `a` down to `b`, positioned at `row`, with the first `N` attributes set up.
    #[inline]
    fn new<const N: usize>(a: &ScreenVertex, b: &ScreenVertex, end: usize, row: i32) -> Self {
        let (x0, y0) = (i64::from(a.x.0), i64::from(a.y.0));
        let (x1, y1) = (i64::from(b.x.0), i64::from(b.y.0));
        let dy = y1 - y0;
        debug_assert!(dy > 0);
        let dx = x1 - x0;
        let one = i64::from(Fx28_4::ONE);
        let half = i64::from(Fx28_4::HALF);
        let d = one * dy;
        let yc = i64::from(row) * one + half;
        // (x(yc) - half) / one with x(yc) = x0 + dx * (yc - y0) / dy, over the common denominator one * dy.
        let n = (x0 - half) * dy + dx * (yc - y0);
        let s = one * dx;
        let fy = dy as f32 / one as f32;
        let mut dady = [0.0; ATTRS];
        for (d, (bv, av)) in dady.iter_mut().zip(b.attrs.iter().zip(&a.attrs)).take(N) {
            *d = (bv - av) / fy;
        }
        Self {
            bottom: b.y.0,
            end,
            q: n.div_euclid(d),
            r: n.rem_euclid(d),
            sq: s.div_euclid(d),
            sr: s.rem_euclid(d),
            d,
            x0: a.x.to_f32(),
            y0: a.y.to_f32(),
            dxdy: (dx as f32) / (dy as f32),
            a0: a.attrs,
            dady,
        }
    }

    #[inline]
    fn pixel(&self) -> i64 {
        self.q + i64::from(self.r != 0)
    }

    /// The first pixel whose sample, `shift` raw units right of its centre (`|shift| < 16`), is at or
    /// right of the edge: `ceil((x - 1/2 - shift) / 1)` on the same exact grid as [`Self::pixel`].
    #[inline]
    fn pixel_shifted(&self, shift: i64) -> i64 {
        debug_assert!(shift.abs() < i64::from(Fx28_4::ONE));
        // `shift * dy` in the denominator's units (`d = 16 dy`), so `t` lies in `(-d, 2d)`.
        let t = self.r - shift * self.d / i64::from(Fx28_4::ONE);
        self.q + i64::from(t > 0) + i64::from(t > self.d)
    }

    #[inline]
    fn step(&mut self) {
        self.q += self.sq;
        self.r += self.sr;
        if self.r >= self.d {
            self.r -= self.d;
            self.q += 1;
        }
    }

    #[inline]
    fn sample<const N: usize>(&self, row: i32) -> (f32, [f32; ATTRS]) {
        let t = row as f32 + 0.5 - self.y0;
        let mut a = [0.0; ATTRS];
        for (v, (a0, d)) in a.iter_mut().zip(self.a0.iter().zip(&self.dady)).take(N) {
            *v = a0 + t * d;
        }
        (self.x0 + t * self.dxdy, a)
    }
}

/// Finds the edge of a chain (walking from vertex `from` in steps of `dir`) that covers `row`.
fn edge_for_row<const N: usize>(v: &[ScreenVertex], from: usize, dir: usize, row: i32) -> Option<Edge> {
    let n = v.len();
    let yc = row * Fx28_4::ONE + Fx28_4::HALF;
    let mut i = from;
    for _ in 0..n {
        let j = if i + dir >= n { i + dir - n } else { i + dir };
        if v[j].y.0 < v[i].y.0 {
            return None; // the chain turned upwards: not y-monotone
        }
        if v[j].y.0 > yc {
            return Some(Edge::new::<N>(&v[i], &v[j], j, row));
        }
        i = j;
    }
    None
}

/// Emits the spans of a y-monotone polygon on rows `rows.0..rows.1`, clipped to `0..width`.
///
/// Zero-area polygons emit nothing. The vertex order may be either winding.
pub fn fill_spans(v: &[ScreenVertex], rows: (i32, i32), width: i32, emit: impl FnMut(&Span)) {
    fill_spans_first::<ATTRS>(v, rows, width, emit);
}

/// [`fill_spans`] interpolating only the first `N` attributes (the others are 0 in the spans): a polygon of
/// one colour needs only depth and texture coordinates, half the work per row for small polygons.
pub fn fill_spans_first<const N: usize>(v: &[ScreenVertex], rows: (i32, i32), width: i32, emit: impl FnMut(&Span)) {
    if let Some(winding) = Winding::of(v) {
        walk::<N, false>(v, winding, rows, width, [0; 4], emit);
    }
}

/// [`fill_spans_first`] with each row's samples moved right by `shifts[row % 4]` raw units (each below a
/// pixel): the rows of a frame drawn four rows a pixel, whose samples then lie on a rotated grid
/// ([`ROW_SHIFTS`](crate::render::core::samples::ROW_SHIFTS)). A pixel is covered when its shifted sample
/// is, by the rules above, and the span's attributes are at the shifted sample of its first pixel.
pub fn fill_spans_shifted<const N: usize>(
    v: &[ScreenVertex],
    rows: (i32, i32),
    width: i32,
    shifts: [i32; 4],
    emit: impl FnMut(&Span),
) {
    if let Some(winding) = Winding::of(v) {
        walk::<N, true>(v, winding, rows, width, shifts, emit);
    }
}

/// [`fill_spans_first`], or [`fill_spans_shifted`] by `shifts` when given, of a polygon whose corners run
/// `winding` ([`Winding::of`] them, which set-up stores with each polygon): the fill draws a polygon in
/// every band it crosses, and would otherwise sum its area in each.
#[inline(always)]
pub(crate) fn fill_spans_wound<const N: usize>(
    v: &[ScreenVertex],
    winding: Winding,
    rows: (i32, i32),
    width: i32,
    shifts: Option<[i32; 4]>,
    emit: impl FnMut(&Span),
) {
    debug_assert_eq!(Winding::of(v), Some(winding), "a polygon's stored winding is not its corners'");
    match shifts {
        Some(shifts) => walk::<N, true>(v, winding, rows, width, shifts, emit),
        None => walk::<N, false>(v, winding, rows, width, [0; 4], emit),
    }
}

/// The walk of [`fill_spans_first`] over a polygon wound `winding` (of non-zero area), with each row's
/// samples shifted by `shifts[row % 4]` when `SHIFTED`.
#[inline(always)]
fn walk<const N: usize, const SHIFTED: bool>(
    v: &[ScreenVertex],
    winding: Winding,
    rows: (i32, i32),
    width: i32,
    shifts: [i32; 4],
    mut emit: impl FnMut(&Span),
) {
    let n = v.len();
    if n < 3 {
        return;
    }
    let mut top = 0;
    let (mut ymin, mut ymax) = (v[0].y, v[0].y);
    for (i, p) in v.iter().enumerate().skip(1) {
        if p.y < ymin {
            ymin = p.y;
            top = i;
        }
        ymax = ymax.max(p.y);
    }
    let row_start = ymin.first_centre_at_or_after().max(rows.0);
    let row_end = ymax.first_centre_at_or_after().min(rows.1);
    if row_start >= row_end {
        return;
    }
    // With y down, a clockwise polygon's forward chain from the top runs down the right side.
    let (ldir, rdir) = match winding {
        Winding::Clockwise => (n - 1, 1),
        Winding::CounterClockwise => (1, n - 1),
    };
    let (Some(mut left), Some(mut right)) =
        (edge_for_row::<N>(v, top, ldir, row_start), edge_for_row::<N>(v, top, rdir, row_start))
    else {
        return;
    };
    for row in row_start..row_end {
        let yc = row * Fx28_4::ONE + Fx28_4::HALF;
        if yc >= left.bottom {
            match edge_for_row::<N>(v, left.end, ldir, row) {
                Some(e) => left = e,
                None => return,
            }
        }
        if yc >= right.bottom {
            match edge_for_row::<N>(v, right.end, rdir, row) {
                Some(e) => right = e,
                None => return,
            }
        }
        let shift = if SHIFTED { shifts[(row & 3) as usize] } else { 0 };
        let (xs, xe) = if SHIFTED {
            (left.pixel_shifted(i64::from(shift)), right.pixel_shifted(i64::from(shift)))
        } else {
            (left.pixel(), right.pixel())
        };
        let (xs, xe) = (xs.max(0), xe.min(i64::from(width)));
        if xs < xe {
            let (xl, al) = left.sample::<N>(row);
            let (xr, ar) = right.sample::<N>(row);
            let dx = xr - xl;
            let inv = if dx > 1.0 / 64.0 { 1.0 / dx } else { 0.0 };
            let at = if SHIFTED { 0.5 + shift as f32 / Fx28_4::ONE as f32 } else { 0.5 };
            let off = xs as f32 + at - xl;
            let mut a0 = [0.0; ATTRS];
            let mut da = [0.0; ATTRS];
            for i in 0..N.min(ATTRS) {
                da[i] = (ar[i] - al[i]) * inv;
                a0[i] = al[i] + off * da[i];
            }
            emit(&Span { y: row, x0: xs as i32, x1: xe as i32, a0, da });
        }
        left.step();
        right.step();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sv(x: i32, y: i32) -> ScreenVertex {
        ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs: [0.0; ATTRS] }
    }

    fn covered(v: &[ScreenVertex], w: i32, h: i32) -> Vec<(i32, i32)> {
        let mut out = vec![];
        fill_spans(v, (0, h), w, |s| out.extend((s.x0..s.x1).map(|x| (x, s.y))));
        out
    }

    #[test]
    fn pixel_centres_on_edges_follow_top_left_rule() {
        // A square from (1,1) to (3,3) with corners exactly on pixel corners: covers 2x2 pixels.
        let sq = [sv(16, 16), sv(48, 16), sv(48, 48), sv(16, 48)];
        assert_eq!(covered(&sq, 8, 8), [(1, 1), (2, 1), (1, 2), (2, 2)]);
        // The same square shifted by half a pixel: its left/top edges pass through centres (included),
        // its right/bottom edges through centres too (excluded).
        let sq: Vec<_> = sq.iter().map(|p| sv(p.x.0 + 8, p.y.0 + 8)).collect();
        assert_eq!(covered(&sq, 8, 8), [(1, 1), (2, 1), (1, 2), (2, 2)]);
        // Reversed winding covers the same pixels.
        let rev: Vec<_> = sq.iter().rev().copied().collect();
        assert_eq!(covered(&rev, 8, 8), [(1, 1), (2, 1), (1, 2), (2, 2)]);
    }

    #[test]
    fn a_shifted_row_covers_what_the_polygon_moved_the_other_way_covers_at_centres() {
        use crate::render::core::samples::ROW_SHIFTS;
        use crate::render::core::test_rng::Lcg;
        let mut rng = Lcg(3);
        let (w, h) = (40, 40);
        let mut compared = 0;
        for _ in 0..2000 {
            // A triangle with corners anywhere on the grid, partly outside the frame.
            let mut coord = || (rng.next() % (16 * 48)) as i32 - 64;
            let tri = [sv(coord(), coord()), sv(coord(), coord()), sv(coord(), coord())];
            let mut shifted = vec![];
            fill_spans_shifted::<ATTRS>(&tri, (0, h), w, ROW_SHIFTS, |s| {
                shifted.extend((s.x0..s.x1).map(|x| (x, s.y)));
            });
            for (k, &shift) in ROW_SHIFTS.iter().enumerate() {
                // Sampling `shift` right of the centres is sampling the centres of the polygon moved left.
                let moved: Vec<_> = tri.iter().map(|p| sv(p.x.0 - shift, p.y.0)).collect();
                let want: Vec<_> = covered(&moved, w, h).into_iter().filter(|&(_, y)| y % 4 == k as i32).collect();
                let got: Vec<_> = shifted.iter().copied().filter(|&(_, y)| y % 4 == k as i32).collect();
                assert_eq!(got, want, "{tri:?} rows {k} mod 4");
                compared += got.len();
            }
        }
        assert!(compared > 100_000, "{compared} pixels compared");
        // A span's attributes are at its first pixel's shifted sample: x itself, as an attribute, says where.
        let ramp = |x: i32, y: i32| ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs: [x as f32 / 16.0; ATTRS] };
        let quad = [ramp(0, 0), ramp(320, 0), ramp(320, 64), ramp(0, 64)];
        fill_spans_shifted::<1>(&quad, (0, 4), 20, ROW_SHIFTS, |s| {
            let want = s.x0 as f32 + 0.5 + ROW_SHIFTS[s.y as usize] as f32 / 16.0;
            assert!((s.a0[0] - want).abs() < 1e-5 && (s.da[0] - 1.0).abs() < 1e-5, "{s:?}");
        });
    }

    #[test]
    fn sliver_thinner_than_a_pixel_covers_only_centres_inside() {
        // A triangle 0.25 px wide around x = 2.5: its centres at x = 2.5 are inside for rows it spans.
        let t = [sv(36, 0), sv(44, 0), sv(40, 160)];
        let c = covered(&t, 8, 12);
        assert!(c.iter().all(|&(x, _)| x == 2));
        // Between x = 2.52 and 2.9 nothing is covered.
        let t = [sv(41, 0), sv(46, 0), sv(44, 160)];
        assert!(covered(&t, 8, 12).is_empty());
    }
}
