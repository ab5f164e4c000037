//! The ground of a course in the hills ([`Field`]): level with the road beside it, rising to peaks and
//! falling into a gorge away from it; and the piers that carry the viaduct across the gorge.
//!
//! Near the road the ground is a distance-weighted mean of the road's own level (Shepard's weights, the
//! fourth power of the inverse distance, over the samples within reach), so the verges are level with the
//! road, two legs of a climb at different heights are joined by a smooth slope, and no leg's level bleeds
//! into the ground beside another. Beyond [`NEAR`] it blends into the far field (the plain, the peaks and the
//! gorge), reaching it at [`FAR`]. Under the viaduct's open span the ground is kept a few metres below the
//! deck, so the span always stands clear of it. Boulders (three models each) lie on the slopes near the road.

use glam::{Vec2, Vec3};
use serde_json::json;

use super::circuit::Circuit;
use super::mesh::{Block, MeshBuilder, Scene};
use super::spec::{DECK_DEPTH, Relief, WHITE};
use super::textures::Mats;
use super::util::{r3, smoothstep};
use crate::gltf_out::{Doc, placed};

/// Side of the buckets the road samples are sorted into (m).
const CELL: f32 = 50.0;
/// Within this plan distance of the centreline the ground is the road's level.
const NEAR: f32 = 12.0;
/// From this plan distance on, the ground is the far field alone.
const FAR: f32 = 110.0;
/// The least clearance under the viaduct's deck (m).
const CLEARANCE: f32 = 3.0;
/// Spacing of the viaduct's piers along the road (m).
const PIER_STEP: f32 = 36.0;

/// The ground's height anywhere on the plan of a course in the hills.
pub(super) struct Field {
    relief: &'static Relief,
    origin: Vec2,
    cols: usize,
    rows: usize,
    /// The road samples on the ground (plan position, ground level under the road), by bucket.
    buckets: Vec<Vec<(Vec2, f32)>>,
    /// The viaduct's open samples (plan position, underside of the deck).
    deck: Vec<(Vec2, f32)>,
}

impl Field {
    /// The ground around circuit `c`, shaped by `relief`.
    pub(super) fn new(c: &Circuit, relief: &'static Relief) -> Field {
        let (lo, hi) = c.bounds();
        let origin = lo - Vec2::splat(FAR + CELL);
        let cols = ((hi.x - origin.x + FAR + CELL) / CELL).ceil() as usize + 1;
        let rows = ((hi.y - origin.y + FAR + CELL) / CELL).ceil() as usize + 1;
        let mut buckets = vec![vec![]; cols * rows];
        let mut deck = vec![];
        for (i, s) in c.samples.iter().enumerate() {
            let q = Vec2::new(s.p.x, s.p.z);
            if c.in_viaduct(i) {
                deck.push((q, s.p.y - DECK_DEPTH));
            } else if c.on_ground(i) {
                let g = ((q - origin) / CELL).floor();
                buckets[g.y as usize * cols + g.x as usize].push((q, s.base));
            }
        }
        Field { relief, origin, cols, rows, buckets, deck }
    }

    /// The far field at `p`: the plain at 0 m, the peaks, and the gorge cut into them.
    fn far(&self, p: Vec2) -> f32 {
        let peaks: f32 = self
            .relief
            .peaks
            .iter()
            .map(|&(x, z, h, r)| h * libm::expf(-p.distance_squared(Vec2::new(x, z)) / (2.0 * r * r)))
            .sum();
        let ((x0, z0), (x1, z1), depth, half) = self.relief.gorge;
        let (a, b) = (Vec2::new(x0, z0), Vec2::new(x1, z1));
        let t = ((p - a).dot(b - a) / (b - a).length_squared().max(1e-6)).clamp(0.0, 1.0);
        let across = p.distance(a + (b - a) * t);
        let cut = depth * libm::sinf(std::f32::consts::PI * t) * (1.0 - smoothstep(0.0, half, across));
        peaks - cut
    }

    /// The road's level near `p` (Shepard's mean over the samples within [`FAR`]) and the plan distance to
    /// the nearest of them (infinite when none is within reach).
    fn road_level(&self, p: Vec2) -> (f32, f32) {
        let g = ((p - self.origin) / CELL).floor();
        let reach = (FAR / CELL).ceil() as i64 + 1;
        let (mut sum, mut weights, mut nearest) = (0.0f64, 0.0f64, f32::INFINITY);
        for row in (g.y as i64 - reach)..=(g.y as i64 + reach) {
            for col in (g.x as i64 - reach)..=(g.x as i64 + reach) {
                if row < 0 || col < 0 || row >= self.rows as i64 || col >= self.cols as i64 {
                    continue;
                }
                for &(q, level) in &self.buckets[row as usize * self.cols + col as usize] {
                    let d2 = f64::from(q.distance_squared(p));
                    nearest = nearest.min(d2 as f32);
                    let w = 1.0 / ((d2 + 4.0) * (d2 + 4.0));
                    sum += w * f64::from(level);
                    weights += w;
                }
            }
        }
        if weights > 0.0 { ((sum / weights) as f32, nearest.sqrt()) } else { (0.0, f32::INFINITY) }
    }

    /// The ground's height at `p` (x, z).
    pub(super) fn height(&self, p: Vec2) -> f32 {
        let (road, d) = self.road_level(p);
        let far = self.far(p);
        let ground = road + (far - road) * smoothstep(NEAR, FAR, d);
        self.deck
            .iter()
            .map(|&(q, under)| under - CLEARANCE + 1.5 * (q.distance(p) - 10.0).max(0.0))
            .fold(ground, f32::min)
    }
}

/// The viaduct's piers: a pair of columns under a cap beam every [`PIER_STEP`] metres of its open span,
/// standing a metre into the ground.
pub(super) fn viaduct_piers(scene: &mut Scene, m: &Mats, c: &Circuit, ground: impl Fn(Vec2) -> f32) {
    let (s0, s1) = c.viaduct;
    let count = ((s1 - s0) / PIER_STEP).floor() as usize;
    let mut mb = MeshBuilder::default();
    for k in 1..count {
        let f = c.at(s0 + (s1 - s0) * k as f32 / count as f32);
        let underside = f.p.y - DECK_DEPTH;
        let cap = 1.4;
        for lat in [-4.0, 4.0] {
            let q = f.p + f.right * lat;
            let foot = ground(Vec2::new(q.x, q.z)) - 1.0;
            let base = Vec3::new(q.x, foot, q.z);
            let block =
                Block { base, ax: f.right, az: f.fwd, half: Vec2::new(1.1, 1.6), height: underside - cap - foot };
            mb.cuboid(m.concrete, None, &block, 4.0, WHITE);
        }
        let base = Vec3::new(f.p.x, underside - cap, f.p.z);
        let block = Block { base, ax: f.right, az: f.fwd, half: Vec2::new(6.5, 1.4), height: cap };
        mb.cuboid(m.concrete, None, &block, 4.0, WHITE);
    }
    scene.add("viaduct piers", &mb);
}

/// A boulder's three models (close, mid, long): a ring of `k` stones' faces round a rounded top, fewer at
/// each step down: 42, 15 and 4 triangles.
fn boulder_meshes(doc: &mut Doc, m: &Mats) -> [usize; 3] {
    let ring = |k: usize, r: f32, y: f32, twist: f32| -> Vec<Vec3> {
        (0..k)
            .map(|i| {
                let a = (i as f32 + twist) / k as f32 * std::f32::consts::TAU;
                // A lumpy outline: every other stone sticks out.
                let r = r * if i % 2 == 0 { 1.0 } else { 0.82 };
                Vec3::new(libm::cosf(a) * r, y, libm::sinf(a) * r)
            })
            .collect()
    };
    let mut out = [0; 3];
    for (level, (k, rings)) in [(7usize, 3usize), (5, 2), (4, 1)].into_iter().enumerate() {
        let mut mb = MeshBuilder::default();
        let levels: Vec<Vec<Vec3>> = match rings {
            3 => vec![ring(k, 1.0, -0.3, 0.0), ring(k, 0.95, 0.45, 0.3), ring(k, 0.6, 0.85, 0.6)],
            2 => vec![ring(k, 1.0, -0.3, 0.0), ring(k, 0.75, 0.6, 0.4)],
            _ => vec![ring(k, 1.0, -0.3, 0.0)],
        };
        for pair in levels.windows(2) {
            for i in 0..k {
                let (a, b) = (pair[0][i], pair[0][(i + 1) % k]);
                let (c, d) = (pair[1][(i + 1) % k], pair[1][i]);
                let out = (a + b) * 0.5 * Vec3::new(1.0, 0.0, 1.0);
                let uvs = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(1.0, 0.0), Vec2::new(0.0, 0.0)];
                mb.face(m.rock, &[a, b, c], &uvs[..3], out, WHITE);
                mb.face(m.rock, &[a, c, d], &[uvs[0], uvs[2], uvs[3]], out, WHITE);
            }
        }
        let top = levels.last().map_or(&[][..], |l| &l[..]);
        let apex = Vec3::Y * if rings == 1 { 1.1 } else { 1.05 };
        for i in 0..k {
            let (a, b) = (top[i], top[(i + 1) % k]);
            let uvs = [Vec2::new(0.0, 1.0), Vec2::new(1.0, 1.0), Vec2::new(0.5, 0.0)];
            mb.face(m.rock, &[a, b, apex], &uvs, (a + b) * 0.5 + Vec3::Y, WHITE);
        }
        out[level] = doc.mesh(&format!("boulder {}", ["close", "mid", "long"][level]), &mb.prims);
    }
    out
}

/// `count` boulders on the slopes near the road (20 to 260 m from the centre line, off the track's corridor
/// and the keep-out footprints), from 1.5 to 7 m across, each a LOD node.
pub(super) fn boulders(scene: &mut Scene, m: &Mats, c: &Circuit, count: usize, ground: impl Fn(Vec2) -> f32) {
    let meshes = boulder_meshes(&mut scene.doc, m);
    let mut placed_at: Vec<Vec2> = vec![];
    let mut tries = 0;
    while placed_at.len() < count && tries < count * 20 {
        tries += 1;
        let i = scene.rng.int(0, c.n() as i32 - 1) as usize;
        let s = &c.samples[i];
        let side = if scene.rng.unit() < 0.5 { -1.0 } else { 1.0 };
        let lateral = 20.0 + 240.0 * scene.rng.unit() * scene.rng.unit();
        let q = Vec2::new(s.p.x + s.right.x * side * lateral, s.p.z + s.right.z * side * lateral);
        let size = scene.rng.range(0.75, 2.2) * if scene.rng.unit() < 0.15 { 1.6 } else { 1.0 };
        let yaw = scene.rng.range(0.0, std::f32::consts::TAU);
        let clear = c.distance(q) > 18.0 + size
            && !c.touches(q - Vec2::splat(size + 2.0), q + Vec2::splat(size + 2.0))
            && scene.keep_out.iter().all(|&(k, r)| k.distance(q) > r)
            && placed_at.iter().all(|p| p.distance_squared(q) > 36.0);
        if !clear {
            continue;
        }
        placed_at.push(q);
        let mut transform = placed(Vec3::new(q.x, ground(q), q.y), yaw);
        let squash = scene.rng.range(0.6, 1.0);
        transform["scale"] = json!([r3(size), r3(size * squash), r3(size * scene.rng.range(0.8, 1.2))]);
        scene.doc.lod_node(&format!("boulder {}", placed_at.len()), meshes, [0.03, 0.008, 0.0], transform, true);
    }
}
