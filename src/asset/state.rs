//! The state of one glTF load, shared by its two halves: the scene walk (`loader`) and mesh building
//! (`meshes`). It sits below both so that neither imports the other's file.

use std::collections::BTreeMap;

use glam::Vec3;

use super::accessor::AccessorCache;
use super::budget::Meter;
use super::scene::LoadedScene;
use super::sources::Images;

/// The state of one load: the scene walk is in [`super::loader`], the mesh building in [`super::meshes`].
pub(super) struct Loader<'a> {
    pub(super) file: String,
    pub(super) base: super::uri::Base<'a>,
    pub(super) doc: &'a gltf::Document,
    /// Each glTF buffer's bytes, by buffer index.
    pub(super) buffers: &'a [&'a [u8]],
    pub(super) images: Images<'a>,
    pub(super) accessors: AccessorCache,
    pub(super) meter: Meter,
    pub(super) out: LoadedScene,
    /// glTF mesh index -> index in `out.meshes`.
    pub(super) mesh_map: BTreeMap<usize, usize>,
    /// Index in `out.meshes` -> its winding-reversed copy's index.
    pub(super) mirrored: BTreeMap<usize, usize>,
    /// Each of `out.meshes`' local box of finite vertex positions (None when it has none).
    pub(super) local_bounds: Vec<Option<(Vec3, Vec3)>>,
    /// The cut-out hulls found so far.
    pub(super) trims: super::trim::Trimmer,
}
