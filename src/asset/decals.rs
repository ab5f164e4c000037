//! Decals: primitives lying exactly in the plane of an earlier primitive of the same mesh, over it (road
//! markings on a road, a number plate on a door). A z-buffer cannot order such polygons (their depths are
//! equal up to rounding, so they fight); painter's methods draw them after the surface, in submission
//! order. Found here once at load time, each decal's material gets a depth bias of one more than the
//! surface it lies on, and the z-buffer then draws it on top too.
//!
//! Coplanar means: unit normals within about 0.25° and plane offsets within 1e-4 of the mesh's size
//! (planes are bucketed by those quantized values, and neighbouring offset buckets are searched too).
//! Over means the two polygons' outlines, projected onto that plane, overlap by more than that tolerance
//! (separating axes on their convex hulls).
//!
//! The search visits pairs of polygons in one plane bucket, which is quadratic in a flat mesh; its work
//! is bounded by one budget of pairs visited (every candidate looked at is charged, whether or not its
//! material can be under the polygon) for the whole load ([`crate::asset::LoadBudget::decal_pairs`], 4 Mi by
//! default, about a third of a second), shared by all meshes in load order, so a file of many flat meshes
//! costs no more than one. A material stops being searched once it has the highest bias it can get, so an
//! honest decal layer costs a few pairs. Past the budget, decals are left unmarked (they fight in the
//! z-buffer; painter's methods still draw them in order).

use std::collections::BTreeMap;

use glam::{Vec2, Vec3};

use crate::render::Mesh;

/// Sets [`crate::render::Material::depth_bias`] on every material of `mesh` whose polygons lie on and over
/// polygons of an earlier material; returns how many materials were marked.
///
/// `pairs_left` is the work budget, in polygon pairs compared, that this call takes from: the loader
/// passes one budget shared by all the meshes of a load ([`crate::asset::LoadBudget::decal_pairs`]), so
/// the time spent grows with the budget, not with the number of meshes. When it runs out, the rest of the
/// mesh (and any later mesh) is left unmarked: its decals fight in the z-buffer, nothing else changes.
pub fn mark_decals(mesh: &mut Mesh, pairs_left: &mut u64) -> usize {
    if *pairs_left == 0 {
        return 0;
    }
    let size = mesh.bounds().radius.max(1e-6);
    let tol = 1e-4 * size;
    let polys = mesh.polygons();
    let mut planes: Vec<Option<(Vec3, f32)>> = Vec::with_capacity(polys.len());
    let mut buckets: BTreeMap<(i32, i32, i32, i64), Vec<usize>> = BTreeMap::new();
    for (i, p) in polys.iter().enumerate() {
        let pts: Vec<Vec3> = mesh.polygon_indices(p).iter().map(|&k| mesh.vertices()[k as usize].position).collect();
        let plane = plane_of(&pts);
        if let Some((n, d)) = plane {
            buckets.entry(key(n, d, tol)).or_default().push(i);
        }
        planes.push(plane);
    }
    let materials = mesh.materials().len();
    let mut bias = vec![0u8; materials];
    // Materials in order, so a surface's own bias is final before the decals on it are set.
    let mut by_material: Vec<Vec<usize>> = vec![vec![]; materials];
    for (i, p) in polys.iter().enumerate() {
        if let Some(v) = by_material.get_mut(p.material as usize) {
            v.push(i);
        }
    }
    // The highest bias of the materials before `m`: `m` can get at most one more, and once it has that, the
    // rest of its polygons cannot change anything.
    let mut below = 0u8;
    // The first material lies on nothing earlier: it is never searched.
    for (m, members) in by_material.iter().enumerate().skip(1) {
        let ceiling = below.saturating_add(1);
        'poly: for &i in members {
            if bias[m] >= ceiling {
                break;
            }
            let Some((n, d)) = planes[i] else { continue };
            let (kx, ky, kz, kd) = key(n, d, tol);
            for dd in [kd.saturating_sub(1), kd, kd.saturating_add(1)] {
                let Some(cands) = buckets.get(&(kx, ky, kz, dd)) else { continue };
                for &j in cands {
                    // Every candidate visited is charged, the ones the filter below skips too: a bucket of
                    // one material's polygons would otherwise be walked for free, once per polygon.
                    if *pairs_left == 0 {
                        break 'poly;
                    }
                    *pairs_left -= 1;
                    let under = polys[j].material as usize;
                    if under >= m || bias[under] < bias[m] {
                        continue;
                    }
                    if overlap_in_plane(mesh, i, j, n, tol) {
                        bias[m] = bias[m].max(bias[under].saturating_add(1));
                    }
                }
            }
        }
        below = below.max(bias[m]);
    }
    let mut marked = 0;
    for (mat, b) in mesh.materials_mut().iter_mut().zip(bias) {
        if b > 0 {
            mat.depth_bias = b;
            marked += 1;
        }
    }
    marked
}

/// The plane `(unit normal, offset)` of a polygon by Newell's method, the normal's sign made canonical
/// (first non-zero component positive) so both windings of one plane share a key.
fn plane_of(pts: &[Vec3]) -> Option<(Vec3, f32)> {
    let k = pts.len();
    let mut normal = Vec3::ZERO;
    let mut sum = Vec3::ZERO;
    for i in 0..k {
        let (a, b) = (pts[i], pts[(i + 1) % k]);
        normal += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        sum += a;
    }
    let len = normal.length();
    if !(len > 0.0 && len.is_finite()) || k == 0 {
        return None;
    }
    let mut n = normal / len;
    let first = if n.x.abs() > 1e-6 {
        n.x
    } else if n.y.abs() > 1e-6 {
        n.y
    } else {
        n.z
    };
    if first < 0.0 {
        n = -n;
    }
    Some((n, n.dot(sum / k as f32)))
}

fn key(n: Vec3, d: f32, tol: f32) -> (i32, i32, i32, i64) {
    let q = |x: f32| (x * 256.0).round() as i32;
    (q(n.x), q(n.y), q(n.z), (d / (10.0 * tol)).round() as i64)
}

/// Whether polygons `a` and `b` of `mesh`, both in the plane with normal `n`, overlap there.
fn overlap_in_plane(mesh: &Mesh, a: usize, b: usize, n: Vec3, tol: f32) -> bool {
    let helper = if n.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let u = n.cross(helper).normalize();
    let v = n.cross(u);
    let outline = |i: usize| -> Vec<Vec2> {
        let p = &mesh.polygons()[i];
        mesh.polygon_indices(p)
            .iter()
            .map(|&k| {
                let x = mesh.vertices()[k as usize].position;
                Vec2::new(x.dot(u), x.dot(v))
            })
            .collect()
    };
    let (pa, pb) = (outline(a), outline(b));
    for poly in [&pa, &pb] {
        for i in 0..poly.len() {
            let e = poly[(i + 1) % poly.len()] - poly[i];
            let axis = Vec2::new(-e.y, e.x).normalize_or_zero();
            if axis == Vec2::ZERO {
                continue;
            }
            let range = |pts: &[Vec2]| {
                pts.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), p| {
                    let t = p.dot(axis);
                    (lo.min(t), hi.max(t))
                })
            };
            let ((a0, a1), (b0, b1)) = (range(&pa), range(&pb));
            if a1 <= b0 + tol || b1 <= a0 + tol {
                return false;
            }
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{Material, MeshBuilder, Vertex};

    fn quad(b: &mut MeshBuilder, m: u32, x0: f32, x1: f32, y: f32) {
        let idx: Vec<u32> = [(x0, 0.0), (x1, 0.0), (x1, 1.0), (x0, 1.0)]
            .iter()
            .map(|&(x, z)| b.vertex(Vertex::new(Vec3::new(x, y, -z), Vec2::ZERO)))
            .collect();
        b.polygon(&idx, m);
    }

    #[test]
    fn coplanar_overlapping_later_primitives_are_decals_and_others_are_not() {
        let mut b = MeshBuilder::new();
        let road = b.material(Material::default());
        let marking = b.material(Material::default());
        let on_marking = b.material(Material::default());
        let lifted = b.material(Material::default());
        let beside = b.material(Material::default());
        quad(&mut b, road, 0.0, 10.0, 0.0);
        quad(&mut b, marking, 4.0, 5.0, 0.0);
        quad(&mut b, on_marking, 4.2, 4.8, 0.0);
        quad(&mut b, lifted, 2.0, 3.0, 0.5);
        quad(&mut b, beside, 10.0, 12.0, 0.0); // touches the road's edge only
        let mut mesh = b.build().unwrap();
        let mut pairs = 1000;
        assert_eq!(mark_decals(&mut mesh, &mut pairs), 2);
        assert!(pairs < 1000, "the pairs compared are taken from the budget");
        let biases: Vec<u8> = mesh.materials().iter().map(|m| m.depth_bias).collect();
        assert_eq!(biases, [0, 1, 2, 0, 0]);
    }

    #[test]
    fn a_tiny_mesh_far_away_does_not_overflow_the_plane_key() {
        // Offset / tolerance is past i64: the key saturates, and its neighbours must too.
        let mut b = MeshBuilder::new();
        let under = b.material(Material::default());
        let over = b.material(Material::default());
        quad(&mut b, under, 0.0, 1e-3, 1e20);
        quad(&mut b, over, 0.0, 1e-3, 1e20);
        let mut mesh = b.build().unwrap();
        let mut pairs = 100;
        assert_eq!(mark_decals(&mut mesh, &mut pairs), 1);
    }

    #[test]
    fn candidates_the_filter_skips_are_charged_too() {
        // One surface, then 600 side-by-side tiles of a second material in its plane but beside it: each
        // tile's bucket holds 600 candidates of its own material, which the filter skips. Uncharged, that
        // is 360,000 free visits (a flat mesh of a million quads would be 10^12); charged, the budget of
        // 1,000 runs out and the search stops.
        let mut b = MeshBuilder::new();
        let ground = b.material(Material::default());
        let tiles = b.material(Material::default());
        quad(&mut b, ground, -10.0, -9.0, 0.0);
        for k in 0..600 {
            quad(&mut b, tiles, k as f32, k as f32 + 1.0, 0.0);
        }
        let mut mesh = b.build().unwrap();
        let mut pairs = 1000;
        assert_eq!(mark_decals(&mut mesh, &mut pairs), 0);
        assert_eq!(pairs, 0, "every candidate visited is charged");
        // The first material is never searched: a flat one-material mesh costs nothing.
        let mut b = MeshBuilder::new();
        let only = b.material(Material::default());
        for k in 0..600 {
            quad(&mut b, only, k as f32, k as f32 + 1.0, 0.0);
        }
        let mut mesh = b.build().unwrap();
        let mut pairs = 1000;
        assert_eq!(mark_decals(&mut mesh, &mut pairs), 0);
        assert_eq!(pairs, 1000);
    }
}
