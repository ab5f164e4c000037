//! The race circuit: a closed figure-eight of about 4.2 km that crosses over itself on a bridge, written as
//! `circuit.gltf` + `circuit.bin`, its PNG textures and `centerline.json`.
//!
//! The plan is a polygon of hand-placed corner points whose corners are rounded by circular arcs of given
//! radii, so straights and corner radii are exact (a 640 m main straight, hairpins of 32-45 m, sweepers of
//! 150-220 m). Heights come from smooth bumps along the track (the bridge ramps and two crests on
//! embankments); banking is a roll of the cross-section that follows the smoothed curvature. The ground is
//! flat (y = 0) around the circuit and rolls gently further out, up to a ring of distant hills. Everything is
//! made from constants and a fixed-seed PRNG: the same bytes on every run.
//!
//! Conventions: glTF (Y up, metres, counter-clockwise front faces). Every polygon is oriented by the normal it
//! should face ([`MeshBuilder::face`]) and carries a vertex colour from a fixed sun, so the unlit renderer
//! still shows the shape of things (and the banking).

use std::path::Path;

use glam::{Mat3, Quat, Vec2, Vec3};
use serde_json::{Value, json};

use crate::gltf_out::{Doc, Primitive, WrapMode, placed};
use crate::paint::Canvas;

/// What other generators need to know about the circuit.
#[derive(Clone, Debug, Default)]
pub struct TrackInfo {
    /// Start grid slots: position on the road surface and heading (yaw about +Y, 0 = facing -Z, positive
    /// toward +X: forward = (sin yaw, 0, -cos yaw)).
    pub grid: Vec<(Vec3, f32)>,
    /// Named viewpoints: (name, eye, target).
    pub views: Vec<(String, Vec3, Vec3)>,
}

/// Corner points of the plan (x, z in metres) and the radius of the arc that rounds each, in racing order.
/// The straight into corner 0 climbs over the straight into corner 7 on a bridge.
const CORNERS: [(f32, f32, f32); 11] = [
    (-130.0, 360.0, 45.0),   // 0: tight left onto the main straight
    (670.0, 360.0, 170.0),   // 1: fast left at the end of the main straight
    (760.0, 70.0, 220.0),    // 2: fast left over the first crest
    (710.0, -200.0, 32.0),   // 3: hairpin
    (535.0, -150.0, 70.0),   // 4: right
    (390.0, -290.0, 60.0),   // 5: left
    (120.0, -260.0, 150.0),  // 6: fast left onto the diagonal that passes under the bridge
    (-300.0, 215.0, 35.0),   // 7: tight right
    (-600.0, 260.0, 160.0),  // 8: long fast right
    (-655.0, -170.0, 40.0),  // 9: tight right after the second crest
    (-385.0, -285.0, 150.0), // 10: fast right onto the diagonal that climbs over the bridge
];
/// The straight (into this corner) that carries the bridge.
const BRIDGE_EDGE: usize = 0;
/// The straight (into this corner) with the start line, and how far along it the line is.
const START_EDGE: usize = 1;
const START_AT: f32 = 250.0;
/// Crests on embankments: (plan segment: 2k = straight into corner k, 2k+1 = arc of corner k), fraction along
/// it, height, half-length of the top, length of each ramp.
const CRESTS: [(usize, f32, f32, f32, f32); 2] = [(5, 0.5, 5.0, 30.0, 150.0), (18, 0.5, 4.0, 20.0, 110.0)];

/// Half the road width.
const HALF_WIDTH: f32 = 6.0;
/// Road surface above the ground where the track is at ground level.
const ROAD_LIFT: f32 = 0.08;
/// Centreline sample spacing (the road mesh uses every sample in tight corners and every other elsewhere).
const SAMPLE_STEP: f32 = 5.0;
/// Height of the upper road's embankment at the crossing (road surface ~8.4 m, deck underside ~7.1 m).
const BRIDGE_HEIGHT: f32 = 8.3;
/// Deck thickness under the road on the bridge.
const DECK_DEPTH: f32 = 1.3;
/// Kerb width outside the road edge.
const KERB_WIDTH: f32 = 1.2;
/// Barrier offset from the centreline on straights, and on embankments.
const BARRIER_OFFSET: f32 = 11.0;
const BARRIER_OFFSET_RAISED: f32 = 8.0;
/// Start grid size.
const GRID_SLOTS: usize = 12;
/// Side of the centreline: left, right.
const SIDE: [f32; 2] = [-1.0, 1.0];
/// Ground tile size (the painter's methods need polygons of moderate size), the finer tiles near the track,
/// and the ground's radius.
const TILE: f32 = 100.0;
const FINE_TILE: f32 = 25.0;
/// How far the grass strips beside the track reach beyond the track's corridor (they cover what the finer
/// tiles leave out near the track).
const APRON: f32 = 44.0;
/// Metres per repeat of the grass texture (world-space coordinates, so overlapping grass looks the same).
const GRASS_UV: f32 = 20.0;
const GROUND_RADIUS: f32 = 2150.0;
/// Trees: how far from the centreline they must stay.
const TREE_CLEARANCE: f32 = 30.0;
/// Direction toward the sun (for the baked shading).
const SUN: Vec3 = Vec3::new(0.30, 0.80, 0.52);
const WHITE: Vec3 = Vec3::ONE;

/// Writes `circuit.gltf`, its `.bin`, textures and `centerline.json` into `dir`.
pub fn generate(dir: &Path) -> std::io::Result<TrackInfo> {
    let circuit = Circuit::new()?;
    write_textures(dir)?;
    let mut doc = Doc::new();
    let mats = Mats::new(&mut doc);
    let mut scene = Scene { doc, rng: Rng::new(0x5eed_7ac4), keep_out: vec![] };
    track_meshes(&mut scene, &mats, &circuit);
    bridge_mesh(&mut scene, &mats, &circuit);
    let grid = grid_slots(&circuit);
    start_mesh(&mut scene, &mats, &circuit, &grid);
    let stands = grandstands(&mut scene, &mats, &circuit);
    buildings(&mut scene, &mats, &circuit);
    let terrain = Terrain::new(&circuit);
    ground_meshes(&mut scene, &mats, &circuit, &terrain);
    hills_meshes(&mut scene, &mats, &terrain);
    trees(&mut scene, &mats, &circuit, &terrain);
    let info = TrackInfo { views: views(&circuit, &grid, &stands), grid };
    let cameras = camera_nodes(&mut scene.doc, &info);
    scene.doc.write(dir, "circuit")?;
    add_cameras(&dir.join("circuit.gltf"), cameras)?;
    write_centerline(dir, &circuit)?;
    Ok(info)
}

// ---------------------------------------------------------------------------------------------------------
// Small helpers

/// A small deterministic PRNG (xorshift64*).
struct Rng(u64);

impl Rng {
    fn new(seed: u64) -> Self {
        Self(seed | 1)
    }

    fn next(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        x.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }

    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }

    /// Uniform integer in lo..=hi.
    fn int(&mut self, lo: i32, hi: i32) -> i32 {
        lo + (self.next() % (hi - lo + 1).max(1) as u64) as i32
    }
}

fn other(msg: String) -> std::io::Error {
    std::io::Error::other(format!("track: {msg}"))
}

fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The left of a plan direction (x, z), seen from above with -Z ahead.
fn left(d: Vec2) -> Vec2 {
    Vec2::new(d.y, -d.x)
}

/// Plan cross product (x, z).
fn cross2(a: Vec2, b: Vec2) -> f32 {
    a.x * b.y - a.y * b.x
}

/// Distance between two positions on a closed loop of length `len`.
fn loop_dist(a: f32, b: f32, len: f32) -> f32 {
    let d = (a - b).rem_euclid(len);
    d.min(len - d)
}

fn uv(u: f32, v: f32) -> Vec2 {
    Vec2::new(u, v)
}

/// Texture coordinates from world x and z (for ground-like surfaces).
fn world_uvs(pts: &[Vec3], metres: f32) -> Vec<Vec2> {
    pts.iter().map(|p| Vec2::new(p.x / metres, p.z / metres)).collect()
}

/// The yaw to give [`placed`] so that a node's local -Z points along `d` (glTF rotation about +Y).
fn node_yaw(d: Vec3) -> f32 {
    (-d.x).atan2(-d.z)
}

/// Rounds for JSON output (3 decimals, no negative zero).
fn r3(v: f32) -> f64 {
    (f64::from(v) * 1000.0).round() / 1000.0 + 0.0
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
struct MeshBuilder {
    prims: Vec<Primitive>,
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
    fn face(&mut self, mat: usize, pts: &[Vec3], uvs: &[Vec2], want: Vec3, tint: Vec3) {
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
    fn cuboid(&mut self, side: usize, top: Option<usize>, b: &Block, tex: f32, tint: Vec3) {
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
struct Block {
    base: Vec3,
    ax: Vec3,
    az: Vec3,
    half: Vec2,
    height: f32,
}

/// The document being built, the PRNG for placement, and footprints that trees must avoid.
struct Scene {
    doc: Doc,
    rng: Rng,
    /// (centre, radius) on the plan (x, z).
    keep_out: Vec<(Vec2, f32)>,
}

impl Scene {
    /// Adds `mb` as a mesh placed by a root node at the origin (nothing when it is empty).
    fn add(&mut self, name: &str, mb: &MeshBuilder) {
        if mb.triangles() > 0 {
            let mesh = self.doc.mesh(name, &mb.prims);
            self.doc.node(json!({"name": name, "mesh": mesh}), true);
        }
    }
}

// ---------------------------------------------------------------------------------------------------------
// The plan: straights and arcs

#[derive(Clone, Copy, Debug)]
enum Piece {
    /// A straight from `p0` along `d`.
    Line { p0: Vec2, d: Vec2 },
    /// An arc from `p0` leaving along `d`, bending toward `side` with radius `r`; `sign` is +1 for left.
    Arc { p0: Vec2, d: Vec2, side: Vec2, r: f32, sign: f32 },
}

#[derive(Clone, Copy, Debug)]
struct Segment {
    s0: f32,
    len: f32,
    piece: Piece,
}

/// The closed centreline in plan: straights between corners rounded by arcs.
struct Plan {
    segs: Vec<Segment>,
    length: f32,
}

impl Plan {
    fn new(corners: &[(f32, f32, f32)]) -> std::io::Result<Plan> {
        let n = corners.len();
        let pt = |i: usize| Vec2::new(corners[i % n].0, corners[i % n].1);
        // Per corner: incoming and outgoing directions, signed turn, tangent length.
        let mut fillets = vec![];
        for (i, c) in corners.iter().enumerate() {
            let p = pt(i);
            let a = (p - pt(i + n - 1)).normalize_or_zero();
            let b = (pt(i + 1) - p).normalize_or_zero();
            let turn = left(a).dot(b).atan2(a.dot(b));
            fillets.push((p, a, b, turn, c.2 * (turn.abs() / 2.0).tan(), c.2));
        }
        let mut segs = vec![];
        let mut s = 0.0;
        for (i, &(p, a, _, turn, t, r)) in fillets.iter().enumerate() {
            let (q, _, qb, _, qt, _) = fillets[(i + n - 1) % n];
            let start = q + qb * qt;
            let end = p - a * t;
            let len = (end - start).dot(a);
            if len < 0.0 {
                return Err(other(format!("corner {i} does not fit its neighbours")));
            }
            segs.push(Segment { s0: s, len, piece: Piece::Line { p0: start, d: a } });
            s += len;
            let sign = if turn >= 0.0 { 1.0 } else { -1.0 };
            let len = r * turn.abs();
            segs.push(Segment { s0: s, len, piece: Piece::Arc { p0: end, d: a, side: left(a) * sign, r, sign } });
            s += len;
        }
        Ok(Plan { segs, length: s })
    }

    /// Position, direction and signed curvature (positive turning left) at distance `s`.
    fn eval(&self, s: f32) -> (Vec2, Vec2, f32) {
        let s = s.rem_euclid(self.length);
        let k = self.segs.partition_point(|g| g.s0 + g.len <= s).min(self.segs.len() - 1);
        let g = self.segs[k];
        let u = s - g.s0;
        match g.piece {
            Piece::Line { p0, d } => (p0 + d * u, d, 0.0),
            Piece::Arc { p0, d, side, r, sign } => {
                let th = u / r;
                (p0 + (d * th.sin() + side * (1.0 - th.cos())) * r, d * th.cos() + side * th.sin(), sign / r)
            }
        }
    }

    /// Where the straight into corner `edge` crosses another straight: (its s, the other's s, the point, its
    /// direction, the other's direction).
    fn crossing(&self, edge: usize) -> Option<(f32, f32, Vec2, Vec2, Vec2)> {
        let g = self.segs.get(2 * edge)?;
        let Piece::Line { p0, d } = g.piece else { return None };
        for (j, h) in self.segs.iter().enumerate() {
            let Piece::Line { p0: q0, d: e } = h.piece else { continue };
            let den = cross2(d, e);
            if j == 2 * edge || den.abs() < 1e-4 {
                continue;
            }
            let w = q0 - p0;
            let (t, u) = (cross2(w, e) / den, cross2(w, d) / den);
            if (0.0..=g.len).contains(&t) && (0.0..=h.len).contains(&u) {
                return Some((g.s0 + t, h.s0 + u, p0 + d * t, d, e));
            }
        }
        None
    }

    /// Distance along the plan of `frac` of segment `seg`.
    fn at_segment(&self, seg: usize, frac: f32) -> f32 {
        self.segs.get(seg).map_or(0.0, |g| g.s0 + g.len * frac)
    }
}

// ---------------------------------------------------------------------------------------------------------
// The circuit: samples along the centreline in racing order from the start line

/// One centreline sample.
#[derive(Clone, Copy, Debug)]
struct Sample {
    /// Distance from the start line.
    s: f32,
    /// Road surface at the centre.
    p: Vec3,
    /// Horizontal unit vectors ahead and to the right.
    fwd: Vec3,
    right: Vec3,
    /// The banked lateral unit vector (to the right edge).
    lat: Vec3,
    /// Roll of the cross-section, radians, positive raising the right side (left-hand corners).
    bank: f32,
    /// Smoothed and exact curvature, positive turning left.
    kappa: f32,
    kappa_raw: f32,
    /// Height of the embankment under the road.
    h: f32,
    /// Barrier offsets from the centreline, left and right.
    bo: [f32; 2],
    /// Gravel run-off (outside of tight corners), left and right.
    gravel: [bool; 2],
}

impl Sample {
    /// The cross-section at `s` from the plan position and direction, the smoothed and exact curvature, the
    /// embankment height and the bank angle: barriers further out on the outside of tight corners (gravel
    /// there), closer in on embankments.
    fn new(s: f32, (pos, dir): (Vec2, Vec2), (kappa, kappa_raw): (f32, f32), h: f32, bank: f32) -> Sample {
        let fwd = Vec3::new(dir.x, 0.0, dir.y);
        let right = Vec3::new(-dir.y, 0.0, dir.x);
        let lat = right * bank.cos() + Vec3::Y * bank.sin();
        // The roll pivots about the lower edge, so that edge stays at the lift above the ground.
        let p = Vec3::new(pos.x, h + ROAD_LIFT + HALF_WIDTH * bank.sin().abs(), pos.y);
        let extra = 10.0 * ((kappa.abs() - 0.006) * 80.0).clamp(0.0, 1.0);
        let outside = usize::from(kappa > 0.0);
        let mut bo = [BARRIER_OFFSET; 2];
        let mut gravel = [false; 2];
        bo[outside] += extra;
        gravel[outside] = extra > 2.0;
        let raised = smoothstep(0.4, 2.0, h);
        let bo = bo.map(|b| b + (BARRIER_OFFSET_RAISED - b) * raised);
        Sample { s, p, fwd, right, lat, bank, kappa, kappa_raw, h, bo, gravel }
    }

    fn edge(&self, side: usize) -> Vec3 {
        self.p + self.lat * (HALF_WIDTH * SIDE[side])
    }

    fn out(&self, side: usize) -> Vec3 {
        self.right * SIDE[side]
    }

    /// The verge's outer line (foot of the barrier), level with the road edge.
    fn verge(&self, side: usize) -> Vec3 {
        self.edge(side) + self.out(side) * (self.bo[side] - HALF_WIDTH)
    }
}

/// Heights along the plan: smooth bumps of (centre, height, half-length of the top, length of each ramp).
struct Profile {
    bumps: Vec<(f32, f32, f32, f32)>,
    length: f32,
}

impl Profile {
    fn height(&self, s: f32) -> f32 {
        let bump = |&(c, h, top, ramp): &(f32, f32, f32, f32)| {
            h * smoothstep(0.0, 1.0, (top + ramp - loop_dist(s, c, self.length)) / ramp)
        };
        self.bumps.iter().map(bump).sum()
    }
}

/// A position and frame on the centreline.
#[derive(Clone, Copy, Debug)]
struct Frame {
    p: Vec3,
    fwd: Vec3,
    right: Vec3,
    lat: Vec3,
}

struct Circuit {
    length: f32,
    step: f32,
    samples: Vec<Sample>,
    /// Start-line distances of the crossing on the upper and the lower road, and its plan point.
    upper_s: f32,
    lower_s: f32,
    cross_point: Vec2,
    /// Sample nearest the crossing on the upper road, and how many samples either side are open span.
    upper_i: usize,
    span: usize,
    /// Offset along the upper road of the pier rows either side of the lower road.
    pier_offset: f32,
    /// Start-line distances of the corners' apexes.
    apex: Vec<f32>,
    /// How far from the centreline each sample's grass apron reaches, left and right.
    apron: Vec<[f32; 2]>,
    /// Each sample's corridor, left and right ([`Circuit::reach`]).
    widths: Vec<[f32; 2]>,
    /// Texture repeat lengths that divide the lap exactly (road, kerb, barrier).
    road_tile: f32,
    kerb_tile: f32,
    barrier_tile: f32,
}

impl Circuit {
    fn new() -> std::io::Result<Circuit> {
        let plan = Plan::new(&CORNERS)?;
        let length = plan.length;
        let start = plan.at_segment(2 * START_EDGE, 0.0) + START_AT;
        let race = |raw: f32| (raw - start).rem_euclid(length);
        let (up_raw, low_raw, cross_point, up_dir, low_dir) =
            plan.crossing(BRIDGE_EDGE).ok_or_else(|| other("the bridge straight crosses nothing".into()))?;
        let mut bumps = vec![(up_raw, BRIDGE_HEIGHT, 35.0, 185.0)];
        bumps.extend(CRESTS.iter().map(|&(seg, frac, h, top, ramp)| (plan.at_segment(seg, frac), h, top, ramp)));
        let profile = Profile { bumps, length };
        let n = (length / SAMPLE_STEP).round() as usize;
        let step = length / n as f32;
        let raw: Vec<(Vec2, Vec2, f32)> = (0..n).map(|i| plan.eval(start + i as f32 * step)).collect();
        let upper_s = race(up_raw);
        let lower_s = race(low_raw);
        let mut samples = Vec::with_capacity(n);
        for (i, &(pos, dir, kappa_raw)) in raw.iter().enumerate() {
            let s = i as f32 * step;
            let kappa = (0..11).map(|j| raw[(i + n + j - 5) % n].2).sum::<f32>() / 11.0;
            // No banking where the roads cross.
            let calm = smoothstep(60.0, 100.0, loop_dist(s, upper_s, length))
                * smoothstep(40.0, 80.0, loop_dist(s, lower_s, length));
            let bank = (kappa * 24.0).clamp(-0.18, 0.18) * calm;
            samples.push(Sample::new(s, (pos, dir), (kappa, kappa_raw), profile.height(start + s), bank));
        }
        let upper_i = (upper_s / step).round() as usize % n;
        let lower_i = (lower_s / step).round() as usize % n;
        // The open span must clear the lower road's barriers (with room for the piers) and the abutments'
        // feet; the piers stand just outside the lower road's barriers.
        let (sin_a, cos_a) = (cross2(up_dir, low_dir).abs().max(0.2), up_dir.dot(low_dir).abs());
        let lower_bo = samples[lower_i].bo[0].max(samples[lower_i].bo[1]);
        let pier_offset = (lower_bo + 2.0 + 6.0 * cos_a) / sin_a;
        let abutment = (lower_bo + 5.0 + (BARRIER_OFFSET_RAISED + 2.5) * cos_a) / sin_a;
        let span = (abutment / step).ceil() as usize;
        let apex = (0..CORNERS.len()).map(|k| race(plan.at_segment(2 * k + 1, 0.5))).collect();
        let tile = |t: f32| length / (length / t).round();
        let mut c = Circuit {
            length,
            step,
            samples,
            upper_s,
            lower_s,
            cross_point,
            upper_i,
            span,
            pier_offset,
            apex,
            road_tile: tile(12.0),
            kerb_tile: tile(3.0),
            barrier_tile: tile(4.0),
            apron: vec![],
            widths: vec![],
        };
        c.widths = (0..c.n()).map(|i| [c.reach(i, 0), c.reach(i, 1)]).collect();
        c.apron = (0..c.n()).map(|i| [0, 1].map(|side| c.apron_extent(i, side))).collect();
        Ok(c)
    }

    /// Half-width of the corridor kept free of ground on one side of sample `i`: to the barrier line, or to
    /// the embankment's foot.
    fn reach(&self, i: usize, side: usize) -> f32 {
        let y = self.samples[i].verge(side).y;
        self.samples[i].bo[side] + if y > 0.15 { self.foot(i, y) } else { 0.0 }
    }

    /// Whether no ground may lie within the corridor of sample `i` (everything but the open span).
    fn on_ground(&self, i: usize) -> bool {
        !self.in_span(i)
    }

    /// The corridor around sample `j` as a plan rectangle, grown by `margin`: centre, ahead and right unit
    /// vectors, range along (symmetric) and range across (left, right). The corridor is the union of these.
    fn slab(&self, j: usize, margin: f32) -> (Vec2, Vec2, Vec2, f32, [f32; 2]) {
        let t = &self.samples[j];
        let across = [-(self.widths[j][0] + margin), self.widths[j][1] + margin];
        (
            Vec2::new(t.p.x, t.p.z),
            Vec2::new(t.fwd.x, t.fwd.z),
            Vec2::new(t.right.x, t.right.z),
            self.step * 0.5 + 0.5,
            across,
        )
    }

    /// How far the apron of sample `i` may reach: up to [`APRON`] beyond the corridor, stopping short of any
    /// other part of the track (the bridge ramps excepted: ground under them is hidden by the embankment).
    fn apron_extent(&self, i: usize, side: usize) -> f32 {
        let s = &self.samples[i];
        let start = self.reach(i, side);
        let origin = Vec2::new(s.p.x, s.p.z);
        let out = Vec2::new(s.right.x, s.right.z) * SIDE[side];
        let clear = |x: f32| {
            let q = origin + out * x;
            (0..self.n()).all(|j| {
                if !self.on_ground(j) || (self.bridge_zone(j) && self.samples[j].h > 0.5) {
                    return true;
                }
                let (p, fwd, right, along, across) = self.slab(j, 1.0);
                let (a, l) = ((q - p).dot(fwd), (q - p).dot(right));
                a.abs() >= along || l <= across[0] || l >= across[1]
            })
        };
        // On the inside of a corner the apron stops at the centre of the arc (beyond it would fold over).
        let limit = if s.kappa_raw * SIDE[side] < 0.0 { 1.0 / s.kappa_raw.abs() } else { f32::INFINITY };
        let cap = (start + APRON).min(limit);
        let mut a = start;
        while a < cap {
            let next = (a + 2.0).min(cap);
            if !clear(next) {
                break;
            }
            a = next;
        }
        a
    }

    /// Whether a plan rectangle overlaps the corridor (grown by 3 m) of any sample on the ground (separating
    /// axis test against each sample's rectangle).
    fn touches(&self, lo: Vec2, hi: Vec2) -> bool {
        let rect = [lo, Vec2::new(hi.x, lo.y), hi, Vec2::new(lo.x, hi.y)];
        let range = |pts: &[Vec2], axis: Vec2, origin: Vec2| {
            pts.iter()
                .map(|q| (*q - origin).dot(axis))
                .fold((f32::INFINITY, f32::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
        };
        (0..self.n()).any(|j| {
            if !self.on_ground(j) {
                return false;
            }
            let (p, fwd, right, along, across) = self.slab(j, 3.0);
            let corners = [(-along, across[0]), (along, across[0]), (along, across[1]), (-along, across[1])]
                .map(|(a, l)| p + fwd * a + right * l);
            let (f0, f1) = range(&rect, fwd, p);
            let (r0, r1) = range(&rect, right, p);
            let (x0, x1) = range(&corners, Vec2::X, Vec2::ZERO);
            let (z0, z1) = range(&corners, Vec2::Y, Vec2::ZERO);
            f1 > -along
                && f0 < along
                && r1 > across[0]
                && r0 < across[1]
                && x1 > lo.x
                && x0 < hi.x
                && z1 > lo.y
                && z0 < hi.y
        })
    }

    fn n(&self) -> usize {
        self.samples.len()
    }

    /// Index distance between two samples around the loop.
    fn index_dist(&self, a: usize, b: usize) -> usize {
        let d = (a + self.n() - b) % self.n();
        d.min(self.n() - d)
    }

    /// Whether sample `i` is over the open span of the bridge (no embankment under it).
    fn in_span(&self, i: usize) -> bool {
        self.index_dist(i, self.upper_i) <= self.span
    }

    /// Whether sample `i` is on the bridge's ramps (steep concrete sides, parapets).
    fn bridge_zone(&self, i: usize) -> bool {
        loop_dist(self.samples[i].s, self.upper_s, self.length) < 240.0
    }

    /// Whether sample `i` has kerbs.
    fn kerb(&self, i: usize) -> bool {
        self.samples[i].kappa.abs() > 1.0 / 260.0
    }

    /// Horizontal reach of the embankment side beyond the barrier at sample `i`, for a verge `height` up.
    fn foot(&self, i: usize, height: f32) -> f32 {
        if self.bridge_zone(i) { 0.2 * height + 0.3 } else { 1.5 * height + 0.3 }
    }

    /// Whether the road mesh needs every sample around `i` (tight corners, the crossing).
    fn fine(&self, i: usize) -> bool {
        let lower_i = (self.lower_s / self.step).round() as usize % self.n();
        self.samples[i].kappa_raw.abs() > 1.0 / 90.0
            || self.index_dist(i, self.upper_i) <= self.span + 6
            || self.index_dist(i, lower_i) <= 8
    }

    /// The samples the road mesh uses, in order.
    fn road_indices(&self) -> Vec<usize> {
        let n = self.n();
        let mut idx = vec![0];
        let mut i = 0;
        while i < n {
            i += if self.fine(i) || self.fine((i + 1) % n) { 1 } else { 2 };
            if i < n {
                idx.push(i);
            }
        }
        idx
    }

    /// The frame at distance `s` from the start line (interpolated between samples).
    fn at(&self, s: f32) -> Frame {
        let x = s.rem_euclid(self.length) / self.step;
        let i = (x.floor() as usize).min(self.n() - 1);
        let t = x - i as f32;
        let (a, b) = (&self.samples[i], &self.samples[(i + 1) % self.n()]);
        Frame {
            p: a.p.lerp(b.p, t),
            fwd: a.fwd.lerp(b.fwd, t).normalize_or_zero(),
            right: a.right.lerp(b.right, t).normalize_or_zero(),
            lat: a.lat.lerp(b.lat, t).normalize_or_zero(),
        }
    }

    /// Plan distance from `p` (x, z) to the nearest centreline sample.
    fn distance(&self, p: Vec2) -> f32 {
        self.samples.iter().map(|s| Vec2::new(s.p.x, s.p.z).distance_squared(p)).fold(f32::INFINITY, f32::min).sqrt()
    }

    /// Plan bounds of the centreline.
    fn bounds(&self) -> (Vec2, Vec2) {
        let mut lo = Vec2::splat(f32::INFINITY);
        let mut hi = Vec2::splat(f32::NEG_INFINITY);
        for s in &self.samples {
            lo = lo.min(Vec2::new(s.p.x, s.p.z));
            hi = hi.max(Vec2::new(s.p.x, s.p.z));
        }
        (lo, hi)
    }
}

// ---------------------------------------------------------------------------------------------------------
// Textures and materials

/// Material indices.
struct Mats {
    road: usize,
    kerb: usize,
    grass: usize,
    gravel: usize,
    armco: usize,
    tyres: usize,
    concrete: usize,
    parapet: usize,
    chequer: usize,
    crowd: usize,
    windows: usize,
    roof: usize,
    canopy: usize,
    paint: usize,
    tree: usize,
    hills: usize,
}

impl Mats {
    fn new(doc: &mut Doc) -> Mats {
        let mut tex = |name: &str, wrap| doc.texture(&format!("{name}.png"), wrap);
        let t_asphalt = tex("asphalt", WrapMode::Repeat);
        let t_kerb = tex("kerb", WrapMode::Repeat);
        let t_grass = tex("grass", WrapMode::Repeat);
        let t_gravel = tex("gravel", WrapMode::Repeat);
        let t_armco = tex("armco", WrapMode::Repeat);
        let t_tyres = tex("tyres", WrapMode::Repeat);
        let t_concrete = tex("concrete", WrapMode::Repeat);
        let t_chequer = tex("chequer", WrapMode::Repeat);
        let t_crowd = tex("crowd", WrapMode::Repeat);
        let t_windows = tex("windows", WrapMode::Repeat);
        let t_tree = tex("trees", WrapMode::Clamp);
        let white = glam::Vec4::ONE;
        Mats {
            road: doc.material("asphalt", white, Some(t_asphalt), false, None),
            kerb: doc.material("kerb", white, Some(t_kerb), false, None),
            grass: doc.material("grass", white, Some(t_grass), false, None),
            gravel: doc.material("gravel", white, Some(t_gravel), false, None),
            armco: doc.material("armco", white, Some(t_armco), true, Some(0.5)),
            tyres: doc.material("tyre wall", white, Some(t_tyres), true, None),
            concrete: doc.material("concrete", white, Some(t_concrete), false, None),
            parapet: doc.material("parapet", white, Some(t_concrete), true, None),
            chequer: doc.material("chequer", white, Some(t_chequer), false, None),
            crowd: doc.material("crowd", white, Some(t_crowd), false, None),
            windows: doc.material("windows", white, Some(t_windows), false, None),
            roof: doc.material("roof", glam::Vec4::new(0.42, 0.43, 0.46, 1.0), None, false, None),
            canopy: doc.material("canopy", glam::Vec4::new(0.85, 0.86, 0.88, 1.0), None, true, None),
            paint: doc.material("paint", glam::Vec4::new(0.95, 0.95, 0.93, 1.0), None, false, None),
            tree: doc.material("trees", white, Some(t_tree), true, Some(0.5)),
            hills: doc.material("hills", white, None, false, None),
        }
    }
}

fn shade(c: [u8; 3], d: i32) -> [u8; 4] {
    let f = |v: u8| (i32::from(v) + d).clamp(0, 255) as u8;
    [f(c[0]), f(c[1]), f(c[2]), 255]
}

/// A canvas of `base` with per-pixel grain of +-`amp`.
fn grain(size: u32, base: [u8; 3], amp: i32, rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(size, size, [0, 0, 0, 255]);
    for y in 0..size as i32 {
        for x in 0..size as i32 {
            let d = rng.int(-amp, amp);
            c.set(x, y, shade(base, d));
        }
    }
    c
}

fn write_textures(dir: &Path) -> std::io::Result<()> {
    let mut rng = Rng::new(0x7e57_0001);
    let rng = &mut rng;
    // Asphalt: 128 px across the 12 m road, white edge lines, darker wheel tracks.
    let mut asphalt = grain(128, [84, 84, 88], 9, rng);
    for y in 0..128 {
        for x in 0..128 {
            let g = rng.int(-8, 8);
            if (3..7).contains(&x) || (121..125).contains(&x) {
                asphalt.set(x, y, shade([226, 226, 220], g));
            } else if (26..40).contains(&x) || (88..102).contains(&x) {
                asphalt.set(x, y, shade([74, 74, 78], g));
            }
        }
    }
    asphalt.save(&dir.join("asphalt.png"))?;
    // Kerb: red and white stripes along the track, the outer quarter a shade darker.
    let mut kerb = Canvas::new(64, 64, [0, 0, 0, 255]);
    for y in 0..64 {
        for x in 0..64 {
            let base = if y < 32 { [206, 36, 30] } else { [240, 240, 236] };
            kerb.set(x, y, shade(base, rng.int(-6, 6) - if x >= 48 { 30 } else { 0 }));
        }
    }
    kerb.save(&dir.join("kerb.png"))?;
    grain(64, [74, 128, 54], 7, rng).save(&dir.join("grass.png"))?;
    let mut gravel = grain(64, [196, 180, 144], 16, rng);
    for _ in 0..90 {
        let (x, y) = (rng.int(0, 63), rng.int(0, 63));
        gravel.set(x, y, [150, 136, 110, 255]);
        gravel.set(x + 1, y, [226, 214, 186, 255]);
    }
    gravel.save(&dir.join("gravel.png"))?;
    armco_texture(rng).save(&dir.join("armco.png"))?;
    tyres_texture(rng).save(&dir.join("tyres.png"))?;
    let mut concrete = grain(64, [172, 170, 164], 8, rng);
    for i in 0..64 {
        concrete.set(i, 0, [120, 118, 114, 255]);
        concrete.set(0, i, [120, 118, 114, 255]);
    }
    concrete.save(&dir.join("concrete.png"))?;
    let mut chequer = Canvas::new(64, 64, [0, 0, 0, 255]);
    for y in 0..64 {
        for x in 0..64 {
            let c = if (x / 8 + y / 8) % 2 == 0 { [20, 20, 22, 255] } else { [238, 238, 236, 255] };
            chequer.set(x, y, c);
        }
    }
    chequer.save(&dir.join("chequer.png"))?;
    crowd_texture(rng).save(&dir.join("crowd.png"))?;
    windows_texture(rng).save(&dir.join("windows.png"))?;
    trees_texture(rng).save(&dir.join("trees.png"))
}

/// Armco: two steel rails on posts every 4 m; transparent between (alpha mask).
fn armco_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(64, 64, [90, 90, 90, 0]);
    for y in 0..64 {
        for x in 0..64 {
            let rail = (4..22).contains(&y) || (26..42).contains(&y);
            if rail {
                let ridge = [0, 18, 30, 18, 0, -18][(y % 6) as usize];
                c.set(x, y, shade([176, 180, 186], ridge + rng.int(-5, 5)));
            } else if x < 5 && y >= 2 {
                c.set(x, y, shade([96, 98, 104], rng.int(-5, 5)));
            }
        }
    }
    c
}

/// Tyre wall: red and white belt on top, stacked tyres below.
fn tyres_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(64, 64, [28, 28, 30, 255]);
    for y in 0..64i32 {
        for x in 0..64i32 {
            let col = if y < 18 {
                if (x / 16) % 2 == 0 { [210, 40, 34] } else { [236, 236, 232] }
            } else {
                let (cx, cy) = ((x / 16) * 16 + 8, if y < 41 { 29 } else { 52 });
                let r2 = (x - cx) * (x - cx) + (y - cy) * (y - cy);
                if r2 < 16 {
                    [52, 52, 56]
                } else if r2 < 64 {
                    [18, 18, 20]
                } else {
                    [34, 34, 36]
                }
            };
            c.set(x, y, shade(col, rng.int(-4, 4)));
        }
    }
    c
}

/// Crowd: rows of spectators (shirts and heads) on dark seats; one row per 16 px.
fn crowd_texture(rng: &mut Rng) -> Canvas {
    let mut c = grain(128, [46, 52, 70], 6, rng);
    let shirts = [[200, 40, 40], [240, 200, 40], [40, 90, 200], [240, 240, 240], [40, 160, 70], [230, 120, 30]];
    let skins = [[236, 196, 160], [200, 150, 110], [140, 96, 66]];
    for row in 0..8 {
        let mut x = rng.int(0, 3);
        while x < 126 {
            let y = row * 16 + 3 + rng.int(0, 2);
            if rng.unit() < 0.88 {
                let shirt = shirts[rng.int(0, 5) as usize];
                let skin = skins[rng.int(0, 2) as usize];
                for dy in 0..8 {
                    for dx in 0..4 {
                        c.set(x + dx, y + 4 + dy, shade(shirt, rng.int(-10, 10)));
                    }
                }
                for dy in 0..3 {
                    for dx in 1..4 {
                        c.set(x + dx, y + dy, shade(skin, 0));
                    }
                }
            }
            x += 5 + rng.int(0, 2);
        }
    }
    c
}

/// Windows: one 4 m x 4 m wall panel with a divided window.
fn windows_texture(rng: &mut Rng) -> Canvas {
    let mut c = grain(64, [206, 200, 188], 5, rng);
    for y in 0..64 {
        for x in 0..64 {
            if y < 5 {
                c.set(x, y, shade([150, 146, 140], 0));
            } else if (14..48).contains(&y) && (6..58).contains(&x) && !(30..34).contains(&x) {
                let t = (y - 14) * 2;
                c.set(x, y, [60 + t as u8, 86 + t as u8, 112 + t as u8, 255]);
            } else if y == 48 && (4..60).contains(&x) {
                c.set(x, y, [120, 116, 110, 255]);
            }
        }
    }
    c
}

/// Trees: a broadleaf in the left half and a conifer in the right half (64 x 128 each), transparent around.
fn trees_texture(rng: &mut Rng) -> Canvas {
    let mut c = Canvas::new(128, 128, [60, 90, 50, 0]);
    let trunk = [96, 70, 46];
    for y in 84..128 {
        for x in 29..36 {
            c.set(x, y, shade(trunk, rng.int(-8, 8)));
        }
        for x in 94..98 {
            c.set(x, y, shade(trunk, rng.int(-8, 8)));
        }
    }
    // Broadleaf: a cluster of discs, lighter toward the top left.
    let discs = [(32.0, 50.0, 26.0), (18.0, 64.0, 15.0), (46.0, 64.0, 15.0), (32.0, 28.0, 19.0), (22.0, 40.0, 15.0)];
    for y in 0..128 {
        for x in 0..64 {
            let (fx, fy) = (x as f32 + 0.5, y as f32 + 0.5);
            let inside = discs
                .iter()
                .map(|&(cx, cy, r)| r - ((fx - cx).powi(2) + (fy - cy).powi(2)).sqrt())
                .fold(-1e9, f32::max);
            if inside > 0.0 && (inside > 3.0 || rng.unit() < 0.6) {
                let lit = ((64.0 - fx) * 0.3 + (90.0 - fy) * 0.5) as i32;
                c.set(x, y, shade([52, 102, 44], lit / 2 + rng.int(-14, 14)));
            }
        }
    }
    // Conifer: stacked tiers narrowing toward the top.
    for y in 6..116 {
        let fy = y as f32;
        let tier = ((fy - 6.0) % 22.0) / 22.0;
        let half = (fy - 6.0) / 110.0 * 27.0 * (0.7 + 0.3 * tier) + 1.0;
        for x in 64..128 {
            let dx = (x as f32 + 0.5 - 96.0).abs();
            if dx < half && (dx < half - 2.0 || rng.unit() < 0.6) {
                c.set(x, y, shade([34, 82, 48], (tier * 20.0) as i32 + rng.int(-12, 12)));
            }
        }
    }
    c
}

// ---------------------------------------------------------------------------------------------------------
// Road, roadside and bridge

/// The road ribbon with kerbs, verges, barriers and embankments, in chunks of consecutive segments.
fn track_meshes(scene: &mut Scene, m: &Mats, c: &Circuit) {
    let idx = c.road_indices();
    let segs: Vec<(usize, usize)> = (0..idx.len()).map(|k| (idx[k], idx[(k + 1) % idx.len()])).collect();
    for (k, chunk) in segs.chunks(24).enumerate() {
        let mut mb = MeshBuilder::default();
        for &(a, b) in chunk {
            track_segment(&mut mb, m, c, a, b);
        }
        scene.add(&format!("track {k:02}"), &mb);
    }
}

fn track_segment(mb: &mut MeshBuilder, m: &Mats, c: &Circuit, a: usize, b: usize) {
    let (sa, sb) = (&c.samples[a], &c.samples[b]);
    let s = (sa.s, if b == 0 { c.length } else { sb.s });
    let (va, vb) = (s.0 / c.road_tile, s.1 / c.road_tile);
    let (la, ra, lb, rb) = (sa.edge(0), sa.edge(1), sb.edge(0), sb.edge(1));
    mb.face(m.road, &[la, sa.p, sb.p, lb], &[uv(0.0, va), uv(0.5, va), uv(0.5, vb), uv(0.0, vb)], Vec3::Y, WHITE);
    mb.face(m.road, &[sa.p, ra, rb, sb.p], &[uv(0.5, va), uv(1.0, va), uv(1.0, vb), uv(0.5, vb)], Vec3::Y, WHITE);
    let open = c.in_span(a) && c.in_span(b);
    for side in 0..2 {
        roadside(mb, m, c, (a, b), side, s, open);
    }
    if open {
        let d = Vec3::Y * DECK_DEPTH;
        let pts = [sa.verge(0) - d, sa.verge(1) - d, sb.verge(1) - d, sb.verge(0) - d];
        mb.face(m.concrete, &pts, &world_uvs(&pts, 4.0), Vec3::NEG_Y, WHITE);
    }
    if c.in_span(a) && !c.in_span(b) {
        end_wall(mb, m, c, a, -sa.fwd);
    }
    if !c.in_span(a) && c.in_span(b) {
        end_wall(mb, m, c, b, sb.fwd);
    }
}

/// One side of a segment: kerb, verge, barrier, and the embankment side or the bridge deck's fascia.
fn roadside(
    mb: &mut MeshBuilder,
    m: &Mats,
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
    let (mat, bh) = if c.bridge_zone(a) && sa.h.max(sb.h) > 0.8 {
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
    } else if wa.y.max(wb.y) > 0.15 {
        let foot = |i: usize, w: Vec3, o: Vec3| {
            let f = w + o * c.foot(i, w.y);
            Vec3::new(f.x, -0.05, f.z)
        };
        let (fa, fb) = (foot(a, wa, oa), foot(b, wb, ob));
        let pts = [wa, wb, fb, fa];
        if c.bridge_zone(a) || c.bridge_zone(b) {
            let uvs = [uv(ua, 0.0), uv(ub, 0.0), uv(ub, wb.y / 4.0), uv(ua, wa.y / 4.0)];
            mb.face(m.concrete, &pts, &uvs, oa + ob + Vec3::Y, WHITE);
        } else {
            mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), oa + ob + Vec3::Y, WHITE);
        }
        apron(mb, m, c, (a, b), side, [fa * Vec3::new(1.0, 0.0, 1.0), fb * Vec3::new(1.0, 0.0, 1.0)]);
    } else {
        apron(mb, m, c, (a, b), side, [wa, wb]);
    }
}

/// The grass beside the corridor, from `inner` (the barrier line or the embankment's foot) out to the
/// sample's apron extent at ground level: a narrow strip along the barrier, then the rest (narrow polygons
/// next to the barriers keep the painter's order close to right).
fn apron(mb: &mut MeshBuilder, m: &Mats, c: &Circuit, (a, b): (usize, usize), side: usize, inner: [Vec3; 2]) {
    let at = |i: usize, lateral: f32| {
        let s = &c.samples[i];
        let q = s.p + s.out(side) * lateral.min(c.apron[i][side]);
        Vec3::new(q.x, 0.0, q.z)
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

/// The end of an embankment at the open span: a wall across it, from the verges down to the ground.
fn end_wall(mb: &mut MeshBuilder, m: &Mats, c: &Circuit, i: usize, facing: Vec3) {
    let s = &c.samples[i];
    let drop = Vec3::Y * 0.02;
    let foot = |side: usize| {
        let w = s.verge(side);
        let f = w + s.out(side) * c.foot(i, w.y);
        Vec3::new(f.x, -0.05, f.z)
    };
    let pts = [foot(0), foot(1), s.verge(1) - drop, s.verge(0) - drop];
    let top = s.p.y / 4.0;
    let w = pts[0].distance(pts[1]) / 8.0;
    mb.face(m.concrete, &pts, &[uv(-w, top), uv(w, top), uv(w * 0.6, 0.0), uv(-w * 0.6, 0.0)], facing, WHITE);
}

/// Piers under the bridge either side of the lower road: two columns and a cap beam per row.
fn bridge_mesh(scene: &mut Scene, m: &Mats, c: &Circuit) {
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
fn grid_slots(c: &Circuit) -> Vec<(Vec3, f32)> {
    (0..GRID_SLOTS)
        .map(|k| {
            let f = c.at(c.length - 8.0 - 8.0 * k as f32);
            let lat = if k % 2 == 0 { -2.8 } else { 2.8 };
            (f.p + f.lat * lat, f.fwd.x.atan2(-f.fwd.z))
        })
        .collect()
}

/// The start/finish gantry, the chequered line across the road and the grid slot markings.
fn start_mesh(scene: &mut Scene, m: &Mats, c: &Circuit, grid: &[(Vec3, f32)]) {
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
        let fwd = Vec3::new(yaw.sin(), 0.0, -yaw.cos());
        let right = Vec3::new(yaw.cos(), 0.0, yaw.sin());
        let centre = p + fwd * 2.6 + lift;
        let (x, z) = (right * 1.4, fwd * 0.15);
        let pts = [centre - x - z, centre + x - z, centre + x + z, centre - x + z];
        mb.face(m.paint, &pts, &[Vec2::ZERO; 4], Vec3::Y, WHITE);
    }
    scene.add("start", &mb);
}

// ---------------------------------------------------------------------------------------------------------
// Grandstands and buildings

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
fn footprint_clear(c: &Circuit, centre: Vec3, ax: Vec3, az: Vec3, half: Vec2) -> f32 {
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
fn grandstands(scene: &mut Scene, m: &Mats, c: &Circuit) -> Vec<(Vec3, Vec3)> {
    let mb = grandstand_mesh(m);
    let mesh = scene.doc.mesh("grandstand", &mb.prims);
    let spots = [(40.0, 1usize, 5.0), (c.apex[3], 1, 6.0), (c.lower_s - 110.0, 0, 5.0)];
    let mut placed_at = vec![];
    for (k, &(s, side, gap)) in spots.iter().enumerate() {
        let i = (s.rem_euclid(c.length) / c.step).round() as usize % c.n();
        let smp = &c.samples[i];
        let out = smp.out(side);
        let front = smp.p + out * (smp.bo[0].max(smp.bo[1]) + gap);
        let front = Vec3::new(front.x, 0.0, front.z);
        let along = Vec3::new(-out.z, 0.0, out.x);
        let centre = front + out * 7.0;
        if footprint_clear(c, centre, along, out, Vec2::new(40.0, 7.0)) < BARRIER_OFFSET + 3.0 {
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
fn buildings(scene: &mut Scene, m: &Mats, c: &Circuit) {
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
        if footprint_clear(c, base, smp.fwd, out, half) < BARRIER_OFFSET + 4.0 {
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

// ---------------------------------------------------------------------------------------------------------
// Ground, hills, trees

/// Ground heights on a square grid of `TILE` m: flat near the circuit, rolling further out, rising toward
/// the hills. Each tile is drawn as two triangles split from its (-x, -z) corner to its (+x, +z) corner.
struct Terrain {
    origin: Vec2,
    n: usize,
    heights: Vec<f32>,
    centre: Vec2,
}

impl Terrain {
    fn new(c: &Circuit) -> Terrain {
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
                let roll = 7.0 + 6.0 * (p.x / 170.0 + 1.0).sin() * (p.y / 210.0).cos();
                let rise = 30.0 * smoothstep(1300.0, 2100.0, p.distance(centre));
                heights.push(away * (roll + rise));
            }
        }
        Terrain { origin, n, heights, centre }
    }

    fn vertex(&self, i: usize, j: usize) -> Vec3 {
        let p = self.origin + Vec2::new(i as f32, j as f32) * TILE;
        Vec3::new(p.x, self.heights[j * (self.n + 1) + i], p.y)
    }

    /// Ground height at (x, z), as drawn.
    fn height(&self, p: Vec2) -> f32 {
        let g = (p - self.origin) / TILE;
        let (i, j) = (g.x.floor().clamp(0.0, self.n as f32 - 1.0), g.y.floor().clamp(0.0, self.n as f32 - 1.0));
        let (fx, fz) = ((g.x - i).clamp(0.0, 1.0), (g.y - j).clamp(0.0, 1.0));
        let (i, j) = (i as usize, j as usize);
        let a = self.vertex(i, j).y;
        let b = self.vertex(i + 1, j).y;
        let cc = self.vertex(i + 1, j + 1).y;
        let d = self.vertex(i, j + 1).y;
        if fz >= fx { a + fz * (d - a) + fx * (cc - d) } else { a + fx * (b - a) + fz * (cc - b) }
    }
}

/// Grass tiles in blocks of 8 x 8 (one mesh each), within the ground radius. Tiles near the track are split
/// into finer tiles and those reaching into the track's corridor are left out (the aprons cover the rest), so
/// no ground lies under the road; the finer tiles overlap their neighbours by 1 m so that no crack opens where
/// their corners meet the coarse tiles' edges.
fn ground_meshes(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain) {
    for bj in (0..t.n).step_by(8) {
        for bi in (0..t.n).step_by(8) {
            let mut mb = MeshBuilder::default();
            for j in bj..(bj + 8).min(t.n) {
                for i in bi..(bi + 8).min(t.n) {
                    let (a, b, cc, d) =
                        (t.vertex(i, j), t.vertex(i + 1, j), t.vertex(i + 1, j + 1), t.vertex(i, j + 1));
                    let (lo, hi) = (Vec2::new(a.x, a.z), Vec2::new(cc.x, cc.z));
                    if ((lo + hi) * 0.5).distance(t.centre) > GROUND_RADIUS {
                        continue;
                    }
                    if !c.touches(lo, hi) {
                        // Counter-clockwise from above, fanned from `a` (the split the height function assumes).
                        let pts = [a, d, cc, b];
                        mb.face(m.grass, &pts, &world_uvs(&pts, GRASS_UV), Vec3::Y, WHITE);
                        continue;
                    }
                    let k = (TILE / FINE_TILE) as usize;
                    for fj in 0..k {
                        for fi in 0..k {
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
            }
            scene.add(&format!("ground {:02} {:02}", bj / 8, bi / 8), &mb);
        }
    }
}

/// A ring of low, coarse hills beyond the ground's edge, in four meshes.
fn hills_meshes(scene: &mut Scene, m: &Mats, t: &Terrain) {
    const K: usize = 48;
    let mut rng = Rng::new(0x0000_4111_5eed);
    let ridge: Vec<(f32, f32)> = (0..K).map(|_| (rng.range(2280.0, 2420.0), rng.range(110.0, 250.0))).collect();
    let ring = |k: usize, r: f32| {
        let a = (k % K) as f32 / K as f32 * std::f32::consts::TAU;
        t.centre + Vec2::new(a.cos(), a.sin()) * r
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

/// The three tree models of each species (shared by all trees): two crossed quads, one quad, one quad turned
/// 45 degrees.
fn tree_meshes(doc: &mut Doc, m: &Mats) -> [[usize; 3]; 2] {
    let mut out = [[0; 3]; 2];
    for (sp, (w, h)) in [(3.0f32, 12.0f32), (2.75, 11.0)].into_iter().enumerate() {
        let (u0, u1) = (sp as f32 * 0.5, sp as f32 * 0.5 + 0.5);
        let uvs = [uv(u0, 1.0), uv(u1, 1.0), uv(u1, 0.0), uv(u0, 0.0)];
        let quad = |dir: Vec3| [-dir * w, dir * w, dir * w + Vec3::Y * h, -dir * w + Vec3::Y * h];
        let mut close = MeshBuilder::default();
        close.face(m.tree, &quad(Vec3::X), &uvs, Vec3::Z, WHITE);
        close.face(m.tree, &quad(Vec3::NEG_Z), &uvs, Vec3::X, WHITE);
        let mut mid = MeshBuilder::default();
        mid.face(m.tree, &quad(Vec3::X), &uvs, Vec3::Z, WHITE);
        let mut long = MeshBuilder::default();
        let diag = Vec3::new(1.0, 0.0, -1.0).normalize();
        long.face(m.tree, &quad(diag), &uvs, Vec3::new(1.0, 0.0, 1.0), WHITE);
        let name = ["broadleaf", "conifer"][sp];
        out[sp] = [
            doc.mesh(&format!("{name} close"), &close.prims),
            doc.mesh(&format!("{name} mid"), &mid.prims),
            doc.mesh(&format!("{name} long"), &long.prims),
        ];
    }
    out
}

/// About 250 trees in clumps and scattered, clear of the track, buildings and grandstands, each a LOD node.
fn trees(scene: &mut Scene, m: &Mats, c: &Circuit, t: &Terrain) {
    let meshes = tree_meshes(&mut scene.doc, m);
    let (lo, hi) = c.bounds();
    let (lo, hi) = (lo - Vec2::splat(300.0), hi + Vec2::splat(300.0));
    let mut placed_trees: Vec<Vec2> = vec![];
    let ok = |p: Vec2, trees: &[Vec2], keep_out: &[(Vec2, f32)]| {
        p.distance(t.centre) < GROUND_RADIUS - 250.0
            && trees.iter().all(|q| q.distance_squared(p) > 36.0)
            && keep_out.iter().all(|&(k, r)| k.distance(p) > r)
            && c.distance(p) > TREE_CLEARANCE
    };
    let mut candidates = vec![];
    let rng = &mut scene.rng;
    for _ in 0..20 {
        let centre = Vec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y));
        let count = rng.int(8, 16);
        for _ in 0..count * 2 {
            let (a, r) = (rng.range(0.0, std::f32::consts::TAU), 70.0 * rng.unit().sqrt());
            candidates.push(centre + Vec2::new(a.cos(), a.sin()) * r);
        }
    }
    for _ in 0..70 {
        candidates.push(Vec2::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y)));
    }
    for p in candidates {
        if placed_trees.len() >= 260 || !ok(p, &placed_trees, &scene.keep_out) {
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

// ---------------------------------------------------------------------------------------------------------
// Views, cameras and the centreline file

/// Named viewpoints: behind the grid, the crossover, the whole circuit, the hairpin, on board from pole, and
/// on the lower road approaching the bridge.
fn views(c: &Circuit, grid: &[(Vec3, f32)], stands: &[(Vec3, Vec3)]) -> Vec<(String, Vec3, Vec3)> {
    let mut v = vec![];
    let start = c.at(0.0);
    if let Some(&(last, _)) = grid.last() {
        v.push(("grid".to_string(), last - start.fwd * 30.0 + Vec3::Y * 13.0, start.p + start.fwd * 6.0));
    }
    let x = Vec3::new(c.cross_point.x, 0.0, c.cross_point.y);
    let low = c.at(c.lower_s);
    v.push(("bridge".to_string(), x - low.fwd * 95.0 + low.right * 45.0 + Vec3::Y * 24.0, x + Vec3::Y * 3.0));
    let (lo, hi) = c.bounds();
    let mid = (lo + hi) * 0.5;
    v.push(("overview".to_string(), Vec3::new(mid.x, 1000.0, mid.y + 780.0), Vec3::new(mid.x, 0.0, mid.y - 30.0)));
    let apex = c.at(c.apex[3]);
    let hairpin_eye = stands.get(1).map_or(apex.p + apex.right * 40.0 + Vec3::Y * 15.0, |&(front, to_track)| {
        front + to_track * 2.0 + Vec3::Y * 12.0
    });
    v.push(("hairpin".to_string(), hairpin_eye, apex.p));
    if let Some(&(pole, yaw)) = grid.first() {
        let fwd = Vec3::new(yaw.sin(), 0.0, -yaw.cos());
        v.push(("onboard".to_string(), pole + Vec3::Y * 1.1, pole + fwd * 60.0 + Vec3::Y * 0.8));
    }
    let (entry, apex8) = (c.at(c.apex[8] - 110.0), c.at(c.apex[8] - 30.0));
    v.push(("sweeper".to_string(), entry.p + entry.right * 3.0 + Vec3::Y * 3.0, apex8.p + Vec3::Y * 1.0));
    let under = c.at(c.lower_s - 90.0);
    v.push(("underpass".to_string(), under.p + Vec3::Y * 1.4, x + Vec3::Y * 2.0));
    v
}

/// Adds one perspective camera node per view; returns the cameras for [`add_cameras`].
fn camera_nodes(doc: &mut Doc, info: &TrackInfo) -> Vec<Value> {
    let round = |v: f32| (f64::from(v) * 1e6).round() / 1e6 + 0.0;
    let mut cameras = vec![];
    for (k, (name, eye, target)) in info.views.iter().enumerate() {
        let f = (*target - *eye).normalize_or_zero();
        let r = f.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let u = r.cross(f);
        let q = Quat::from_mat3(&Mat3::from_cols(r, u, -f)).normalize();
        let (znear, yfov) = if name == "onboard" || name == "underpass" { (0.3, 1.0) } else { (1.0, 0.9) };
        cameras.push(json!({"name": name, "type": "perspective", "perspective": {"yfov": yfov, "znear": znear, "zfar": 12000.0}}));
        doc.node(
            json!({
                "name": name,
                "camera": k,
                "translation": [round(eye.x), round(eye.y), round(eye.z)],
                "rotation": [round(q.x), round(q.y), round(q.z), round(q.w)],
            }),
            true,
        );
    }
    cameras
}

/// The glTF writer knows no cameras: adds the `cameras` array to the written file.
fn add_cameras(path: &Path, cameras: Vec<Value>) -> std::io::Result<()> {
    let text = std::fs::read_to_string(path)?;
    let mut g: Value = serde_json::from_str(&text).map_err(std::io::Error::other)?;
    g["cameras"] = json!(cameras);
    let mut text = serde_json::to_string_pretty(&g).map_err(std::io::Error::other)?;
    text.push('\n');
    std::fs::write(path, text)
}

/// `centerline.json`: lap length and a sample every ~5 m from the start line in racing order: road-surface
/// centre `p`, `bank` (radians, positive raises the right side) and road `width`.
fn write_centerline(dir: &Path, c: &Circuit) -> std::io::Result<()> {
    let samples: Vec<Value> = c
        .samples
        .iter()
        .map(|s| json!({"p": [r3(s.p.x), r3(s.p.y), r3(s.p.z)], "bank": r3(s.bank), "width": r3(2.0 * HALF_WIDTH)}))
        .collect();
    let v = json!({"length_m": r3(c.length), "samples": samples});
    let mut text = serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?;
    text.push('\n');
    std::fs::write(dir.join("centerline.json"), text)
}
