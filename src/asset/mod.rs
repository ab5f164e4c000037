//! Loading glTF 2.0 assets into the renderer's meshes, textures, instances and cameras.
//!
//! One loader serves the shipped cars and track and any user-supplied file. Files are read through
//! [`uri::locate`], which keeps external references inside the asset's folder, and through
//! [`accessor`], which checks every range; [`validate`] catches what the `gltf` crate would unwrap; and
//! everything one load reads, decodes, builds and places is charged to a [`LoadBudget`]. So a broken or
//! hostile file gives an [`AssetError`] naming the file and what is wrong (or which limit it passes), never
//! a panic, a hang or an unbounded allocation.

pub mod accessor;
pub mod budget;
pub mod decals;
pub mod error;
pub mod export;
pub mod loader;
pub mod meshes;
pub mod quads;
pub mod scene;
pub mod sources;
mod state;
mod trim;
pub mod uri;
pub mod validate;

pub use budget::{LoadBudget, OverBudget};
pub use loader::{
    AssetError, LoadedScene, SceneCamera, load, load_from_slice, load_from_slice_with_budget, load_with_budget,
};
