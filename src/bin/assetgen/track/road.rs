//! The road and its roadside (kerbs, verges, barriers, embankments, aprons), the bridge, the start/finish line
//! and the start grid.

use glam::{Vec2, Vec3};

use super::circuit::Circuit;
use super::mesh::{Block, MeshBuilder, Scene, uv, world_uvs};
use super::spec::{BARRIER_OFFSET_RAISED, DECK_DEPTH, GRASS_UV, GRID_SLOTS, HALF_WIDTH, KERB_WIDTH, WHITE};
use super::terrain::Terrain;
use super::textures::Mats;

/// How far below the road the viaduct's abutment walls reach (below the ground kept under its deck).
const ABUTMENT_DEPTH: f32 = 7.0;

/// The road ribbon with kerbs, verges, barriers and embankments, in chunks of consecutive segments.
pub(super) fn track_meshes(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain) {
    let idx = c.road_indices();
    let segs: Vec<(usize, usize)> = (0..idx.len()).map(|k| (idx[k], idx[(k + 1) % idx.len()])).collect();
    for (k, chunk) in segs.chunks(24).enumerate() {
        let mut mb = MeshBuilder::default();
        for &(a, b) in chunk {
            track_segment(&mut mb, (m, t), c, a, b);
        }
        scene.add(&format!("track {k:02}"), &mb);
    }
}

fn track_segment(mb: &mut MeshBuilder, (m, t): (&Mats, &Terrain), c: &Circuit, a: usize, b: usize) {
    let (sa, sb) = (&c.samples[a], &c.samples[b]);
    let s = (sa.s, if b == 0 { c.length } else { sb.s });
    let (va, vb) = (s.0 / c.road_tile, s.1 / c.road_tile);
    let (la, ra, lb, rb) = (sa.edge(0), sa.edge(1), sb.edge(0), sb.edge(1));
    mb.face(m.road, &[la, sa.p, sb.p, lb], &[uv(0.0, va), uv(0.5, va), uv(0.5, vb), uv(0.0, vb)], Vec3::Y, WHITE);
    mb.face(m.road, &[sa.p, ra, rb, sb.p], &[uv(0.5, va), uv(1.0, va), uv(1.0, vb), uv(0.5, vb)], Vec3::Y, WHITE);
    let open = c.open(a) && c.open(b);
    for side in 0..2 {
        roadside(mb, (m, t), c, (a, b), side, s, open);
    }
    if open {
        let d = Vec3::Y * DECK_DEPTH;
        let pts = [sa.verge(0) - d, sa.verge(1) - d, sb.verge(1) - d, sb.verge(0) - d];
        mb.face(m.concrete, &pts, &world_uvs(&pts, 4.0), Vec3::NEG_Y, WHITE);
    }
    if c.open(a) && !c.open(b) {
        end_wall(mb, m, c, a, -sa.fwd);
    }
    if !c.open(a) && c.open(b) {
        end_wall(mb, m, c, b, sb.fwd);
    }
}

/// One side of a segment: kerb, verge, barrier, and the embankment side or the bridge deck's fascia.
fn roadside(
    mb: &mut MeshBuilder,
    (m, t): (&Mats, &Terrain),
    c: &Circuit,
    (a, b): (usize, usize),
    side: usize,
    s: (f32, f32),
    open: bool,
) {
    let (sa, sb) = (&c.samples[a], &c.samples[b]);
    let kerb = c.kerb(a) || c.kerb(b);
    let kw = if kerb { KERB_WIDTH } else { 0.0 };
    let (ea, eb) = (sa.edge(side), sb.edge(side));
    let (oa, ob) = (sa.out(side), sb.out(side));
    let (ka, kb) = (ea + oa * kw, eb + ob * kw);
    if kerb {
        let (va, vb) = (s.0 / c.kerb_tile, s.1 / c.kerb_tile);
        mb.face(m.kerb, &[ea, eb, kb, ka], &[uv(0.0, va), uv(0.0, vb), uv(1.0, vb), uv(1.0, va)], Vec3::Y, WHITE);
    }
    let (wa, wb) = (sa.verge(side), sb.verge(side));
    let gravel = sa.gravel[side] || sb.gravel[side];
    let verge = [ka, kb, wb, wa];
    let metres = if gravel { 8.0 } else { GRASS_UV };
    mb.face(if gravel { m.gravel } else { m.grass }, &verge, &world_uvs(&verge, metres), Vec3::Y, WHITE);
    let (ua, ub) = (s.0 / c.barrier_tile, s.1 / c.barrier_tile);
    let (mat, bh) = if (c.bridge_zone(a) && sa.h.max(sb.h) > 0.8) || c.in_viaduct(a) || c.in_viaduct(b) {
        (m.parapet, 1.0)
    } else if gravel {
        (m.tyres, 1.0)
    } else {
        (m.armco, 0.8)
    };
    let up = Vec3::Y * bh;
    let bar = [wa, wb, wb + up, wa + up];
    mb.face(mat, &bar, &[uv(ua, bh), uv(ub, bh), uv(ub, 0.0), uv(ua, 0.0)], -(oa + ob), WHITE);
    if open {
        let d = Vec3::Y * DECK_DEPTH;
        let h = DECK_DEPTH / 4.0;
        mb.face(
            m.concrete,
            &[wa, wb, wb - d, wa - d],
            &[uv(ua, 0.0), uv(ub, 0.0), uv(ub, h), uv(ua, h)],
            oa + ob,
            WHITE,
        );
    } else if (wa.y - sa.base).max(wb.y - sb.base) > 0.15 {
        let foot = |i: usize, w: Vec3, o: Vec3| {
            let base = c.samples[i].base;
            let f = w + o * c.foot(i, w.y - base);
            Vec3::new(f.x, base - 0.05, f.z)
        };
        let (fa, fb) = (foot(a, wa, oa), foot(b, wb, ob));
        let pts = [wa, wb, fb, fa];
        if c.bridge_zone(a) || c.bridge_zone(b) {
            let uvs = [uv(ua, 0.0), uv(ub, 0.0), uv(ub, wb.y / 4.0), uv(ua, wa.y / 4.0)];
            mb.face(m.concrete, &pts, &uvs, oa + ob + Vec3::Y, WHITE);
        } else {
            mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), oa + ob + Vec3::Y, WHITE);
        }
        let ground = |f: Vec3, i: usize| Vec3::new(f.x, c.samples[i].base, f.z);
        apron(mb, (m, t), c, (a, b), side, [ground(fa, a), ground(fb, b)]);
    } else {
        apron(mb, (m, t), c, (a, b), side, [wa, wb]);
    }
}

/// The grass beside the corridor, from `inner` (the barrier line or the embankment's foot) out to the
/// sample's apron extent at ground level: a narrow strip along the barrier, then the rest (narrow polygons
/// next to the barriers keep the painter's order close to right).
fn apron(
    mb: &mut MeshBuilder,
    (m, t): (&Mats, &Terrain),
    c: &Circuit,
    (a, b): (usize, usize),
    side: usize,
    inner: [Vec3; 2],
) {
    let at = |i: usize, lateral: f32| {
        let s = &c.samples[i];
        let q = s.p + s.out(side) * lateral.min(c.apron[i][side]);
        Vec3::new(q.x, t.apron_level(Vec2::new(q.x, q.z)), q.z)
    };
    let mid = [at(a, c.reach(a, side) + 8.0), at(b, c.reach(b, side) + 8.0)];
    let outer = [at(a, f32::INFINITY), at(b, f32::INFINITY)];
    for (near, far) in [(inner, mid), (mid, outer)] {
        let mut pts: Vec<Vec3> = vec![];
        for p in [near[0], near[1], far[1], far[0]] {
            let distinct = pts.last().is_none_or(|q: &Vec3| q.distance_squared(p) > 0.01);
            if distinct && (pts.len() < 3 || pts[0].distance_squared(p) > 0.01) {
                pts.push(p);
            }
        }
        if pts.len() >= 3 {
            mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
        }
    }
}

/// The end of an embankment at an open span: a wall across it, from the verges down to the ground (at the
/// viaduct, below the ground kept under its deck).
fn end_wall(mb: &mut MeshBuilder, m: &Mats, c: &Circuit, i: usize, facing: Vec3) {
    let s = &c.samples[i];
    let drop = Vec3::Y * 0.02;
    let depth = if c.in_span(i) { 0.05 } else { ABUTMENT_DEPTH };
    let foot = |side: usize| {
        let w = s.verge(side);
        let f = w + s.out(side) * c.foot(i, w.y - s.base);
        Vec3::new(f.x, s.base - depth, f.z)
    };
    let pts = [foot(0), foot(1), s.verge(1) - drop, s.verge(0) - drop];
    let top = if c.in_span(i) { s.p.y / 4.0 } else { (s.p.y - s.base + depth) / 4.0 };
    let w = pts[0].distance(pts[1]) / 8.0;
    mb.face(m.concrete, &pts, &[uv(-w, top), uv(w, top), uv(w * 0.6, 0.0), uv(-w * 0.6, 0.0)], facing, WHITE);
}

/// Piers under the bridge either side of the lower road: two columns and a cap beam per row.
pub(super) fn bridge_mesh(scene: &mut Scene, m: &Mats, c: &Circuit) {
    let mut mb = MeshBuilder::default();
    for sign in [-1.0, 1.0] {
        let f = c.at(c.upper_s + sign * c.pier_offset);
        let underside = f.p.y - DECK_DEPTH;
        let ground = Vec3::new(f.p.x, -0.05, f.p.z);
        for lat in [-4.5, 4.5] {
            let base = ground + f.right * lat;
            let height = underside - 0.9 + 0.05;
            mb.cuboid(
                m.concrete,
                None,
                &Block { base, ax: f.right, az: f.fwd, half: Vec2::splat(0.7), height },
                4.0,
                WHITE,
            );
        }
        let base = Vec3::new(f.p.x, underside - 0.9, f.p.z);
        let block = Block { base, ax: f.right, az: f.fwd, half: Vec2::new(BARRIER_OFFSET_RAISED, 0.9), height: 0.9 };
        mb.cuboid(m.concrete, None, &block, 4.0, WHITE);
    }
    let p = c.cross_point;
    scene.keep_out.push((p, 60.0));
    scene.add("bridge piers", &mb);
}

/// Start grid slots: two staggered columns behind the line, pole on the left (the first corner is a left).
pub(super) fn grid_slots(c: &Circuit) -> Vec<(Vec3, f32)> {
    (0..GRID_SLOTS)
        .map(|k| {
            let f = c.at(c.length - 8.0 - 8.0 * k as f32);
            let lat = if k % 2 == 0 { -2.8 } else { 2.8 };
            (f.p + f.lat * lat, libm::atan2f(f.fwd.x, -f.fwd.z))
        })
        .collect()
}

/// The start/finish gantry, the chequered line across the road and the grid slot markings.
pub(super) fn start_mesh(scene: &mut Scene, m: &Mats, c: &Circuit, grid: &[(Vec3, f32)]) {
    let mut mb = MeshBuilder::default();
    let f = c.at(0.0);
    let s0 = &c.samples[0];
    let reach = s0.bo[0].max(s0.bo[1]) + 1.5;
    for sign in [-1.0, 1.0] {
        let base = Vec3::new(f.p.x, -0.05, f.p.z) + f.right * (sign * reach);
        let post = Block { base, ax: f.right, az: f.fwd, half: Vec2::splat(0.5), height: 8.9 };
        mb.cuboid(m.paint, Some(m.paint), &post, 4.0, Vec3::splat(0.8));
    }
    let base = Vec3::new(f.p.x, 7.2, f.p.z);
    let beam = Block { base, ax: f.right, az: f.fwd, half: Vec2::new(reach + 0.6, 0.6), height: 1.6 };
    mb.cuboid(m.chequer, Some(m.roof), &beam, 3.2, WHITE);
    // The line: 1.6 m of chequer across the road, 0.4 m squares.
    let lift = Vec3::Y * 0.05;
    let (l, r, h) = (f.p - f.lat * HALF_WIDTH + lift, f.p + f.lat * HALF_WIDTH + lift, f.fwd * 0.8);
    let u = 2.0 * HALF_WIDTH / 3.2;
    mb.face(
        m.chequer,
        &[l - h, r - h, r + h, l + h],
        &[uv(0.0, 0.5), uv(u, 0.5), uv(u, 0.0), uv(0.0, 0.0)],
        Vec3::Y,
        WHITE,
    );
    for &(p, yaw) in grid {
        let fwd = Vec3::new(libm::sinf(yaw), 0.0, -libm::cosf(yaw));
        let right = Vec3::new(libm::cosf(yaw), 0.0, libm::sinf(yaw));
        let centre = p + fwd * 2.6 + lift;
        let (x, z) = (right * 1.4, fwd * 0.15);
        let pts = [centre - x - z, centre + x - z, centre + x + z, centre - x + z];
        mb.face(m.paint, &pts, &[Vec2::ZERO; 4], Vec3::Y, WHITE);
    }
    scene.add("start", &mb);
}
