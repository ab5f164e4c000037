//! Mip-maps: how a texture's chain of smaller levels is made, and how a level of detail `λ` is measured.
//!
//! **The chain.** Level `k + 1` is the box filter of level `k`: each texel is the rounded mean (`(sum +
//! n/2) / n`) of a block of level-`k` texels, per channel, alpha included, averaged in the stored 8-bit
//! values with no gamma conversion. The renderer uses texels as stored (the `render` command promises it),
//! and everything that averages colours in this program averages stored values: bilinear filtering,
//! blending, the anti-aliased resolve and the bench's 4x4-supersampled reference image. A level made in
//! linear light would be a different mean from the one the reference takes over the same texels, so the
//! chain would move the mip-mapped frames away from the reference rather than towards it. The blocks are
//! 2x2; a level of odd size `n` is followed by one of `max(1, n / 2)` (as OpenGL sizes them), and its last
//! column (row) is folded into the block of the next level's last column (row), which then averages three
//! columns (rows): blocks are 2x2, 3x2, 2x3 or, in the last corner, 3x3 texels, every texel of level `k`
//! counted exactly once and with equal weight. A side of 1 stays 1 (a block one texel wide). The chain goes
//! down to 1x1; it holds about a third as many texels again as level 0 and is made in one pass per level.
//!
//! **The level of detail.** `λ = log2 ρ`, with `ρ` the texels one screen pixel spans (OpenGL's scale
//! factor): per pixel, the larger of the lengths of `(du/dx, dv/dx)` and `(du/dy, dv/dy)` in texels; per
//! span, the same at the span's middle pixel; per polygon (as Quake chose a surface's level once), the
//! square root of the ratio of the polygon's area in texels to its area in pixels. `λ <= 0` is
//! magnification: level 0. Nearest and bilinear filtering sample one level, the one nearest to `λ`
//! (`floor(λ + 1/2)`); trilinear samples the two levels around `λ` bilinearly and blends them by its
//! fraction.

use crate::render::core::vertex::{ScreenVertex, slot};

/// A polygon's `λ` is carried in steps of `1 / LOD_STEPS` in one byte (up to level 15.9).
pub const LOD_STEPS: f32 = 16.0;

/// The size of the level after one of `width` x `height` texels.
#[must_use]
pub fn next_size(width: u32, height: u32) -> (u32, u32) {
    ((width / 2).max(1), (height / 2).max(1))
}

/// The source texels `start..end` (on one axis, of `size`) that texel `i` of the next level (of `next`
/// texels) averages: two, or three for the last of an odd size, or the one of a side of 1.
#[inline]
fn block(i: u32, size: u32, next: u32) -> (u32, u32) {
    let start = (2 * i).min(size - 1);
    let end = if i + 1 == next { size } else { 2 * i + 2 };
    (start, end)
}

/// Texel `(i, j)` of the level after `src` (`w` x `h` texels), whose size is `(nw, nh)`.
fn reduced_texel(src: &[u32], (w, h): (u32, u32), (nw, nh): (u32, u32), (i, j): (u32, u32)) -> u32 {
    let (x0, x1) = block(i, w, nw);
    let (y0, y1) = block(j, h, nh);
    let mut sum = [0u32; 4];
    for y in y0..y1 {
        let row = y as usize * w as usize;
        for &t in src.get(row + x0 as usize..row + x1 as usize).unwrap_or_default() {
            for (c, s) in sum.iter_mut().enumerate() {
                *s += (t >> (8 * c)) & 0xff;
            }
        }
    }
    let n = (x1 - x0) * (y1 - y0);
    sum.iter().enumerate().fold(0, |acc, (c, &s)| acc | ((s + n / 2) / n) << (8 * c))
}

/// The level after `src` (`w` x `h` texels, packed): its size and texels.
#[must_use]
pub fn reduce(src: &[u32], (w, h): (u32, u32)) -> (u32, u32, Vec<u32>) {
    let (nw, nh) = next_size(w, h);
    let mut out = Vec::with_capacity(nw as usize * nh as usize);
    for j in 0..nh {
        out.extend((0..nw).map(|i| reduced_texel(src, (w, h), (nw, nh), (i, j))));
    }
    (nw, nh, out)
}

/// Remakes the texels of `dst` (the level after `src`) whose blocks meet the source rectangle
/// `x0..x1, y0..y1`, and returns the rectangle of `dst` remade (what changes in the level after it).
pub fn refresh(
    src: &[u32],
    (w, h): (u32, u32),
    dst: &mut [u32],
    (x0, y0, x1, y1): (u32, u32, u32, u32),
) -> (u32, u32, u32, u32) {
    let (nw, nh) = next_size(w, h);
    if x0 >= x1 || y0 >= y1 {
        return (0, 0, 0, 0);
    }
    // Block `i` starts at `2i` and the last one runs to the end, so these are the blocks meeting the range.
    let (i0, i1) = ((x0 / 2).min(nw - 1), ((x1 - 1) / 2).min(nw - 1) + 1);
    let (j0, j1) = ((y0 / 2).min(nh - 1), ((y1 - 1) / 2).min(nh - 1) + 1);
    for j in j0..j1 {
        for i in i0..i1 {
            if let Some(t) = dst.get_mut(j as usize * nw as usize + i as usize) {
                *t = reduced_texel(src, (w, h), (nw, nh), (i, j));
            }
        }
    }
    (i0, j0, i1, j1)
}

/// The one level nearest/bilinear sampling uses for `λ`, of levels `0..=last`: `floor(λ + 1/2)`, 0 for
/// magnification and NaN.
#[inline]
#[must_use]
pub fn nearest_level(lod: f32, last: usize) -> usize {
    // `as usize` saturates and sends NaN and negatives to 0.
    ((lod + 0.5) as usize).min(last)
}

/// `log2 x` for a positive, finite, normal `x`, within 2e-4 and exact at powers of two: the exponent
/// plus a quartic in the mantissa (least squares on `[1, 2)`, ending at 0 and 1). A level of detail needs
/// no more, and the per-pixel choice takes one a pixel, where `log2f` was half its cost.
#[inline]
#[must_use]
pub fn log2_approx(x: f32) -> f32 {
    let bits = x.to_bits();
    let exponent = ((bits >> 23) & 0xff) as i32 - 127;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000) - 1.0;
    let c = LOG2_QUARTIC;
    exponent as f32 + m * (c[0] + m * (c[1] + m * (c[2] + m * c[3])))
}

/// [`log2_approx`]'s quartic in the mantissa `m - 1`, lowest power first (the vector loops evaluate the same
/// one, in the same order).
pub(crate) const LOG2_QUARTIC: [f32; 4] = [1.438_073_3, -0.674_766_7, 0.317_000_7, -0.080_307_3];

/// `λ` from the squared lengths (in texels) of the pixel's footprint along x and along y.
#[inline]
#[must_use]
pub fn lod_from_squares(rho_x2: f32, rho_y2: f32) -> f32 {
    let rho2 = rho_x2.max(rho_y2);
    // Half the log of the square: one logarithm and no square root. Zero, NaN and infinity give no level.
    if rho2.is_finite() && rho2 > 0.0 { 0.5 * log2_approx(rho2) } else { 0.0 }
}

/// A polygon's `λ` in steps of 1/[`LOD_STEPS`], clamped to `0..=255`, from its corners' screen positions
/// (pixels) and `1/w`, `s/w`, `t/w` (so `u = s/q`, `v = t/q`), for a texture of `size` texels: the ratio
/// of its area in texels to its area in pixels.
#[must_use]
pub fn polygon_lod(mut corners: impl Iterator<Item = [f32; 5]>, (tw, th): (u32, u32)) -> u8 {
    // Each corner's `(x, y, u, v)`, its divisions done once (each edge's two ends would do them twice).
    let at = |c: [f32; 5]| [c[0], c[1], c[3] / c[2], c[4] / c[2]];
    let Some(first) = corners.next().map(at) else { return 0 };
    let (mut screen, mut texels) = (0.0f32, 0.0f32);
    let mut edge = |a: &[f32; 4], b: &[f32; 4]| {
        screen += a[0] * b[1] - b[0] * a[1];
        texels += a[2] * b[3] - b[2] * a[3];
    };
    let mut a = first;
    for b in corners.map(at) {
        edge(&a, &b);
        a = b;
    }
    edge(&a, &first);
    let ratio = (texels * tw as f32 * th as f32 / screen).abs();
    let lod = if ratio.is_finite() && ratio > 0.0 { 0.5 * log2_approx(ratio) } else { 0.0 };
    // `as u8` saturates, NaN and negatives giving 0.
    (lod * LOD_STEPS + 0.5) as u8
}

/// [`polygon_lod`] of screen vertices.
#[must_use]
pub fn polygon_lod_of(v: &[ScreenVertex], size: (u32, u32)) -> u8 {
    let corner = |p: &ScreenVertex| [p.x.to_f32(), p.y.to_f32(), p.attrs[slot::Q], p.attrs[slot::S], p.attrs[slot::T]];
    polygon_lod(v.iter().map(corner), size)
}

/// The change of a polygon's `1/w`, `s/w` and `t/w` per pixel along x and along y (they are planes in
/// screen space), for the level of detail at a pixel.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TexGradients {
    /// `d/dx` of `1/w`, `s/w`, `t/w`.
    pub dx: [f32; 3],
    /// `d/dy` of `1/w`, `s/w`, `t/w`.
    pub dy: [f32; 3],
}

impl TexGradients {
    /// The planes of a polygon measured in a frame of four rows a pixel, as in a frame of twice the width
    /// and height: the change per pixel along x halved, and along y (per row, a quarter of a pixel) doubled
    /// (exactly, powers of two).
    #[must_use]
    pub(crate) fn in_tall_frame(self) -> Self {
        Self { dx: self.dx.map(|d| d * 0.5), dy: self.dy.map(|d| d * 2.0) }
    }

    /// The planes with every change multiplied by `2^bias`: footprints that much longer, their level of
    /// detail `bias` coarser (the mip bias, for levels measured per span or pixel).
    #[must_use]
    pub(crate) fn biased(self, bias: f32) -> Self {
        let k = libm::exp2f(bias);
        Self { dx: self.dx.map(|d| d * k), dy: self.dy.map(|d| d * k) }
    }

    /// The planes through a polygon's corners, from the fan triangle of largest area (the best
    /// conditioned); all zero for a polygon with no area.
    #[must_use]
    pub fn of(v: &[ScreenVertex]) -> Self {
        let Some(p0) = v.first() else { return Self::default() };
        let pos = |p: &ScreenVertex| (p.x.to_f32(), p.y.to_f32());
        let (x0, y0) = pos(p0);
        let mut best = (0.0f32, 0usize);
        for i in 1..v.len().saturating_sub(1) {
            let ((x1, y1), (x2, y2)) = (pos(&v[i]), pos(&v[i + 1]));
            let det = (x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0);
            if det.abs() > best.0.abs() {
                best = (det, i);
            }
        }
        let (det, i) = best;
        if det == 0.0 || !det.is_finite() {
            return Self::default();
        }
        let (p1, p2) = (&v[i], &v[i + 1]);
        let ((x1, y1), (x2, y2)) = (pos(p1), pos(p2));
        let (e1x, e1y, e2x, e2y) = (x1 - x0, y1 - y0, x2 - x0, y2 - y0);
        let mut g = Self::default();
        for (k, s) in [slot::Q, slot::S, slot::T].into_iter().enumerate() {
            let (d1, d2) = (p1.attrs[s] - p0.attrs[s], p2.attrs[s] - p0.attrs[s]);
            g.dx[k] = (d1 * e2y - d2 * e1y) / det;
            g.dy[k] = (d2 * e1x - d1 * e2x) / det;
        }
        g
    }

    /// The extent in texels (of a texture of `size` texels) across and down of the pixel's footprint at a
    /// point where `1/w`, `s/w`, `t/w` are `qst`: `|du/dx| + |du/dy|` and `|dv/dx| + |dv/dy|`, the
    /// footprint parallelogram's shadow on each texture axis (the `area` filter's box).
    #[inline]
    #[must_use]
    pub fn extent_at(&self, [q, s, t]: [f32; 3], (tw, th): (u32, u32)) -> [f32; 2] {
        let w = 1.0 / q;
        let (u, v) = (s * w, t * w);
        let (du_dx, du_dy) = ((self.dx[1] - u * self.dx[0]) * w, (self.dy[1] - u * self.dy[0]) * w);
        let (dv_dx, dv_dy) = ((self.dx[2] - v * self.dx[0]) * w, (self.dy[2] - v * self.dy[0]) * w);
        [(du_dx.abs() + du_dy.abs()) * tw as f32, (dv_dx.abs() + dv_dy.abs()) * th as f32]
    }

    /// `λ` at a point where `1/w`, `s/w`, `t/w` are `qst`, for a texture of `size` texels (level 0).
    #[inline]
    #[must_use]
    pub fn lod_at(&self, [q, s, t]: [f32; 3], (tw, th): (u32, u32)) -> f32 {
        // u = s/q, so du = (ds - u dq) / q; likewise v.
        let w = 1.0 / q;
        let (u, v) = (s * w, t * w);
        let (tw, th) = (tw as f32 * w, th as f32 * w);
        let square = |d: &[f32; 3]| {
            let (du, dv) = ((d[1] - u * d[0]) * tw, (d[2] - v * d[0]) * th);
            du * du + dv * dv
        };
        lod_from_squares(square(&self.dx), square(&self.dy))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::fixed::Fx28_4;
    use crate::render::core::test_rng::Lcg;
    use crate::render::core::vertex::ATTRS;

    #[test]
    fn an_extent_is_the_footprint_s_shadow_on_each_axis_by_finite_differences() {
        // Planes of 1/w, s/w, t/w in perspective, rotated and sheared: u = s/q and v = t/q differentiated
        // numerically along x and y (in f64), against `extent_at`'s closed form.
        let mut rng = Lcg(17);
        for _ in 0..2000 {
            let mut r = |s: f32| (rng.unit() - 0.5) * s;
            let g = TexGradients { dx: [r(0.02), r(0.2), r(0.2)], dy: [r(0.02), r(0.2), r(0.2)] };
            let qst = [0.5 + r(0.5).abs(), r(4.0), r(4.0)];
            let size = (64, 16);
            let at = |x: f64, y: f64| {
                let p = |i: usize| f64::from(qst[i]) + x * f64::from(g.dx[i]) + y * f64::from(g.dy[i]);
                (p(1) / p(0) * 64.0, p(2) / p(0) * 16.0)
            };
            let h = 1e-4;
            let (ux, vx) = ((at(h, 0.0).0 - at(-h, 0.0).0) / (2.0 * h), (at(h, 0.0).1 - at(-h, 0.0).1) / (2.0 * h));
            let (uy, vy) = ((at(0.0, h).0 - at(0.0, -h).0) / (2.0 * h), (at(0.0, h).1 - at(0.0, -h).1) / (2.0 * h));
            let want = [ux.abs() + uy.abs(), vx.abs() + vy.abs()];
            let got = g.extent_at(qst, size);
            for a in 0..2 {
                let err = (f64::from(got[a]) - want[a]).abs();
                assert!(err <= 1e-3 * want[a].max(1e-2), "axis {a}: {} against {} ({g:?} at {qst:?})", got[a], want[a]);
            }
        }
    }

    /// The box filter written the slow way: every source texel added to the next-level texel it falls in.
    fn slow_reduce(src: &[u32], w: u32, h: u32) -> Vec<u32> {
        let (nw, nh) = next_size(w, h);
        let mut sums = vec![[0u32; 5]; (nw * nh) as usize];
        for y in 0..h {
            for x in 0..w {
                let (i, j) = ((x / 2).min(nw - 1), (y / 2).min(nh - 1));
                let s = &mut sums[(j * nw + i) as usize];
                let t = src[(y * w + x) as usize];
                for (c, sc) in s.iter_mut().take(4).enumerate() {
                    *sc += (t >> (8 * c)) & 0xff;
                }
                s[4] += 1;
            }
        }
        let mean = |s: &[u32; 5]| (0..4).fold(0, |a, c| a | ((s[c] + s[4] / 2) / s[4]) << (8 * c));
        sums.iter().map(mean).collect()
    }

    fn noise(n: usize, mut seed: u32) -> Vec<u32> {
        (0..n)
            .map(|_| {
                seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                seed
            })
            .collect()
    }

    #[test]
    fn a_level_is_the_box_filter_of_the_one_above_at_every_size() {
        for (w, h) in [(8, 8), (7, 5), (1, 9), (6, 1), (3, 3), (2, 2), (1, 1), (5, 2)] {
            let src = noise((w * h) as usize, w * 31 + h);
            let (nw, nh, got) = reduce(&src, (w, h));
            assert_eq!((nw, nh), next_size(w, h));
            assert_eq!(got, slow_reduce(&src, w, h), "{w}x{h}");
        }
        // By hand: a 3x1 row folds its last texel into one 3-texel mean, rounded to nearest.
        let (nw, nh, one) = reduce(&[0x0000_0001, 0x0000_0002, 0x0000_0002], (3, 1));
        assert_eq!((nw, nh, one), (1, 1, vec![0x0000_0002]));
        let (_, _, two) = reduce(&[0xff00_00ff, 0x0000_0000, 0x0100_0001, 0x0000_0000], (2, 2));
        // (255 + 1) / 4 = 64 for blue and alpha; nothing else.
        assert_eq!(two, vec![0x4000_0040]);
    }

    #[test]
    fn refresh_remakes_exactly_the_blocks_a_change_meets() {
        let (w, h) = (9u32, 7u32);
        let mut src = noise((w * h) as usize, 5);
        let (_, _, mut dst) = reduce(&src, (w, h));
        for (x0, y0, x1, y1) in [(8, 6, 9, 7), (0, 0, 1, 1), (3, 2, 6, 5), (7, 0, 9, 2)] {
            for y in y0..y1 {
                for x in x0..x1 {
                    src[(y * w + x) as usize] ^= 0x3377_55aa;
                }
            }
            refresh(&src, (w, h), &mut dst, (x0, y0, x1, y1));
            assert_eq!(dst, reduce(&src, (w, h)).2, "after changing {x0},{y0}..{x1},{y1}");
        }
    }

    fn sv(x: f32, y: f32, q: f32, u: f32, v: f32) -> ScreenVertex {
        let mut attrs = [0.0; ATTRS];
        attrs[slot::Q] = q;
        attrs[slot::S] = u * q;
        attrs[slot::T] = v * q;
        ScreenVertex { x: Fx28_4((x * 16.0) as i32), y: Fx28_4((y * 16.0) as i32), attrs }
    }

    #[test]
    fn the_quick_logarithm_is_within_its_bound_and_exact_at_powers_of_two() {
        for e in -100..100 {
            assert_eq!(log2_approx(libm::exp2f(e as f32)), e as f32);
        }
        let mut x = 1e-30f32;
        while x < 1e30 {
            let err = (log2_approx(x) - libm::log2f(x)).abs();
            assert!(err < 2e-4, "{x:e}: {err:e}");
            x *= 1.000_37;
        }
    }

    #[test]
    fn lod_of_a_square_at_known_scales() {
        // A 32-pixel square mapping the whole of a 32 * 2^k texture: one pixel spans 2^k texels.
        for k in 0..5u32 {
            let size = 32 << k;
            let quad = [sv(0.0, 0.0, 0.5, 0.0, 0.0), sv(32.0, 0.0, 0.5, 1.0, 0.0), sv(32.0, 32.0, 0.5, 1.0, 1.0)];
            let lod = polygon_lod_of(&quad, (size, size));
            assert_eq!(lod, (k * 16) as u8, "polygon, scale 2^{k}");
            let g = TexGradients::of(&quad);
            let at = g.lod_at([0.5, 0.25, 0.1], (size, size));
            assert!((at - k as f32).abs() < 1e-4, "pixel, scale 2^{k}: {at}");
            assert_eq!(nearest_level(at, 10), k as usize);
        }
        // Magnified: level 0.
        let quad = [sv(0.0, 0.0, 1.0, 0.0, 0.0), sv(64.0, 0.0, 1.0, 1.0, 0.0), sv(0.0, 64.0, 1.0, 0.0, 1.0)];
        assert_eq!(polygon_lod_of(&quad, (8, 8)), 0);
        assert_eq!(nearest_level(TexGradients::of(&quad).lod_at([1.0, 0.5, 0.5], (8, 8)), 3), 0);
        assert_eq!(nearest_level(f32::NAN, 3), 0);
        assert_eq!(nearest_level(1.49, 3), 1);
        assert_eq!(nearest_level(1.5, 3), 2);
        assert_eq!(nearest_level(9.0, 3), 3);
    }
}
