//! Coverage samples of a polygon, a pixel row at a time: for each sample of the pattern, the run of pixels
//! whose sample it covers, decided exactly.
//!
//! **Sub-pixel and fill rules.** Sample `j` of pixel `(x, y)` sits at `(16x + X[j], 16y + Y[j])` in
//! [`Fx28_4`] units ([`SamplePattern`]), on the vertices' own grid. It is covered when
//! `top <= 16y + Y[j] < bottom` and `left <= 16x + X[j] < right` at that height: left and top edges
//! inclusive, right and bottom exclusive, the top-left rule the pixel centres follow in `scanline`. Each
//! sample row is walked like a scan line of its own, its edge crossings stepped by an exact
//! quotient-and-remainder DDA from the exact crossing at the first row, so a sample on an edge shared by
//! two polygons of one surface belongs to exactly one of them: shared edges stay watertight for every
//! pattern, and a row's coverage does not depend on which band draws it.

use crate::render::core::fixed::Fx28_4;
use crate::render::core::samples::{MAX_SAMPLES, SamplePattern};
use crate::render::core::vertex::{ScreenVertex, signed_area2};

/// The samples of one pixel row a polygon covers: for sample `j` of `N`, pixels `l[j]..r[j]` (empty when
/// equal).
///
/// The count is a constant so that a pixel's mask is one short loop the compiler unrolls and vectorises.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowCoverage<const N: usize> {
    /// The row.
    pub(crate) y: i32,
    l: [i32; N],
    r: [i32; N],
    /// Pixels with at least one covered sample: `lo..hi`.
    pub(crate) lo: i32,
    pub(crate) hi: i32,
    /// Pixels with every sample covered: `inner.0..inner.1` (empty when `inner.0 >= inner.1`).
    pub(crate) inner: (i32, i32),
}

impl<const N: usize> RowCoverage<N> {
    /// The mask of samples of pixel `x` covered (bit `j` for sample `j`).
    #[inline]
    pub(crate) fn mask(&self, x: i32) -> u16 {
        super::sample_lanes::within(&self.l, &self.r, x)
    }
}

/// One edge of a chain as a sample row crosses it: the first pixel whose sample lies at or right of it.
struct SampleEdge {
    /// Raw y of the lower vertex: the edge covers sample rows strictly above it.
    bottom: i32,
    /// Index of the lower vertex, where the chain continues.
    end: usize,
    /// First pixel = q + (r != 0), the ceiling of (x(Y) - X) / 16; each row adds sq + sr / d.
    dda: [i32; 5],
}

impl SampleEdge {
    /// The edge from `a` down to `b` crossed by the sample row of pixel row `row` for sample `(sx, sy)`;
    /// `None` if its steps do not fit 32 bits (they do for any corner inside the clip's guard band).
    fn new(a: &ScreenVertex, b: &ScreenVertex, end: usize, row: i32, (sx, sy): (i32, i32)) -> Option<Self> {
        let (x0, y0) = (i64::from(a.x.0), i64::from(a.y.0));
        let (x1, y1) = (i64::from(b.x.0), i64::from(b.y.0));
        let (dx, dy) = (x1 - x0, y1 - y0);
        debug_assert!(dy > 0);
        let one = i64::from(Fx28_4::ONE);
        let d = one * dy;
        let ys = i64::from(row) * one + i64::from(sy);
        // (x(ys) - sx) / one with x(ys) = x0 + dx * (ys - y0) / dy, over the common denominator one * dy.
        let n = (x0 - i64::from(sx)) * dy + dx * (ys - y0);
        let s = one * dx;
        let narrow = |v: i64| i32::try_from(v).ok();
        // Room for a step's sums: the quotient moves by at most the edge's width in pixels.
        let (s, d) = (narrow(s)?, narrow(d)?);
        d.checked_mul(2)?;
        let q = n.div_euclid(i64::from(d));
        let r = n - q * i64::from(d);
        let dda = [narrow(q)?, narrow(r)?, s.div_euclid(d), s.rem_euclid(d), d];
        Some(Self { bottom: b.y.0, end, dda })
    }
}

/// The edge of a chain (from vertex `from`, in steps of `dir`) that the sample row `ys` (raw y) crosses;
/// `None` when the chain turns upwards (the polygon is not y-monotone) or ends.
fn edge_for(v: &[ScreenVertex], from: usize, dir: usize, row: i32, sample: (i32, i32)) -> Option<SampleEdge> {
    let n = v.len();
    let ys = row * Fx28_4::ONE + sample.1;
    let mut i = from;
    for _ in 0..n {
        let j = if i + dir >= n { i + dir - n } else { i + dir };
        if v[j].y.0 < v[i].y.0 {
            return None;
        }
        if v[j].y.0 > ys {
            return SampleEdge::new(&v[i], &v[j], j, row, sample);
        }
        i = j;
    }
    None
}

/// One side's edges, a lane per sample: the exact quotient-and-remainder DDA of each sample row's
/// crossing, stepped together.
#[derive(Clone, Copy)]
struct Side<const N: usize> {
    q: [i32; N],
    r: [i32; N],
    sq: [i32; N],
    sr: [i32; N],
    d: [i32; N],
    /// Raw y of each lane's edge's lower vertex, and that vertex's index.
    bottom: [i32; N],
    end: [usize; N],
}

impl<const N: usize> Side<N> {
    const EMPTY: Self =
        Self { q: [0; N], r: [0; N], sq: [0; N], sr: [0; N], d: [1; N], bottom: [i32::MIN; N], end: [0; N] };

    /// Puts `e` in lane `j`.
    #[inline]
    fn set(&mut self, j: usize, e: &SampleEdge) {
        let [q, r, sq, sr, d] = e.dda;
        (self.q[j], self.r[j], self.sq[j], self.sr[j], self.d[j]) = (q, r, sq, sr, d);
        (self.bottom[j], self.end[j]) = (e.bottom, e.end);
    }

    /// Lane `j`'s first pixel at or right of its edge, clipped to `0..=width`.
    #[inline(always)]
    fn pixel(&self, j: usize, width: i32) -> i32 {
        (self.q[j] + i32::from(self.r[j] != 0)).clamp(0, width)
    }

    /// Every lane one row down.
    #[inline(always)]
    fn step(&mut self) {
        for j in 0..N {
            let r = self.r[j] + self.sr[j];
            let carry = r >= self.d[j];
            self.r[j] = if carry { r - self.d[j] } else { r };
            self.q[j] += self.sq[j] + i32::from(carry);
        }
    }
}

/// A y-monotone polygon's corners, its top corner and which way round each chain goes from it.
struct Chains<'v> {
    v: &'v [ScreenVertex],
    top: usize,
    ldir: usize,
    rdir: usize,
}

/// Every sample's walk down the polygon, a lane per sample: its rows and its two current edges.
struct Walks<const N: usize> {
    /// Lane `j` walks pixel rows `first[j]..last[j]`.
    first: [i32; N],
    last: [i32; N],
    left: Side<N>,
    right: Side<N>,
}

impl<const N: usize> Walks<N> {
    /// Makes sure each lane walking pixel row `row` is on the edges its sample row crosses there: its
    /// first edges on its first row, the next ones past a corner. `None` when the polygon turns out not
    /// y-monotone.
    #[inline]
    fn enter(&mut self, c: &Chains<'_>, row: i32, pattern: &SamplePattern) -> Option<()> {
        for j in 0..N {
            if !(self.first[j]..self.last[j]).contains(&row) {
                continue;
            }
            let sample = pattern.positions[j];
            let y = row * Fx28_4::ONE + sample.1;
            if row == self.first[j] {
                self.left.set(j, &edge_for(c.v, c.top, c.ldir, row, sample)?);
                self.right.set(j, &edge_for(c.v, c.top, c.rdir, row, sample)?);
                continue;
            }
            if y >= self.left.bottom[j] {
                self.left.set(j, &edge_for(c.v, self.left.end[j], c.ldir, row, sample)?);
            }
            if y >= self.right.bottom[j] {
                self.right.set(j, &edge_for(c.v, self.right.end[j], c.rdir, row, sample)?);
            }
        }
        Some(())
    }
}

/// Calls `emit` for every pixel row in `rows` (clipped to `0..width` across) where the y-monotone polygon
/// `v` covers at least one sample of `pattern`, which has `N` samples. Zero-area polygons cover nothing;
/// either winding works.
pub(crate) fn for_each_row<const N: usize>(
    v: &[ScreenVertex],
    pattern: &SamplePattern,
    rows: (i32, i32),
    width: i32,
    mut emit: impl FnMut(&RowCoverage<N>),
) {
    debug_assert!(pattern.count == N && N <= MAX_SAMPLES, "a pattern of {} samples walked as {N}", pattern.count);
    let n = v.len();
    let area = signed_area2(v);
    if n < 3 || area == 0 {
        return;
    }
    let mut top = 0;
    let (mut ymin, mut ymax) = (v[0].y.0, v[0].y.0);
    for (i, p) in v.iter().enumerate().skip(1) {
        if p.y.0 < ymin {
            ymin = p.y.0;
            top = i;
        }
        ymax = ymax.max(p.y.0);
    }
    let (ldir, rdir) = if area > 0 { (n - 1, 1) } else { (1, n - 1) };
    let chains = Chains { v, top, ldir, rdir };
    // Sample row `16y + sy` is covered for y in ceil((ymin - sy) / 16) .. ceil((ymax - sy) / 16).
    let ceil16 = |a: i32| a.div_euclid(Fx28_4::ONE) + i32::from(a.rem_euclid(Fx28_4::ONE) != 0);
    let mut walks = Walks { first: [0; N], last: [0; N], left: Side::EMPTY, right: Side::EMPTY };
    let (mut first, mut last) = (i32::MAX, i32::MIN);
    for (j, &(_, sy)) in pattern.positions.iter().enumerate().take(N) {
        let (a, b) = (ceil16(ymin - sy).max(rows.0), ceil16(ymax - sy).min(rows.1));
        (walks.first[j], walks.last[j]) = if a < b { (a, b) } else { (i32::MIN, i32::MIN) };
        if a < b {
            first = first.min(a);
            last = last.max(b);
        }
    }
    let mut cov = RowCoverage { y: 0, l: [0; N], r: [0; N], lo: 0, hi: 0, inner: (0, 0) };
    for row in first..last.max(first) {
        if walks.enter(&chains, row, pattern).is_none() {
            return;
        }
        let (mut lo, mut hi, mut in_lo, mut in_hi) = (i32::MAX, i32::MIN, i32::MIN, i32::MAX);
        for j in 0..N {
            let (l, r) = (walks.left.pixel(j, width), walks.right.pixel(j, width));
            let on = (walks.first[j] <= row) & (row < walks.last[j]) & (l < r);
            let (l, r) = if on { (l, r) } else { (0, 0) };
            (cov.l[j], cov.r[j]) = (l, r);
            lo = if on { lo.min(l) } else { lo };
            hi = if on { hi.max(r) } else { hi };
            in_lo = in_lo.max(l);
            in_hi = in_hi.min(r);
        }
        walks.left.step();
        walks.right.step();
        if lo < hi {
            (cov.y, cov.lo, cov.hi, cov.inner) = (row, lo, hi, (in_lo, in_hi));
            emit(&cov);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::vertex::ATTRS;

    fn sv(x: i32, y: i32) -> ScreenVertex {
        ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs: [0.0; ATTRS] }
    }

    /// Every pixel `v` covers a sample of under `p` (in a `w` x `h` frame) as `(x, y, mask, inner)`, for
    /// any of the standard counts.
    fn pixels(v: &[ScreenVertex], p: &SamplePattern, w: i32, h: i32) -> Vec<(i32, i32, u16, bool)> {
        fn go<const N: usize>(v: &[ScreenVertex], p: &SamplePattern, w: i32, h: i32) -> Vec<(i32, i32, u16, bool)> {
            let mut out = Vec::new();
            for_each_row::<N>(v, p, (0, h), w, |c| {
                out.extend((c.lo..c.hi).map(|x| (x, c.y, c.mask(x), c.inner.0 <= x && x < c.inner.1)));
            });
            out
        }
        match p.count {
            4 => go::<4>(v, p, w, h),
            8 => go::<8>(v, p, w, h),
            _ => go::<16>(v, p, w, h),
        }
    }

    /// Adds one to every (pixel, sample) `v` covers, in a `w` x `h` frame.
    fn add(v: &[ScreenVertex], p: &SamplePattern, counts: &mut [u32], w: i32, h: i32) {
        for (x, y, m, inner) in pixels(v, p, w, h) {
            assert!(!inner || m == p.full(), "inner pixels are fully covered");
            for j in 0..p.count {
                counts[((y * w + x) as usize) * p.count + j] += u32::from(m >> j & 1);
            }
        }
    }

    #[test]
    fn a_pixel_cut_through_its_centre_is_half_covered_within_one_sample() {
        for n in [4, 8, 16] {
            let p = SamplePattern::standard(n).unwrap();
            // Half-planes through the centre of pixel (4, 4), raw (72, 72), in 40 directions around the
            // circle (integer steps, so the edge passes exactly through the centre): a big triangle with one
            // edge there.
            let steps = [(1, 0), (4, 1), (3, 1), (2, 1), (3, 2), (1, 1), (2, 3), (1, 2), (1, 3), (1, 4)];
            let turns = |(a, b): (i32, i32)| [(a, b), (-b, a), (-a, -b), (b, -a)];
            for (dx, dy) in steps.into_iter().flat_map(turns) {
                let far = 300;
                let pt = |s: i32, t: i32| sv(72 + dx * s - dy * t, 72 + dy * s + dx * t);
                let tri = [pt(-far, 0), pt(far, 0), pt(0, far)];
                let mut counts = vec![0; 9 * 9 * n];
                add(&tri, &p, &mut counts, 9, 9);
                let covered: u32 = counts[(4 * 9 + 4) * n..(4 * 9 + 5) * n].iter().sum();
                let share = f64::from(covered) / n as f64;
                assert!(
                    (share - 0.5).abs() <= 1.0 / n as f64 + 1e-9,
                    "{n} samples, edge along ({dx}, {dy}): {covered}/{n} covered"
                );
            }
        }
    }

    #[test]
    fn triangles_of_one_surface_cover_every_sample_exactly_once() {
        let mut rng = Lcg(7);
        let (w, h) = (24, 20);
        for n in [4, 8, 16] {
            let p = SamplePattern::standard(n).unwrap();
            for _ in 0..20 {
                // A grid of jittered points over the frame and beyond, cut into triangles both ways.
                let (gx, gy) = (6, 5);
                let pts: Vec<Vec<(i32, i32)>> = (0..=gy)
                    .map(|j| {
                        (0..=gx)
                            .map(|i| {
                                let edge = |k: i32, m: i32| k == 0 || k == m;
                                let jx = if edge(i, gx) { 0 } else { rng.range(-18, 18) };
                                let jy = if edge(j, gy) { 0 } else { rng.range(-18, 18) };
                                (-32 + i * (w * 16 + 64) / gx + jx, -32 + j * (h * 16 + 64) / gy + jy)
                            })
                            .collect()
                    })
                    .collect();
                let mut counts = vec![0; (w * h) as usize * n];
                for j in 0..gy as usize {
                    for i in 0..gx as usize {
                        let [a, b, c, d] = [pts[j][i], pts[j][i + 1], pts[j + 1][i + 1], pts[j + 1][i]];
                        let v = |q: (i32, i32)| sv(q.0, q.1);
                        if (i + j) % 2 == 0 {
                            add(&[v(a), v(b), v(c)], &p, &mut counts, w, h);
                            add(&[v(a), v(c), v(d)], &p, &mut counts, w, h);
                        } else {
                            add(&[v(a), v(b), v(d)], &p, &mut counts, w, h);
                            add(&[v(b), v(c), v(d)], &p, &mut counts, w, h);
                        }
                    }
                }
                assert!(counts.iter().all(|&c| c == 1), "{n} samples: a sample covered {:?} times", {
                    counts.iter().find(|&&c| c != 1)
                });
            }
        }
    }

    #[test]
    fn a_sample_on_a_vertex_or_edge_follows_the_top_left_rule() {
        let p = SamplePattern::standard(4).unwrap();
        // A square from sample (6, 2) of pixel 0 to sample (6, 2) of pixel (1, 1): its top-left corner is
        // on sample 0 of pixel (0, 0), which it covers; its right and bottom edges run through samples
        // of pixel (1, 1), which it does not.
        let sq = [sv(6, 2), sv(22, 2), sv(22, 18), sv(6, 18)];
        let mut counts = vec![0; 3 * 3 * 4];
        add(&sq, &p, &mut counts, 3, 3);
        assert_eq!(counts[0], 1, "top-left sample on the corner is in");
        assert_eq!(counts[4 * 4], 0, "sample 0 of pixel (1, 1) on the far corner is out");
        assert_eq!(counts.iter().sum::<u32>(), 4, "exactly one pixel's worth of samples");
    }

    /// Whether the sample at raw `(x, y)` is inside triangle `t` by edge functions and the top-left rule,
    /// written apart from the walk above.
    fn reference(t: &[ScreenVertex], (x, y): (i64, i64)) -> bool {
        let p = |v: &ScreenVertex| (i64::from(v.x.0), i64::from(v.y.0));
        let (a, mut b, mut c) = (p(&t[0]), p(&t[1]), p(&t[2]));
        let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
        if area == 0 {
            return false;
        }
        if area < 0 {
            std::mem::swap(&mut b, &mut c);
        }
        [(a, b), (b, c), (c, a)].iter().all(|&(s, e)| {
            let (dx, dy) = (e.0 - s.0, e.1 - s.1);
            let f = dx * (y - s.1) - dy * (x - s.0);
            f > 0 || (f == 0 && (dy < 0 || (dy == 0 && dx > 0)))
        })
    }

    #[test]
    fn masks_match_edge_functions_on_random_triangles() {
        let mut rng = Lcg(11);
        let (w, h) = (20, 16);
        for n in [4, 8, 16] {
            let p = SamplePattern::standard(n).unwrap();
            for case in 0..3000 {
                let size = [24, 80, 400][case % 3];
                let mut pt = || sv(rng.range(-size, w * 16 + size), rng.range(-size, h * 16 + size));
                let t = [pt(), pt(), pt()];
                let mut got = vec![0u16; (w * h) as usize];
                for (x, y, m, _) in pixels(&t, &p, w, h) {
                    got[(y * w + x) as usize] = m;
                }
                for py in 0..h {
                    for px in 0..w {
                        let mut want = 0u16;
                        for (j, &(sx, sy)) in p.positions[..n].iter().enumerate() {
                            let at = (i64::from(px * 16 + sx), i64::from(py * 16 + sy));
                            want |= u16::from(reference(&t, at)) << j;
                        }
                        assert_eq!(got[(py * w + px) as usize], want, "{n} samples, case {case}: pixel ({px}, {py})");
                    }
                }
            }
        }
    }
}
