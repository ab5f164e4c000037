//! Writing what one frame draws as a binary glTF (GLB): every drawn instance's polygons in world space
//! (after the LOD choice), as triangles grouped by material, with the textures as PNG and the frame's
//! camera as a camera node. Any glTF viewer opens it; the llvmpipe comparison script renders it.
//!
//! Polygons are fanned from their first vertex (the renderer's polygons are planar; the few concave ones
//! the loader keeps are rare and small). Materials keep the base colour, texture, wrap modes, alpha mask
//! and double-sidedness; sampling is nearest, as the renderer's default.

use std::collections::BTreeMap;

use glam::{Mat4, Vec2, Vec3, Vec4};
use serde_json::{Value, json};
use thiserror::Error;

use crate::render::{AlphaMode, Camera, DrawList, Material, Projection, Wrap};

/// Why a frame could not be exported.
#[derive(Debug, Error)]
pub enum ExportError {
    /// A texture could not be encoded as PNG.
    #[error("texture {index}: {source}")]
    Texture {
        /// Texture index in the draw list.
        index: usize,
        /// What the PNG encoder reported.
        source: image::ImageError,
    },
    /// The frame is too large for one GLB (over 4 GiB).
    #[error("the frame's geometry does not fit in one GLB ({bytes} bytes)")]
    TooLarge {
        /// Bytes needed.
        bytes: usize,
    },
}

/// Triangles of one material, in world space.
#[derive(Default)]
struct Group {
    material: Option<Material>,
    positions: Vec<Vec3>,
    uvs: Vec<Vec2>,
    colors: Vec<Vec4>,
    indices: Vec<u32>,
}

/// What [`export_glb`] wrote.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ExportSummary {
    /// Instances written (drawn, not culled).
    pub instances: usize,
    /// Triangles written.
    pub triangles: usize,
    /// Primitives (materials) written.
    pub primitives: usize,
}

fn material_key(m: &Material) -> String {
    format!(
        "{:?}|{:?}|{:?}|{}|{:?}",
        m.base_color.to_array().map(f32::to_bits),
        m.texture,
        m.sampler,
        m.double_sided,
        m.alpha_mode
    )
}

fn wrap_code(w: Wrap) -> u32 {
    match w {
        Wrap::Repeat => 10497,
        Wrap::ClampToEdge => 33071,
        Wrap::MirroredRepeat => 33648,
    }
}

/// The file's binary chunk and the JSON arrays that describe it, filled group by group.
#[derive(Default)]
struct Writer {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
    materials: Vec<Value>,
    primitives: Vec<Value>,
    images: Vec<Value>,
    textures: Vec<Value>,
    samplers: Vec<Value>,
    /// (texture index in the draw list, wrap S, wrap T) -> glTF texture index.
    texture_slot: BTreeMap<(usize, u32, u32), usize>,
}

impl Writer {
    /// Appends `bytes` to the binary chunk 4-byte aligned and returns a buffer view for it.
    fn view(&mut self, bytes: &[u8], target: Option<u32>) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let mut v = json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()});
        if let Some(t) = target {
            v["target"] = json!(t);
        }
        self.bin.extend_from_slice(bytes);
        self.views.push(v);
        self.views.len() - 1
    }

    /// Writes one material's triangles as a primitive: its four accessors, its material (and texture).
    /// A group with no triangles, or no finite position to bound, is left out.
    fn group(&mut self, g: &Group, list: &DrawList<'_>) -> Result<(), ExportError> {
        let Some(m) = &g.material else { return Ok(()) };
        if g.indices.is_empty() {
            return Ok(());
        }
        let (mut lo, mut hi) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));
        for p in g.positions.iter().filter(|p| p.is_finite()) {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        if !(lo.is_finite() && hi.is_finite()) {
            return Ok(());
        }
        let floats = |v: &mut Vec<u8>, xs: &[f32]| xs.iter().for_each(|x| v.extend_from_slice(&x.to_le_bytes()));
        let mut pos = vec![];
        g.positions.iter().for_each(|p| floats(&mut pos, &p.to_array()));
        let mut uv = vec![];
        g.uvs.iter().for_each(|p| floats(&mut uv, &p.to_array()));
        let mut col = vec![];
        g.colors.iter().for_each(|p| floats(&mut col, &p.to_array()));
        let mut ind = vec![];
        g.indices.iter().for_each(|i| ind.extend_from_slice(&i.to_le_bytes()));
        let n = g.positions.len();
        let pv = self.view(&pos, Some(34962));
        self.accessors.push(json!({"bufferView": pv, "componentType": 5126, "count": n, "type": "VEC3",
            "min": lo.to_array(), "max": hi.to_array()}));
        let uvv = self.view(&uv, Some(34962));
        self.accessors.push(json!({"bufferView": uvv, "componentType": 5126, "count": n, "type": "VEC2"}));
        let cv = self.view(&col, Some(34962));
        self.accessors.push(json!({"bufferView": cv, "componentType": 5126, "count": n, "type": "VEC4"}));
        let iv = self.view(&ind, Some(34963));
        self.accessors
            .push(json!({"bufferView": iv, "componentType": 5125, "count": g.indices.len(), "type": "SCALAR"}));
        let a = self.accessors.len();
        let mut pbr =
            json!({"baseColorFactor": m.base_color.to_array(), "metallicFactor": 0.0, "roughnessFactor": 1.0});
        if let Some(t) = m.texture.filter(|&t| t < list.textures.len()) {
            let slot = self.texture(list, t, m)?;
            pbr["baseColorTexture"] = json!({"index": slot});
        }
        let mut mat = json!({"pbrMetallicRoughness": pbr, "doubleSided": m.double_sided});
        if let AlphaMode::Mask { cutoff } = m.alpha_mode {
            mat["alphaMode"] = json!("MASK");
            mat["alphaCutoff"] = json!(cutoff);
        }
        self.materials.push(mat);
        self.primitives.push(json!({
            "attributes": {"POSITION": a - 4, "TEXCOORD_0": a - 3, "COLOR_0": a - 2},
            "indices": a - 1,
            "material": self.materials.len() - 1,
            "mode": 4
        }));
        Ok(())
    }

    /// The glTF texture for texture `t` of `list` with `m`'s wrap modes, encoded as PNG the first time.
    fn texture(&mut self, list: &DrawList<'_>, t: usize, m: &Material) -> Result<usize, ExportError> {
        let key = (t, wrap_code(m.sampler.wrap_s), wrap_code(m.sampler.wrap_t));
        if let Some(&s) = self.texture_slot.get(&key) {
            return Ok(s);
        }
        let tex = &list.textures[t];
        let rgba: Vec<u8> =
            tex.texels().iter().flat_map(|p| [(p >> 16) as u8, (p >> 8) as u8, *p as u8, (p >> 24) as u8]).collect();
        let mut png = vec![];
        image::ImageEncoder::write_image(
            image::codecs::png::PngEncoder::new(&mut png),
            &rgba,
            tex.width(),
            tex.height(),
            image::ExtendedColorType::Rgba8,
        )
        .map_err(|source| ExportError::Texture { index: t, source })?;
        let bv = self.view(&png, None);
        self.images.push(json!({"bufferView": bv, "mimeType": "image/png"}));
        self.samplers.push(json!({"magFilter": 9728, "minFilter": 9728, "wrapS": key.1, "wrapT": key.2}));
        self.textures.push(json!({"source": self.images.len() - 1, "sampler": self.samplers.len() - 1}));
        self.texture_slot.insert(key, self.textures.len() - 1);
        Ok(self.textures.len() - 1)
    }
}

/// Every drawn instance's polygons in world space, fanned into triangles and grouped by material; with
/// the instances and triangles counted.
fn group_by_material(
    list: &DrawList<'_>,
    meshes: &[Option<usize>],
    eye: Vec3,
) -> (BTreeMap<String, Group>, usize, usize) {
    let mut groups: BTreeMap<String, Group> = BTreeMap::new();
    let mut instances = 0;
    let mut triangles = 0;
    for (inst, chosen) in list.instances.iter().zip(meshes) {
        let Some(mesh) = chosen.and_then(|m| list.meshes.get(m)) else { continue };
        instances += 1;
        // A mesh that faces the eye is written turned as this frame draws it.
        let model: Mat4 = mesh.placed_model(&inst.model, eye);
        for poly in mesh.polygons() {
            let material = mesh.materials().get(poly.material as usize).cloned().unwrap_or_default();
            let g = groups.entry(material_key(&material)).or_default();
            g.material.get_or_insert(material);
            let idx = mesh.polygon_indices(poly);
            let base = g.positions.len() as u32;
            for &i in idx {
                let v = mesh.vertices()[i as usize];
                g.positions.push(model.transform_point3(v.position));
                g.uvs.push(v.uv);
                g.colors.push(v.color);
            }
            for k in 1..idx.len().saturating_sub(1) {
                g.indices.extend_from_slice(&[base, base + k as u32, base + k as u32 + 1]);
                triangles += 1;
            }
        }
    }
    (groups, instances, triangles)
}

/// The frame camera as a glTF perspective camera (an orthographic one is written with a 0.8 rad field of
/// view: the renderer's frames are perspective).
fn camera_json(camera: &Camera, (width, height): (usize, usize)) -> Value {
    let (yfov, znear, zfar) = match camera.projection {
        Projection::Perspective { yfov, znear, zfar, .. } => (yfov, znear, zfar),
        Projection::Orthographic { znear, zfar, .. } => (0.8, znear, Some(zfar)),
    };
    let mut persp = json!({"yfov": yfov, "znear": znear, "aspectRatio": width as f32 / height.max(1) as f32});
    if let Some(f) = zfar {
        persp["zfar"] = json!(f);
    }
    persp
}

/// The GLB container: the header, the JSON chunk padded with spaces, the binary chunk padded with zeros.
fn glb(doc: &Value, mut bin: Vec<u8>) -> Result<Vec<u8>, ExportError> {
    let mut json = serde_json::to_vec(doc).unwrap_or_default();
    while !json.len().is_multiple_of(4) {
        json.push(b' ');
    }
    while !bin.len().is_multiple_of(4) {
        bin.push(0);
    }
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let total32 = u32::try_from(total).map_err(|_| ExportError::TooLarge { bytes: total })?;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&total32.to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    Ok(out)
}

/// The GLB of the instances `meshes` says are drawn (one entry per instance of `list`, as
/// the meshes [`crate::render::Renderer::frame_lod`] gives), seen by `camera` in a `width` x `height` frame.
pub fn export_glb(
    list: &DrawList<'_>,
    meshes: &[Option<usize>],
    camera: &Camera,
    (width, height): (usize, usize),
) -> Result<(Vec<u8>, ExportSummary), ExportError> {
    let eye = camera.view.inverse().w_axis.truncate();
    let (groups, instances, triangles) = group_by_material(list, meshes, eye);
    let mut w = Writer::default();
    for g in groups.values() {
        w.group(g, list)?;
    }
    let camera_node = camera.view.inverse().to_cols_array();
    let summary = ExportSummary { instances, triangles, primitives: w.primitives.len() };
    let mut doc = json!({
        "asset": {"version": "2.0", "generator": concat!("scanline-racer ", env!("CARGO_PKG_VERSION"), " export-frame")},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0, "name": "frame"}, {"camera": 0, "name": "frame camera", "matrix": camera_node}],
        "meshes": [{"primitives": w.primitives}],
        "cameras": [{"type": "perspective", "perspective": camera_json(camera, (width, height))}],
        "materials": w.materials,
        "accessors": w.accessors,
        "bufferViews": w.views,
        "buffers": [{"byteLength": w.bin.len()}],
        "extras": {"width": width, "height": height, "instances": instances, "triangles": triangles}
    });
    if !w.images.is_empty() {
        doc["images"] = json!(w.images);
        doc["textures"] = json!(w.textures);
        doc["samplers"] = json!(w.samplers);
    }
    Ok((glb(&doc, w.bin)?, summary))
}
