//! Turning triangle pairs back into the quads they came from.
//!
//! glTF stores only triangles, so an exporter writes a quad `a b c d` as `a b c` followed by `a c d` (and a
//! convex polygon as a fan of such pairs). The scanline renderer draws a convex polygon of any vertex count
//! in one pass, so such a pair is merged back into one polygon when that changes nothing in the image: the
//! four points are coplanar, the quad is convex, and the texture coordinates and colours of the fourth point
//! are the affine continuation of the first three (so interpolating across the quad equals interpolating
//! across the two triangles). A box then has 6 polygons, not 12, as the seed's long-shot model does.

use glam::{Vec2, Vec3, Vec4};

use crate::render::Vertex;

fn affine_coords(a: Vec3, b: Vec3, c: Vec3, d: Vec3) -> Option<(f32, f32)> {
    let (e1, e2, p) = (b - a, c - a, d - a);
    let (g11, g12, g22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let det = g11 * g22 - g12 * g12;
    if det.abs() <= f32::EPSILON * g11 * g22 || !det.is_finite() {
        return None;
    }
    let (r1, r2) = (p.dot(e1), p.dot(e2));
    Some(((r1 * g22 - r2 * g12) / det, (r2 * g11 - r1 * g12) / det))
}

fn close2(x: Vec2, y: Vec2) -> bool {
    (x - y).abs().max_element() <= 4e-6 * (1.0 + x.abs().max_element())
}

fn close4(x: Vec4, y: Vec4) -> bool {
    (x - y).abs().max_element() <= 1e-3
}

/// True when triangles `a b c` and `a c d` form one planar, convex quad with affine attributes.
fn mergeable(v: &[Vertex], [a, b, c]: [u32; 3], d: u32) -> bool {
    let get = |i: u32| v.get(i as usize);
    let (Some(va), Some(vb), Some(vc), Some(vd)) = (get(a), get(b), get(c), get(d)) else {
        return false;
    };
    if d == b || d == a || d == c {
        return false;
    }
    let (pa, pb, pc, pd) = (va.position, vb.position, vc.position, vd.position);
    let n = (pb - pa).cross(pc - pa);
    let size = (pb - pa).length().max((pc - pa).length()).max((pd - pa).length());
    if n.length() <= 1e-12 * size * size || !n.is_finite() || !size.is_finite() {
        return false;
    }
    let nn = n.normalize();
    if (pd - pa).dot(nn).abs() > 1e-6 * size {
        return false;
    }
    let quad = [pa, pb, pc, pd];
    let convex = (0..4).all(|i| {
        let (p, q, r) = (quad[i], quad[(i + 1) % 4], quad[(i + 2) % 4]);
        (q - p).cross(r - q).dot(nn) > 1e-9 * size * size
    });
    if !convex {
        return false;
    }
    let Some((s, t)) = affine_coords(pa, pb, pc, pd) else {
        return false;
    };
    let uv = va.uv + s * (vb.uv - va.uv) + t * (vc.uv - va.uv);
    let col = va.color + s * (vb.color - va.color) + t * (vc.color - va.color);
    close2(uv, vd.uv) && close4(col, vd.color)
}

/// Groups a triangle list into polygons: each `a b c` + `a c d` pair that `mergeable` accepts becomes the
/// quad `a b c d`; every other triangle stays a triangle. Order is kept.
#[must_use]
pub fn merge_pairs(vertices: &[Vertex], tris: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut out = Vec::with_capacity(tris.len());
    let mut i = 0;
    while i < tris.len() {
        let t = tris[i];
        if let Some(&[a2, c2, d]) = tris.get(i + 1)
            && a2 == t[0]
            && c2 == t[2]
            && mergeable(vertices, t, d)
        {
            out.push(vec![t[0], t[1], t[2], d]);
            i += 2;
        } else {
            out.push(t.to_vec());
            i += 1;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, u: f32, w: f32) -> Vertex {
        Vertex { position: Vec3::new(x, y, 0.0), uv: Vec2::new(u, w), color: Vec4::ONE }
    }

    #[test]
    fn planar_affine_quads_merge_and_others_do_not() {
        let square = [v(0., 0., 0., 0.), v(1., 0., 1., 0.), v(1., 1., 1., 1.), v(0., 1., 0., 1.)];
        assert_eq!(merge_pairs(&square, &[[0, 1, 2], [0, 2, 3]]), vec![vec![0, 1, 2, 3]]);
        // A trapezoid with a square's texture coordinates is not affine: kept as two triangles.
        let trap = [v(0., 0., 0., 0.), v(2., 0., 1., 0.), v(1.5, 1., 1., 1.), v(0.5, 1., 0., 1.)];
        assert_eq!(merge_pairs(&trap, &[[0, 1, 2], [0, 2, 3]]).len(), 2);
        // A concave quad is kept as triangles.
        let dart = [v(0., 0., 0., 0.), v(2., 0., 2., 0.), v(1., 0.4, 1., 0.4), v(1., 2., 1., 2.)];
        assert_eq!(merge_pairs(&dart, &[[0, 1, 2], [0, 2, 3]]).len(), 2);
        // Non-adjacent pairs and a lone triangle pass through.
        assert_eq!(merge_pairs(&square, &[[0, 1, 2], [1, 2, 3], [0, 1, 3]]).len(), 3);
        // A fan over a hexagon becomes quads where it can.
        let hex: Vec<Vertex> = (0..6)
            .map(|i| {
                let a = i as f32 * std::f32::consts::TAU / 6.0;
                v(libm::cosf(a), libm::sinf(a), libm::cosf(a), libm::sinf(a))
            })
            .collect();
        let fan: Vec<[u32; 3]> = (1..5).map(|k| [0, k, k + 1]).collect();
        assert_eq!(merge_pairs(&hex, &fan), vec![vec![0, 1, 2, 3], vec![0, 3, 4, 5]]);
    }
}
