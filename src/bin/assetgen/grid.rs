//! The grid scene: the circuit with every car on its start-grid slot, as one glTF file (`assets/grid.gltf`)
//! that shares the track's and cars' buffers and images by relative URI instead of copying them.
//!
//! It is the scene for the "full grid on the circuit" frame, for LOD measurements (cars from near to far)
//! and for any glTF viewer.

use std::path::Path;

use glam::Vec3;
use serde_json::{Value, json};

use crate::cars::CarInfo;
use crate::track::TrackInfo;

/// Index fields that must be shifted when documents are concatenated.
#[derive(Default)]
struct Offsets {
    buffers: usize,
    views: usize,
    accessors: usize,
    images: usize,
    samplers: usize,
    textures: usize,
    materials: usize,
    meshes: usize,
    nodes: usize,
    cameras: usize,
}

#[derive(Default)]
struct Merged {
    arrays: serde_json::Map<String, Value>,
    roots: Vec<usize>,
}

const ARRAYS: [&str; 10] = [
    "buffers",
    "bufferViews",
    "accessors",
    "images",
    "samplers",
    "textures",
    "materials",
    "meshes",
    "nodes",
    "cameras",
];

fn shift(v: &mut Value, by: usize) {
    if let Some(i) = v.as_u64() {
        *v = json!(i as usize + by);
    }
}

/// Rewrites one item of the array `key` of a document being appended: file URIs get `folder` in front, and
/// indices into other arrays are shifted past what is already merged (`o`).
fn relocate(key: &str, item: &mut Value, folder: &str, o: &Offsets) {
    match key {
        "buffers" | "images" => {
            if let Some(uri) = item.get("uri").and_then(Value::as_str) {
                item["uri"] = json!(format!("{folder}{uri}"));
            }
        }
        "bufferViews" => shift(&mut item["buffer"], o.buffers),
        "accessors" => shift(&mut item["bufferView"], o.views),
        "textures" => {
            shift(&mut item["sampler"], o.samplers);
            shift(&mut item["source"], o.images);
        }
        "materials" => {
            if let Some(t) = item.pointer_mut("/pbrMetallicRoughness/baseColorTexture/index") {
                shift(t, o.textures);
            }
        }
        "meshes" => {
            if let Some(prims) = item.get_mut("primitives").and_then(Value::as_array_mut) {
                for p in prims {
                    if let Some(attrs) = p.get_mut("attributes").and_then(Value::as_object_mut) {
                        attrs.values_mut().for_each(|a| shift(a, o.accessors));
                    }
                    shift(&mut p["indices"], o.accessors);
                    shift(&mut p["material"], o.materials);
                }
            }
        }
        "nodes" => {
            if item.get("mesh").is_some() {
                shift(&mut item["mesh"], o.meshes);
            }
            if item.get("camera").is_some() {
                shift(&mut item["camera"], o.cameras);
            }
            if let Some(ch) = item.get_mut("children").and_then(Value::as_array_mut) {
                ch.iter_mut().for_each(|c| shift(c, o.nodes));
            }
            if let Some(ids) = item.pointer_mut("/extensions/MSFT_lod/ids").and_then(Value::as_array_mut) {
                ids.iter_mut().for_each(|c| shift(c, o.nodes));
            }
        }
        // Samplers and cameras point at nothing.
        _ => {}
    }
}

impl Merged {
    fn len(&self, key: &str) -> usize {
        self.arrays.get(key).and_then(Value::as_array).map_or(0, Vec::len)
    }

    fn offsets(&self) -> Offsets {
        Offsets {
            buffers: self.len("buffers"),
            views: self.len("bufferViews"),
            accessors: self.len("accessors"),
            images: self.len("images"),
            samplers: self.len("samplers"),
            textures: self.len("textures"),
            materials: self.len("materials"),
            meshes: self.len("meshes"),
            nodes: self.len("nodes"),
            cameras: self.len("cameras"),
        }
    }

    /// Appends a document whose files live in `folder` (relative to the merged file). Its scene's root nodes
    /// become roots here, wrapped in a node with `transform` when given; camera roots are kept only when
    /// `keep_cameras`.
    fn add(&mut self, mut doc: Value, folder: &str, transform: Option<Value>, keep_cameras: bool) {
        let o = self.offsets();
        let roots: Vec<usize> = doc
            .pointer("/scenes/0/nodes")
            .and_then(Value::as_array)
            .map(|r| r.iter().filter_map(Value::as_u64).map(|i| i as usize).collect())
            .unwrap_or_default();
        let is_camera = |r: usize| doc.get("nodes").and_then(|n| n.get(r)).is_some_and(|n| n.get("camera").is_some());
        let roots: Vec<usize> =
            roots.into_iter().filter(|&r| keep_cameras || !is_camera(r)).map(|r| r + o.nodes).collect();
        for key in ARRAYS {
            let mut items = doc.get_mut(key).map(Value::take).and_then(|v| v.as_array().cloned()).unwrap_or_default();
            items.iter_mut().for_each(|item| relocate(key, item, folder, &o));
            let entry = self.arrays.entry(key.to_string()).or_insert_with(|| json!([]));
            if let Some(a) = entry.as_array_mut() {
                a.extend(items);
            }
        }
        match transform {
            Some(mut t) => {
                t["children"] = json!(roots);
                let nodes = self.arrays.entry("nodes".to_string()).or_insert_with(|| json!([]));
                if let Some(a) = nodes.as_array_mut() {
                    a.push(t);
                    self.roots.push(a.len() - 1);
                }
            }
            None => self.roots.extend(roots),
        }
    }

    fn camera(&mut self, name: &str, eye: Vec3, target: Vec3) {
        let world = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse();
        let (_, r, t) = world.to_scale_rotation_translation();
        let r6 = |v: f32| (f64::from(v) * 1e6).round() / 1e6;
        let cam = self.len("cameras");
        self.arrays.entry("cameras".to_string()).or_insert_with(|| json!([]));
        if let Some(a) = self.arrays.get_mut("cameras").and_then(Value::as_array_mut) {
            a.push(json!({"name": name, "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.2, "zfar": 6000.0}}));
        }
        if let Some(a) = self.arrays.get_mut("nodes").and_then(Value::as_array_mut) {
            a.push(json!({"name": name, "camera": cam, "translation": [r6(t.x), r6(t.y), r6(t.z)], "rotation": [r6(r.x), r6(r.y), r6(r.z), r6(r.w)]}));
            self.roots.push(a.len() - 1);
        }
    }
}

fn read_json(path: &Path) -> std::io::Result<Value> {
    let text = std::fs::read_to_string(path)?;
    serde_json::from_str(&text).map_err(std::io::Error::other)
}

/// Writes `grid.gltf` into `out` (beside the `cars` and `track` folders).
pub fn generate(out: &Path, cars: &[CarInfo], track: &TrackInfo) -> std::io::Result<()> {
    let mut m = Merged::default();
    m.add(read_json(&out.join("track/circuit/circuit.gltf"))?, "track/circuit/", None, true);
    for (car, (pos, yaw)) in cars.iter().zip(&track.grid) {
        let doc = read_json(&out.join(format!("cars/{}.gltf", car.name)))?;
        // Cars face -Z in their own space; a slot's yaw turns the forward direction (sin yaw, 0, -cos yaw).
        let (s, c) = libm::sincosf(-0.5 * yaw);
        let r6 = |v: f32| (f64::from(v) * 1e6).round() / 1e6;
        let t = json!({"name": format!("{} on grid", car.name), "translation": [r6(pos.x), r6(pos.y), r6(pos.z)], "rotation": [0.0, r6(s), 0.0, r6(c)]});
        m.add(doc, "cars/", Some(t), false);
    }
    let last_car = cars.len().min(track.grid.len()).checked_sub(1).and_then(|i| track.grid.get(i));
    if let Some((pos, yaw)) = last_car {
        // Behind the last car, above, looking up the grid: every car from near to far.
        let fwd = Vec3::new(libm::sinf(*yaw), 0.0, -libm::cosf(*yaw));
        m.camera("grid behind", *pos - fwd * 9.0 + Vec3::Y * 2.5, *pos + fwd * 40.0);
        // Low at the side of the front row, looking back down the grid: the cars' faces and numbers.
        if let Some((front, _)) = track.grid.first() {
            let side = Vec3::new(fwd.z, 0.0, -fwd.x);
            m.camera("grid front", *front + fwd * 12.0 - side * 6.0 + Vec3::Y * 1.6, *pos + Vec3::Y * 0.5);
        }
    }
    let mut g = json!({"asset": {"version": "2.0", "generator": "scanline-racer assetgen"}, "scene": 0, "scenes": [{"nodes": m.roots}], "extensionsUsed": ["MSFT_lod"]});
    for key in ARRAYS {
        if let Some(v) = m.arrays.remove(key).filter(|v| v.as_array().is_some_and(|a| !a.is_empty())) {
            g[key] = v;
        }
    }
    let text = crate::gltf_out::gltf_text(&g)?;
    std::fs::write(out.join("grid.gltf"), text)
}
