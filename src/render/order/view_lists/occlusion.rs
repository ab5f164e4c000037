//! Building one mesh's stored orders (seed 004): the 'may occlude' relation, the favourite stack and the
//! splits that break cycles, as the parent module's doc describes.

use glam::{Vec2, Vec3, Vec4};

use crate::render::core::draw_list::MeshLists;
use crate::render::core::mesh::{Mesh, MeshBuilder, Vertex};

/// Tolerance of plane-side and overlap tests, relative to the mesh's size.
const EPS_REL: f32 = 1e-4;
/// Splits allowed per list, as a multiple of the mesh's polygons (a bound on pathological meshes).
const MAX_SPLITS_PER_POLYGON: usize = 2;

/// A polygon being ordered: its vertices (position, uv, colour) and material; `source` is the mesh
/// polygon it is or was cut from.
#[derive(Clone, Debug)]
struct Prim {
    verts: Vec<Vertex>,
    material: u32,
    source: usize,
    /// Index of this polygon in the extended mesh once known (originals keep their own index).
    mesh_index: Option<u32>,
}

impl Prim {
    /// The polygon's plane `(unit normal, offset)` by Newell's method, `None` when it has no area.
    fn plane(&self) -> Option<(Vec3, f32)> {
        let k = self.verts.len();
        let mut normal = Vec3::ZERO;
        let mut sum = Vec3::ZERO;
        for i in 0..k {
            let (a, b) = (self.verts[i].position, self.verts[(i + 1) % k].position);
            normal += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
            sum += a;
        }
        let len = normal.length();
        (len > 0.0 && len.is_finite() && k > 0).then(|| {
            let n = normal / len;
            (n, n.dot(sum / k as f32))
        })
    }
}

pub(super) fn build_mesh(mesh: &Mesh, dirs: &[Vec3]) -> Option<MeshLists> {
    let originals: Vec<Prim> = mesh
        .polygons()
        .iter()
        .enumerate()
        .map(|(i, p)| Prim {
            verts: mesh.polygon_indices(p).iter().map(|&k| mesh.vertices()[k as usize]).collect(),
            material: p.material,
            source: i,
            mesh_index: Some(i as u32),
        })
        .collect();
    let size = mesh.bounds().radius.max(1e-6);
    let eps = EPS_REL * size;
    let mut pieces: Vec<Prim> = vec![];
    let mut lists = Vec::with_capacity(dirs.len());
    let (mut splits, mut unbroken) = (0, 0);
    let double: Vec<bool> = mesh.materials().iter().map(|m| m.double_sided).collect();
    for &d in dirs {
        let (order, s, u) = order_for(&originals, &double, d, eps, &mut pieces);
        splits += s;
        unbroken += u;
        lists.push(order);
    }
    // The extended mesh: the original polygons, then every piece.
    let mut b = MeshBuilder::new();
    for m in mesh.materials() {
        b.material(m.clone());
    }
    for v in mesh.vertices() {
        b.vertex(*v);
    }
    for p in mesh.polygons() {
        b.polygon(mesh.polygon_indices(p), p.material);
    }
    for piece in &pieces {
        let idx: Vec<u32> = piece.verts.iter().map(|v| b.vertex(*v)).collect();
        b.polygon(&idx, piece.material);
    }
    let ext = b.keep_polygons_as_given().build().ok()?;
    if ext.polygons().len() != mesh.polygons().len() + pieces.len() {
        return None;
    }
    Some(MeshLists { mesh: ext, directions: dirs.to_vec(), lists, splits, unbroken })
}

/// Projected outline (2D, along `d`) and depth range of a prim.
struct Proj {
    pts: Vec<Vec2>,
    near: f32,
    far: f32,
}

fn project(p: &Prim, d: Vec3, u: Vec3, v: Vec3) -> Proj {
    let mut near = f32::INFINITY;
    let mut far = f32::NEG_INFINITY;
    let pts = p
        .verts
        .iter()
        .map(|x| {
            let z = x.position.dot(d);
            near = near.min(z);
            far = far.max(z);
            Vec2::new(x.position.dot(u), x.position.dot(v))
        })
        .collect();
    Proj { pts, near, far }
}

/// Whether two projected outlines overlap by more than `eps` (separating axes of their edges; concave
/// outlines are treated as their hull, which only adds constraints).
fn overlap(a: &[Vec2], b: &[Vec2], eps: f32) -> bool {
    for poly in [a, b] {
        let n = poly.len();
        for i in 0..n {
            let e = poly[(i + 1) % n] - poly[i];
            let axis = Vec2::new(-e.y, e.x);
            let len = axis.length();
            if len <= 0.0 || !len.is_finite() {
                continue;
            }
            let axis = axis / len;
            let (mut a0, mut a1) = (f32::INFINITY, f32::NEG_INFINITY);
            for p in a {
                let t = p.dot(axis);
                a0 = a0.min(t);
                a1 = a1.max(t);
            }
            let (mut b0, mut b1) = (f32::INFINITY, f32::NEG_INFINITY);
            for p in b {
                let t = p.dot(axis);
                b0 = b0.min(t);
                b1 = b1.max(t);
            }
            if a1 <= b0 + eps || b1 <= a0 + eps {
                return false;
            }
        }
    }
    true
}

/// Signed distances of `p`'s vertices to the plane `(n, c)` oriented towards the viewer (looking along `d`).
fn sides(p: &Prim, plane: Option<(Vec3, f32)>, d: Vec3, eps: f32) -> (bool, bool) {
    let Some((mut n, mut c)) = plane else { return (true, true) };
    if n.dot(d) > 0.0 {
        n = -n;
        c = -c;
    }
    let mut all_front = true;
    let mut all_back = true;
    for v in &p.verts {
        let s = v.position.dot(n) - c;
        all_front &= s >= -eps;
        all_back &= s <= eps;
    }
    (all_front, all_back)
}

/// Whether `front` may be in front of `back` somewhere (so `back` must be drawn first). Coplanar
/// overlapping polygons (decals) keep their order in the mesh: the later one is drawn over the earlier.
fn may_occlude(front: &Prim, fp: &Proj, back: &Prim, bp: &Proj, d: Vec3, eps: f32) -> bool {
    if fp.near >= bp.far - eps {
        return false; // wholly behind it
    }
    if !overlap(&fp.pts, &bp.pts, eps) {
        return false;
    }
    let (back_front_of_front, back_behind_front) = sides(back, front.plane(), d, eps);
    if back_front_of_front && back_behind_front {
        // Coplanar: submission order decides, as in the renderer's other painter's methods.
        return front.source > back.source;
    }
    if back_front_of_front {
        return false;
    }
    let (_, front_behind_back) = sides(front, back.plane(), d, eps);
    !front_behind_back
}

/// Splits `p` by `plane` into the parts on either side, or `None` when the plane does not cut it.
fn split(p: &Prim, plane: Option<(Vec3, f32)>, eps: f32) -> Option<(Prim, Prim)> {
    let (n, c) = plane?;
    let dist: Vec<f32> = p.verts.iter().map(|v| v.position.dot(n) - c).collect();
    if !dist.iter().any(|&s| s > eps) || !dist.iter().any(|&s| s < -eps) {
        return None;
    }
    let (mut a, mut b) = (vec![], vec![]);
    let k = p.verts.len();
    for i in 0..k {
        let (v0, v1) = (p.verts[i], p.verts[(i + 1) % k]);
        let (s0, s1) = (dist[i], dist[(i + 1) % k]);
        if s0 >= 0.0 {
            a.push(v0);
        }
        if s0 <= 0.0 {
            b.push(v0);
        }
        if (s0 > 0.0 && s1 < 0.0) || (s0 < 0.0 && s1 > 0.0) {
            let t = s0 / (s0 - s1);
            let lerp = |x: Vec4, y: Vec4| x + (y - x) * t;
            let m = Vertex {
                position: v0.position + (v1.position - v0.position) * t,
                uv: v0.uv + (v1.uv - v0.uv) * t,
                color: lerp(v0.color, v1.color),
            };
            a.push(m);
            b.push(m);
        }
    }
    (a.len() >= 3 && b.len() >= 3).then(|| {
        let mk = |verts| Prim { verts, material: p.material, source: p.source, mesh_index: None };
        (mk(a), mk(b))
    })
}

/// The last favourite on the stack still waiting to be placed (favourites cut up meanwhile are skipped).
fn next_favourite(stack: &mut Vec<usize>, on_stack: &mut [bool], alive: &[bool], placed: &[bool]) -> Option<usize> {
    while let Some(s) = stack.pop() {
        on_stack[s] = false;
        if alive[s] && !placed[s] {
            return Some(s);
        }
    }
    None
}

// long: the favourite-stack walk of seed 004 is one loop over state (stack, placed, alive, pieces) that every step reads and changes.
/// One direction's list (indices into the extended mesh); new pieces are appended to `pieces`. Returns the
/// list, the splits made and the cycles left unbroken.
fn order_for(
    originals: &[Prim],
    double: &[bool],
    d: Vec3,
    eps: f32,
    pieces: &mut Vec<Prim>,
) -> (Vec<u32>, usize, usize) {
    let helper = if d.y.abs() < 0.9 { Vec3::Y } else { Vec3::X };
    let u = d.cross(helper).normalize();
    let v = u.cross(d);
    let mut prims: Vec<Prim> = originals.to_vec();
    let mut proj: Vec<Proj> = prims.iter().map(|p| project(p, d, u, v)).collect();
    let mut alive: Vec<bool> = vec![true; prims.len()];
    let mut placed: Vec<bool> = vec![false; prims.len()];
    let mut list = vec![];
    // Single-sided polygons facing away from this direction go first and take no part in the sort: seen
    // from near this direction they are culled, and where the view turns far enough to show them they are
    // nearly edge-on. (This halves the polygons compared and removes most false cycles of closed models.)
    for (i, p) in prims.iter().enumerate() {
        let single = !double.get(p.material as usize).copied().unwrap_or(true);
        if single && p.plane().is_some_and(|(n, _)| n.dot(d) > 0.05) {
            placed[i] = true;
            list.push(i);
        }
    }
    let mut on_stack: Vec<bool> = vec![false; prims.len()];
    let mut stack: Vec<usize> = vec![];
    let (mut splits, mut unbroken) = (0, 0);
    let max_splits = originals.len() * MAX_SPLITS_PER_POLYGON;
    let mut remaining = prims.len() - list.len();
    // Unplaced prims, farthest first, for picking fresh favourites.
    let farthest = |proj: &[Proj], alive: &[bool], placed: &[bool]| -> Option<usize> {
        (0..proj.len()).filter(|&i| alive[i] && !placed[i]).max_by(|&a, &b| proj[a].far.total_cmp(&proj[b].far))
    };
    let mut fav = farthest(&proj, &alive, &placed);
    while let Some(f) = fav {
        if remaining == 0 {
            break;
        }
        // A candidate the favourite may occlude prevents it.
        let blocker = (0..prims.len()).find(|&c| {
            c != f && alive[c] && !placed[c] && may_occlude(&prims[f], &proj[f], &prims[c], &proj[c], d, eps)
        });
        match blocker {
            None => {
                placed[f] = true;
                remaining -= 1;
                list.push(f);
                fav = next_favourite(&mut stack, &mut on_stack, &alive, &placed)
                    .or_else(|| farthest(&proj, &alive, &placed));
            }
            Some(c) if !on_stack[c] => {
                stack.push(f);
                on_stack[f] = true;
                fav = Some(c);
            }
            Some(c) => {
                // A cycle: c, the favourites stacked after it, and f, each may occlude the next one
                // (c blocked f). Cut the first polygon of it that another's plane cuts.
                let from = stack.iter().rposition(|&s| s == c).unwrap_or(0);
                let mut ring: Vec<usize> = stack[from..].iter().copied().filter(|&s| alive[s]).collect();
                ring.push(f);
                let cut = if splits < max_splits {
                    ring.iter().enumerate().find_map(|(i, &x)| {
                        let y = ring[(i + 1) % ring.len()];
                        split(&prims[y], prims[x].plane(), eps)
                            .map(|parts| (y, parts))
                            .or_else(|| split(&prims[x], prims[y].plane(), eps).map(|parts| (x, parts)))
                    })
                } else {
                    None
                };
                match cut {
                    Some((victim, (a, b))) => {
                        splits += 1;
                        alive[victim] = false;
                        on_stack[victim] = false;
                        for part in [a, b] {
                            proj.push(project(&part, d, u, v));
                            prims.push(part);
                            alive.push(true);
                            placed.push(false);
                            on_stack.push(false);
                        }
                        remaining += 1;
                        if victim == f {
                            fav = Some(prims.len() - 1);
                        }
                    }
                    None => {
                        // Nothing cuts: draw the favourite now and accept the fault.
                        unbroken += 1;
                        placed[f] = true;
                        remaining -= 1;
                        list.push(f);
                        fav = next_favourite(&mut stack, &mut on_stack, &alive, &placed)
                            .or_else(|| farthest(&proj, &alive, &placed));
                    }
                }
            }
        }
    }
    // Map prims to extended-mesh polygon indices: originals keep theirs, pieces are appended.
    let base = originals.len() as u32;
    let mut out = Vec::with_capacity(list.len());
    for i in list {
        let p = &mut prims[i];
        let index = match p.mesh_index {
            Some(k) => k,
            None => {
                let k = base + pieces.len() as u32;
                pieces.push(p.clone());
                p.mesh_index = Some(k);
                k
            }
        };
        out.push(index);
    }
    (out, splits, unbroken)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::Material;
    use crate::render::core::draw_list::ViewLists;

    fn cube() -> Mesh {
        let mut b = MeshBuilder::new();
        let m = b.material(Material::default());
        for axis in 0..3 {
            for s in [-1.0f32, 1.0] {
                let mut idx = vec![];
                for (a, c) in [(-1.0f32, -1.0f32), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    let mut p = [0.0f32; 3];
                    p[axis] = s;
                    p[(axis + 1) % 3] = a * s;
                    p[(axis + 2) % 3] = c;
                    idx.push(b.vertex(Vertex::new(Vec3::from(p), Vec2::ZERO)));
                }
                b.polygon(&idx, m);
            }
        }
        b.build().unwrap()
    }

    #[test]
    fn a_convex_model_needs_no_splits_and_lists_its_back_faces_first() {
        let vl = ViewLists::build(&[cube()], 1, 100);
        let l = vl.get(0).unwrap();
        assert_eq!((l.splits, l.unbroken, l.mesh.polygons().len()), (0, 0, 6));
        for (d, list) in l.directions.iter().zip(&l.lists) {
            assert_eq!(list.len(), 6);
            // Faces turned away from the direction come before every face turned towards it.
            let facing = |i: u32| {
                let p = &l.mesh.polygons()[i as usize];
                let idx = l.mesh.polygon_indices(p);
                let v = |k: usize| l.mesh.vertices()[idx[k] as usize].position;
                (v(1) - v(0)).cross(v(2) - v(0)).dot(*d) < -0.05
            };
            let first_front = list.iter().position(|&i| facing(i)).unwrap();
            assert!(list[first_front..].iter().all(|&i| facing(i) || (l.mesh.polygons().len() == 6)), "{list:?}");
            assert!(list[..first_front].iter().all(|&i| !facing(i)));
        }
    }

    #[test]
    fn two_crossing_quads_are_split_into_an_order_that_exists() {
        // Two quads crossing like an X seen from above: each is in front of the other somewhere.
        let mut b = MeshBuilder::new();
        let m = b.material(Material { double_sided: true, ..Material::default() });
        let quad = |b: &mut MeshBuilder, pts: [Vec3; 4]| {
            let idx: Vec<u32> = pts.iter().map(|&p| b.vertex(Vertex::new(p, Vec2::ZERO))).collect();
            b.polygon(&idx, m);
        };
        quad(
            &mut b,
            [
                Vec3::new(-1.0, -1.0, -1.0),
                Vec3::new(1.0, -1.0, 1.0),
                Vec3::new(1.0, 1.0, 1.0),
                Vec3::new(-1.0, 1.0, -1.0),
            ],
        );
        quad(
            &mut b,
            [
                Vec3::new(-1.0, -1.0, 1.0),
                Vec3::new(1.0, -1.0, -1.0),
                Vec3::new(1.0, 1.0, -1.0),
                Vec3::new(-1.0, 1.0, 1.0),
            ],
        );
        let mesh = b.build().unwrap();
        let l = build_mesh(&mesh, &[Vec3::new(0.0, 0.0, -1.0)]).unwrap();
        assert!(l.splits >= 1 && l.unbroken == 0, "{} splits, {} unbroken", l.splits, l.unbroken);
        assert_eq!(l.lists[0].len(), 2 + l.splits);
    }
}
