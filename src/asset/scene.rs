//! A loaded scene: meshes, textures, LOD sets, placed instances and cameras, and what callers do with it
//! (draw it, find a camera, frame it, merge another scene into it).

use glam::Vec3;

use crate::render::{Camera, DrawList, Instance, LodSet, Mesh, Texture, ViewLists};

/// A camera placed in the scene by a node.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneCamera {
    /// The node's name, else the camera's name, else `camera N`.
    pub name: String,
    /// The camera's name in the file, if any.
    pub camera_name: Option<String>,
    /// The camera, with the node's world transform inverted as its view.
    pub camera: Camera,
}

/// Everything loaded from one glTF file, ready to hand to the renderer.
#[derive(Clone, Debug, Default)]
pub struct LoadedScene {
    /// Meshes (one per glTF mesh used by the scene).
    pub meshes: Vec<Mesh>,
    /// Base-colour textures.
    pub textures: Vec<Texture>,
    /// Placed meshes (or LOD sets) in node traversal order.
    pub instances: Vec<Instance>,
    /// Close/mid/long mesh sets, from `MSFT_lod` or the `_LOD0/1/2` naming convention.
    pub lod_sets: Vec<LodSet>,
    /// Camera nodes in traversal order.
    pub cameras: Vec<SceneCamera>,
    /// Primitives skipped because they are points or lines.
    pub skipped_primitives: usize,
    /// World-space bounds of all finite vertex positions, if any.
    pub bounds: Option<(Vec3, Vec3)>,
    /// Drawing orders made in advance for `view-lists` ([`LoadedScene::prepare_view_lists`]).
    pub view_lists: Option<ViewLists>,
    /// The files read to make the scene: the glTF file itself (when loaded from a file), then the buffers
    /// and images it names, each once; a command refuses to write its output over any of them.
    pub files: Vec<std::path::PathBuf>,
}

impl LoadedScene {
    /// The draw list over this scene.
    #[must_use]
    pub fn draw_list(&self) -> DrawList<'_> {
        DrawList {
            meshes: &self.meshes,
            textures: &self.textures,
            instances: &self.instances,
            lod_sets: &self.lod_sets,
            view_lists: self.view_lists.as_ref(),
        }
    }

    /// Total polygons over all instances, counting LOD sets at their close model.
    #[must_use]
    pub fn polygon_count(&self) -> usize {
        self.instances
            .iter()
            .filter_map(|i| {
                let mesh = match i.lod {
                    Some(set) => self.lod_sets.get(set)?.meshes[0],
                    None => i.mesh,
                };
                self.meshes.get(mesh)
            })
            .map(|m| m.polygons().len())
            .sum()
    }

    /// Builds the drawing orders `view-lists` uses, for every mesh of at most `max_polygons` polygons
    /// (rigid objects; a whole-world mesh is left to per-polygon ordering), at `level` (see
    /// [`crate::render::order::view_lists::directions`]).
    pub fn prepare_view_lists(&mut self, level: u32, max_polygons: usize) {
        self.view_lists = Some(ViewLists::build(&self.meshes, level, max_polygons));
    }

    /// Appends another scene's meshes, textures, LOD sets, instances and cameras; returns the index its first
    /// LOD set got here (its LOD set `k` is this scene's `k + returned`). Orders made in advance are dropped
    /// (the meshes changed).
    pub fn append(&mut self, other: LoadedScene) -> usize {
        self.view_lists = None;
        let (meshes, textures, sets) = (self.meshes.len(), self.textures.len(), self.lod_sets.len());
        self.meshes.extend(other.meshes.into_iter().map(|mut m| {
            m.rebase_textures(textures);
            m
        }));
        self.textures.extend(other.textures);
        self.lod_sets.extend(other.lod_sets.into_iter().map(|mut s| {
            s.meshes = s.meshes.map(|m| m + meshes);
            s
        }));
        self.instances.extend(other.instances.into_iter().map(|mut i| {
            i.mesh += meshes;
            i.lod = i.lod.map(|l| l + sets);
            i
        }));
        self.cameras.extend(other.cameras);
        self.files.extend(other.files);
        self.skipped_primitives += other.skipped_primitives;
        self.bounds = match (self.bounds, other.bounds) {
            (Some((a, b)), Some((c, d))) => Some((a.min(c), b.max(d))),
            (x, None) => x,
            (None, y) => y,
        };
        sets
    }

    /// Picks a camera by traversal index or by node or camera name.
    #[must_use]
    pub fn find_camera(&self, sel: &str) -> Option<&SceneCamera> {
        if let Ok(i) = sel.parse::<usize>() {
            return self.cameras.get(i);
        }
        self.cameras.iter().find(|c| c.name == sel || c.camera_name.as_deref() == Some(sel))
    }

    /// A perspective camera that frames the scene's bounds for a view of the given aspect (width / height).
    #[must_use]
    pub fn framing_camera(&self, aspect: f32) -> Camera {
        let (center, radius) = match self.bounds {
            Some((lo, hi)) => ((lo + hi) * 0.5, ((hi - lo) * 0.5).length().max(1e-6)),
            None => (Vec3::ZERO, 1.0),
        };
        let yfov = 0.8f32;
        let half_x = libm::atanf(libm::tanf(0.5 * yfov) * aspect.clamp(0.05, 20.0));
        let half = half_x.min(0.5 * yfov);
        let dist = radius / libm::sinf(half) * 1.02;
        let eye = center + Vec3::new(0.55, 0.45, 1.0).normalize() * dist;
        let znear = ((dist - radius) * 0.9).max(dist * 1e-3);
        Camera::look_at(eye, center, yfov, znear, Some(dist + radius * 1.1))
    }
}
