//! The ground: grass tiles around the circuit and the ring of distant hills.
//!
//! On the plain the ground near the track is flat (y = 0) and its finer tiles overlap the coarse ones. On a
//! course in the hills the heights come from the relief's [`Field`], and the finer tiles near the track meet
//! the coarse tiles edge to edge: a fine vertex on the border with a coarse tile lies on the coarse tile's
//! edge, so no crack opens between them however the ground curves.

use glam::{Vec2, Vec3};

use super::circuit::Circuit;
use super::mesh::{MeshBuilder, Scene, world_uvs};
use super::relief::Field;
use super::spec::{FINE_TILE, GRASS_UV, GROUND_RADIUS, TILE, WHITE};
use super::textures::Mats;
use super::util::{Rng, smoothstep};

/// Fine tiles along a coarse tile's side.
const SPLIT: usize = (TILE / FINE_TILE) as usize;

/// Ground heights on a square grid of `TILE` m: flat near the circuit, rolling further out, rising toward
/// the hills. Each tile is drawn as two triangles split from its (-x, -z) corner to its (+x, +z) corner.
pub(super) struct Terrain {
    origin: Vec2,
    n: usize,
    heights: Vec<f32>,
    pub(super) centre: Vec2,
    /// The relief's heights, on a course in the hills.
    field: Option<Field>,
    /// Which coarse tiles are drawn as fine tiles (in the hills; on the plain the tiles decide as drawn).
    split: Vec<bool>,
}

impl Terrain {
    pub(super) fn new(c: &Circuit) -> Terrain {
        let Some(relief) = c.layout.relief else { return Self::plain(c) };
        let field = Field::new(c, relief);
        let (lo, hi) = c.bounds();
        let centre = ((lo + hi) * 0.5 / TILE).round() * TILE;
        let n = (2.0 * (GROUND_RADIUS / TILE).ceil()) as usize + 2;
        let origin = centre - Vec2::splat(n as f32 * TILE / 2.0);
        let corner = |i: usize, j: usize| origin + Vec2::new(i as f32, j as f32) * TILE;
        let heights = (0..=n).flat_map(|j| (0..=n).map(move |i| (i, j))).map(|(i, j)| field.height(corner(i, j)));
        let heights = heights.collect();
        let split = (0..n * n).map(|k| c.touches(corner(k % n, k / n), corner(k % n + 1, k / n + 1))).collect();
        Terrain { origin, n, heights, centre, field: Some(field), split }
    }

    /// The ground of a course on the plain.
    fn plain(c: &Circuit) -> Terrain {
        let (lo, hi) = c.bounds();
        let centre = ((lo + hi) * 0.5 / TILE).round() * TILE;
        let n = (2.0 * (GROUND_RADIUS / TILE).ceil()) as usize + 2;
        let origin = centre - Vec2::splat(n as f32 * TILE / 2.0);
        let coarse: Vec<Vec2> = c.samples.iter().step_by(2).map(|s| Vec2::new(s.p.x, s.p.z)).collect();
        let mut heights = Vec::with_capacity((n + 1) * (n + 1));
        for j in 0..=n {
            for i in 0..=n {
                let p = origin + Vec2::new(i as f32, j as f32) * TILE;
                let d = coarse.iter().map(|q| q.distance_squared(p)).fold(f32::INFINITY, f32::min).sqrt();
                let away = smoothstep(260.0, 700.0, d);
                let roll = 7.0 + 6.0 * libm::sinf(p.x / 170.0 + 1.0) * libm::cosf(p.y / 210.0);
                let rise = 30.0 * smoothstep(1300.0, 2100.0, p.distance(centre));
                heights.push(away * (roll + rise));
            }
        }
        Terrain { origin, n, heights, centre, field: None, split: vec![] }
    }

    /// Whether coarse tile (`i`, `j`) is drawn as fine tiles (false outside the grid).
    fn is_split(&self, i: Option<usize>, j: Option<usize>) -> bool {
        match (i, j) {
            (Some(i), Some(j)) if i < self.n && j < self.n => self.split.get(j * self.n + i) == Some(&true),
            _ => false,
        }
    }

    /// The height of vertex (`fi`, `fj`) of the fine tiles of coarse tile (`i`, `j`): on a side shared with
    /// a coarse tile, on that tile's edge; elsewhere the relief's height.
    fn fine_height(&self, (i, j): (usize, usize), (fi, fj): (usize, usize)) -> f32 {
        let h = |a: usize, b: usize| self.heights[b * (self.n + 1) + a];
        let (u, v) = (fi as f32 / SPLIT as f32, fj as f32 / SPLIT as f32);
        if fi == 0 && !self.is_split(i.checked_sub(1), Some(j)) {
            return h(i, j) + (h(i, j + 1) - h(i, j)) * v;
        }
        if fi == SPLIT && !self.is_split(Some(i + 1), Some(j)) {
            return h(i + 1, j) + (h(i + 1, j + 1) - h(i + 1, j)) * v;
        }
        if fj == 0 && !self.is_split(Some(i), j.checked_sub(1)) {
            return h(i, j) + (h(i + 1, j) - h(i, j)) * u;
        }
        if fj == SPLIT && !self.is_split(Some(i), Some(j + 1)) {
            return h(i, j + 1) + (h(i + 1, j + 1) - h(i, j + 1)) * u;
        }
        let p =
            self.origin + Vec2::new(i as f32 * TILE + fi as f32 * FINE_TILE, j as f32 * TILE + fj as f32 * FINE_TILE);
        self.field.as_ref().map_or(0.0, |f| f.height(p))
    }

    /// The level of the ground beside the road at `p`: the plain's 0, or in the hills the ground as drawn
    /// (so that the strips beside the road meet the tiles they overlap without a crack).
    pub(super) fn apron_level(&self, p: Vec2) -> f32 {
        if self.field.is_some() { self.height(p) } else { 0.0 }
    }

    fn vertex(&self, i: usize, j: usize) -> Vec3 {
        let p = self.origin + Vec2::new(i as f32, j as f32) * TILE;
        Vec3::new(p.x, self.heights[j * (self.n + 1) + i], p.y)
    }

    /// Ground height at (x, z), as drawn.
    pub(super) fn height(&self, p: Vec2) -> f32 {
        let g = (p - self.origin) / TILE;
        let (i, j) = (g.x.floor().clamp(0.0, self.n as f32 - 1.0), g.y.floor().clamp(0.0, self.n as f32 - 1.0));
        let (fx, fz) = ((g.x - i).clamp(0.0, 1.0), (g.y - j).clamp(0.0, 1.0));
        let (i, j) = (i as usize, j as usize);
        if self.is_split(Some(i), Some(j)) {
            let k = SPLIT as f32;
            let (fi, fj) = ((fx * k).floor().min(k - 1.0), (fz * k).floor().min(k - 1.0));
            let (u, v) = (fx * k - fi, fz * k - fj);
            let (fi, fj) = (fi as usize, fj as usize);
            let h = |a: usize, b: usize| self.fine_height((i, j), (a, b));
            let (a, b, cc, d) = (h(fi, fj), h(fi + 1, fj), h(fi + 1, fj + 1), h(fi, fj + 1));
            return if v >= u { a + v * (d - a) + u * (cc - d) } else { a + u * (b - a) + v * (cc - b) };
        }
        let a = self.vertex(i, j).y;
        let b = self.vertex(i + 1, j).y;
        let cc = self.vertex(i + 1, j + 1).y;
        let d = self.vertex(i, j + 1).y;
        if fz >= fx { a + fz * (d - a) + fx * (cc - d) } else { a + fx * (b - a) + fz * (cc - b) }
    }
}

/// Grass tiles in blocks of 8 x 8 (one mesh each), within the ground radius. Tiles near the track are split
/// into finer tiles and those reaching into the track's corridor are left out (the aprons cover the rest), so
/// no ground lies under the road. On the plain the finer tiles overlap their neighbours by 1 m so that no
/// crack opens where their corners meet the coarse tiles' edges; in the hills they meet them edge to edge.
pub(super) fn ground_meshes(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain) {
    for bj in (0..t.n).step_by(8) {
        for bi in (0..t.n).step_by(8) {
            let mut mb = MeshBuilder::default();
            for j in bj..(bj + 8).min(t.n) {
                for i in bi..(bi + 8).min(t.n) {
                    let corners = [t.vertex(i, j), t.vertex(i + 1, j), t.vertex(i + 1, j + 1), t.vertex(i, j + 1)];
                    let (lo, hi) = (Vec2::new(corners[0].x, corners[0].z), Vec2::new(corners[2].x, corners[2].z));
                    if ((lo + hi) * 0.5).distance(t.centre) > GROUND_RADIUS {
                        continue;
                    }
                    if t.field.is_some() {
                        relief_tile(&mut mb, (m, c, t), (i, j), corners);
                    } else {
                        plain_tile(&mut mb, (m, c, t), corners);
                    }
                }
            }
            scene.add(&format!("ground {:02} {:02}", bj / 8, bi / 8), &mb);
        }
    }
}

/// One coarse tile on the plain: whole, or as the finer tiles clear of the track's corridor.
fn plain_tile(mb: &mut MeshBuilder, (m, c, t): (&Mats, &Circuit, &Terrain), [a, b, cc, d]: [Vec3; 4]) {
    let (lo, hi) = (Vec2::new(a.x, a.z), Vec2::new(cc.x, cc.z));
    if !c.touches(lo, hi) {
        // Counter-clockwise from above, fanned from `a` (the split the height function assumes).
        let pts = [a, d, cc, b];
        mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
        return;
    }
    for fj in 0..SPLIT {
        for fi in 0..SPLIT {
            let f0 = lo + Vec2::new(fi as f32, fj as f32) * FINE_TILE - Vec2::ONE;
            let f1 = f0 + Vec2::splat(FINE_TILE + 2.0);
            if c.touches(f0, f1) {
                continue;
            }
            let at = |x: f32, z: f32| Vec3::new(x, t.height(Vec2::new(x, z)), z);
            let pts = [at(f0.x, f0.y), at(f0.x, f1.y), at(f1.x, f1.y), at(f1.x, f0.y)];
            mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
        }
    }
}

/// One coarse tile in the hills: whole away from the track, or as the finer tiles clear of its corridor,
/// their vertices on the relief (on a coarse neighbour's edge where they meet one).
fn relief_tile(
    mb: &mut MeshBuilder,
    (m, c, t): (&Mats, &Circuit, &Terrain),
    (i, j): (usize, usize),
    corners: [Vec3; 4],
) {
    let [a, b, cc, d] = corners;
    if !t.is_split(Some(i), Some(j)) {
        let pts = [a, d, cc, b];
        mb.face(cover(m, &pts), &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
        return;
    }
    let lo = Vec2::new(a.x, a.z);
    for fj in 0..SPLIT {
        for fi in 0..SPLIT {
            let f0 = lo + Vec2::new(fi as f32, fj as f32) * FINE_TILE;
            let f1 = f0 + Vec2::splat(FINE_TILE);
            if c.touches(f0 - Vec2::ONE, f1 + Vec2::ONE) {
                continue;
            }
            let at = |x: f32, z: f32, k: (usize, usize)| Vec3::new(x, t.fine_height((i, j), k), z);
            let pts = [
                at(f0.x, f0.y, (fi, fj)),
                at(f0.x, f1.y, (fi, fj + 1)),
                at(f1.x, f1.y, (fi + 1, fj + 1)),
                at(f1.x, f0.y, (fi + 1, fj)),
            ];
            mb.face(cover(m, &pts), &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
        }
    }
}

/// What covers a piece of ground in the hills: rock where it is steep (a slope of more than about 40
/// degrees) or high (above 230 m), grass elsewhere.
fn cover(m: &Mats, pts: &[Vec3]) -> usize {
    let (a, b, c) = (pts[0], pts[1], pts[2]);
    let n = (b - a).cross(c - a).normalize_or_zero();
    let high = pts.iter().map(|p| p.y).sum::<f32>() / pts.len() as f32 > 230.0;
    if n.y.abs() < 0.75 || high { m.rock } else { m.grass }
}

/// A ring of low, coarse hills beyond the ground's edge, in four meshes.
pub(super) fn hills_meshes(scene: &mut Scene, m: &Mats, t: &Terrain) {
    const K: usize = 48;
    let mut rng = Rng::new(0x0000_4111_5eed);
    let ridge: Vec<(f32, f32)> = (0..K).map(|_| (rng.range(2280.0, 2420.0), rng.range(110.0, 250.0))).collect();
    let ring = |k: usize, r: f32| {
        let a = (k % K) as f32 / K as f32 * std::f32::consts::TAU;
        t.centre + Vec2::new(libm::cosf(a), libm::sinf(a)) * r
    };
    let at = |p: Vec2, y: f32| Vec3::new(p.x, y, p.y);
    let green = Vec3::new(0.34, 0.50, 0.30);
    let slope = Vec3::new(0.40, 0.52, 0.44);
    let far = Vec3::new(0.50, 0.58, 0.66);
    for q in 0..4 {
        let mut mb = MeshBuilder::default();
        for k in q * K / 4..(q + 1) * K / 4 {
            let k1 = (k + 1) % K;
            let (r0, h0) = ridge[k];
            let (r1, h1) = ridge[k1];
            let foot = |k: usize| {
                let p = ring(k, 1990.0);
                at(p, t.height(p) - 3.0)
            };
            let (f0, f1) = (foot(k), foot(k1));
            let (m0, m1) =
                (at(ring(k, 2150.0), f0.y + 0.45 * (h0 - f0.y)), at(ring(k1, 2150.0), f1.y + 0.45 * (h1 - f1.y)));
            let (t0, t1) = (at(ring(k, r0), h0), at(ring(k1, r1), h1));
            let (b0, b1) = (at(ring(k, 2750.0), 0.0), at(ring(k1, 2750.0), 0.0));
            let inward = at(t.centre - ring(k, 1.0), 0.0).normalize_or_zero() + Vec3::Y;
            let z = [Vec2::ZERO; 3];
            for (tri, tint) in
                [([f0, f1, m1], green), ([f0, m1, m0], green), ([m0, m1, t1], slope), ([m0, t1, t0], slope)]
            {
                mb.face(m.hills, &tri, &z, inward, tint);
            }
            for (tri, tint) in [([t0, t1, b1], far), ([t0, b1, b0], far)] {
                mb.face(m.hills, &tri, &z, Vec3::Y - inward, tint);
            }
        }
        scene.add(&format!("hills {q}"), &mb);
    }
}
