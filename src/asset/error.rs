//! Why an asset could not be loaded: one error type for the whole load, every variant naming the file.
//!
//! It lives apart from the loader so that the stages below it (sources, meshes) can return it without
//! importing the loader that calls them.

use thiserror::Error;

use super::budget::OverBudget;

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
    /// The file needs more than the load budget allows.
    #[error("{file}: {at}: {over}")]
    Budget {
        /// The file.
        file: String,
        /// Where the limit was passed ("buffer 3", "image 0", "mesh 2 primitive 0", "node 17").
        at: String,
        /// Which limit, and by how much.
        over: OverBudget,
    },
}

impl AssetError {
    /// A budget refusal at `at` in `file`.
    pub(crate) fn budget(file: &str, at: String, over: OverBudget) -> Self {
        AssetError::Budget { file: file.to_string(), at, over }
    }
}
