//! Loading glTF 2.0 assets into the renderer's meshes, textures, instances and cameras.
//!
//! One loader serves the shipped cars and track and any user-supplied file. Files are read through
//! [`uri::resolve`], which keeps external references inside the asset's folder, and through
//! [`accessor`], which checks every range, so a broken or hostile file gives an [`AssetError`] naming the
//! file and what is wrong, never a panic or an unbounded allocation.

pub mod accessor;
pub mod decals;
pub mod export;
pub mod loader;
pub mod quads;
pub mod scene;
pub mod uri;

pub use loader::{AssetError, LoadedScene, SceneCamera, load};
