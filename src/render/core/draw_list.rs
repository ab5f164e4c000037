//! What a frame draws: meshes, textures, placed instances, level-of-detail sets and stored orders.

use glam::Vec3;

use crate::render::core::mesh::Mesh;
use crate::render::core::texture::Texture;

/// One placed mesh, or one placed LOD set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// Index into [`DrawList::meshes`] (ignored when `lod` names a set).
    pub mesh: usize,
    /// Model space to world space.
    pub model: glam::Mat4,
    /// Index into [`DrawList::lod_sets`]: the model is chosen per frame from that set.
    pub lod: Option<usize>,
    /// Drawn see-through: a screen door (every other pixel, in a checkerboard), so what is behind shows
    /// between its pixels in every visibility method, with no blending and no sorting of its own (as the
    /// Saturn drew its shadows and ghosts).
    pub see_through: bool,
}

impl Instance {
    /// A single mesh placed by `model`.
    #[must_use]
    pub fn new(mesh: usize, model: glam::Mat4) -> Self {
        Self { mesh, model, lod: None, see_through: false }
    }

    /// A LOD set placed by `model`.
    #[must_use]
    pub fn of_lod_set(set: usize, model: glam::Mat4) -> Self {
        Self { mesh: 0, model, lod: Some(set), see_through: false }
    }

    /// The same instance drawn see-through (see [`Instance::see_through`]).
    #[must_use]
    pub fn see_through(self) -> Self {
        Self { see_through: true, ..self }
    }
}

/// What to draw: meshes, the textures their materials refer to, and where to put them.
#[derive(Clone, Copy, Debug)]
pub struct DrawList<'a> {
    /// Meshes.
    pub meshes: &'a [Mesh],
    /// Textures, indexed by [`Material::texture`](crate::render::core::mesh::Material::texture).
    pub textures: &'a [Texture],
    /// Instances, drawn in this order (it is the submission order the ordering table keeps within a bucket).
    pub instances: &'a [Instance],
    /// Sets of close/mid/long meshes that instances may refer to.
    pub lod_sets: &'a [LodSet],
    /// Drawing orders made in advance for the meshes (used by
    /// [`Method::ViewLists`](crate::render::core::options::Method::ViewLists); `None` elsewhere).
    pub view_lists: Option<&'a ViewLists>,
}

/// The three models of one object and where they switch.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodSet {
    /// Mesh indices (into the draw list's meshes) of the close, middle and long models.
    pub meshes: [usize; 3],
    /// Projected heights in pixels: below `switch_px[0]` the middle model is used, below `switch_px[1]` the
    /// long one.
    pub switch_px: [f32; 2],
}

/// The stored lists of one mesh.
#[derive(Clone, Debug)]
pub struct MeshLists {
    /// The mesh with every split piece appended after its own polygons; lists index its polygons.
    pub mesh: Mesh,
    /// The stored view directions (model space).
    pub directions: Vec<Vec3>,
    /// For each direction, the polygons of [`MeshLists::mesh`] in drawing order.
    pub lists: Vec<Vec<u32>>,
    /// Polygons split to break cycles, over all directions.
    pub splits: usize,
    /// Cycles left unbroken (no plane of the cycle cut another of its polygons), over all directions.
    pub unbroken: usize,
}

impl MeshLists {
    /// The list for the stored direction nearest to `dir` (model space, from the eye towards the object).
    #[must_use]
    pub fn nearest(&self, dir: Vec3) -> &[u32] {
        let mut best = (f32::NEG_INFINITY, 0);
        for (i, d) in self.directions.iter().enumerate() {
            let c = d.dot(dir);
            if c > best.0 {
                best = (c, i);
            }
        }
        self.lists.get(best.1).map_or(&[], Vec::as_slice)
    }
}

/// Stored lists for the meshes of a draw list (by mesh index; `None` for meshes without lists).
#[derive(Clone, Debug, Default)]
pub struct ViewLists {
    /// Per mesh.
    pub meshes: Vec<Option<MeshLists>>,
}

impl ViewLists {
    /// The lists of mesh `index`, if it has any.
    #[must_use]
    pub fn get(&self, index: usize) -> Option<&MeshLists> {
        self.meshes.get(index).and_then(Option::as_ref)
    }
}
