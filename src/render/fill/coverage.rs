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

/// The samples of one pixel row a polygon covers: for sample `j`, pixels `l[j]..r[j]` (empty when equal).
#[derive(Clone, Copy, Debug)]
pub(crate) struct RowCoverage {
    /// The row.
    pub(crate) y: i32,
    l: [i32; MAX_SAMPLES],
    r: [i32; MAX_SAMPLES],
    n: usize,
    /// Pixels with at least one covered sample: `lo..hi`.
    pub(crate) lo: i32,
    pub(crate) hi: i32,
    /// Pixels with every sample covered: `inner.0..inner.1` (empty when `inner.0 >= inner.1`).
    pub(crate) inner: (i32, i32),
}

impl RowCoverage {
    /// The mask of samples of pixel `x` covered (bit `j` for sample `j`).
    #[inline]
    pub(crate) fn mask(&self, x: i32) -> u16 {
        let mut m = 0u16;
        for j in 0..self.n {
            m |= u16::from(self.l[j] <= x && x < self.r[j]) << j;
        }
        m
    }
}

/// One edge of a chain as a sample row crosses it: the first pixel whose sample lies at or right of it.
struct SampleEdge {
    /// Raw y of the lower vertex: the edge covers sample rows strictly above it.
    bottom: i32,
    /// Index of the lower vertex, where the chain continues.
    end: usize,
    // First pixel = q + (r != 0), the ceiling of (x(Y) - X) / 16.
    q: i64,
    r: i64,
    sq: i64,
    sr: i64,
    d: i64,
}

impl SampleEdge {
    /// The edge from `a` down to `b` crossed by the sample row of pixel row `row` for sample `(sx, sy)`.
    fn new(a: &ScreenVertex, b: &ScreenVertex, end: usize, row: i32, (sx, sy): (i32, i32)) -> Self {
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
        Self { bottom: b.y.0, end, q: n.div_euclid(d), r: n.rem_euclid(d), sq: s.div_euclid(d), sr: s.rem_euclid(d), d }
    }

    #[inline]
    fn pixel(&self) -> i64 {
        self.q + i64::from(self.r != 0)
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
            return Some(SampleEdge::new(&v[i], &v[j], j, row, sample));
        }
        i = j;
    }
    None
}

/// One sample's walk down the polygon: its rows and its two current edges.
struct SampleWalk {
    rows: (i32, i32),
    edges: Option<(SampleEdge, SampleEdge)>,
}

/// A y-monotone polygon's corners, its top corner and which way round each chain goes from it.
struct Chains<'v> {
    v: &'v [ScreenVertex],
    top: usize,
    ldir: usize,
    rdir: usize,
}

impl SampleWalk {
    /// The pixels `l..r` (clipped to `0..width`) whose `sample` row `row` covers; `Some((0, 0))` off the
    /// walk's rows, `None` when the polygon turns out not y-monotone.
    #[inline]
    fn row(&mut self, c: &Chains<'_>, row: i32, sample: (i32, i32), width: i32) -> Option<(i32, i32)> {
        if !(self.rows.0..self.rows.1).contains(&row) {
            return Some((0, 0));
        }
        if self.edges.is_none() {
            self.edges = edge_for(c.v, c.top, c.ldir, row, sample).zip(edge_for(c.v, c.top, c.rdir, row, sample));
        }
        let (left, right) = self.edges.as_mut()?;
        let y = row * Fx28_4::ONE + sample.1;
        if y >= left.bottom {
            *left = edge_for(c.v, left.end, c.ldir, row, sample)?;
        }
        if y >= right.bottom {
            *right = edge_for(c.v, right.end, c.rdir, row, sample)?;
        }
        let xs = left.pixel().clamp(0, i64::from(width));
        let xe = right.pixel().clamp(0, i64::from(width));
        left.step();
        right.step();
        Some(if xs < xe { (xs as i32, xe as i32) } else { (0, 0) })
    }
}

/// Calls `emit` for every pixel row in `rows` (clipped to `0..width` across) where the y-monotone polygon
/// `v` covers at least one sample of `pattern`. Zero-area polygons cover nothing; either winding works.
pub(crate) fn for_each_row(
    v: &[ScreenVertex],
    pattern: &SamplePattern,
    rows: (i32, i32),
    width: i32,
    mut emit: impl FnMut(&RowCoverage),
) {
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
    let count = pattern.count.min(MAX_SAMPLES);
    // Sample row `16y + sy` is covered for y in ceil((ymin - sy) / 16) .. ceil((ymax - sy) / 16).
    let ceil16 = |a: i32| a.div_euclid(Fx28_4::ONE) + i32::from(a.rem_euclid(Fx28_4::ONE) != 0);
    let mut walks: [SampleWalk; MAX_SAMPLES] = std::array::from_fn(|_| SampleWalk { rows: (0, 0), edges: None });
    let (mut first, mut last) = (i32::MAX, i32::MIN);
    for (w, &(_, sy)) in walks.iter_mut().zip(&pattern.positions).take(count) {
        w.rows = (ceil16(ymin - sy).max(rows.0), ceil16(ymax - sy).min(rows.1));
        if w.rows.0 < w.rows.1 {
            first = first.min(w.rows.0);
            last = last.max(w.rows.1);
        }
    }
    let mut cov = RowCoverage { y: 0, l: [0; MAX_SAMPLES], r: [0; MAX_SAMPLES], n: count, lo: 0, hi: 0, inner: (0, 0) };
    for row in first..last.max(first) {
        let (mut lo, mut hi, mut in_lo, mut in_hi) = (i32::MAX, i32::MIN, i32::MIN, i32::MAX);
        for (j, w) in walks.iter_mut().enumerate().take(count) {
            let Some((l, r)) = w.row(&chains, row, pattern.positions[j], width) else { return };
            (cov.l[j], cov.r[j]) = (l, r);
            if l < r {
                lo = lo.min(l);
                hi = hi.max(r);
            }
            in_lo = in_lo.max(l);
            in_hi = in_hi.min(r);
        }
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

    /// Adds one to every (pixel, sample) `v` covers, in a `w` x `h` frame.
    fn add(v: &[ScreenVertex], p: &SamplePattern, counts: &mut [u32], w: i32, h: i32) {
        for_each_row(v, p, (0, h), w, |c| {
            for x in c.lo..c.hi {
                let m = c.mask(x);
                assert!(x < c.inner.0 || x >= c.inner.1 || m == p.full(), "inner pixels are fully covered");
                for j in 0..p.count {
                    counts[((c.y * w + x) as usize) * p.count + j] += u32::from(m >> j & 1);
                }
            }
        });
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
                for_each_row(&t, &p, (0, h), w, |c| {
                    for x in c.lo..c.hi {
                        got[(c.y * w + x) as usize] = c.mask(x);
                    }
                });
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
