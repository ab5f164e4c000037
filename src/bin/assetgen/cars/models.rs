//! The car models: lofted bodies and cabins, wheels, mirrors and wings mapped into the atlas by face
//! orientation, the detail polygons, and the middle and long-shot models.

use glam::{Vec2, Vec3};

use super::spec::{
    BACK, Design, FRONT, HEADLAMP, PLATE, RIDE, ROUNDEL, SIDE, TAIL_LAMP, TOP, UNDER, WHEEL, WHEEL_RADIUS, WHEEL_WIDTH,
};
use crate::gltf_out::Primitive;

pub(super) fn region_uv(r: [f32; 4], s: f32, t: f32) -> Vec2 {
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
pub(super) fn body_profile(d: &Design, t: f32) -> f32 {
    let nose = d.nose * d.body_height;
    if t < 0.3 {
        nose + (d.body_height - nose) * libm::powf(t / 0.3, 0.7)
    } else {
        d.body_height * (1.0 - 0.08 * (t - 0.3))
    }
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

pub(super) fn z_at(d: &Design, t: f32) -> f32 {
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
                Vec3::new(x, center.y + WHEEL_RADIUS * libm::cosf(a), center.z + WHEEL_RADIUS * libm::sinf(a))
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

pub(super) fn axle_z(d: &Design) -> [f32; 2] {
    [z_at(d, 0.17), z_at(d, 0.81)]
}

/// The close-up model: the atlas-textured body, cabin, wheels, mirrors and wing, and the sharp parts on the
/// detail texture, one primitive each.
pub(super) fn close_model(d: &Design, atlas: usize, detail: usize) -> Vec<Primitive> {
    let frame = Frame { length: d.length, width: d.width, height: d.cabin_height };
    let mut body = Primitive::new(atlas);
    close_shell(&mut body, &frame, d);
    // Wheels.
    let wx = 0.5 * d.width - 0.5 * WHEEL_WIDTH + 0.04;
    for z in axle_z(d) {
        for x in [-wx, wx] {
            wheel(&mut body, Vec3::new(x, WHEEL_RADIUS, z));
        }
    }
    mirrors_and_wing(&mut body, &frame, d);
    // Sharp parts on the detail texture: plates, lamps, race numbers, standing just proud of the body.
    let mut det = Primitive::new(detail);
    plates_and_lamps(&mut det, d);
    race_numbers(&mut det, d);
    vec![body, det]
}

/// The close model's lofted body (eleven sections) and cabin.
fn close_shell(body: &mut Primitive, frame: &Frame, d: &Design) {
    let ts: Vec<f32> = (0..=10).map(|i| i as f32 / 10.0).collect();
    let sections: Vec<(f32, Vec<Vec2>)> = ts.iter().map(|&t| (z_at(d, t), body_section(d, t))).collect();
    loft(body, frame, &sections, false, true);
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
    loft(body, frame, &cabin, true, true);
}

/// The close model's door mirrors and (on designs with one) its rear wing on struts.
fn mirrors_and_wing(body: &mut Primitive, frame: &Frame, d: &Design) {
    let (c0, _) = d.cabin;
    // Mirrors.
    let mz = z_at(d, c0 + 0.05);
    let my = body_profile(d, c0 + 0.05);
    for s in [-1.0f32, 1.0] {
        let x0 = s * 0.5 * d.width * 0.95;
        let x1 = s * (0.5 * d.width * 0.95 + 0.14);
        atlas_box(body, frame, Vec3::new(x0.min(x1), my, mz - 0.05), Vec3::new(x0.max(x1), my + 0.1, mz + 0.05), false);
    }
    // Rear wing on struts.
    if d.wing {
        let z = z_at(d, 0.93);
        let top = d.body_height + 0.28;
        atlas_box(
            body,
            frame,
            Vec3::new(-0.45 * d.width, top, z - 0.18),
            Vec3::new(0.45 * d.width, top + 0.05, z + 0.18),
            false,
        );
        for x in [-0.3 * d.width, 0.3 * d.width] {
            atlas_box(
                body,
                frame,
                Vec3::new(x - 0.03, body_profile(d, 0.93) - 0.02, z - 0.06),
                Vec3::new(x + 0.03, top, z + 0.06),
                true,
            );
        }
    }
}

/// Number plates front and back, headlamps and tail lamps, on the detail texture.
fn plates_and_lamps(det: &mut Primitive, d: &Design) {
    let nose_z = z_at(d, 0.0) - 0.005;
    let tail_z = z_at(d, 1.0) + 0.005;
    let plate_w = 0.26;
    let nose_h = d.nose * d.body_height;
    let ph = (RIDE + 0.02, RIDE + 0.12);
    // Front plate faces -Z: seen from the front, +X is on the left.
    region_quad(
        det,
        [
            Vec3::new(plate_w, ph.0, nose_z),
            Vec3::new(-plate_w, ph.0, nose_z),
            Vec3::new(-plate_w, ph.1, nose_z),
            Vec3::new(plate_w, ph.1, nose_z),
        ],
        PLATE,
    );
    region_quad(
        det,
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
            det,
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
            det,
            [
                Vec3::new(r, ty.0, tail_z),
                Vec3::new(l, ty.0, tail_z),
                Vec3::new(l, ty.1, tail_z),
                Vec3::new(r, ty.1, tail_z),
            ],
            TAIL_LAMP,
        );
    }
}

/// Race-number roundels on both doors and the roof, on the detail texture.
fn race_numbers(det: &mut Primitive, d: &Design) {
    let (c0, c1) = d.cabin;
    let door = 0.5 * (c0 + c1);
    let (dz0, dz1) = (z_at(d, door) - 0.32, z_at(d, door) + 0.32);
    let (dy0, dy1) = (RIDE + 0.06, RIDE + 0.06 + 0.64 * 0.7);
    let side_x = 0.5 * d.width * (1.0 - 0.12 * (2.0 * door - 1.0).powi(4)) + 0.006;
    region_quad(
        det,
        [
            Vec3::new(side_x, dy0, dz1),
            Vec3::new(side_x, dy0, dz0),
            Vec3::new(side_x, dy1, dz0),
            Vec3::new(side_x, dy1, dz1),
        ],
        ROUNDEL,
    );
    region_quad(
        det,
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
        det,
        [
            Vec3::new(-0.25, roof, rz1),
            Vec3::new(0.25, roof, rz1),
            Vec3::new(0.25, roof, rz0),
            Vec3::new(-0.25, roof, rz0),
        ],
        ROUNDEL,
    );
}

pub(super) fn mid_model(d: &Design, atlas: usize) -> Vec<Primitive> {
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

pub(super) fn long_model(d: &Design, atlas: usize) -> Vec<Primitive> {
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
