//! Mesh building: polygons with baked light ([`MeshBuilder`]), boxes, and the [`Scene`] being written.

use glam::{Vec2, Vec3};
use serde_json::json;

use super::spec::SUN;
use super::util::Rng;
use crate::gltf_out::{Doc, Primitive};

pub(super) fn uv(u: f32, v: f32) -> Vec2 {
    Vec2::new(u, v)
}

/// Texture coordinates from world x and z (for ground-like surfaces).
pub(super) fn world_uvs(pts: &[Vec3], metres: f32) -> Vec<Vec2> {
    pts.iter().map(|p| Vec2::new(p.x / metres, p.z / metres)).collect()
}

/// The yaw to give [`placed`] so that a node's local -Z points along `d` (glTF rotation about +Y).
///
/// [`placed`]: crate::gltf_out::placed
pub(super) fn node_yaw(d: Vec3) -> f32 {
    libm::atan2f(-d.x, -d.z)
}

/// Newell's normal of a polygon (counter-clockwise gives the right-hand normal).
fn newell(pts: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for (i, a) in pts.iter().enumerate() {
        let b = pts[(i + 1) % pts.len()];
        n += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    n
}

/// Baked light for a unit normal.
fn light(n: Vec3) -> f32 {
    (0.6 + 0.4 * n.dot(SUN.normalize()).max(0.0)).min(1.0)
}

/// Primitives of one mesh, one per material, filled polygon by polygon.
#[derive(Default)]
pub(super) struct MeshBuilder {
    pub(super) prims: Vec<Primitive>,
}

impl MeshBuilder {
    fn prim(&mut self, mat: usize) -> &mut Primitive {
        let i = match self.prims.iter().position(|p| p.material == mat) {
            Some(i) => i,
            None => {
                self.prims.push(Primitive::new(mat));
                self.prims.len() - 1
            }
        };
        &mut self.prims[i]
    }

    /// Adds a planar convex polygon facing `want` (its order is reversed if it winds the other way), with a
    /// vertex colour of `tint` times the baked light.
    pub(super) fn face(&mut self, mat: usize, pts: &[Vec3], uvs: &[Vec2], want: Vec3, tint: Vec3) {
        let n = newell(pts);
        if n.length_squared() < 1e-10 || pts.len() != uvs.len() {
            return;
        }
        let flip = n.dot(want) < 0.0;
        let n = if flip { -n } else { n }.normalize();
        let color = (tint * light(n)).extend(1.0);
        let p = self.prim(mat);
        let base = p.positions.len() as u32;
        if flip {
            p.positions.extend(pts.iter().rev());
            p.uvs.extend(uvs.iter().rev());
        } else {
            p.positions.extend_from_slice(pts);
            p.uvs.extend_from_slice(uvs);
        }
        p.colors.extend(std::iter::repeat_n(color, pts.len()));
        for k in 1..pts.len() as u32 - 1 {
            p.indices.extend_from_slice(&[base, base + k, base + k + 1]);
        }
    }

    /// Adds a box standing on `b.base` (sides, and the top when `top` is given), texture repeating every
    /// `tex` metres.
    pub(super) fn cuboid(&mut self, side: usize, top: Option<usize>, b: &Block, tex: f32, tint: Vec3) {
        let corner = |sx: f32, sz: f32| b.base + b.ax * (b.half.x * sx) + b.az * (b.half.y * sz);
        let c = [corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)];
        let up = Vec3::Y * b.height;
        for k in 0..4 {
            let (p, q) = (c[k], c[(k + 1) % 4]);
            let w = p.distance(q) / tex;
            let h = b.height / tex;
            let out = (p + q) * 0.5 - b.base;
            self.face(side, &[p, q, q + up, p + up], &[uv(0.0, h), uv(w, h), uv(w, 0.0), uv(0.0, 0.0)], out, tint);
        }
        if let Some(t) = top {
            let (u, v) = (b.half.x / tex, b.half.y / tex);
            let pts = c.map(|p| p + up);
            self.face(t, &pts, &[uv(-u, -v), uv(u, -v), uv(u, v), uv(-u, v)], Vec3::Y, tint);
        }
    }

    fn triangles(&self) -> usize {
        self.prims.iter().map(|p| p.indices.len() / 3).sum()
    }
}

/// A box: base centre (bottom), two horizontal unit axes, half extents along them, height.
pub(super) struct Block {
    pub(super) base: Vec3,
    pub(super) ax: Vec3,
    pub(super) az: Vec3,
    pub(super) half: Vec2,
    pub(super) height: f32,
}

/// The document being built, the PRNG for placement, and footprints that trees must avoid.
pub(super) struct Scene {
    pub(super) doc: Doc,
    pub(super) rng: Rng,
    /// (centre, radius) on the plan (x, z).
    pub(super) keep_out: Vec<(Vec2, f32)>,
}

impl Scene {
    /// Adds `mb` as a mesh placed by a root node at the origin (nothing when it is empty).
    pub(super) fn add(&mut self, name: &str, mb: &MeshBuilder) {
        if mb.triangles() > 0 {
            let mesh = self.doc.mesh(name, &mb.prims);
            self.doc.node(json!({"name": name, "mesh": mesh}), true);
        }
    }
}
