//! The street course's dressing: a tunnel under a block, buildings lining both sides of the road a pavement's
//! width behind the barriers, and the blocks and towers that fill the city behind them.
//!
//! Every building is a level-of-detail node (seed 003's close, mid and long models) of a shared model, one
//! model per quantized size and tint, placed and turned by its node: the close model has a shop front, an
//! awning and a plant room on the roof, the mid one the front band and a flat awning, the long one is a box.
//! The rows behind the street and the towers rising over them are what the street's buildings hide, which
//! is the point of the course: most of what lies in the view is behind something.

use std::collections::BTreeMap;

use glam::{Vec2, Vec3};
use serde_json::json;

use super::circuit::{Circuit, Frame};
use super::mesh::{Block, MeshBuilder, Scene, node_yaw, uv};
use super::scenery::footprint_clear;
use super::spec::{GROUND_RADIUS, WHITE};
use super::terrain::Terrain;
use super::textures::Mats;
use super::util::r3;
use crate::gltf_out::{Doc, placed};

/// The tunnel: from this far past the apex of corner [`TUNNEL_CORNER`] to [`TUNNEL_END`] past it.
const TUNNEL_START: f32 = 170.0;
const TUNNEL_END: f32 = 350.0;
const TUNNEL_CORNER: usize = 5;
/// The tunnel's ceiling, and the block's roof over it.
const TUNNEL_CEILING: f32 = 6.2;
const TUNNEL_BLOCK: f32 = 22.0;
/// How far the block over the tunnel reaches beyond each wall.
const TUNNEL_WINGS: f32 = 16.0;
/// Coverage thresholds (projected height over the screen's) for a building's mid and long models.
const COVERAGE: [f32; 3] = [0.12, 0.035, 0.0];
/// Model sizes: lengths along the street, depths, heights (m).
const LENGTHS: [f32; 3] = [16.0, 24.0, 32.0];
const DEPTHS: [f32; 3] = [14.0, 20.0, 26.0];
const HEIGHTS: [f32; 7] = [9.0, 14.0, 21.0, 30.0, 42.0, 60.0, 85.0];
/// Facade tints.
const TINTS: [Vec3; 3] = [Vec3::ONE, Vec3::new(0.90, 0.94, 1.0), Vec3::new(1.0, 0.92, 0.84)];

/// A building's footprint on the plan: centre, unit axis along its length, half extents.
#[derive(Clone, Copy)]
struct Rect {
    centre: Vec2,
    ax: Vec2,
    half: Vec2,
}

impl Rect {
    fn corners(&self) -> [Vec2; 4] {
        let az = Vec2::new(-self.ax.y, self.ax.x);
        [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
            .map(|(a, b)| self.centre + self.ax * (self.half.x * a) + az * (self.half.y * b))
    }

    /// Whether two footprints overlap, grown by `gap` (separating axis test).
    fn overlaps(&self, o: &Rect, gap: f32) -> bool {
        let (a, b) = (self.corners(), o.corners());
        let axes = [self.ax, Vec2::new(-self.ax.y, self.ax.x), o.ax, Vec2::new(-o.ax.y, o.ax.x)];
        axes.iter().all(|&n| {
            let span = |pts: &[Vec2; 4]| {
                pts.iter().map(|p| p.dot(n)).fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), v| (l.min(v), h.max(v)))
            };
            let ((a0, a1), (b0, b1)) = (span(&a), span(&b));
            a1 + gap > b0 && b1 + gap > a0
        })
    }
}

/// The building models made so far, by (length, depth, height, tint) index.
#[derive(Default)]
struct Models(BTreeMap<(usize, usize, usize, usize), [usize; 3]>);

impl Models {
    fn get(&mut self, doc: &mut Doc, m: &Mats, key: (usize, usize, usize, usize)) -> [usize; 3] {
        *self.0.entry(key).or_insert_with(|| {
            let size = Vec3::new(LENGTHS[key.0], HEIGHTS[key.2], DEPTHS[key.1]);
            let name = format!("block {}x{}x{} {}", size.x, size.z, size.y, key.3);
            let [close, mid, long] = building_models(m, size, TINTS[key.3]);
            [
                doc.mesh(&format!("{name} close"), &close.prims),
                doc.mesh(&format!("{name} mid"), &mid.prims),
                doc.mesh(&format!("{name} long"), &long.prims),
            ]
        })
    }
}

/// Index of the entry of `list` nearest `v`.
fn nearest(list: &[f32], v: f32) -> usize {
    (0..list.len()).min_by(|&a, &b| (list[a] - v).abs().total_cmp(&(list[b] - v).abs())).unwrap_or(0)
}

/// The close, mid and long models of a building of `size` (length x, height y, depth z), its front at z = 0
/// facing -Z, its back at z = depth, standing on y = 0.
fn building_models(m: &Mats, size: Vec3, tint: Vec3) -> [MeshBuilder; 3] {
    let (hx, h, d) = (size.x / 2.0, size.y, size.z);
    let band = 4.0f32.min(h * 0.4);
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let wall = |mb: &mut MeshBuilder, mat: usize, a: Vec3, b: Vec3, y0: f32, y1: f32, out: Vec3, tint: Vec3| {
        let w = a.distance(b) / 4.0;
        let (v0, v1) = (y0 / 4.0, y1 / 4.0);
        let pts = [a + Vec3::Y * y0, b + Vec3::Y * y0, b + Vec3::Y * y1, a + Vec3::Y * y1];
        mb.face(mat, &pts, &[uv(0.0, -v0), uv(w, -v0), uv(w, -v1), uv(0.0, -v1)], out, tint);
    };
    let shop = tint * Vec3::new(0.75, 0.72, 0.70);
    let mut out = [MeshBuilder::default(), MeshBuilder::default(), MeshBuilder::default()];
    for (level, mb) in out.iter_mut().enumerate() {
        let (fl, fr, bl, br) = (p(-hx, 0.0, 0.0), p(hx, 0.0, 0.0), p(-hx, 0.0, d), p(hx, 0.0, d));
        if level < 2 {
            wall(mb, m.concrete, fl, fr, 0.0, band, Vec3::NEG_Z, shop);
            wall(mb, m.windows, fl, fr, band, h, Vec3::NEG_Z, tint);
        } else {
            wall(mb, m.windows, fl, fr, 0.0, h, Vec3::NEG_Z, tint);
        }
        wall(mb, m.windows, fr, br, 0.0, h, Vec3::X, tint);
        wall(mb, m.windows, br, bl, 0.0, h, Vec3::Z, tint);
        wall(mb, m.windows, bl, fl, 0.0, h, Vec3::NEG_X, tint);
        let top = [p(-hx, h, 0.0), p(hx, h, 0.0), p(hx, h, d), p(-hx, h, d)];
        mb.face(m.roof, &top, &[Vec2::ZERO; 4], Vec3::Y, WHITE);
        let awning = tint * Vec3::new(0.55, 0.35, 0.30);
        let (ay, ax) = (band - 0.4, hx - 1.0);
        if level == 0 {
            let block =
                Block { base: p(0.0, ay, -0.8), ax: Vec3::X, az: Vec3::Z, half: Vec2::new(ax, 0.8), height: 0.3 };
            mb.cuboid(m.paint, Some(m.paint), &block, 4.0, awning);
            let under = [p(-ax, ay, -1.6), p(ax, ay, -1.6), p(ax, ay, 0.0), p(-ax, ay, 0.0)];
            mb.face(m.paint, &under, &[Vec2::ZERO; 4], Vec3::NEG_Y, awning * 0.7);
            let plant = Block {
                base: p(0.0, h, d * 0.5),
                ax: Vec3::X,
                az: Vec3::Z,
                half: Vec2::new(hx * 0.4, d * 0.2),
                height: 2.6,
            };
            mb.cuboid(m.concrete, Some(m.roof), &plant, 4.0, WHITE);
        } else if level == 1 {
            let slab = [p(-ax, ay, -1.6), p(ax, ay, -1.6), p(ax, ay + 0.3, 0.0), p(-ax, ay + 0.3, 0.0)];
            mb.face(m.paint, &slab, &[Vec2::ZERO; 4], Vec3::Y, awning);
        }
    }
    out
}

/// What places buildings: the footprints taken so far and the models made.
struct Builder<'a> {
    c: &'a Circuit,
    t: &'a Terrain,
    taken: Vec<Rect>,
    models: Models,
    count: usize,
}

impl Builder<'_> {
    /// Places a building whose front centre is `front` on the ground plan, facing `-out`, if its footprint
    /// keeps `clear` metres from the centre line and `gap` from every other footprint; returns whether it did.
    fn place(
        &mut self,
        scene: &mut Scene,
        m: &Mats,
        front: Vec2,
        out: Vec2,
        size: Vec3,
        (clear, gap): (f32, f32),
    ) -> bool {
        let key =
            (nearest(&LENGTHS, size.x), nearest(&DEPTHS, size.z), nearest(&HEIGHTS, size.y), self.count % TINTS.len());
        let size = Vec3::new(LENGTHS[key.0], HEIGHTS[key.2], DEPTHS[key.1]);
        let ax = Vec2::new(-out.y, out.x);
        let rect = Rect { centre: front + out * (size.z / 2.0), ax, half: Vec2::new(size.x / 2.0, size.z / 2.0) };
        let centre3 = Vec3::new(rect.centre.x, 0.0, rect.centre.y);
        let (ax3, out3) = (Vec3::new(ax.x, 0.0, ax.y), Vec3::new(out.x, 0.0, out.y));
        if rect.centre.distance(self.t.centre) > GROUND_RADIUS - 300.0
            || footprint_clear(self.c, centre3, ax3, out3, rect.half) < clear
            || self.taken.iter().any(|r| r.overlaps(&rect, gap))
            || scene.keep_out.iter().any(|&(k, r)| rect.corners().iter().any(|q| q.distance(k) < r))
        {
            return false;
        }
        let ground = rect.corners().iter().map(|&q| self.t.height(q)).fold(f32::INFINITY, f32::min);
        let meshes = self.models.get(&mut scene.doc, m, key);
        let transform = placed(Vec3::new(front.x, ground - 0.2, front.y), node_yaw(-out3));
        let mut transform = transform;
        if ground > 0.5 {
            // On rising ground the building is set deeper so that no gap shows under its downhill side.
            transform["translation"][1] = json!(r3(ground - 1.5));
        }
        scene.doc.lod_node(&format!("building {}", self.count), meshes, COVERAGE, transform, true);
        self.taken.push(rect);
        self.count += 1;
        true
    }
}

/// Where the tunnel starts and ends, as distances from the start line.
fn tunnel_span(c: &Circuit) -> (f32, f32) {
    let apex = c.apex[TUNNEL_CORNER.min(c.apex.len() - 1)];
    (apex + TUNNEL_START, apex + TUNNEL_END)
}

/// The view into the tunnel from the road 40 m before its mouth, 1.2 m up: its walls reach the near plane.
pub(super) fn tunnel_view(c: &Circuit) -> (String, Vec3, Vec3) {
    let (s0, _) = tunnel_span(c);
    let (eye, target) = (c.at(s0 - 40.0), c.at(s0 + 60.0));
    ("tunnel".to_string(), eye.p + eye.right * 2.5 + Vec3::Y * 1.2, target.p + Vec3::Y * 1.5)
}

/// The tunnel: its walls and ceiling, then the block over it; returns the block's footprint.
fn tunnel(scene: &mut Scene, m: &Mats, c: &Circuit) -> Rect {
    let (s0, s1) = tunnel_span(c);
    let i = (((s0 + s1) * 0.5).rem_euclid(c.length) / c.step).round() as usize % c.n();
    let wall_at = c.samples[i].bo.map(|o| o + 0.3);
    scene.add("tunnel", &tunnel_bore(m, c, (s0, s1), wall_at));
    let (a, b) = (c.at(s0), c.at(s1));
    let reach = [wall_at[0] + TUNNEL_WINGS, wall_at[1] + TUNNEL_WINGS];
    scene.add("tunnel block", &tunnel_block(m, (&a, &b), wall_at, reach));
    let mid = (a.p + b.p) * 0.5 + a.right * ((reach[1] - reach[0]) * 0.5);
    Rect {
        centre: Vec2::new(mid.x, mid.z),
        ax: Vec2::new(a.fwd.x, a.fwd.z),
        half: Vec2::new(a.p.distance(b.p) / 2.0, (reach[0] + reach[1]) / 2.0),
    }
}

/// A point on the ground (`y` above it) `lat` metres right of the centre line at frame `f`.
fn beside(f: &Frame, lat: f32, y: f32) -> Vec3 {
    let p = f.p + f.right * lat;
    Vec3::new(p.x, y, p.z)
}

/// The tunnel's walls (`wall_at` metres left and right of the centre line) and ceiling, from `s0` to `s1`,
/// darker than daylight, in 10 m pieces.
fn tunnel_bore(m: &Mats, c: &Circuit, (s0, s1): (f32, f32), wall_at: [f32; 2]) -> MeshBuilder {
    let dark = Vec3::splat(0.5);
    let mut mb = MeshBuilder::default();
    let steps = ((s1 - s0) / 10.0).ceil() as usize;
    let s_at = |k: usize| s0 + (s1 - s0) * k as f32 / steps as f32;
    for k in 0..steps {
        let (f, g) = (c.at(s_at(k)), c.at(s_at(k + 1)));
        let (u0, u1) = (s_at(k) / 4.0, s_at(k + 1) / 4.0);
        let v = TUNNEL_CEILING / 4.0;
        for (side, sign) in [(0usize, -1.0f32), (1, 1.0)] {
            let lat = sign * wall_at[side];
            let pts = [
                beside(&f, lat, -0.05),
                beside(&g, lat, -0.05),
                beside(&g, lat, TUNNEL_CEILING),
                beside(&f, lat, TUNNEL_CEILING),
            ];
            mb.face(m.concrete, &pts, &[uv(u0, v), uv(u1, v), uv(u1, 0.0), uv(u0, 0.0)], -f.right * sign, dark);
        }
        let (l, r) = (-wall_at[0], wall_at[1]);
        let pts = [
            beside(&f, l, TUNNEL_CEILING),
            beside(&f, r, TUNNEL_CEILING),
            beside(&g, r, TUNNEL_CEILING),
            beside(&g, l, TUNNEL_CEILING),
        ];
        let w = (wall_at[0] + wall_at[1]) / 4.0;
        mb.face(m.concrete, &pts, &[uv(0.0, u0), uv(w, u0), uv(w, u1), uv(0.0, u1)], Vec3::NEG_Y, dark * 0.8);
    }
    mb
}

/// The block over the tunnel between frames `a` and `b`: its outer walls `reach` metres out, its roof, and
/// at each portal the wall around the opening (left of it, right of it, above it).
fn tunnel_block(m: &Mats, (a, b): (&Frame, &Frame), wall_at: [f32; 2], reach: [f32; 2]) -> MeshBuilder {
    let mut mb = MeshBuilder::default();
    let top = TUNNEL_BLOCK;
    let mut quad = |pts: [Vec3; 4], out: Vec3| {
        let (w, h) = (pts[0].distance(pts[1]) / 4.0, pts[0].distance(pts[3]) / 4.0);
        mb.face(m.windows, &pts, &[uv(0.0, h), uv(w, h), uv(w, 0.0), uv(0.0, 0.0)], out, WHITE);
    };
    for (lat, out) in [(-reach[0], -a.right), (reach[1], a.right)] {
        quad([beside(a, lat, 0.0), beside(b, lat, 0.0), beside(b, lat, top), beside(a, lat, top)], out);
    }
    let (l, r) = (-wall_at[0], wall_at[1]);
    for (f, out) in [(a, -a.fwd), (b, b.fwd)] {
        for (x0, x1, y0) in [(-reach[0], l, 0.0), (r, reach[1], 0.0), (l, r, TUNNEL_CEILING)] {
            quad([beside(f, x0, y0), beside(f, x1, y0), beside(f, x1, top), beside(f, x0, top)], out);
        }
    }
    let roof =
        [beside(a, -reach[0], top), beside(a, reach[1], top), beside(b, reach[1], top), beside(b, -reach[0], top)];
    let len = a.p.distance(b.p) / 4.0;
    mb.face(m.roof, &roof, &[uv(0.0, 0.0), uv(1.0, 0.0), uv(1.0, len), uv(0.0, len)], Vec3::Y, WHITE);
    mb
}

/// The tunnel, the buildings lining the street, and the city behind them.
pub(super) fn city(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain) {
    let block = tunnel(scene, m, c);
    let mut b = Builder { c, t, taken: vec![block], models: Models::default(), count: 0 };
    // The street: a building every few metres on both sides, a pavement behind the barriers.
    for side in 0..2 {
        let mut s = 0.0;
        while s < c.length {
            let f = c.at(s);
            let i = (s / c.step).round() as usize % c.n();
            let out = Vec2::new(f.right.x, f.right.z) * [-1.0, 1.0][side];
            let length = LENGTHS[scene.rng.int(0, LENGTHS.len() as i32 - 1) as usize];
            let size = Vec3::new(length, scene.rng.range(9.0, 40.0), scene.rng.range(14.0, 26.0));
            let setback = c.samples[i].bo[side] + scene.rng.range(2.5, 4.5);
            let p = f.p + f.right * (setback * [-1.0, 1.0][side]);
            let placed = b.place(scene, m, Vec2::new(p.x, p.z), out, size, (c.samples[i].bo[side] + 2.0, 0.5));
            s += if placed { length + scene.rng.range(0.5, 3.0) } else { 4.0 };
        }
    }
    // The blocks behind: a jittered grid over the city, taller toward its middle.
    let (lo, hi) = c.bounds();
    let (lo, hi) = (lo - Vec2::splat(260.0), hi + Vec2::splat(260.0));
    let middle = (lo + hi) * 0.5;
    let spread = (hi - lo).length() * 0.5;
    let mut z = lo.y;
    while z < hi.y {
        let mut x = lo.x;
        while x < hi.x {
            let jitter = Vec2::new(scene.rng.range(-6.0, 6.0), scene.rng.range(-6.0, 6.0));
            let p = Vec2::new(x, z) + jitter;
            let near = 1.0 - (p.distance(middle) / spread).min(1.0);
            let tall = scene.rng.unit() < 0.12 * near + 0.03;
            let height = if tall { scene.rng.range(50.0, 95.0) } else { scene.rng.range(10.0, 30.0 + 20.0 * near) };
            let size = Vec3::new(scene.rng.range(16.0, 32.0), height, scene.rng.range(14.0, 26.0));
            let out = if scene.rng.unit() < 0.5 { Vec2::Y } else { Vec2::X };
            if scene.rng.unit() < 0.8 {
                b.place(scene, m, p, out, size, (18.0, 4.0));
            }
            x += 38.0;
        }
        z += 36.0;
    }
}
