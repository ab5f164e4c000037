//! A polygon's attributes as planes over the screen: their value at any pixel centre, inside the polygon
//! or not.
//!
//! The anti-aliased fill shades a pixel that an edge crosses once, at its centre, which may lie outside
//! the polygon (as MSAA does without centroid sampling); the scan line's per-row edge interpolation has no
//! value there. Depth, `1/w`, `s/w`, `t/w` and the colours over `w` are linear in screen space, so three
//! corners fix each plane; the corners spanning the largest triangle are taken, for the best conditioning.

use crate::render::core::vertex::{ATTRS, ScreenVertex};

/// The attribute planes of one polygon: value at a reference point and change per pixel in x and y.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Planes {
    /// Reference point (pixels).
    x0: f32,
    y0: f32,
    /// Attributes there.
    a0: [f32; ATTRS],
    /// Change per pixel to the right.
    pub(crate) dx: [f32; ATTRS],
    /// Change per pixel down.
    pub(crate) dy: [f32; ATTRS],
}

impl Planes {
    /// The planes through `v`'s corners; `None` when every corner triple is degenerate.
    pub(crate) fn of(v: &[ScreenVertex]) -> Option<Self> {
        let a = v.first()?;
        let pos = |p: &ScreenVertex| (f64::from(p.x.0) / 16.0, f64::from(p.y.0) / 16.0);
        let (ax, ay) = pos(a);
        let mut best = (0.0f64, 0usize);
        for i in 1..v.len().saturating_sub(1) {
            let ((bx, by), (cx, cy)) = (pos(&v[i]), pos(&v[i + 1]));
            let area = ((bx - ax) * (cy - ay) - (cx - ax) * (by - ay)).abs();
            if area > best.0 {
                best = (area, i);
            }
        }
        if best.0 <= 0.0 {
            return None;
        }
        let (b, c) = (&v[best.1], &v[best.1 + 1]);
        let ((bx, by), (cx, cy)) = (pos(b), pos(c));
        let (e1, e2) = ((bx - ax, by - ay), (cx - ax, cy - ay));
        let det = e1.0 * e2.1 - e2.0 * e1.1;
        let mut planes = Self { x0: ax as f32, y0: ay as f32, a0: a.attrs, dx: [0.0; ATTRS], dy: [0.0; ATTRS] };
        for k in 0..ATTRS {
            let (da1, da2) = (f64::from(b.attrs[k] - a.attrs[k]), f64::from(c.attrs[k] - a.attrs[k]));
            planes.dx[k] = ((da1 * e2.1 - da2 * e1.1) / det) as f32;
            planes.dy[k] = ((e1.0 * da2 - e2.0 * da1) / det) as f32;
        }
        Some(planes)
    }

    /// The attributes at the centre of pixel `(x, y)`.
    #[inline]
    pub(crate) fn at(&self, x: i32, y: i32) -> [f32; ATTRS] {
        let (ox, oy) = (x as f32 + 0.5 - self.x0, y as f32 + 0.5 - self.y0);
        let mut out = [0.0; ATTRS];
        for (k, o) in out.iter_mut().enumerate() {
            *o = self.a0[k] + ox * self.dx[k] + oy * self.dy[k];
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::fixed::Fx28_4;

    #[test]
    fn planes_reproduce_the_corners_and_extrapolate_linearly() {
        let f = |x: f32, y: f32| [1.0 + 0.5 * x - 0.25 * y, 2.0 * y, -x, 3.0, 0.0, 0.0, 0.0, 0.0];
        let v: Vec<ScreenVertex> = [(8.0f32, 8.0f32), (40.0, 12.0), (30.0, 50.0), (10.0, 30.0)]
            .iter()
            .map(|&(x, y)| ScreenVertex { x: Fx28_4((x * 16.0) as i32), y: Fx28_4((y * 16.0) as i32), attrs: f(x, y) })
            .collect();
        let p = Planes::of(&v).unwrap();
        for (x, y) in [(0, 0), (20, 20), (100, -5)] {
            let want = f(x as f32 + 0.5, y as f32 + 0.5);
            let got = p.at(x, y);
            for k in 0..ATTRS {
                assert!((got[k] - want[k]).abs() < 1e-3, "({x}, {y}) attribute {k}: {} vs {}", got[k], want[k]);
            }
        }
        let line: Vec<ScreenVertex> = v.iter().map(|p| ScreenVertex { y: Fx28_4(0), ..*p }).collect();
        assert!(Planes::of(&line).is_none());
    }
}
