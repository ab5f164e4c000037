//! Small triangles: coverage by edge functions over the bounding box, attributes from the triangle's plane.
//!
//! A triangle a few pixels across costs the scanline walker ([`crate::render::fill::scanline`]) more in set-up than in
//! pixels: each edge is positioned with 64-bit divisions, each row samples both edges and divides for the
//! attribute steps, and each row's span goes through the span dispatch on its own. Here a triangle whose
//! bounding box is at most [`MAX_SIDE`] pixels each way, and whose shading takes a fast path, is set up once,
//! at polygon set-up: three integer edge functions and the plane of its attributes (one division for the
//! whole triangle). Each band's fill then draws its rows in one call of the pixel loop chosen for the polygon
//! ([`crate::render::fill::span_lanes::dispatch`]). A flat triangle whose box is at most
//! [`NARROW`](crate::render::core::small::NARROW) columns wide is drawn a row's four columns at a time instead
//! ([`fill_flat_narrow`](crate::render::fill::small::fill_flat_narrow), and with AVX2 `fill::small_avx2`).
//!
//! **Sub-pixel and fill rules** are the scanline walker's, decided with exact integers on the same
//! [`Fx28_4`] grid: pixel `(x, y)` is sampled at its centre `(x + 0.5, y + 0.5)`, rows whose centre lies in
//! `[top, bottom)` are covered, and within a row a centre on a left edge is in, on a right edge out. An edge
//! from an upper vertex `a` to a lower vertex `b` has the edge function
//! `F = (X - a.x)(b.y - a.y) - (b.x - a.x)(Y - a.y)` (raw units, `(X, Y)` the centre): the centre is right of
//! or on the edge when `F >= 0`. A triangle is convex, so a centre is inside when it is right of or on every
//! left edge and strictly left of every right edge; horizontal edges are decided by the row rule. This is
//! exactly the set of pixels the walker's quotient-and-remainder steps give (a test compares the two), so a
//! shared edge between a small and a large triangle has no gap and no overlap.
//!
//! Attributes come from the plane through the three vertices, `a(x, y) = a0 + dadx (x - x0) + dady (y - y0)`,
//! evaluated at each row's first covered centre from the first vertex rather than stepped from row to row,
//! so a row's values do not depend on which band draws it. They differ from the walker's only by rounding.

use crate::render::core::fixed::Fx28_4;
use crate::render::core::small::{Corner, EdgeFn, MAX_SIDE, SmallFrame, SmallTriangle, TexPlanes};
use crate::render::core::vertex::{ScreenVertex, signed_area2};
impl EdgeFn {
    /// The edge between `p` and `q` (in the triangle's order), for a triangle of winding `area` (not 0),
    /// with the function evaluated at raw centre `(cx, cy)`; a horizontal edge gives a function positive
    /// everywhere (the row rule decides those).
    #[inline(always)]
    fn new(p: &Corner, q: &Corner, area: i64, (cx, cy): (i32, i32)) -> Self {
        let (dx, dy) = (q.x.0 - p.x.0, q.y.0 - p.y.0);
        // F taken from p to q; from the upper end to the lower, as above, it is the same or its negative.
        let f = (cx - p.x.0) * dy - dx * (cy - p.y.0);
        // With y down and a positive area the polygon's forward order runs down its right side. A centre is
        // inside a left edge when F >= 0, that is F + 1 > 0, and inside a right edge when -F > 0. Either
        // way the F taken from p to q is negated exactly when the area is positive, and a right edge is one
        // going down in a positive area or up in a negative one.
        // Selects rather than branches or multiplications: which edges are left or right is random from one
        // triangle to the next (so a branch on it mispredicts often), and set-up is bound by its instruction
        // count.
        let flip = area > 0;
        let right = (dy > 0) == flip;
        let (f, dx, dy) = if flip { (-f, -dx, -dy) } else { (f, dx, dy) };
        let one = Fx28_4::ONE;
        if dy == 0 {
            return Self { at_row: 1, step_x: 0, step_y: 0 };
        }
        Self { at_row: f + 1 - i32::from(right), step_x: dy * one, step_y: -dx * one }
    }
}

/// The first column and row whose centres a triangle with corners at `(x, y)` may cover and the first
/// after them: `(col0, col1, row0, row1)`.
#[inline(always)]
fn bounds([(x0, y0), (x1, y1), (x2, y2)]: [(Fx28_4, Fx28_4); 3], reach: i32) -> (i32, i32, i32, i32) {
    let first = |a: i32| Fx28_4(a).first_centre_at_or_after();
    let (x, y) = ([x0.0, x1.0, x2.0], [y0.0, y1.0, y2.0]);
    let (min, max) = (|v: [i32; 3]| v[0].min(v[1]).min(v[2]), |v: [i32; 3]| v[0].max(v[1]).max(v[2]));
    // A sample `reach` right of a centre is inside only if that centre is within `reach` of the corners'
    // range; one more unit on the right keeps a centre exactly there (a column that may be cut by the row's
    // rule, decided by the edge functions).
    let grow = if reach > 0 { reach + 1 } else { 0 };
    (first(min(x) - grow), first(max(x) + grow), first(min(y)), first(max(y)))
}

impl SmallTriangle {
    /// Sets up triangle `v` of signed area `area` ([`signed_area2`]) for a frame `width` pixels wide; `None`
    /// when `v` is not a triangle or its bounding box is larger than [`MAX_SIDE`] (the caller uses the
    /// scanline walker then). A zero-area triangle, or one wholly left or right of the frame, is set up with
    /// no rows. Only the first `N` attributes are set up (the others are 0): a flat colour needs only the
    /// depth, and its texture planes are [`TexPlanes::NONE`].
    #[inline]
    pub(crate) fn new<const N: usize>(v: &[ScreenVertex], area: i64, frame: SmallFrame) -> Option<(Self, TexPlanes)> {
        let [p0, p1, p2] = v else { return None };
        debug_assert_eq!(area, signed_area2(v));
        let corner =
            |p: &ScreenVertex| Corner { x: p.x, y: p.y, attrs: [p.attrs[0], p.attrs[1], p.attrs[2], p.attrs[3]] };
        Self::from_corners::<N>(&[corner(p0), corner(p1), corner(p2)], area, frame)
    }

    /// Whether a triangle with corners at `(x, y)` has a bounding box this path takes in `frame` (at most
    /// [`MAX_SIDE`] pixel centres across, its columns widened by the frame's reach, and the frame's rows).
    #[inline]
    pub(crate) fn fits(xy: [(Fx28_4, Fx28_4); 3], frame: SmallFrame) -> bool {
        let (col0, col1, row0, row1) = bounds(xy, frame.reach);
        col1 - col0 <= MAX_SIDE && row1 - row0 <= frame.rows
    }

    /// [`Self::new`] from the three corners' positions and first four attributes (depth, `1/w`, `s/w`,
    /// `t/w`), for set-up that has them without building screen vertices; `area` is [`signed_area2`] of the
    /// corners.
    #[inline(always)]
    pub(crate) fn from_corners<const N: usize>(
        v: &[Corner; 3],
        area: i64,
        SmallFrame { width, reach, rows }: SmallFrame,
    ) -> Option<(Self, TexPlanes)> {
        let [p0, p1, p2] = v;
        let (col0, col1, row0, row1) = bounds([(p0.x, p0.y), (p1.x, p1.y), (p2.x, p2.y)], reach);
        if col1 - col0 > MAX_SIDE || row1 - row0 > rows {
            return None;
        }
        let (x_start, x_end) = (col0.max(0), col1.min(width));
        if area == 0 || x_start >= x_end || row0 >= row1 {
            let edges = [EdgeFn { at_row: 0, step_x: 0, step_y: 0 }; 3];
            let empty = Self { edges, x_columns: 0, rows: [row0, row0], y0: 0.0, depth: [0.0; 3] };
            return Some((empty, TexPlanes::NONE));
        }
        let centre = |i: i32| i * Fx28_4::ONE + Fx28_4::HALF;
        let origin = (centre(x_start), centre(row0));
        let edges =
            [EdgeFn::new(p0, p1, area, origin), EdgeFn::new(p1, p2, area, origin), EdgeFn::new(p2, p0, area, origin)];
        // The attributes' plane, from the vertices' exact grid positions.
        let (x0, y0) = (p0.x.to_f32(), p0.y.to_f32());
        let (e1x, e1y) = (p1.x.to_f32() - x0, p1.y.to_f32() - y0);
        let (e2x, e2y) = (p2.x.to_f32() - x0, p2.y.to_f32() - y0);
        // The area in square pixels is `area / 256`. For corners within 2^20 pixels of the origin (every
        // triangle that can draw a pixel in a frame smaller than that) it equals `e1x * e2y - e2x * e1y`
        // bit for bit, every product being a whole number of 1/256ths below 2^24; it is known sooner, and
        // beyond that range it is the exact one.
        let inv_det = 256.0 / area as f32;
        let ox = x_start as f32 + 0.5 - x0;
        let columns = (x_end - x_start) as u32;
        debug_assert!(x_start < 1 << 24 && columns <= MAX_SIDE as u32);
        let (mut a0, mut dadx, mut dady) = ([0.0f32; 4], [0.0f32; 4], [0.0f32; 4]);
        for i in 0..N.min(4) {
            let (d1, d2) = (p1.attrs[i] - p0.attrs[i], p2.attrs[i] - p0.attrs[i]);
            dadx[i] = (d1 * e2y - d2 * e1y) * inv_det;
            dady[i] = (d2 * e1x - d1 * e2x) * inv_det;
            a0[i] = p0.attrs[i] + dadx[i] * ox;
        }
        let t = Self {
            edges,
            x_columns: x_start as u32 | columns << 24,
            rows: [row0, row1],
            y0,
            depth: [a0[0], dadx[0], dady[0]],
        };
        let planes = TexPlanes {
            a0: [a0[1], a0[2], a0[3]],
            dadx: [dadx[1], dadx[2], dadx[3]],
            dady: [dady[1], dady[2], dady[3]],
        };
        Some((t, planes))
    }
}
