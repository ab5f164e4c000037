//! Scenery beside the track: grandstands, buildings and trees.

use glam::{Vec2, Vec3};
use serde_json::json;

use super::circuit::Circuit;
use super::mesh::{Block, MeshBuilder, Scene, node_yaw, uv};
use super::spec::{GROUND_RADIUS, TREE_CLEARANCE, WHITE};
use super::terrain::Terrain;
use super::textures::Mats;
use super::util::r3;
use crate::gltf_out::{Doc, placed};

/// The grandstand (shared mesh): 80 m long, eight stepped rows rising away from the track (local -Z faces the
/// track, the front wall at z = 0), a back wall and a roof; in 20 m sections for depth ordering.
fn grandstand_mesh(m: &Mats) -> MeshBuilder {
    let mut mb = MeshBuilder::default();
    let (rows, depth, rise, front) = (8, 1.4, 0.75, 1.6);
    let back_z = rows as f32 * depth;
    let top_y = front + rise * (rows - 1) as f32;
    let roof_y = top_y + 3.2;
    for sec in 0..4 {
        let (x0, x1) = (-40.0 + 20.0 * sec as f32, -20.0 + 20.0 * sec as f32);
        let (u0, u1) = (x0 / 6.0, x1 / 6.0);
        let wall = |z: f32, y0: f32, y1: f32| {
            [Vec3::new(x0, y0, z), Vec3::new(x1, y0, z), Vec3::new(x1, y1, z), Vec3::new(x0, y1, z)]
        };
        mb.face(
            m.concrete,
            &wall(0.0, 0.0, front),
            &[uv(u0, 0.4), uv(u1, 0.4), uv(u1, 0.0), uv(u0, 0.0)],
            Vec3::NEG_Z,
            WHITE,
        );
        for r in 0..rows {
            let (z0, y) = (r as f32 * depth, front + rise * r as f32);
            if r > 0 {
                let riser = wall(z0, y - rise, y);
                mb.face(m.crowd, &riser, &[uv(u0, 0.35), uv(u1, 0.35), uv(u1, 0.0), uv(u0, 0.0)], Vec3::NEG_Z, WHITE);
            }
            let tread = [
                Vec3::new(x0, y, z0),
                Vec3::new(x1, y, z0),
                Vec3::new(x1, y, z0 + depth),
                Vec3::new(x0, y, z0 + depth),
            ];
            mb.face(m.crowd, &tread, &[uv(u0, 1.0), uv(u1, 1.0), uv(u1, 0.35), uv(u0, 0.35)], Vec3::Y, WHITE);
        }
        let bw = wall(back_z, 0.0, roof_y);
        let v = roof_y / 4.0;
        mb.face(m.concrete, &bw, &[uv(u0, v), uv(u1, v), uv(u1, 0.0), uv(u0, 0.0)], Vec3::Z, WHITE);
        let riser = wall(back_z, top_y, roof_y);
        mb.face(m.concrete, &riser, &[uv(u0, 0.8), uv(u1, 0.8), uv(u1, 0.0), uv(u0, 0.0)], Vec3::NEG_Z, WHITE);
        let roof = [
            Vec3::new(x0, roof_y, back_z),
            Vec3::new(x1, roof_y, back_z),
            Vec3::new(x1, roof_y - 1.0, 1.5),
            Vec3::new(x0, roof_y - 1.0, 1.5),
        ];
        mb.face(m.canopy, &roof, &[Vec2::ZERO; 4], Vec3::Y, WHITE);
    }
    // The ends: one slab per row (the stepped profile is not convex), and the end of the upper back wall.
    for x in [-40.0, 40.0f32] {
        let out = Vec3::X * x.signum();
        for r in 0..rows {
            let (z0, y) = (r as f32 * depth, front + rise * r as f32);
            let pts = [
                Vec3::new(x, 0.0, z0),
                Vec3::new(x, 0.0, z0 + depth),
                Vec3::new(x, y, z0 + depth),
                Vec3::new(x, y, z0),
            ];
            mb.face(
                m.concrete,
                &pts,
                &[
                    uv(z0 / 4.0, y / 4.0),
                    uv((z0 + depth) / 4.0, y / 4.0),
                    uv((z0 + depth) / 4.0, 0.0),
                    uv(z0 / 4.0, 0.0),
                ],
                out,
                WHITE,
            );
        }
        let pts = [
            Vec3::new(x, top_y, back_z - 0.3),
            Vec3::new(x, top_y, back_z),
            Vec3::new(x, roof_y, back_z),
            Vec3::new(x, roof_y, back_z - 0.3),
        ];
        mb.face(m.concrete, &pts, &[uv(0.0, 0.8), uv(0.1, 0.8), uv(0.1, 0.0), uv(0.0, 0.0)], out, WHITE);
    }
    mb
}

/// Lowest plan distance from the centreline of a footprint (corners and edge midpoints of a rectangle).
pub(super) fn footprint_clear(c: &Circuit, centre: Vec3, ax: Vec3, az: Vec3, half: Vec2) -> f32 {
    let mut d = f32::INFINITY;
    for (sx, sz) in
        [(-1.0, -1.0), (0.0, -1.0), (1.0, -1.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (-1.0, 1.0), (-1.0, 0.0)]
    {
        let p = centre + ax * (half.x * sx) + az * (half.y * sz);
        d = d.min(c.distance(Vec2::new(p.x, p.z)));
    }
    d
}

/// Three grandstands (main straight, hairpin, by the bridge); returns (front centre, direction to the track)
/// of each placed.
pub(super) fn grandstands(scene: &mut Scene, m: &Mats, c: &Circuit) -> Vec<(Vec3, Vec3)> {
    let mb = grandstand_mesh(m);
    let mesh = scene.doc.mesh("grandstand", &mb.prims);
    let spots = [(40.0, 1usize, 5.0), (c.apex[3], 1, 6.0), (c.lower_s - 110.0, 0, 5.0)];
    let mut placed_at = vec![];
    for (k, &(s, side, gap)) in spots.iter().enumerate() {
        let i = (s.rem_euclid(c.length) / c.step).round() as usize % c.n();
        let smp = &c.samples[i];
        let out = smp.out(side);
        let front = smp.p + out * (smp.bo[0].max(smp.bo[1]) + gap);
        let front = Vec3::new(front.x, smp.base, front.z);
        let along = Vec3::new(-out.z, 0.0, out.x);
        let centre = front + out * 7.0;
        if footprint_clear(c, centre, along, out, Vec2::new(40.0, 7.0)) < c.layout.barrier_offset + 3.0 {
            continue;
        }
        let transform = placed(front, node_yaw(-out));
        let mut node = transform;
        node["name"] = json!(format!("grandstand {}", k + 1));
        node["mesh"] = json!(mesh);
        scene.doc.node(node, true);
        scene.keep_out.push((Vec2::new(centre.x, centre.z), 48.0));
        placed_at.push((front, -out));
    }
    placed_at
}

/// Buildings beside the track: pit building, control tower and a few others, boxes with a windows texture.
pub(super) fn buildings(scene: &mut Scene, m: &Mats, c: &Circuit) {
    // (distance from the start line, side, gap beyond the barrier, length along the track, depth, height)
    let list = [
        (15.0, 0usize, 10.0, 150.0, 16.0, 8.0),
        (c.length - 60.0, 0, 12.0, 12.0, 12.0, 24.0),
        (170.0, 1, 10.0, 50.0, 14.0, 11.0),
        (c.apex[5] - 90.0, 1, 14.0, 40.0, 20.0, 7.0),
        (c.apex[8] + 120.0, 0, 16.0, 60.0, 18.0, 9.0),
        (c.apex[2] - 20.0, 1, 18.0, 30.0, 22.0, 12.0),
        (c.apex[6] + 160.0, 1, 16.0, 36.0, 16.0, 8.0),
        (c.apex[10] - 60.0, 0, 20.0, 28.0, 28.0, 10.0),
    ];
    for (k, &(s, side, gap, len, depth, height)) in list.iter().enumerate() {
        let i = (s.rem_euclid(c.length) / c.step).round() as usize % c.n();
        let smp = &c.samples[i];
        let out = smp.out(side);
        let reach = smp.bo[side] + gap + depth / 2.0;
        let centre = smp.p + out * reach;
        let base = Vec3::new(centre.x, -0.05, centre.z);
        let half = Vec2::new(len / 2.0, depth / 2.0);
        if footprint_clear(c, base, smp.fwd, out, half) < c.layout.barrier_offset + 4.0 {
            continue;
        }
        let mut mb = MeshBuilder::default();
        let tint = [Vec3::ONE, Vec3::new(0.92, 0.95, 1.0), Vec3::new(1.0, 0.95, 0.88)][k % 3];
        let block = Block { base, ax: smp.fwd, az: out, half, height: height + 0.05 };
        mb.cuboid(m.windows, Some(m.roof), &block, 4.0, tint);
        scene.add(&format!("building {}", k + 1), &mb);
        scene.keep_out.push((Vec2::new(base.x, base.z), half.length() + 8.0));
    }
}

/// The three tree models of each species (shared by all trees): two crossed quads close by; further away
/// one quad that turns to face the eye (the middle and long models are the same mesh), so that a distant
/// tree keeps the width its close model shows from every side rather than thinning to a sliver seen edge on.
fn tree_meshes(doc: &mut Doc, m: &Mats) -> [[usize; 3]; 2] {
    let mut out = [[0; 3]; 2];
    for (sp, (w, h)) in [(3.0f32, 12.0f32), (2.75, 11.0)].into_iter().enumerate() {
        let (u0, u1) = (sp as f32 * 0.5, sp as f32 * 0.5 + 0.5);
        let uvs = [uv(u0, 1.0), uv(u1, 1.0), uv(u1, 0.0), uv(u0, 0.0)];
        let quad = |dir: Vec3| [-dir * w, dir * w, dir * w + Vec3::Y * h, -dir * w + Vec3::Y * h];
        let mut close = MeshBuilder::default();
        close.face(m.tree, &quad(Vec3::X), &uvs, Vec3::Z, WHITE);
        close.face(m.tree, &quad(Vec3::NEG_Z), &uvs, Vec3::X, WHITE);
        let mut far = MeshBuilder::default();
        far.face(m.tree, &quad(Vec3::X), &uvs, Vec3::Z, WHITE);
        let name = ["broadleaf", "conifer"][sp];
        let close = doc.mesh(&format!("{name} close"), &close.prims);
        let far = doc.mesh(&format!("{name} far"), &far.prims);
        doc.face_eye(far);
        out[sp] = [close, far, far];
    }
    out
}

/// How trees are planted: clumps, trees scattered between them, the most trees, and how far beyond the
/// track's plan bounds they may stand.
pub(super) struct Planting {
    pub(super) clumps: usize,
    pub(super) scattered: usize,
    pub(super) most: usize,
    pub(super) margin: f32,
    /// Trees tried in the band 32 to 220 m either side of the road, before the rest (the view from the road
    /// is where trees are seen from close by).
    pub(super) roadside: usize,
}

/// The circuit's trees: about 250 in clumps and scattered within 300 m of the track.
pub(super) const PARKLAND: Planting = Planting { clumps: 20, scattered: 70, most: 260, margin: 300.0, roadside: 0 };

/// Trees in clumps and scattered, clear of the track, buildings and grandstands, each a LOD node.
pub(super) fn trees(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain, plant: &Planting) {
    let meshes = tree_meshes(&mut scene.doc, m);
    let (lo, hi) = c.bounds();
    let (lo, hi) = (lo - Vec2::splat(plant.margin), hi + Vec2::splat(plant.margin));
    let mut placed_trees: Vec<Vec2> = vec![];
    let ok = |p: Vec2, trees: &[Vec2], keep_out: &[(Vec2, f32)]| {
        p.distance(t.centre) < GROUND_RADIUS - 250.0
            && trees.iter().all(|q| q.distance_squared(p) > 36.0)
            && keep_out.iter().all(|&(k, r)| k.distance(p) > r)
            && c.distance(p) > TREE_CLEARANCE
    };
    let mut candidates = vec![];
    let rng = &mut scene.rng;
    for _ in 0..plant.roadside {
        let smp = &c.samples[rng.int(0, c.n() as i32 - 1) as usize];
        let lateral = rng.range(32.0, 220.0) * if rng.unit() < 0.5 { -1.0 } else { 1.0 };
        candidates.push(Vec2::new(smp.p.x + smp.right.x * lateral, smp.p.z + smp.right.z * lateral));
    }
    for _ in 0..plant.clumps {
        let centre = Vec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        let count = rng.int(8, 16);
        for _ in 0..count * 2 {
            let (a, r) = (rng.range(0.0, std::f32::consts::TAU), 70.0 * rng.unit().sqrt());
            candidates.push(centre + Vec2::new(libm::cosf(a), libm::sinf(a)) * r);
        }
    }
    for _ in 0..plant.scattered {
        candidates.push(Vec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y)));
    }
    for p in candidates {
        if placed_trees.len() >= plant.most || !ok(p, &placed_trees, &scene.keep_out) {
            continue;
        }
        placed_trees.push(p);
    }
    for (k, p) in placed_trees.iter().enumerate() {
        let sp = usize::from(scene.rng.unit() < 0.45);
        let scale = scene.rng.range(0.8, 1.3);
        let yaw = scene.rng.range(0.0, std::f32::consts::TAU);
        let mut transform = placed(Vec3::new(p.x, t.height(*p) - 0.2, p.y), yaw);
        transform["scale"] = json!([r3(scale), r3(scale), r3(scale)]);
        scene.doc.lod_node(&format!("tree {k}"), meshes[sp], [0.06, 0.016, 0.0], transform, true);
    }
}
