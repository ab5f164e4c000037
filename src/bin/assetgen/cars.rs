//! The cars: eight designs, each one glTF file holding a close-up, a middle-range and a long-shot model
//! (seed 003, Namco) with textures of matching resolution, linked by `MSFT_lod`.
//!
//! - close: a lofted body, cabin, four ten-sided wheels, mirrors and (on some) a rear wing, about 240
//!   polygons, textured from a 256x256 atlas; the parts that must stay sharp when enlarged (number plates,
//!   race numbers, head and tail lamps) are separate polygons on a 128x128 detail texture of their own, so
//!   they get several times the atlas's texel density.
//! - mid: a coarse body and cabin and flat wheel discs, 20-30 polygons, on the same atlas box-filtered to 64x64.
//! - long: a hexahedron (6 polygons) on the atlas box-filtered to 16x16.
//!
//! Why these sizes: the models switch where the next coarser texture still has about one texel per pixel.
//! A car is about 4.5 m long and its atlas spends its full width on that length; the switch to the middle
//! model comes when the car's projected bounding sphere is 100 px tall at 720 px (the car then spans about
//! 80 px, and the 64-texel middle atlas gives 0.8 texel per pixel), and to the long shot at 25 px (the
//! 16-texel atlas gives 0.8 texel per pixel over about 20 px). Above 100 px the 256-texel atlas is at most
//! magnified 1:1 until the car is 250 px long, and the detail parts until several times that.

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};
use serde_json::json;

use crate::gltf_out::{Doc, Primitive, WrapMode};
use crate::paint::{Canvas, Rgba};

/// What the grid scene needs to know about each car file.
#[derive(Clone, Debug)]
pub struct CarInfo {
    /// File stem, e.g. `car_1` (the file is `cars/car_1.gltf`).
    pub name: String,
}

/// How the livery's second colour is laid out.
#[derive(Clone, Copy, Debug)]
enum Pattern {
    Stripe,
    TwoTone,
    Chevron,
    Band,
}

/// One car design: proportions and livery.
#[derive(Clone, Copy, Debug)]
struct Design {
    number: u32,
    length: f32,
    width: f32,
    /// Height of the body's top (the cabin rises above it).
    body_height: f32,
    cabin_height: f32,
    /// Cabin start and end along the length (0 = nose, 1 = tail).
    cabin: (f32, f32),
    /// Nose height as a fraction of the body height.
    nose: f32,
    wing: bool,
    base: Rgba,
    accent: Rgba,
    pattern: Pattern,
}

const DESIGNS: [Design; 8] = [
    Design {
        number: 1,
        length: 4.5,
        width: 1.9,
        body_height: 0.75,
        cabin_height: 1.15,
        cabin: (0.38, 0.72),
        nose: 0.55,
        wing: true,
        base: [200, 30, 30, 255],
        accent: [250, 250, 250, 255],
        pattern: Pattern::Stripe,
    },
    Design {
        number: 2,
        length: 4.7,
        width: 1.95,
        body_height: 0.7,
        cabin_height: 1.1,
        cabin: (0.42, 0.75),
        nose: 0.5,
        wing: true,
        base: [20, 60, 170, 255],
        accent: [250, 200, 20, 255],
        pattern: Pattern::TwoTone,
    },
    Design {
        number: 3,
        length: 4.3,
        width: 1.85,
        body_height: 0.8,
        cabin_height: 1.25,
        cabin: (0.35, 0.8),
        nose: 0.65,
        wing: false,
        base: [30, 140, 60, 255],
        accent: [240, 240, 240, 255],
        pattern: Pattern::Band,
    },
    Design {
        number: 5,
        length: 4.6,
        width: 1.9,
        body_height: 0.72,
        cabin_height: 1.12,
        cabin: (0.4, 0.7),
        nose: 0.5,
        wing: true,
        base: [250, 200, 20, 255],
        accent: [20, 20, 20, 255],
        pattern: Pattern::Chevron,
    },
    Design {
        number: 7,
        length: 4.4,
        width: 1.8,
        body_height: 0.78,
        cabin_height: 1.2,
        cabin: (0.36, 0.76),
        nose: 0.6,
        wing: false,
        base: [240, 240, 240, 255],
        accent: [30, 90, 200, 255],
        pattern: Pattern::Stripe,
    },
    Design {
        number: 8,
        length: 4.8,
        width: 2.0,
        body_height: 0.68,
        cabin_height: 1.05,
        cabin: (0.45, 0.74),
        nose: 0.45,
        wing: true,
        base: [240, 110, 20, 255],
        accent: [40, 40, 120, 255],
        pattern: Pattern::TwoTone,
    },
    Design {
        number: 11,
        length: 4.5,
        width: 1.88,
        body_height: 0.74,
        cabin_height: 1.16,
        cabin: (0.4, 0.73),
        nose: 0.55,
        wing: true,
        base: [120, 30, 160, 255],
        accent: [240, 240, 240, 255],
        pattern: Pattern::Band,
    },
    Design {
        number: 27,
        length: 4.35,
        width: 1.86,
        body_height: 0.82,
        cabin_height: 1.28,
        cabin: (0.34, 0.78),
        nose: 0.62,
        wing: false,
        base: [25, 25, 25, 255],
        accent: [220, 30, 30, 255],
        pattern: Pattern::Chevron,
    },
];

/// Coverage hints for `MSFT_screencoverage` (fractions of a 720-pixel frame): see the module docs.
const COVERAGE: [f32; 3] = [100.0 / 720.0, 25.0 / 720.0, 0.0];

// Atlas layout (fractions of the 256x256 atlas; the 64 and 16 versions share it).
const SIDE: [f32; 4] = [0.0, 0.0, 1.0, 0.375];
const TOP: [f32; 4] = [0.0, 0.375, 1.0, 0.6875];
const FRONT: [f32; 4] = [0.0, 0.6875, 0.25, 1.0];
const BACK: [f32; 4] = [0.25, 0.6875, 0.5, 1.0];
const WHEEL: [f32; 4] = [0.5, 0.6875, 0.75, 1.0];
const UNDER: [f32; 4] = [0.75, 0.6875, 1.0, 1.0];

// Detail texture layout (fractions of the 128x128 detail texture).
const PLATE: [f32; 4] = [0.0, 0.0, 1.0, 0.25];
const ROUNDEL: [f32; 4] = [0.0, 0.25, 0.5, 0.75];
const HEADLAMP: [f32; 4] = [0.5, 0.25, 1.0, 0.5];
const TAIL_LAMP: [f32; 4] = [0.5, 0.5, 1.0, 0.75];

const WHEEL_RADIUS: f32 = 0.33;
const WHEEL_WIDTH: f32 = 0.26;
const RIDE: f32 = 0.14;

fn region_uv(r: [f32; 4], s: f32, t: f32) -> Vec2 {
    Vec2::new(r[0] + (r[2] - r[0]) * s.clamp(0.0, 1.0), r[1] + (r[3] - r[1]) * t.clamp(0.0, 1.0))
}

/// Model space: length along Z with the nose at -Z (glTF forward), width along X, up +Y, origin on the ground
/// at the centre.
struct Frame {
    length: f32,
    width: f32,
    height: f32,
}

impl Frame {
    /// Atlas coordinates of a point on a face with normal `n`, by the face's dominant axis.
    fn atlas_uv(&self, p: Vec3, n: Vec3) -> Vec2 {
        let along = (p.z + 0.5 * self.length) / self.length;
        let up = 1.0 - p.y / self.height;
        let across = p.x / self.width + 0.5;
        let a = n.abs();
        if a.x >= a.y && a.x >= a.z {
            region_uv(SIDE, along, up)
        } else if a.y >= a.z {
            if n.y > 0.0 { region_uv(TOP, along, across) } else { region_uv(UNDER, across, along) }
        } else if n.z < 0.0 {
            region_uv(FRONT, across, up)
        } else {
            region_uv(BACK, across, up)
        }
    }
}

fn normal(pts: &[Vec3]) -> Vec3 {
    let mut n = Vec3::ZERO;
    for i in 0..pts.len() {
        let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
        n += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
    }
    n.normalize_or_zero()
}

/// Adds a polygon mapped into the atlas by its orientation.
fn atlas_face(prim: &mut Primitive, frame: &Frame, pts: &[Vec3]) {
    let n = normal(pts);
    let uvs: Vec<Vec2> = pts.iter().map(|&p| frame.atlas_uv(p, n)).collect();
    prim.polygon(pts, &uvs);
}

/// Adds a quad mapped onto a whole region of a texture (corners in order: bottom-left, bottom-right,
/// top-right, top-left as seen from the front of the face).
fn region_quad(prim: &mut Primitive, pts: [Vec3; 4], r: [f32; 4]) {
    let uvs = [region_uv(r, 0.0, 1.0), region_uv(r, 1.0, 1.0), region_uv(r, 1.0, 0.0), region_uv(r, 0.0, 0.0)];
    prim.polygon(&pts, &uvs);
}

/// Joins cross-sections (each counter-clockwise seen from +Z, ordered from the nose at -Z to the tail)
/// into side quads, and caps the ends when asked.
fn loft(prim: &mut Primitive, frame: &Frame, sections: &[(f32, Vec<Vec2>)], open_bottom: bool, caps: bool) {
    for w in sections.windows(2) {
        let ((z0, s0), (z1, s1)) = (&w[0], &w[1]);
        let n = s0.len();
        for k in 0..n {
            if open_bottom && k == 0 {
                continue;
            }
            let (a, b) = (s0[k], s0[(k + 1) % n]);
            let (c, d) = (s1[(k + 1) % n], s1[k]);
            let quad = [a.extend(*z0), b.extend(*z0), c.extend(*z1), d.extend(*z1)];
            atlas_face(prim, frame, &quad);
        }
    }
    if caps {
        if let Some((z, s)) = sections.first() {
            let front: Vec<Vec3> = s.iter().rev().map(|p| p.extend(*z)).collect();
            atlas_face(prim, frame, &front);
        }
        if let Some((z, s)) = sections.last() {
            let back: Vec<Vec3> = s.iter().map(|p| p.extend(*z)).collect();
            atlas_face(prim, frame, &back);
        }
    }
}

/// Body height along the length (0 = nose, 1 = tail).
fn body_profile(d: &Design, t: f32) -> f32 {
    let nose = d.nose * d.body_height;
    if t < 0.3 { nose + (d.body_height - nose) * (t / 0.3).powf(0.7) } else { d.body_height * (1.0 - 0.08 * (t - 0.3)) }
}

/// The body's cross-section at `t`: eight points counter-clockwise seen from +Z.
fn body_section(d: &Design, t: f32) -> Vec<Vec2> {
    let h = body_profile(d, t);
    let taper = 1.0 - 0.12 * (2.0 * t - 1.0).powi(4);
    let w = 0.5 * d.width * taper;
    let y_side = RIDE + 0.45 * (h - RIDE);
    vec![
        Vec2::new(-0.86 * w, RIDE),
        Vec2::new(0.86 * w, RIDE),
        Vec2::new(w, y_side),
        Vec2::new(0.94 * w, RIDE + 0.85 * (h - RIDE)),
        Vec2::new(0.62 * w, h),
        Vec2::new(-0.62 * w, h),
        Vec2::new(-0.94 * w, RIDE + 0.85 * (h - RIDE)),
        Vec2::new(-w, y_side),
    ]
}

fn z_at(d: &Design, t: f32) -> f32 {
    (t - 0.5) * d.length
}

/// The cabin's cross-section: a trapezoid (open at the bottom, which sits on the body).
fn cabin_section(d: &Design, t: f32, base: f32, top: f32) -> Vec<Vec2> {
    let w = 0.5 * d.width * 0.8;
    let _ = t;
    vec![Vec2::new(-w, base), Vec2::new(w, base), Vec2::new(0.7 * w, top), Vec2::new(-0.7 * w, top)]
}

/// A wheel: a ten-sided cylinder across X at `center`, tread and both caps.
fn wheel(prim: &mut Primitive, center: Vec3) {
    const N: usize = 10;
    let ring = |x: f32| -> Vec<Vec3> {
        (0..N)
            .map(|i| {
                let a = i as f32 / N as f32 * std::f32::consts::TAU;
                Vec3::new(x, center.y + WHEEL_RADIUS * a.cos(), center.z + WHEEL_RADIUS * a.sin())
            })
            .collect()
    };
    let (x0, x1) = (center.x - 0.5 * WHEEL_WIDTH, center.x + 0.5 * WHEEL_WIDTH);
    let (left, right) = (ring(x0), ring(x1));
    for i in 0..N {
        let j = (i + 1) % N;
        let quad = [left[i], left[j], right[j], right[i]];
        // The ring runs from +Y towards +Z; this order faces outwards.
        let t0 = i as f32 / N as f32;
        let t1 = (i + 1) as f32 / N as f32;
        let uvs = [
            region_uv(UNDER, 0.0, t0),
            region_uv(UNDER, 0.0, t1),
            region_uv(UNDER, 1.0, t1),
            region_uv(UNDER, 1.0, t0),
        ];
        prim.polygon(&quad, &uvs);
    }
    let cap_uv = |p: Vec3| {
        region_uv(WHEEL, 0.5 + 0.5 * (p.z - center.z) / WHEEL_RADIUS, 0.5 - 0.5 * (p.y - center.y) / WHEEL_RADIUS)
    };
    // Outer caps face -X (left) and +X (right).
    let l: Vec<Vec3> = left.iter().rev().copied().collect();
    prim.polygon(&l, &l.iter().map(|&p| cap_uv(p)).collect::<Vec<_>>());
    prim.polygon(&right, &right.iter().map(|&p| cap_uv(p)).collect::<Vec<_>>());
}

/// A small box from `lo` to `hi`, mapped into the atlas.
fn atlas_box(prim: &mut Primitive, frame: &Frame, lo: Vec3, hi: Vec3, skip_bottom: bool) {
    let p = |x: bool, y: bool, z: bool| {
        Vec3::new(if x { hi.x } else { lo.x }, if y { hi.y } else { lo.y }, if z { hi.z } else { lo.z })
    };
    let faces = [
        [p(false, false, false), p(false, true, false), p(true, true, false), p(true, false, false)], // -Z
        [p(false, false, true), p(true, false, true), p(true, true, true), p(false, true, true)],     // +Z
        [p(false, false, false), p(false, false, true), p(false, true, true), p(false, true, false)], // -X
        [p(true, false, false), p(true, true, false), p(true, true, true), p(true, false, true)],     // +X
        [p(false, true, false), p(false, true, true), p(true, true, true), p(true, true, false)],     // +Y
        [p(false, false, false), p(true, false, false), p(true, false, true), p(false, false, true)], // -Y
    ];
    for (i, f) in faces.iter().enumerate() {
        if skip_bottom && i == 5 {
            continue;
        }
        atlas_face(prim, frame, f);
    }
}

fn axle_z(d: &Design) -> [f32; 2] {
    [z_at(d, 0.17), z_at(d, 0.81)]
}

fn close_model(d: &Design, atlas: usize, detail: usize) -> Vec<Primitive> {
    let frame = Frame { length: d.length, width: d.width, height: d.cabin_height };
    let mut body = Primitive::new(atlas);
    let ts: Vec<f32> = (0..=10).map(|i| i as f32 / 10.0).collect();
    let sections: Vec<(f32, Vec<Vec2>)> = ts.iter().map(|&t| (z_at(d, t), body_section(d, t))).collect();
    loft(&mut body, &frame, &sections, false, true);
    // Cabin: five sections, windscreen and rear window as the sloped ends.
    let (c0, c1) = d.cabin;
    let base = body_profile(d, c0).min(body_profile(d, c1)) - 0.02;
    let cabin_ts = [c0, c0 + 0.3 * (c1 - c0), 0.5 * (c0 + c1), c0 + 0.8 * (c1 - c0), c1];
    let cabin: Vec<(f32, Vec<Vec2>)> = cabin_ts
        .iter()
        .enumerate()
        .map(|(i, &t)| {
            let top = if i == 0 || i == 4 { base + 0.25 * (d.cabin_height - base) } else { d.cabin_height };
            (z_at(d, t), cabin_section(d, t, base, top))
        })
        .collect();
    loft(&mut body, &frame, &cabin, true, true);
    // Wheels.
    let wx = 0.5 * d.width - 0.5 * WHEEL_WIDTH + 0.04;
    for z in axle_z(d) {
        for x in [-wx, wx] {
            wheel(&mut body, Vec3::new(x, WHEEL_RADIUS, z));
        }
    }
    // Mirrors.
    let mz = z_at(d, c0 + 0.05);
    let my = body_profile(d, c0 + 0.05);
    for s in [-1.0f32, 1.0] {
        let x0 = s * 0.5 * d.width * 0.95;
        let x1 = s * (0.5 * d.width * 0.95 + 0.14);
        atlas_box(
            &mut body,
            &frame,
            Vec3::new(x0.min(x1), my, mz - 0.05),
            Vec3::new(x0.max(x1), my + 0.1, mz + 0.05),
            false,
        );
    }
    // Rear wing on struts.
    if d.wing {
        let z = z_at(d, 0.93);
        let top = d.body_height + 0.28;
        atlas_box(
            &mut body,
            &frame,
            Vec3::new(-0.45 * d.width, top, z - 0.18),
            Vec3::new(0.45 * d.width, top + 0.05, z + 0.18),
            false,
        );
        for x in [-0.3 * d.width, 0.3 * d.width] {
            atlas_box(
                &mut body,
                &frame,
                Vec3::new(x - 0.03, body_profile(d, 0.93) - 0.02, z - 0.06),
                Vec3::new(x + 0.03, top, z + 0.06),
                true,
            );
        }
    }
    // Sharp parts on the detail texture: plates, lamps, race numbers, standing just proud of the body.
    let mut det = Primitive::new(detail);
    let nose_z = z_at(d, 0.0) - 0.005;
    let tail_z = z_at(d, 1.0) + 0.005;
    let plate_w = 0.26;
    let nose_h = d.nose * d.body_height;
    let ph = (RIDE + 0.02, RIDE + 0.12);
    // Front plate faces -Z: seen from the front, +X is on the left.
    region_quad(
        &mut det,
        [
            Vec3::new(plate_w, ph.0, nose_z),
            Vec3::new(-plate_w, ph.0, nose_z),
            Vec3::new(-plate_w, ph.1, nose_z),
            Vec3::new(plate_w, ph.1, nose_z),
        ],
        PLATE,
    );
    region_quad(
        &mut det,
        [
            Vec3::new(-plate_w, ph.0, tail_z),
            Vec3::new(plate_w, ph.0, tail_z),
            Vec3::new(plate_w, ph.1, tail_z),
            Vec3::new(-plate_w, ph.1, tail_z),
        ],
        PLATE,
    );
    let lamp_y = (RIDE + 0.14, nose_h - 0.03);
    for s in [-1.0f32, 1.0] {
        let (xa, xb) = (s * 0.5 * d.width * 0.55, s * 0.5 * d.width * 0.8);
        let (l, r) = if s < 0.0 { (xa, xb) } else { (xb, xa) };
        region_quad(
            &mut det,
            [
                Vec3::new(l, lamp_y.0, nose_z),
                Vec3::new(r, lamp_y.0, nose_z),
                Vec3::new(r, lamp_y.1, nose_z),
                Vec3::new(l, lamp_y.1, nose_z),
            ],
            HEADLAMP,
        );
        let ty = (RIDE + 0.3, RIDE + 0.42);
        region_quad(
            &mut det,
            [
                Vec3::new(r, ty.0, tail_z),
                Vec3::new(l, ty.0, tail_z),
                Vec3::new(l, ty.1, tail_z),
                Vec3::new(r, ty.1, tail_z),
            ],
            TAIL_LAMP,
        );
    }
    // Race numbers on both doors and the roof.
    let door = 0.5 * (c0 + c1);
    let (dz0, dz1) = (z_at(d, door) - 0.32, z_at(d, door) + 0.32);
    let (dy0, dy1) = (RIDE + 0.06, RIDE + 0.06 + 0.64 * 0.7);
    let side_x = 0.5 * d.width * (1.0 - 0.12 * (2.0 * door - 1.0).powi(4)) + 0.006;
    region_quad(
        &mut det,
        [
            Vec3::new(side_x, dy0, dz1),
            Vec3::new(side_x, dy0, dz0),
            Vec3::new(side_x, dy1, dz0),
            Vec3::new(side_x, dy1, dz1),
        ],
        ROUNDEL,
    );
    region_quad(
        &mut det,
        [
            Vec3::new(-side_x, dy0, dz0),
            Vec3::new(-side_x, dy0, dz1),
            Vec3::new(-side_x, dy1, dz1),
            Vec3::new(-side_x, dy1, dz0),
        ],
        ROUNDEL,
    );
    let roof = d.cabin_height + 0.004;
    let (rz0, rz1) = (z_at(d, door) - 0.25, z_at(d, door) + 0.25);
    region_quad(
        &mut det,
        [
            Vec3::new(-0.25, roof, rz1),
            Vec3::new(0.25, roof, rz1),
            Vec3::new(0.25, roof, rz0),
            Vec3::new(-0.25, roof, rz0),
        ],
        ROUNDEL,
    );
    vec![body, det]
}

fn mid_model(d: &Design, atlas: usize) -> Vec<Primitive> {
    let frame = Frame { length: d.length, width: d.width, height: d.cabin_height };
    let mut p = Primitive::new(atlas);
    let quad_section = |t: f32| {
        let h = body_profile(d, t);
        let w = 0.5 * d.width;
        vec![Vec2::new(-w, RIDE), Vec2::new(w, RIDE), Vec2::new(w, h), Vec2::new(-w, h)]
    };
    let sections: Vec<(f32, Vec<Vec2>)> =
        [0.0, 0.15, 0.3, 1.0].iter().map(|&t| (z_at(d, t), quad_section(t))).collect();
    loft(&mut p, &frame, &sections, false, true);
    let (c0, c1) = d.cabin;
    let base = body_profile(d, c0).min(body_profile(d, c1)) - 0.02;
    let cabin = vec![
        (z_at(d, c0), cabin_section(d, c0, base, d.cabin_height)),
        (z_at(d, c1), cabin_section(d, c1, base, d.cabin_height)),
    ];
    loft(&mut p, &frame, &cabin, true, true);
    // Wheels as discs on the outside of the body.
    let wx = 0.5 * d.width + 0.01;
    for z in axle_z(d) {
        let (y0, y1) = (0.0, 2.0 * WHEEL_RADIUS);
        let (z0, z1) = (z - WHEEL_RADIUS, z + WHEEL_RADIUS);
        region_quad(
            &mut p,
            [Vec3::new(wx, y0, z1), Vec3::new(wx, y0, z0), Vec3::new(wx, y1, z0), Vec3::new(wx, y1, z1)],
            WHEEL,
        );
        region_quad(
            &mut p,
            [Vec3::new(-wx, y0, z0), Vec3::new(-wx, y0, z1), Vec3::new(-wx, y1, z1), Vec3::new(-wx, y1, z0)],
            WHEEL,
        );
    }
    vec![p]
}

fn long_model(d: &Design, atlas: usize) -> Vec<Primitive> {
    let frame = Frame { length: d.length, width: d.width, height: d.cabin_height };
    let mut p = Primitive::new(atlas);
    let h = 0.5 * (d.body_height + d.cabin_height);
    atlas_box(
        &mut p,
        &frame,
        Vec3::new(-0.5 * d.width, 0.02, -0.5 * d.length),
        Vec3::new(0.5 * d.width, h, 0.5 * d.length),
        false,
    );
    vec![p]
}

fn shade(c: Rgba, f: f32) -> Rgba {
    [
        (f32::from(c[0]) * f).min(255.0) as u8,
        (f32::from(c[1]) * f).min(255.0) as u8,
        (f32::from(c[2]) * f).min(255.0) as u8,
        255,
    ]
}

/// Paints the 256x256 atlas: livery on the sides and top, grille and lamps front and back, wheel and tyre.
fn paint_atlas(d: &Design) -> Canvas {
    let mut c = Canvas::new(256, 256, d.base);
    let glass = [40, 55, 75, 255];
    let dark = [25, 25, 28, 255];
    let sub = |r: [f32; 4], x0: f32, y0: f32, x1: f32, y1: f32| {
        [r[0] + (r[2] - r[0]) * x0, r[1] + (r[3] - r[1]) * y0, r[0] + (r[2] - r[0]) * x1, r[1] + (r[3] - r[1]) * y1]
    };
    // Side: v = 1 - y / cabin_height; sill dark, livery, windows at cabin height.
    let v_of = |y: f32| 1.0 - y / d.cabin_height;
    match d.pattern {
        Pattern::Stripe => c.rect(sub(SIDE, 0.0, v_of(0.52), 1.0, v_of(0.42)), d.accent),
        Pattern::TwoTone => c.rect(sub(SIDE, 0.0, 0.0, 1.0, v_of(0.5)), d.accent),
        Pattern::Band => c.rect(sub(SIDE, 0.55, 0.0, 0.75, 1.0), d.accent),
        Pattern::Chevron => {
            for k in 0..8 {
                let x = 0.1 + 0.1 * k as f32;
                c.rect(sub(SIDE, x, v_of(0.6 - 0.03 * k as f32), x + 0.05, v_of(0.3 + 0.03 * k as f32)), d.accent);
            }
        }
    }
    c.rect(sub(SIDE, 0.0, v_of(RIDE + 0.1), 1.0, 1.0), shade(d.base, 0.45));
    let (c0, c1) = d.cabin;
    let base = body_profile(d, c0).min(body_profile(d, c1));
    c.rect(sub(SIDE, c0 + 0.03, v_of(d.cabin_height - 0.05), c1 - 0.03, v_of(base + 0.05)), glass);
    for z in axle_z(d) {
        let t = z / d.length + 0.5;
        let cx = SIDE[0] + t * (SIDE[2] - SIDE[0]);
        let cy = SIDE[1] + v_of(WHEEL_RADIUS) * (SIDE[3] - SIDE[1]);
        c.disc(cx, cy, WHEEL_RADIUS / d.length * 1.1, dark);
    }
    // The race number painted on the door too, for the mid and long models (the close one has its own polygon).
    let door_t = 0.5 * (c0 + c1);
    let (rx, ry) = (SIDE[0] + door_t * (SIDE[2] - SIDE[0]), SIDE[1] + v_of(0.42) * (SIDE[3] - SIDE[1]));
    c.disc(rx, ry, 0.05, [250, 250, 250, 255]);
    c.number(d.number, rx, ry, 0.05, [10, 10, 10, 255]);
    // Top: racing stripes, windscreen and roof.
    if !matches!(d.pattern, Pattern::Band) {
        c.rect(sub(TOP, 0.0, 0.4, 1.0, 0.48), d.accent);
        c.rect(sub(TOP, 0.0, 0.52, 1.0, 0.6), d.accent);
    }
    c.rect(sub(TOP, c0, 0.15, c0 + 0.3 * (c1 - c0), 0.85), glass);
    c.rect(sub(TOP, c0 + 0.8 * (c1 - c0), 0.15, c1, 0.85), glass);
    // Front: grille and lamp areas; back: tail-light bar.
    c.rect(sub(FRONT, 0.25, 0.65, 0.75, 0.85), dark);
    c.rect(sub(FRONT, 0.05, 0.45, 0.3, 0.6), [240, 240, 200, 255]);
    c.rect(sub(FRONT, 0.7, 0.45, 0.95, 0.6), [240, 240, 200, 255]);
    c.rect(sub(FRONT, 0.15, 0.0, 0.85, 0.35), glass);
    c.rect(sub(BACK, 0.05, 0.45, 0.95, 0.6), [200, 20, 20, 255]);
    c.rect(sub(BACK, 0.15, 0.0, 0.85, 0.35), glass);
    // Wheel face: tyre with a hub; underside and tread: dark.
    c.rect(WHEEL, dark);
    c.disc(0.5 + 0.125, 0.6875 + 0.15625, 0.07, [170, 170, 175, 255]);
    c.disc(0.5 + 0.125, 0.6875 + 0.15625, 0.025, shade(d.base, 0.8));
    c.rect(UNDER, [35, 35, 38, 255]);
    c
}

/// Paints the 128x128 detail texture: number plate, race-number roundel, head and tail lamps.
fn paint_detail(d: &Design) -> Canvas {
    let mut c = Canvas::new(128, 128, [0, 0, 0, 255]);
    c.rect(PLATE, [245, 245, 235, 255]);
    c.rect([0.03, 0.03, 0.97, 0.22], [250, 250, 245, 255]);
    c.number(1000 + d.number * 37 % 1000, 0.5, 0.125, 0.13, [20, 20, 20, 255]);
    c.rect(ROUNDEL, d.base);
    c.disc(0.25, 0.5, 0.22, [250, 250, 250, 255]);
    c.number(d.number, 0.25, 0.5, 0.2, [10, 10, 10, 255]);
    c.rect(HEADLAMP, [60, 60, 60, 255]);
    c.disc(0.75, 0.375, 0.11, [255, 250, 210, 255]);
    c.disc(0.72, 0.35, 0.04, [255, 255, 255, 255]);
    c.rect(TAIL_LAMP, [70, 0, 0, 255]);
    c.rect([0.55, 0.55, 0.95, 0.7], [230, 30, 30, 255]);
    c.rect([0.0, 0.75, 1.0, 1.0], d.accent);
    c
}

/// Writes one glTF file per design (with its textures) into `dir`.
pub fn generate(dir: &Path) -> std::io::Result<Vec<CarInfo>> {
    let mut out = vec![];
    for (i, d) in DESIGNS.iter().enumerate() {
        let name = format!("car_{}", i + 1);
        let atlas = paint_atlas(d);
        atlas.save(&dir.join(format!("{name}_256.png")))?;
        atlas.downscale(64, 64).save(&dir.join(format!("{name}_64.png")))?;
        atlas.downscale(16, 16).save(&dir.join(format!("{name}_16.png")))?;
        paint_detail(d).save(&dir.join(format!("{name}_detail.png")))?;
        let mut doc = Doc::new();
        let textures = [
            doc.texture(&format!("{name}_256.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_detail.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_64.png"), WrapMode::Clamp),
            doc.texture(&format!("{name}_16.png"), WrapMode::Clamp),
        ];
        let white = Vec4::ONE;
        let m_close = doc.material("body 256", white, Some(textures[0]), false, None);
        let m_detail = doc.material("detail 128", white, Some(textures[1]), false, None);
        let m_mid = doc.material("body 64", white, Some(textures[2]), false, None);
        let m_long = doc.material("body 16", white, Some(textures[3]), false, None);
        let close = doc.mesh(&format!("{name} close"), &close_model(d, m_close, m_detail));
        let mid = doc.mesh(&format!("{name} mid"), &mid_model(d, m_mid));
        let long = doc.mesh(&format!("{name} long"), &long_model(d, m_long));
        doc.lod_node(&name, [close, mid, long], COVERAGE, json!({}), true);
        // Cameras for quick looks: front three-quarter, side, rear three-quarter.
        let target = Vec3::new(0.0, 0.5, 0.0);
        doc.camera_node("front", Vec3::new(-4.0, 2.2, -5.5), target, 0.7);
        doc.camera_node("side", Vec3::new(-8.0, 1.0, 0.0), target, 0.7);
        doc.camera_node("rear", Vec3::new(4.5, 2.5, 6.0), target, 0.7);
        doc.write(dir, &name)?;
        out.push(CarInfo { name });
    }
    Ok(out)
}
