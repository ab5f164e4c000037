//! The glTF loader: the document, its buffers and images, the node hierarchy, meshes, materials, cameras,
//! all within one [`LoadBudget`].
//!
//! A load goes: read the file ([`crate::userfile::read_regular`]: regular files only, at most
//! [`LoadBudget::file_bytes`]); parse and validate it ([`super::sources::parse`], a GLB's binary chunk
//! borrowed, not copied); check what the `gltf` crate's validation lets through but its accessors unwrap
//! ([`super::validate`]); read the buffers, each distinct source once ([`super::sources::load_buffers`]);
//! walk the scene, building each glTF mesh the first time a node places it ([`super::meshes`]; accessors
//! read once each) and decoding each image source the first time a material names it.
//!
//! Every cost is charged to the load's [`Meter`]: buffer and image bytes, decoded texels, accessor values,
//! vertices and polygons after instancing, node visits and depth (see [`LoadBudget`] for the defaults). A
//! file that needs more is refused with [`AssetError::Budget`], one line that names the limit. Meshes are
//! stored once however often they are placed. The scene's bounds transform every placed vertex up to
//! [`EXACT_BOUNDS_VERTICES`] per load, then each placement's local box (computed once per mesh) by its
//! eight corners, so a hierarchy that places a big mesh many times costs 8 transforms per placement.
//!
//! A placement whose world transform has a negative determinant mirrors the mesh, and glTF says the front
//! face flips with it: such an instance draws a winding-reversed copy of its mesh (made once per mesh and
//! cached; LOD sets likewise), so single-sided polygons face the way the file means.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{Mat4, Vec3};

use super::accessor::AccessorCache;
pub use super::budget::LoadBudget;
use super::budget::{Limit, Meter, OverBudget};
pub use super::error::AssetError;
use super::error::{CameraProblem, LodProblem, ParseError, Place, SceneProblem};
use super::meshes::reversed_winding;
pub use super::scene::{LoadedScene, SceneCamera};
pub use super::sources::MAX_IMAGE_SIDE;
use super::sources::{Images, Parsed, load_buffers, parse};
use super::state::Loader;
use super::uri::Base;
use crate::render::{Camera, Instance, LodSet, Mesh, Projection};
use crate::userfile::{FileProblem, read_regular};

/// Switch sizes (projected height in pixels) for LOD sets that give no `MSFT_screencoverage` hints.
pub const DEFAULT_SWITCH_PX: [f32; 2] = [100.0, 24.0];
/// `MSFT_screencoverage` values are read as fractions of a frame this many pixels tall, so that larger frames
/// keep finer models at the same share of the screen (texel density is what matters).
pub const COVERAGE_HEIGHT: f32 = 720.0;

/// Loads a `.gltf` or `.glb` file within the default [`LoadBudget`].
pub fn load(path: &Path) -> Result<LoadedScene, AssetError> {
    load_with_budget(path, &LoadBudget::default())
}

/// Loads a `.gltf` or `.glb` file within `budget`.
pub fn load_with_budget(path: &Path, budget: &LoadBudget) -> Result<LoadedScene, AssetError> {
    let file = path.display().to_string();
    let bytes = read_regular(path, budget.file_bytes, "a glTF file").map_err(|e| match e.problem {
        FileProblem::TooBig { size, limit, .. } => {
            AssetError::budget(&file, Place::File, OverBudget { limit: Limit::FileBytes, needed: size, allowed: limit })
        }
        problem => AssetError::Read { file: file.clone(), problem },
    })?;
    let base = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let mut scene = load_from_slice_with_budget(&bytes, base, &file, budget)?;
    scene.files.insert(0, path.to_path_buf());
    Ok(scene)
}

/// Loads glTF or GLB bytes within the default [`LoadBudget`]; external files are resolved inside
/// `base_dir`; `file` names the source in errors.
pub fn load_from_slice(bytes: &[u8], base_dir: &Path, file: &str) -> Result<LoadedScene, AssetError> {
    load_from_slice_with_budget(bytes, base_dir, file, &LoadBudget::default())
}

/// Loads a glTF file of a tree of files built into the program (`files`, by path), named by its path in
/// that tree (`track/circuit/circuit.gltf`), within the default [`LoadBudget`]; the files it names are found in
/// the same tree, relative to its folder.
pub fn load_embedded(path: &str, files: &[(&str, &[u8])]) -> Result<LoadedScene, AssetError> {
    let bytes = files.iter().find(|(n, _)| *n == path).map(|(_, b)| *b).ok_or_else(|| AssetError::Read {
        file: path.to_string(),
        problem: FileProblem::Io(std::io::Error::from(std::io::ErrorKind::NotFound)),
    })?;
    let dir = path.rsplit_once('/').map_or("", |(d, _)| d);
    load_from_base(bytes, Base::Embedded { dir, files }, path, &LoadBudget::default())
}

/// Loads glTF or GLB bytes within `budget`; external files are resolved inside `base_dir`; `file` names
/// the source in errors.
pub fn load_from_slice_with_budget(
    bytes: &[u8],
    base_dir: &Path,
    file: &str,
    budget: &LoadBudget,
) -> Result<LoadedScene, AssetError> {
    load_from_base(bytes, Base::Folder(base_dir), file, budget)
}

/// Loads glTF or GLB bytes within `budget`, the files they name found from `base`.
fn load_from_base(bytes: &[u8], base: Base<'_>, file: &str, budget: &LoadBudget) -> Result<LoadedScene, AssetError> {
    let mut meter = Meter::new(*budget);
    meter.charge(Limit::FileBytes, bytes.len() as u64).map_err(|over| AssetError::budget(file, Place::File, over))?;
    let parse_error = |problem: ParseError| AssetError::Parse { file: file.to_string(), problem };
    let Parsed { doc, blob } = parse(bytes).map_err(parse_error)?;
    super::validate::check(doc.as_json()).map_err(|e| parse_error(e.into()))?;
    let buffers = load_buffers(&doc, blob, base, &mut meter, file)?;
    let slices = buffers.slices();
    let mut loader = Loader {
        file: file.to_string(),
        base,
        doc: &doc,
        buffers: &slices,
        images: Images::default(),
        accessors: AccessorCache::default(),
        meter,
        out: LoadedScene::default(),
        mesh_map: BTreeMap::new(),
        mirrored: BTreeMap::new(),
        local_bounds: vec![],
        trims: super::trim::Trimmer::default(),
    };
    loader.load_scene()?;
    let mut out = loader.out;
    out.files = buffers.files().chain(loader.images.files()).cloned().collect();
    Ok(out)
}

/// Vertex transforms the scene's bounds may spend per load on exact boxes (4 Mi, tens of milliseconds):
/// placements are bounded by transforming every vertex of their mesh until this runs out, then by the
/// eight corners of the mesh's local box (a conservative box, looser under rotation). The budget caps
/// vertices after instancing anyway; this keeps a scene of millions of them from paying twice.
pub const EXACT_BOUNDS_VERTICES: u64 = 1 << 22;

/// The world-space box of everything placed so far.
struct Bounds {
    lo: Vec3,
    hi: Vec3,
    /// Vertex transforms left for exact boxes.
    exact_left: u64,
}

impl Bounds {
    fn grow(&mut self, p: Vec3) {
        if p.is_finite() {
            self.lo = self.lo.min(p);
            self.hi = self.hi.max(p);
        }
    }

    /// Adds `mesh` placed at `world`: exactly while the work allows, else its local box's corners.
    fn add(&mut self, mesh: &Mesh, local: Option<(Vec3, Vec3)>, world: Mat4) {
        let Some((lo, hi)) = local else { return };
        let n = mesh.vertices().len() as u64;
        if n <= self.exact_left {
            self.exact_left -= n;
            for v in mesh.vertices() {
                self.grow(world.transform_point3(v.position));
            }
            return;
        }
        for k in 0..8 {
            let corner = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            self.grow(world.transform_point3(corner));
        }
    }
}

/// The box of a mesh's finite vertex positions.
fn local_bounds(mesh: &Mesh) -> Option<(Vec3, Vec3)> {
    let mut lo = Vec3::splat(f32::INFINITY);
    let mut hi = Vec3::splat(f32::NEG_INFINITY);
    for v in mesh.vertices() {
        if v.position.is_finite() {
            lo = lo.min(v.position);
            hi = hi.max(v.position);
        }
    }
    (lo.cmple(hi).all()).then_some((lo, hi))
}

impl<'a> Loader<'a> {
    fn load_scene(&mut self) -> Result<(), AssetError> {
        let doc = self.doc;
        let roots: Vec<gltf::Node<'a>> = match doc.default_scene().or_else(|| doc.scenes().next()) {
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
        // Visits are charged when a node is pushed, not when it is popped, so that neither the stack nor the
        // work of grouping a node's children (a node may list a million children) outgrows the budget.
        self.meter
            .charge(Limit::NodeVisits, roots.len() as u64)
            .map_err(|over| AssetError::budget(&self.file, Place::RootNodes, over))?;
        // (node, parent's world transform, depth, nodes holding its middle and long models by naming convention)
        let mut stack: Vec<(gltf::Node<'a>, Mat4, usize, Vec<gltf::Node<'a>>)> =
            roots.into_iter().rev().map(|n| (n, Mat4::IDENTITY, 0, vec![])).collect();
        // The current node's ancestors (depth-first, so the path is the stack of nodes above it).
        let mut path: Vec<usize> = vec![];
        let mut on_path = vec![false; doc.nodes().len()];
        let mut bounds = Bounds {
            lo: Vec3::splat(f32::INFINITY),
            hi: Vec3::splat(f32::NEG_INFINITY),
            exact_left: EXACT_BOUNDS_VERTICES,
        };
        while let Some((node, parent, depth, named_lods)) = stack.pop() {
            let at = Place::Node(node.index());
            self.meter.check_depth(depth as u64).map_err(|over| AssetError::budget(&self.file, at, over))?;
            while path.len() > depth {
                if let Some(n) = path.pop() {
                    on_path[n] = false;
                }
            }
            if on_path.get(node.index()).copied().unwrap_or(false) {
                return Err(self.scene_error(SceneProblem::Cycle { node: node.index() }));
            }
            if let Some(flag) = on_path.get_mut(node.index()) {
                *flag = true;
            }
            path.push(node.index());
            let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
            if let Some(mesh) = node.mesh() {
                self.place(doc, &node, &mesh, world, named_lods, &mut bounds)?;
            }
            if let Some(cam) = node.camera() {
                let camera = self.camera(&cam, world)?;
                let name = node
                    .name()
                    .or(cam.name())
                    .map_or_else(|| format!("camera {}", self.out.cameras.len()), str::to_string);
                self.out.cameras.push(SceneCamera { name, camera_name: cam.name().map(str::to_string), camera });
            }
            self.meter
                .charge(Limit::NodeVisits, node.children().len() as u64)
                .map_err(|over| AssetError::budget(&self.file, Place::Children(node.index()), over))?;
            for (child, alternates) in named_lod_groups(node.children().collect()).into_iter().rev() {
                stack.push((child, world, depth + 1, alternates));
            }
        }
        if bounds.lo.is_finite() && bounds.hi.is_finite() {
            self.out.bounds = Some((bounds.lo, bounds.hi));
        }
        Ok(())
    }

    /// Places a node's mesh (or LOD set) at `world`: charges its vertices and polygons after instancing,
    /// uses the winding-reversed meshes when `world` mirrors, and grows the scene's bounds.
    fn place(
        &mut self,
        doc: &'a gltf::Document,
        node: &gltf::Node<'a>,
        mesh: &gltf::Mesh<'a>,
        world: Mat4,
        named_lods: Vec<gltf::Node<'a>>,
        bounds: &mut Bounds,
    ) -> Result<(), AssetError> {
        let index = self.mesh_index(mesh)?;
        let (alternates, coverage) = match self.msft_lod(doc, node)? {
            Some(found) => found,
            None => (named_lods, None),
        };
        let mut meshes = [index; 3];
        for (k, alt) in alternates.iter().take(2).enumerate() {
            let Some(m) = alt.mesh() else {
                return Err(self.scene_error(SceneProblem::LodWithoutMesh { node: alt.index() }));
            };
            meshes[k + 1] = self.mesh_index(&m)?;
        }
        if alternates.len() == 1 {
            meshes[2] = meshes[1];
        }
        // NaN (a broken transform) is not mirrored; the renderer drops its polygons anyway.
        if world.determinant() < 0.0 {
            for m in &mut meshes {
                *m = self.mirrored(*m)?;
            }
        }
        let (mut vertices, mut polygons) = (0, 0);
        for &m in &meshes {
            let mesh =
                self.out.meshes.get(m).ok_or_else(|| self.scene_error(SceneProblem::MissingMeshSlot { slot: m }))?;
            vertices = vertices.max(mesh.vertices().len() as u64);
            polygons = polygons.max(mesh.polygons().len() as u64);
        }
        self.meter
            .charge(Limit::Vertices, vertices)
            .and_then(|()| self.meter.charge(Limit::Polygons, polygons))
            .map_err(|over| AssetError::budget(&self.file, Place::Node(node.index()), over))?;
        if let Some(mesh) = self.out.meshes.get(meshes[0]) {
            bounds.add(mesh, self.local_bounds.get(meshes[0]).copied().flatten(), world);
        }
        if alternates.is_empty() {
            self.out.instances.push(Instance::new(meshes[0], world));
        } else {
            let switch_px = coverage.map_or(DEFAULT_SWITCH_PX, |c| [c[0] * COVERAGE_HEIGHT, c[1] * COVERAGE_HEIGHT]);
            self.out.lod_sets.push(LodSet { meshes, switch_px });
            self.out.instances.push(Instance::of_lod_set(self.out.lod_sets.len() - 1, world));
        }
        Ok(())
    }

    fn scene_error(&self, problem: SceneProblem) -> AssetError {
        AssetError::Scene { file: self.file.clone(), problem }
    }

    /// The renderer mesh for a glTF mesh, loading it the first time.
    fn mesh_index(&mut self, mesh: &gltf::Mesh<'_>) -> Result<usize, AssetError> {
        if let Some(&i) = self.mesh_map.get(&mesh.index()) {
            return Ok(i);
        }
        let m = self.mesh(mesh)?;
        self.local_bounds.push(local_bounds(&m));
        self.out.meshes.push(m);
        let i = self.out.meshes.len() - 1;
        self.mesh_map.insert(mesh.index(), i);
        Ok(i)
    }

    /// The winding-reversed copy of `out.meshes[index]`, made the first time a mirrored placement needs it.
    fn mirrored(&mut self, index: usize) -> Result<usize, AssetError> {
        if let Some(&i) = self.mirrored.get(&index) {
            return Ok(i);
        }
        let mesh = self
            .out
            .meshes
            .get(index)
            .ok_or_else(|| self.scene_error(SceneProblem::MissingMeshSlot { slot: index }))?;
        let copy = reversed_winding(mesh).map_err(|e| self.scene_error(SceneProblem::Mirrored(e)))?;
        self.local_bounds.push(self.local_bounds.get(index).copied().flatten());
        self.out.meshes.push(copy);
        let i = self.out.meshes.len() - 1;
        self.mirrored.insert(index, i);
        // A copy mirrored again is the original.
        self.mirrored.insert(i, index);
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
        let bad = |problem| self.scene_error(SceneProblem::MsftLod { node: node.index(), problem });
        let ids = ext.get("ids").and_then(|v| v.as_array()).ok_or_else(|| bad(LodProblem::NoIds))?;
        let mut alternates = vec![];
        for (entry, id) in ids.iter().take(8).enumerate() {
            let n = id
                .as_u64()
                .and_then(|i| doc.nodes().nth(usize::try_from(i).ok()?))
                .ok_or_else(|| bad(LodProblem::MissingNode { entry }))?;
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
        let bad = |problem| self.scene_error(SceneProblem::Camera { camera: cam.index(), problem });
        let positive = |v: f32| v.is_finite() && v > 0.0;
        let projection = match cam.projection() {
            gltf::camera::Projection::Perspective(p) => {
                if !(positive(p.yfov()) && p.yfov() < std::f32::consts::PI) {
                    return Err(bad(CameraProblem::FieldOfView { yfov: p.yfov() }));
                }
                if !positive(p.znear()) || p.zfar().is_some_and(|f| !(f.is_finite() && f > p.znear())) {
                    return Err(bad(CameraProblem::PerspectiveDepth { znear: p.znear(), zfar: p.zfar() }));
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
                    return Err(bad(CameraProblem::Magnification { xmag: o.xmag(), ymag: o.ymag() }));
                }
                if !(o.znear().is_finite() && o.znear() >= 0.0 && o.zfar().is_finite() && o.zfar() > o.znear()) {
                    return Err(bad(CameraProblem::OrthographicDepth { znear: o.znear(), zfar: o.zfar() }));
                }
                Projection::Orthographic { xmag: o.xmag(), ymag: o.ymag(), znear: o.znear(), zfar: o.zfar() }
            }
        };
        let view = world.inverse();
        if !view.is_finite() {
            return Err(bad(CameraProblem::NotInvertible));
        }
        Ok(Camera { view, projection })
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
    // Each child's name is split once and the first child of each (prefix, level) is found through a map:
    // linear in the children (a node may list a million), not quadratic.
    let keys: Vec<Option<(String, u8)>> = children.iter().map(split).collect();
    let mut first: BTreeMap<(&str, u8), usize> = BTreeMap::new();
    for (i, k) in keys.iter().enumerate() {
        if let Some((prefix, level)) = k {
            first.entry((prefix.as_str(), *level)).or_insert(i);
        }
    }
    let find = |prefix: &str, level: u8| first.get(&(prefix, level)).map(|&i| &children[i]);
    let mut out = vec![];
    for (c, k) in children.iter().zip(&keys) {
        match k {
            Some((prefix, 0)) if find(prefix, 1).is_some() => {
                let alts: Vec<_> = [1, 2].iter().filter_map(|&l| find(prefix, l).cloned()).collect();
                out.push((c.clone(), alts));
            }
            Some((prefix, 1 | 2)) if find(prefix, 0).is_some() && find(prefix, 1).is_some() => {}
            _ => out.push((c.clone(), vec![])),
        }
    }
    out
}
