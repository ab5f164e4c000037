//! A small, deterministic glTF 2.0 writer: one `.bin` buffer and PNG images beside one `.gltf` file.
//!
//! Keys are written sorted (serde_json's default map) and floats as Rust prints them, so the same input gives
//! the same bytes on every run and machine.

use std::path::Path;

use glam::{Vec2, Vec3, Vec4};
use serde_json::{Value, json};

/// One triangle list of a mesh with one material.
#[derive(Clone, Debug, Default)]
pub struct Primitive {
    /// Positions.
    pub positions: Vec<Vec3>,
    /// Texture coordinates (same length as positions), or empty.
    pub uvs: Vec<Vec2>,
    /// Vertex colours (same length as positions), or empty.
    pub colors: Vec<Vec4>,
    /// Triangle indices.
    pub indices: Vec<u32>,
    /// Material index in the document.
    pub material: usize,
}

impl Primitive {
    /// A primitive for `material` with no geometry yet.
    pub fn new(material: usize) -> Self {
        Self { material, ..Self::default() }
    }

    /// Adds a planar convex polygon (fan-triangulated, counter-clockwise seen from its front).
    pub fn polygon(&mut self, pts: &[Vec3], uvs: &[Vec2]) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(pts);
        self.uvs.extend_from_slice(uvs);
        for k in 1..pts.len().saturating_sub(1) {
            self.indices.extend_from_slice(&[base, base + k as u32, base + k as u32 + 1]);
        }
    }
}

/// How a texture repeats (glTF sampler wrap mode).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WrapMode {
    /// 10497.
    Repeat,
    /// 33071.
    Clamp,
}

/// Builds one glTF document.
#[derive(Debug, Default)]
pub struct Doc {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    textures: Vec<Value>,
    images: Vec<Value>,
    samplers: Vec<Value>,
    nodes: Vec<Value>,
    cameras: Vec<Value>,
    roots: Vec<usize>,
    extensions_used: Vec<&'static str>,
}

fn round(v: f32) -> f64 {
    // Six decimals keep the JSON stable and small; positions are stored exactly in the .bin anyway.
    (f64::from(v) * 1e6).round() / 1e6
}

impl Doc {
    /// An empty document.
    pub fn new() -> Self {
        Self::default()
    }

    fn view(&mut self, data: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": data.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(data);
        self.views.push(v);
        self.views.len() - 1
    }

    fn floats(&mut self, data: &[f32], count: usize, kind: &str, minmax: Option<(Vec<f32>, Vec<f32>)>) -> usize {
        let bytes: Vec<u8> = data.iter().flat_map(|f| f.to_le_bytes()).collect();
        let view = self.view(&bytes, Some(34962));
        let mut a = json!({"bufferView": view, "componentType": 5126, "count": count, "type": kind});
        if let Some((lo, hi)) = minmax {
            a["min"] = json!(lo.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
            a["max"] = json!(hi.iter().map(|&v| f64::from(v)).collect::<Vec<_>>());
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }

    fn indices(&mut self, idx: &[u32]) -> usize {
        let (bytes, ct): (Vec<u8>, u32) = if idx.iter().all(|&i| i < 65536) {
            (idx.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(), 5123)
        } else {
            (idx.iter().flat_map(|i| i.to_le_bytes()).collect(), 5125)
        };
        let view = self.view(&bytes, Some(34963));
        self.accessors.push(json!({"bufferView": view, "componentType": ct, "count": idx.len(), "type": "SCALAR"}));
        self.accessors.len() - 1
    }

    /// Adds a sampler + image (a PNG file name relative to the .gltf) + texture; returns the texture index.
    pub fn texture(&mut self, uri: &str, wrap: WrapMode) -> usize {
        let w = match wrap {
            WrapMode::Repeat => 10497,
            WrapMode::Clamp => 33071,
        };
        self.samplers.push(json!({"magFilter": 9728, "minFilter": 9728, "wrapS": w, "wrapT": w}));
        self.images.push(json!({"uri": uri}));
        self.textures.push(json!({"sampler": self.samplers.len() - 1, "source": self.images.len() - 1}));
        self.textures.len() - 1
    }

    /// Adds a material; `mask` is the alpha cutoff for `alphaMode` MASK.
    pub fn material(
        &mut self,
        name: &str,
        color: Vec4,
        texture: Option<usize>,
        double_sided: bool,
        mask: Option<f32>,
    ) -> usize {
        let mut pbr = json!({"baseColorFactor": [round(color.x), round(color.y), round(color.z), round(color.w)], "metallicFactor": 0.0, "roughnessFactor": 1.0});
        if let Some(t) = texture {
            pbr["baseColorTexture"] = json!({"index": t});
        }
        let mut m = json!({"name": name, "pbrMetallicRoughness": pbr, "doubleSided": double_sided});
        if let Some(c) = mask {
            m["alphaMode"] = json!("MASK");
            m["alphaCutoff"] = json!(round(c));
        }
        self.materials.push(m);
        self.materials.len() - 1
    }

    /// Marks mesh `index` as turning about its Y axis to face the eye (the loader reads
    /// `"extras": {"billboard": "y"}`).
    pub fn face_eye(&mut self, index: usize) {
        if let Some(m) = self.meshes.get_mut(index) {
            m["extras"] = json!({"billboard": "y"});
        }
    }

    /// Adds a mesh of primitives; returns its index.
    pub fn mesh(&mut self, name: &str, prims: &[Primitive]) -> usize {
        let mut out = vec![];
        for p in prims.iter().filter(|p| !p.indices.is_empty()) {
            let mut lo = vec![f32::INFINITY; 3];
            let mut hi = vec![f32::NEG_INFINITY; 3];
            for v in &p.positions {
                for (k, c) in v.to_array().iter().enumerate() {
                    lo[k] = lo[k].min(*c);
                    hi[k] = hi[k].max(*c);
                }
            }
            let pos: Vec<f32> = p.positions.iter().flat_map(|v| v.to_array()).collect();
            let mut attrs = json!({"POSITION": self.floats(&pos, p.positions.len(), "VEC3", Some((lo, hi)))});
            if !p.uvs.is_empty() {
                let uv: Vec<f32> = p.uvs.iter().flat_map(|v| v.to_array()).collect();
                attrs["TEXCOORD_0"] = json!(self.floats(&uv, p.uvs.len(), "VEC2", None));
            }
            if !p.colors.is_empty() {
                let c: Vec<f32> = p.colors.iter().flat_map(|v| v.to_array()).collect();
                attrs["COLOR_0"] = json!(self.floats(&c, p.colors.len(), "VEC4", None));
            }
            let indices = self.indices(&p.indices);
            out.push(json!({"attributes": attrs, "indices": indices, "material": p.material, "mode": 4}));
        }
        self.meshes.push(json!({"name": name, "primitives": out}));
        self.meshes.len() - 1
    }

    /// Adds a node; returns its index. `root` puts it in the scene's root list.
    pub fn node(&mut self, node: Value, root: bool) -> usize {
        self.nodes.push(node);
        let i = self.nodes.len() - 1;
        if root {
            self.roots.push(i);
        }
        i
    }

    /// Adds a LOD node: `meshes[0]` at `translation`/`rotation` with `MSFT_lod` alternates holding the middle
    /// and long models, and `MSFT_screencoverage` hints (fractions of the frame height, see the loader).
    pub fn lod_node(
        &mut self,
        name: &str,
        meshes: [usize; 3],
        coverage: [f32; 3],
        mut transform: Value,
        root: bool,
    ) -> usize {
        let mid = self.node(json!({"name": format!("{name} mid"), "mesh": meshes[1]}), false);
        let long = self.node(json!({"name": format!("{name} long"), "mesh": meshes[2]}), false);
        transform["name"] = json!(name);
        transform["mesh"] = json!(meshes[0]);
        transform["extensions"] = json!({"MSFT_lod": {"ids": [mid, long]}});
        transform["extras"] = json!({"MSFT_screencoverage": coverage.iter().map(|&c| round(c)).collect::<Vec<_>>()});
        if !self.extensions_used.contains(&"MSFT_lod") {
            self.extensions_used.push("MSFT_lod");
        }
        self.node(transform, root)
    }

    /// Adds a perspective camera node named `name` at `eye` looking at `target` (a root node).
    pub fn camera_node(&mut self, name: &str, eye: Vec3, target: Vec3, yfov: f32) -> usize {
        let world = glam::camera::rh::view::look_at_mat4(eye, target, Vec3::Y).inverse();
        let (_, r, t) = world.to_scale_rotation_translation();
        self.cameras.push(json!({"name": name, "type": "perspective", "perspective": {"yfov": round(yfov), "znear": 0.1, "zfar": 5000.0}}));
        let camera = self.cameras.len() - 1;
        self.node(
            json!({"name": name, "camera": camera, "translation": [round(t.x), round(t.y), round(t.z)], "rotation": [round(r.x), round(r.y), round(r.z), round(r.w)]}),
            true,
        )
    }

    /// Writes `dir/name.gltf` and `dir/name.bin`.
    pub fn write(self, dir: &Path, name: &str) -> std::io::Result<()> {
        let bin_name = format!("{name}.bin");
        let mut g = json!({
            "asset": {"version": "2.0", "generator": "scanline-racer assetgen"},
            "buffers": [{"byteLength": self.bin.len(), "uri": bin_name}],
            "bufferViews": self.views,
            "accessors": self.accessors,
            "meshes": self.meshes,
            "materials": self.materials,
            "nodes": self.nodes,
            "scenes": [{"nodes": self.roots}],
            "scene": 0,
        });
        if !self.textures.is_empty() {
            g["textures"] = json!(self.textures);
            g["images"] = json!(self.images);
            g["samplers"] = json!(self.samplers);
        }
        if !self.cameras.is_empty() {
            g["cameras"] = json!(self.cameras);
        }
        if !self.extensions_used.is_empty() {
            g["extensionsUsed"] = json!(self.extensions_used);
        }
        std::fs::write(dir.join(format!("{name}.gltf")), gltf_text(&g)?)?;
        std::fs::write(dir.join(bin_name), &self.bin)
    }
}

/// A glTF document's text: one top-level member per line, and one element per line in the arrays of
/// objects (nodes, meshes, accessors...), each compact. A scene of thousands of nodes stays a few megabytes
/// (indenting every number takes several times that), and a change to one node is a change to one line.
pub fn gltf_text(g: &Value) -> std::io::Result<String> {
    let compact = |v: &Value| serde_json::to_string(v).map_err(std::io::Error::other);
    let Value::Object(members) = g else { return compact(g) };
    let mut lines = vec![];
    for (key, value) in members {
        let key = compact(&Value::String(key.clone()))?;
        match value {
            Value::Array(items) if items.iter().all(Value::is_object) && !items.is_empty() => {
                let items: Vec<String> = items.iter().map(compact).collect::<Result<_, _>>()?;
                lines.push(format!("{key}: [\n{}\n]", items.join(",\n")));
            }
            _ => lines.push(format!("{key}: {}", compact(value)?)),
        }
    }
    Ok(format!("{{\n{}\n}}\n", lines.join(",\n")))
}

/// A node transform as glTF JSON (translation and a rotation about +Y).
pub fn placed(translation: Vec3, yaw: f32) -> Value {
    let (s, c) = libm::sincosf(0.5 * yaw);
    json!({"translation": [round(translation.x), round(translation.y), round(translation.z)], "rotation": [0.0, round(s), 0.0, round(c)]})
}
