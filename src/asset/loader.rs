//! The glTF loader: document, buffers, images, node hierarchy, meshes, materials and cameras.

use std::collections::BTreeMap;
use std::io::Cursor;
use std::path::Path;

use glam::{Mat4, Vec2, Vec3, Vec4};
use gltf::mesh::Mode;
use thiserror::Error;

use super::accessor::{Elements, read_floats, read_indices};
use super::quads::merge_pairs;
pub use super::scene::{LoadedScene, SceneCamera};
use super::uri::{UriError, resolve};
use crate::render::{
    AlphaMode, Camera, Instance, LodSet, Material, Mesh, MeshBuilder, Projection, Sampler, Texture, Vertex, Wrap,
};

/// Switch sizes (projected height in pixels) for LOD sets that give no `MSFT_screencoverage` hints.
pub const DEFAULT_SWITCH_PX: [f32; 2] = [100.0, 24.0];
/// `MSFT_screencoverage` values are read as fractions of a frame this many pixels tall, so that larger frames
/// keep finer models at the same share of the screen (texel density is what matters).
pub const COVERAGE_HEIGHT: f32 = 720.0;

/// Largest glTF or GLB file accepted (1 GiB).
pub const MAX_FILE_BYTES: u64 = 1 << 30;
/// Largest texture side accepted.
pub const MAX_IMAGE_SIDE: u32 = 8192;
/// Deepest node hierarchy accepted (deeper is taken as a cycle).
pub const MAX_NODE_DEPTH: usize = 256;
/// Most node visits in one scene (bounds a hierarchy that instances a subtree many times).
pub const MAX_NODE_VISITS: usize = 1 << 20;

/// Why an asset could not be loaded; every variant names the file.
#[derive(Debug, Error)]
pub enum AssetError {
    /// The file could not be read.
    #[error("{file}: cannot read: {reason}")]
    Read {
        /// The file.
        file: String,
        /// The I/O error.
        reason: String,
    },
    /// The file is not valid glTF 2.0 (JSON, GLB container or schema).
    #[error("{file}: not a valid glTF 2.0 file: {reason}")]
    Parse {
        /// The file.
        file: String,
        /// What the parser reported.
        reason: String,
    },
    /// A buffer could not be resolved or is shorter than declared.
    #[error("{file}: buffer {index}: {reason}")]
    Buffer {
        /// The file.
        file: String,
        /// glTF buffer index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// An image could not be resolved or decoded.
    #[error("{file}: image {index}: {reason}")]
    Image {
        /// The file.
        file: String,
        /// glTF image index.
        index: usize,
        /// What is wrong.
        reason: String,
    },
    /// A mesh primitive has bad accessors or indices.
    #[error("{file}: mesh {mesh} primitive {primitive}: {reason}")]
    Primitive {
        /// The file.
        file: String,
        /// glTF mesh index.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// What is wrong.
        reason: String,
    },
    /// The node hierarchy or a camera is unusable.
    #[error("{file}: {reason}")]
    Scene {
        /// The file.
        file: String,
        /// What is wrong.
        reason: String,
    },
}

/// Loads a `.gltf` or `.glb` file.
pub fn load(path: &Path) -> Result<LoadedScene, AssetError> {
    let file = path.display().to_string();
    let read_err = |e: std::io::Error| AssetError::Read { file: file.clone(), reason: e.to_string() };
    let size = std::fs::metadata(path).map_err(read_err)?.len();
    if size > MAX_FILE_BYTES {
        return Err(AssetError::Read { file, reason: format!("{size} bytes is over the {MAX_FILE_BYTES}-byte limit") });
    }
    let bytes = std::fs::read(path).map_err(read_err)?;
    let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    load_from_slice(&bytes, base, &file)
}

/// Loads glTF or GLB bytes; external files are resolved inside `base_dir`; `file` names the source in errors.
pub fn load_from_slice(bytes: &[u8], base_dir: &Path, file: &str) -> Result<LoadedScene, AssetError> {
    let gltf = gltf::Gltf::from_slice(bytes)
        .map_err(|e| AssetError::Parse { file: file.to_string(), reason: one_line(&e.to_string()) })?;
    let mut loader = Loader {
        file: file.to_string(),
        base_dir,
        buffers: vec![],
        images: BTreeMap::new(),
        out: LoadedScene::default(),
    };
    loader.load_buffers(&gltf)?;
    loader.load_scene(&gltf.document)?;
    Ok(loader.out)
}

fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

struct Loader<'a> {
    file: String,
    base_dir: &'a Path,
    buffers: Vec<Vec<u8>>,
    /// glTF image index -> texture index (None when it failed to be wanted; errors are returned).
    images: BTreeMap<usize, usize>,
    out: LoadedScene,
}

impl Loader<'_> {
    fn load_buffers(&mut self, gltf: &gltf::Gltf) -> Result<(), AssetError> {
        for b in gltf.document.buffers() {
            let err = |reason: String| AssetError::Buffer { file: self.file.clone(), index: b.index(), reason };
            let data = match b.source() {
                gltf::buffer::Source::Bin => {
                    gltf.blob.clone().ok_or_else(|| err("refers to a GLB binary chunk that is missing".into()))?
                }
                gltf::buffer::Source::Uri(uri) => {
                    resolve(uri, self.base_dir).map_err(|e: UriError| err(e.to_string()))?
                }
            };
            if data.len() < b.length() {
                return Err(err(format!("holds {} bytes, but byteLength says {}", data.len(), b.length())));
            }
            self.buffers.push(data);
        }
        Ok(())
    }

    fn texture(&mut self, image: gltf::Image<'_>) -> Result<usize, AssetError> {
        if let Some(&t) = self.images.get(&image.index()) {
            return Ok(t);
        }
        let err = |reason: String| AssetError::Image { file: self.file.clone(), index: image.index(), reason };
        let bytes: Vec<u8> = match image.source() {
            gltf::image::Source::Uri { uri, .. } => resolve(uri, self.base_dir).map_err(|e| err(e.to_string()))?,
            gltf::image::Source::View { view, .. } => {
                let buf = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or_else(|| err("buffer view refers to a missing buffer".into()))?;
                let end = view
                    .offset()
                    .checked_add(view.length())
                    .ok_or_else(|| err("buffer view range overflows".into()))?;
                buf.get(view.offset()..end).ok_or_else(|| err("buffer view runs past its buffer".into()))?.to_vec()
            }
        };
        let texture = decode_image(&bytes).map_err(err)?;
        self.out.textures.push(texture);
        let t = self.out.textures.len() - 1;
        self.images.insert(image.index(), t);
        Ok(t)
    }

    fn load_scene(&mut self, doc: &gltf::Document) -> Result<(), AssetError> {
        let roots: Vec<gltf::Node<'_>> = match doc.default_scene().or_else(|| doc.scenes().next()) {
            Some(scene) => scene.nodes().collect(),
            None => {
                let mut is_child = vec![false; doc.nodes().len()];
                for n in doc.nodes() {
                    for c in n.children() {
                        is_child[c.index()] = true;
                    }
                }
                doc.nodes().filter(|n| !is_child[n.index()]).collect()
            }
        };
        let mut mesh_map: BTreeMap<usize, usize> = BTreeMap::new();
        // (node, parent's world transform, depth, nodes holding its middle and long models by naming convention)
        let mut stack: Vec<(gltf::Node<'_>, Mat4, usize, Vec<gltf::Node<'_>>)> =
            roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY, 0, vec![])).collect();
        let mut visits = 0usize;
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        while let Some((node, parent, depth, named_lods)) = stack.pop() {
            visits += 1;
            if depth > MAX_NODE_DEPTH || visits > MAX_NODE_VISITS {
                return Err(AssetError::Scene {
                    file: self.file.clone(),
                    reason: format!("node hierarchy is cyclic or too large (node {} at depth {depth})", node.index()),
                });
            }
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if let Some(mesh) = node.mesh() {
                let index = self.mesh_index(&mesh, &mut mesh_map)?;
                for v in self.out.meshes[index].vertices() {
                    let p = world.transform_point3(v.position);
                    if p.is_finite() {
                        lo = lo.min(p);
                        hi = hi.max(p);
                    }
                }
                let (alternates, coverage) = match self.msft_lod(doc, &node)? {
                    Some(found) => found,
                    None => (named_lods, None),
                };
                if alternates.is_empty() {
                    self.out.instances.push(Instance::new(index, world));
                } else {
                    let mut meshes = [index; 3];
                    for (k, alt) in alternates.iter().take(2).enumerate() {
                        let Some(m) = alt.mesh() else {
                            return Err(self.scene_error(format!("LOD node {} has no mesh", alt.index())));
                        };
                        meshes[k + 1] = self.mesh_index(&m, &mut mesh_map)?;
                    }
                    if alternates.len() == 1 {
                        meshes[2] = meshes[1];
                    }
                    let switch_px =
                        coverage.map_or(DEFAULT_SWITCH_PX, |c| [c[0] * COVERAGE_HEIGHT, c[1] * COVERAGE_HEIGHT]);
                    self.out.lod_sets.push(LodSet { meshes, switch_px });
                    self.out.instances.push(Instance::of_lod_set(self.out.lod_sets.len() - 1, world));
                }
            }
            if let Some(cam) = node.camera() {
                let camera = self.camera(&cam, world)?;
                let name = node
                    .name()
                    .or(cam.name())
                    .map_or_else(|| format!("camera {}", self.out.cameras.len()), str::to_string);
                self.out.cameras.push(SceneCamera { name, camera_name: cam.name().map(str::to_string), camera });
            }
            for (child, alternates) in named_lod_groups(node.children().collect()).into_iter().rev() {
                stack.push((child, world, depth + 1, alternates));
            }
        }
        if lo.is_finite() && hi.is_finite() {
            self.out.bounds = Some((lo, hi));
        }
        Ok(())
    }

    fn scene_error(&self, reason: String) -> AssetError {
        AssetError::Scene { file: self.file.clone(), reason }
    }

    /// The renderer mesh for a glTF mesh, loading it the first time.
    fn mesh_index(&mut self, mesh: &gltf::Mesh<'_>, map: &mut BTreeMap<usize, usize>) -> Result<usize, AssetError> {
        if let Some(&i) = map.get(&mesh.index()) {
            return Ok(i);
        }
        let m = self.mesh(mesh)?;
        self.out.meshes.push(m);
        let i = self.out.meshes.len() - 1;
        map.insert(mesh.index(), i);
        Ok(i)
    }

    /// The `MSFT_lod` alternates of a node (nodes with the middle and long models) and its
    /// `MSFT_screencoverage` hints, if the node has the extension.
    #[allow(clippy::type_complexity)]
    fn msft_lod<'d>(
        &self,
        doc: &'d gltf::Document,
        node: &gltf::Node<'d>,
    ) -> Result<Option<(Vec<gltf::Node<'d>>, Option<[f32; 2]>)>, AssetError> {
        let Some(ext) = node.extension_value("MSFT_lod") else {
            return Ok(None);
        };
        let bad = |what: &str| self.scene_error(format!("node {}: MSFT_lod {what}", node.index()));
        let ids = ext.get("ids").and_then(|v| v.as_array()).ok_or_else(|| bad("has no 'ids' array"))?;
        let mut alternates = vec![];
        for id in ids.iter().take(8) {
            let n = id
                .as_u64()
                .and_then(|i| doc.nodes().nth(usize::try_from(i).ok()?))
                .ok_or_else(|| bad("names a missing node"))?;
            alternates.push(n);
        }
        let coverage = node.extras().as_ref().and_then(|raw| {
            let v: serde_json::Value = serde_json::from_str(raw.get()).ok()?;
            let c = v.get("MSFT_screencoverage")?.as_array()?;
            let f = |i: usize| {
                c.get(i).and_then(serde_json::Value::as_f64).map(|x| x as f32).filter(|x| x.is_finite() && *x >= 0.0)
            };
            Some([f(0)?, f(1).unwrap_or(0.0)])
        });
        Ok(Some((alternates, coverage)))
    }

    fn camera(&self, cam: &gltf::Camera<'_>, world: Mat4) -> Result<Camera, AssetError> {
        let bad = |what: &str| AssetError::Scene {
            file: self.file.clone(),
            reason: format!("camera {}: {what}", cam.index()),
        };
        let positive = |v: f32| v.is_finite() && v > 0.0;
        let projection = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                if !(positive(p.yfov()) && p.yfov() < std::f32::consts::PI) {
                    return Err(bad("yfov must be between 0 and pi"));
                }
                if !positive(p.znear()) || p.zfar().is_some_and(|f| !(f.is_finite() && f > p.znear())) {
                    return Err(bad("znear must be positive and zfar beyond it"));
                }
                Projection::Perspective {
                    yfov: p.yfov(),
                    aspect: p.aspect_ratio().filter(|a| positive(*a)),
                    znear: p.znear(),
                    zfar: p.zfar(),
                }
            }
            gltf::camera::Projection::Orthographic(o) => {
                if !(o.xmag().is_finite() && o.xmag() != 0.0 && o.ymag().is_finite() && o.ymag() != 0.0) {
                    return Err(bad("xmag and ymag must be finite and non-zero"));
                }
                if !(o.znear().is_finite() && o.znear() >= 0.0 && o.zfar().is_finite() && o.zfar() > o.znear()) {
                    return Err(bad("znear must be at least 0 and zfar beyond it"));
                }
                Projection::Orthographic { xmag: o.xmag(), ymag: o.ymag(), znear: o.znear(), zfar: o.zfar() }
            }
        };
        let view = world.inverse();
        if !view.is_finite() {
            return Err(bad("its node transform cannot be inverted"));
        }
        Ok(Camera { view, projection })
    }

    fn mesh(&mut self, mesh: &gltf::Mesh<'_>) -> Result<Mesh, AssetError> {
        let mut b = MeshBuilder::new();
        let file = self.file.clone();
        for prim in mesh.primitives() {
            let err = |reason: String| AssetError::Primitive {
                file: file.clone(),
                mesh: mesh.index(),
                primitive: prim.index(),
                reason,
            };
            if !matches!(prim.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
                self.out.skipped_primitives += 1;
                continue;
            }
            let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
                self.out.skipped_primitives += 1;
                continue;
            };
            let positions = read_floats(&pos_acc, &self.buffers).map_err(|e| err(format!("POSITION: {e}")))?;
            if positions.width != 3 {
                return Err(err("POSITION must be VEC3".into()));
            }
            let n = positions.len();
            let gmat = prim.material();
            let pbr = gmat.pbr_metallic_roughness();
            let mut material = Material {
                base_color: Vec4::from(pbr.base_color_factor()),
                double_sided: gmat.double_sided(),
                alpha_mode: match gmat.alpha_mode() {
                    gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: gmat.alpha_cutoff().unwrap_or(0.5) },
                    _ => AlphaMode::Opaque,
                },
                ..Material::default()
            };
            let mut uv_set = None;
            if let Some(info) = pbr.base_color_texture() {
                let tex = info.texture();
                material.texture = Some(self.texture(tex.source())?);
                let s = tex.sampler();
                material.sampler = Sampler { wrap_s: wrap(s.wrap_s()), wrap_t: wrap(s.wrap_t()) };
                uv_set = Some(info.tex_coord());
            }
            let uvs = match uv_set.and_then(|set| prim.get(&gltf::Semantic::TexCoords(set))) {
                Some(acc) => {
                    let e = read_floats(&acc, &self.buffers).map_err(|e| err(format!("TEXCOORD: {e}")))?;
                    check_attr(&e, n, 2, "TEXCOORD").map_err(err)?;
                    Some(e)
                }
                None => None,
            };
            let colors = match prim.get(&gltf::Semantic::Colors(0)) {
                Some(acc) => {
                    let e = read_floats(&acc, &self.buffers).map_err(|e| err(format!("COLOR_0: {e}")))?;
                    if e.width != 3 && e.width != 4 {
                        return Err(err("COLOR_0 must be VEC3 or VEC4".into()));
                    }
                    check_attr(&e, n, e.width, "COLOR_0").map_err(err)?;
                    Some(e)
                }
                None => None,
            };
            let indices: Vec<u32> = match prim.indices() {
                Some(acc) => read_indices(&acc, &self.buffers).map_err(|e| err(format!("indices: {e}")))?,
                None => (0..n as u32).collect(),
            };
            if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
                return Err(err(format!("index {bad} is out of range for {n} vertices")));
            }
            let base = b.vertex_count() as u32;
            let mut verts = Vec::with_capacity(n);
            for i in 0..n {
                let position = Vec3::new(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2));
                let uv = uvs.as_ref().map_or(Vec2::ZERO, |e| Vec2::new(e.get(i, 0), e.get(i, 1)));
                let color = colors.as_ref().map_or(Vec4::ONE, |e| {
                    Vec4::new(e.get(i, 0), e.get(i, 1), e.get(i, 2), if e.width == 4 { e.get(i, 3) } else { 1.0 })
                });
                verts.push(Vertex { position, uv, color });
            }
            let m = b.material(material);
            for v in &verts {
                b.vertex(*v);
            }
            for poly in merge_pairs(&verts, &triangles(prim.mode(), &indices)) {
                let idx: Vec<u32> = poly.iter().map(|&i| base + i).collect();
                b.polygon(&idx, m);
            }
        }
        let mut built = b.build().map_err(|e| AssetError::Primitive {
            file: self.file.clone(),
            mesh: mesh.index(),
            primitive: 0,
            reason: e.to_string(),
        })?;
        super::decals::mark_decals(&mut built);
        Ok(built)
    }
}

/// Splits a node's children into the ones to visit, each with the siblings that hold its middle and long
/// models under the naming convention `NAME_LOD0`, `NAME_LOD1`, `NAME_LOD2` (LOD1 and LOD2 are not visited
/// on their own). Order is kept.
fn named_lod_groups(children: Vec<gltf::Node<'_>>) -> Vec<(gltf::Node<'_>, Vec<gltf::Node<'_>>)> {
    let split = |n: &gltf::Node<'_>| -> Option<(String, u8)> {
        let name = n.name()?;
        let (prefix, level) = name.rsplit_once("_LOD")?;
        let level: u8 = level.parse().ok().filter(|l| *l <= 2)?;
        Some((prefix.to_string(), level))
    };
    let find =
        |prefix: &str, level: u8| children.iter().find(|c| split(c).is_some_and(|(p, l)| p == prefix && l == level));
    let mut out = vec![];
    for c in &children {
        match split(c) {
            Some((prefix, 0)) if find(&prefix, 1).is_some() => {
                let alts: Vec<_> = [1, 2].iter().filter_map(|&l| find(&prefix, l).cloned()).collect();
                out.push((c.clone(), alts));
            }
            Some((prefix, 1 | 2)) if find(&prefix, 0).is_some() && find(&prefix, 1).is_some() => {}
            _ => out.push((c.clone(), vec![])),
        }
    }
    out
}

fn check_attr(e: &Elements, n: usize, width: usize, what: &str) -> Result<(), String> {
    if e.width != width {
        return Err(format!("{what} has {} components, expected {width}", e.width));
    }
    if e.len() != n {
        return Err(format!("{what} has {} elements, POSITION has {n}", e.len()));
    }
    Ok(())
}

fn wrap(w: gltf::texture::WrappingMode) -> Wrap {
    match w {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// Triangles of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN index list, with glTF's winding rules.
fn triangles(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
            .map(|i| if i % 2 == 0 { [idx[i], idx[i + 1], idx[i + 2]] } else { [idx[i + 1], idx[i], idx[i + 2]] })
            .collect(),
        Mode::TriangleFan => (1..idx.len().saturating_sub(1)).map(|i| [idx[i], idx[i + 1], idx[0]]).collect(),
        _ => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    }
}

/// Decodes PNG or JPEG bytes into a texture, refusing images over [`MAX_IMAGE_SIDE`] before decoding.
fn decode_image(bytes: &[u8]) -> Result<Texture, String> {
    let mut reader = image::ImageReader::new(Cursor::new(bytes)).with_guessed_format().map_err(|e| e.to_string())?;
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_IMAGE_SIDE);
    limits.max_image_height = Some(MAX_IMAGE_SIDE);
    limits.max_alloc = Some(512 << 20);
    reader.limits(limits);
    let img = reader.decode().map_err(|e| one_line(&e.to_string()))?;
    let rgba = img.to_rgba8();
    Texture::from_rgba8(rgba.width(), rgba.height(), rgba.as_raw()).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_follow_gltf_winding() {
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3]), [[0, 1, 2], [2, 1, 3]]);
        assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]), [[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3]), [[0, 1, 2]]);
        assert!(triangles(Mode::TriangleStrip, &[0]).is_empty());
    }
}
