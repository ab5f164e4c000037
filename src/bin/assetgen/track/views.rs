//! Named viewpoints, the glTF cameras made from them, and `centerline.json`.

use std::path::Path;

use glam::{Mat3, Quat, Vec3};
use serde_json::{Value, json};

use super::circuit::Circuit;
use super::spec::HALF_WIDTH;
use super::util::r3;
use crate::gltf_out::Doc;

/// Named viewpoints: behind the grid, the crossover, the whole circuit, the hairpin, on board from pole, and
/// on the lower road approaching the bridge.
pub(super) fn views(c: &Circuit, grid: &[(Vec3, f32)], stands: &[(Vec3, Vec3)]) -> Vec<(String, Vec3, Vec3)> {
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
    let [hairpin, sweeper] = c.layout.view_corners;
    let apex = c.at(c.apex[hairpin]);
    let hairpin_eye = stands.get(1).map_or(apex.p + apex.right * 40.0 + Vec3::Y * 15.0, |&(front, to_track)| {
        front + to_track * 2.0 + Vec3::Y * 12.0
    });
    v.push(("hairpin".to_string(), hairpin_eye, apex.p));
    if let Some(&(pole, yaw)) = grid.first() {
        let fwd = Vec3::new(libm::sinf(yaw), 0.0, -libm::cosf(yaw));
        v.push(("onboard".to_string(), pole + Vec3::Y * 1.1, pole + fwd * 60.0 + Vec3::Y * 0.8));
    }
    let (entry, apex8) = (c.at(c.apex[sweeper] - 110.0), c.at(c.apex[sweeper] - 30.0));
    v.push(("sweeper".to_string(), entry.p + entry.right * 3.0 + Vec3::Y * 3.0, apex8.p + Vec3::Y * 1.0));
    let under = c.at(c.lower_s - 90.0);
    v.push(("underpass".to_string(), under.p + Vec3::Y * 1.4, x + Vec3::Y * 2.0));
    v
}

/// The views of a course in the hills: across the plain from the ridge's highest point ("vista"), and the
/// viaduct from the gorge below it ("viaduct"), and the whole course from the plain with the mountains
/// behind ("panorama").
pub(super) fn mountain_views(c: &Circuit) -> Vec<(String, Vec3, Vec3)> {
    let top = c.samples.iter().max_by(|a, b| a.base.total_cmp(&b.base)).map_or(c.at(0.0).p, |s| s.p);
    let (lo, hi) = c.bounds();
    let middle = (lo + hi) * 0.5;
    let below = Vec3::new(middle.x, 0.0, lo.y - 600.0);
    let (s0, s1) = c.viaduct;
    let mid = c.at((s0 + s1) * 0.5);
    let under = mid.p - mid.right * 160.0 - mid.fwd * 60.0;
    vec![
        ("vista".to_string(), top + Vec3::Y * 3.0, below),
        ("viaduct".to_string(), Vec3::new(under.x, mid.p.y - 25.0, under.z), mid.p - Vec3::Y * 10.0),
        ("panorama".to_string(), Vec3::new(lo.x - 300.0, 160.0, lo.y - 500.0), Vec3::new(middle.x, 60.0, hi.y)),
    ]
}

/// Adds one perspective camera node per view; returns the cameras for [`add_cameras`].
pub(super) fn camera_nodes(doc: &mut Doc, views: &[(String, Vec3, Vec3)]) -> Vec<Value> {
    let round = |v: f32| (f64::from(v) * 1e6).round() / 1e6 + 0.0;
    let mut cameras = vec![];
    for (k, (name, eye, target)) in views.iter().enumerate() {
        let f = (*target - *eye).normalize_or_zero();
        let r = f.cross(Vec3::Y).try_normalize().unwrap_or(Vec3::X);
        let u = r.cross(f);
        let q = Quat::from_mat3(&Mat3::from_cols(r, u, -f)).normalize();
        let (znear, yfov) =
            if name == "onboard" || name == "underpass" || name == "tunnel" { (0.3, 1.0) } else { (1.0, 0.9) };
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
pub(super) fn add_cameras(path: &Path, cameras: Vec<Value>) -> std::io::Result<()> {
    let text = std::fs::read_to_string(path)?;
    let mut g: Value = serde_json::from_str(&text).map_err(std::io::Error::other)?;
    g["cameras"] = json!(cameras);
    let text = crate::gltf_out::gltf_text(&g)?;
    std::fs::write(path, text)
}

/// `centerline.json`: the course's title and what it is like, lap length and a sample every ~5 m from the
/// start line in racing order: road-surface centre `p`, `bank` (radians, positive raises the right side),
/// road `width` and `barrier` offsets.
pub(super) fn write_centerline(dir: &Path, c: &Circuit) -> std::io::Result<()> {
    let samples: Vec<Value> = c
        .samples
        .iter()
        .map(|s| {
            json!({
                "p": [r3(s.p.x), r3(s.p.y), r3(s.p.z)],
                "bank": r3(s.bank),
                "width": r3(2.0 * HALF_WIDTH),
                "barrier": [r3(s.bo[0]), r3(s.bo[1])],
            })
        })
        .collect();
    let (title, about) = (c.layout.title, c.layout.about);
    let v = json!({"title": title, "about": about, "length_m": r3(c.length), "samples": samples});
    let mut text = serde_json::to_string_pretty(&v).map_err(std::io::Error::other)?;
    text.push('\n');
    std::fs::write(dir.join("centerline.json"), text)
}
