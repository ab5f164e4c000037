//! Splitting screen polygons that a scan line would cut in more than one span.
//!
//! A planar polygon that is not y-monotone in this view (a 'U', a star, a concave shape turned on its side)
//! is split into triangles by ear clipping on the snapped fixed-point positions, with exact integer
//! predicates. Each triangle is y-monotone, so the scanline fill can draw it, and the triangles tile the
//! polygon exactly, so the coverage is the polygon's.

use crate::render::core::vertex::ScreenVertex;

fn cross(o: &ScreenVertex, a: &ScreenVertex, b: &ScreenVertex) -> i64 {
    let (ox, oy) = (i64::from(o.x.0), i64::from(o.y.0));
    (i64::from(a.x.0) - ox) * (i64::from(b.y.0) - oy) - (i64::from(a.y.0) - oy) * (i64::from(b.x.0) - ox)
}

/// True when `p` lies inside or on triangle `a b c` of orientation `sign`.
fn in_triangle(p: &ScreenVertex, a: &ScreenVertex, b: &ScreenVertex, c: &ScreenVertex, sign: i64) -> bool {
    cross(a, b, p) * sign >= 0 && cross(b, c, p) * sign >= 0 && cross(c, a, p) * sign >= 0
}

/// Triangulates a simple polygon of orientation `area_sign` (the sign of its signed area), appending index
/// triples into `v` to `out`. Self-intersecting input falls back to a fan for what ear clipping cannot take.
pub fn triangulate(v: &[ScreenVertex], area_sign: i64, out: &mut Vec<[usize; 3]>) {
    let mut rest: Vec<usize> = (0..v.len()).collect();
    let mut guard = v.len() * v.len() + 8;
    while rest.len() > 3 && guard > 0 {
        guard -= 1;
        let m = rest.len();
        let mut clipped = false;
        for k in 0..m {
            let (ia, ib, ic) = (rest[(k + m - 1) % m], rest[k], rest[(k + 1) % m]);
            let (a, b, c) = (&v[ia], &v[ib], &v[ic]);
            let turn = cross(a, b, c) * area_sign;
            if turn == 0 {
                // A collinear or repeated vertex contributes no area: drop it.
                rest.remove(k);
                clipped = true;
                break;
            }
            if turn < 0 {
                continue;
            }
            let blocked = rest.iter().any(|&j| {
                if j == ia || j == ib || j == ic {
                    return false;
                }
                let p = &v[j];
                let same = |q: &ScreenVertex| p.x == q.x && p.y == q.y;
                !same(a) && !same(b) && !same(c) && in_triangle(p, a, b, c, area_sign)
            });
            if !blocked {
                out.push([ia, ib, ic]);
                rest.remove(k);
                clipped = true;
                break;
            }
        }
        if !clipped {
            break;
        }
    }
    if rest.len() >= 3 {
        for k in 1..rest.len() - 1 {
            out.push([rest[0], rest[k], rest[k + 1]]);
        }
    }
}

/// True when every horizontal line cuts the polygon outline at most twice (y goes down once and up once).
#[must_use]
pub fn is_y_monotone(v: &[ScreenVertex]) -> bool {
    if v.len() <= 3 {
        return true; // a triangle (or less) always is
    }
    let next = || v.iter().skip(1).chain(v.first());
    let dirs = || v.iter().zip(next()).map(|(p, q)| (q.y.0 - p.y.0).signum());
    let mut changes = 0;
    // Start from the last non-zero direction so the count is cyclic.
    let mut last = dirs().filter(|&d| d != 0).last().unwrap_or(0);
    for d in dirs() {
        if d != 0 {
            if d != last {
                changes += 1;
            }
            last = d;
        }
    }
    changes <= 2
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::core::fixed::Fx28_4;
    use crate::render::core::vertex::{ATTRS, signed_area2};

    fn sv(x: i32, y: i32) -> ScreenVertex {
        ScreenVertex { x: Fx28_4(x), y: Fx28_4(y), attrs: [0.0; ATTRS] }
    }

    #[test]
    fn ear_clipping_preserves_area() {
        // A 'U' opening upwards (y down): not y-monotone.
        let w: Vec<ScreenVertex> = [(0, 0), (10, 0), (10, 20), (20, 20), (20, 0), (30, 0), (30, 30), (0, 30)]
            .iter()
            .map(|&(x, y)| sv(x * 16, y * 16))
            .collect();
        assert!(!is_y_monotone(&w));
        let total = signed_area2(&w);
        let mut tris = vec![];
        triangulate(&w, total.signum(), &mut tris);
        assert_eq!(tris.len(), 6);
        let sum: i64 = tris.iter().map(|t| signed_area2(&[w[t[0]], w[t[1]], w[t[2]]])).sum();
        assert_eq!(sum, total);
        for t in &tris {
            assert_eq!(signed_area2(&[w[t[0]], w[t[1]], w[t[2]]]).signum(), total.signum());
        }
    }

    #[test]
    fn monotone_detection() {
        let convex = [sv(0, 0), sv(10, 0), sv(10, 10), sv(0, 10)];
        assert!(is_y_monotone(&convex));
        // A 'W' shape dips down twice.
        let w = [sv(0, 0), sv(5, 10), sv(10, 2), sv(15, 10), sv(20, 0), sv(10, 20)];
        assert!(!is_y_monotone(&w));
    }
}
