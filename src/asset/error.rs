//! Why an asset could not be loaded: one error type for the whole load, every variant naming the file and
//! the part of it that is wrong (buffer, image, mesh and primitive, node, camera), with what was wrong as a
//! typed problem that keeps the error it came from.
//!
//! It lives apart from the loader so that the stages below it (sources, meshes) can return it without
//! importing the loader that calls them.

use thiserror::Error;

use super::accessor::AccessorError;
use super::budget::OverBudget;
use super::uri::UriError;
use super::validate::Unsupported;
use crate::render::MeshError;
use crate::render::core::texture::TextureError;
use crate::userfile::FileProblem;

/// Why an asset could not be loaded; every variant names the file.
#[derive(Debug, Error)]
pub enum AssetError {
    /// The file could not be read.
    #[error("{file}: cannot read: {problem}")]
    Read {
        /// The file.
        file: String,
        /// What is wrong with it.
        #[source]
        problem: FileProblem,
    },
    /// The file is not valid glTF 2.0 (JSON, GLB container or schema).
    #[error("{file}: not a valid glTF 2.0 file: {problem}")]
    Parse {
        /// The file.
        file: String,
        /// What the parser or the checks reported.
        #[source]
        problem: ParseError,
    },
    /// A buffer could not be resolved or is shorter than declared.
    #[error("{file}: buffer {index}: {problem}")]
    Buffer {
        /// The file.
        file: String,
        /// glTF buffer index.
        index: usize,
        /// What is wrong.
        #[source]
        problem: BufferProblem,
    },
    /// An image could not be resolved or decoded.
    #[error("{file}: image {index}: {problem}")]
    Image {
        /// The file.
        file: String,
        /// glTF image index.
        index: usize,
        /// What is wrong.
        #[source]
        problem: ImageProblem,
    },
    /// A mesh primitive has bad accessors or indices.
    #[error("{file}: mesh {mesh} primitive {primitive}: {problem}")]
    Primitive {
        /// The file.
        file: String,
        /// glTF mesh index.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// What is wrong.
        #[source]
        problem: PrimitiveProblem,
    },
    /// A mesh as a whole could not be built (its primitives together are too large to index).
    #[error("{file}: mesh {mesh}: {problem}")]
    Mesh {
        /// The file.
        file: String,
        /// glTF mesh index.
        mesh: usize,
        /// What the mesh builder reported.
        #[source]
        problem: MeshError,
    },
    /// The node hierarchy or a camera is unusable.
    #[error("{file}: {problem}")]
    Scene {
        /// The file.
        file: String,
        /// What is wrong.
        #[source]
        problem: SceneProblem,
    },
    /// The file needs more than the load budget allows.
    #[error("{file}: {at}: {over}")]
    Budget {
        /// The file.
        file: String,
        /// Where the limit was passed.
        at: Place,
        /// Which limit, and by how much.
        over: OverBudget,
    },
}

impl AssetError {
    /// A budget refusal at `at` in `file`.
    pub(crate) fn budget(file: &str, at: Place, over: OverBudget) -> Self {
        AssetError::Budget { file: file.to_string(), at, over }
    }
}

/// Most characters of a parser's message kept in an error (validation lists every problem it finds).
const MAX_REASON_CHARS: usize = 400;

/// A library's message on one line, cut to [`MAX_REASON_CHARS`].
fn one_line(s: &str) -> String {
    let line = s.split_whitespace().collect::<Vec<_>>().join(" ");
    match line.char_indices().nth(MAX_REASON_CHARS) {
        Some((cut, _)) => format!("{} … ({} more characters)", &line[..cut], line.len() - cut),
        None => line,
    }
}

/// Why the document did not parse or validate.
#[derive(Debug, Error)]
pub enum ParseError {
    /// A GLB header whose declared length is shorter than the 12-byte header itself.
    #[error("GLB header declares {declared} bytes, less than the header itself")]
    GlbLength {
        /// The length the header declares.
        declared: u32,
    },
    /// A file that starts like a GLB but ends inside its header.
    #[error("GLB header is cut short")]
    GlbCut,
    /// The `gltf` crate refused the GLB container, the JSON or the schema (its message on one line).
    #[error("{}", one_line(&.0.to_string()))]
    Gltf(#[source] gltf::Error),
    /// A field the `gltf` crate accepts but would panic on.
    #[error(transparent)]
    Unsupported(#[from] Unsupported),
}

/// What is wrong with a buffer.
#[derive(Debug, Error)]
pub enum BufferProblem {
    /// Its URI is refused or its bytes cannot be read.
    #[error(transparent)]
    Uri(#[from] UriError),
    /// It holds fewer bytes than it declares.
    #[error("holds {holds} bytes, but byteLength says {declared}")]
    Short {
        /// Bytes it holds.
        holds: u64,
        /// Its `byteLength`.
        declared: usize,
    },
    /// It has no URI and the file has no GLB binary chunk.
    #[error("refers to a GLB binary chunk that is missing")]
    NoBinaryChunk,
}

/// What is wrong with an image.
#[derive(Debug, Error)]
pub enum ImageProblem {
    /// A texture names an image the file does not have.
    #[error("does not exist")]
    Missing,
    /// It names a buffer view the file does not have.
    #[error("names a missing buffer view")]
    MissingView,
    /// Its buffer view names a buffer the file does not have.
    #[error("buffer view refers to a missing buffer")]
    ViewMissingBuffer,
    /// Its buffer view's offset plus length overflows.
    #[error("buffer view range overflows")]
    ViewOverflow,
    /// Its buffer view runs past the end of its buffer.
    #[error("buffer view {view} (bytes {start}..{end}) runs past its buffer of {buffer_len} bytes")]
    ViewPastBuffer {
        /// glTF buffer view index.
        view: usize,
        /// First byte.
        start: usize,
        /// One past the last byte.
        end: usize,
        /// The buffer's length.
        buffer_len: usize,
    },
    /// It has neither a `uri` nor a `bufferView`.
    #[error("has neither a uri nor a bufferView")]
    NoSource,
    /// Its URI is refused or its bytes cannot be read.
    #[error(transparent)]
    Uri(#[from] UriError),
    /// Wider or taller than any texture may be.
    #[error("{width}x{height} is over the {limit}-texel limit per side")]
    TooBig {
        /// Width in pixels.
        width: u32,
        /// Height in pixels.
        height: u32,
        /// The largest side accepted.
        limit: u32,
    },
    /// Its format could not be told from its first bytes.
    #[error("{0}")]
    Format(#[source] std::io::Error),
    /// It does not decode (the decoder's message on one line).
    #[error("{}", one_line(&.0.to_string()))]
    Decode(#[source] image::ImageError),
    /// The decoded pixels do not make a texture.
    #[error(transparent)]
    Texture(#[from] TextureError),
}

/// What is wrong with a mesh primitive.
#[derive(Debug, Error)]
pub enum PrimitiveProblem {
    /// An accessor of the primitive cannot be read.
    #[error("{semantic}: {source}")]
    Accessor {
        /// What the accessor holds (`POSITION`, `TEXCOORD`, `COLOR_0`, `indices`).
        semantic: &'static str,
        /// What is wrong with it.
        source: AccessorError,
    },
    /// Positions are not three-component vectors.
    #[error("POSITION must be VEC3, not {components} components")]
    PositionWidth {
        /// Components per position.
        components: usize,
    },
    /// Colours are neither RGB nor RGBA.
    #[error("COLOR_0 must be VEC3 or VEC4, not {components} components")]
    ColorWidth {
        /// Components per colour.
        components: usize,
    },
    /// An attribute has another number of components than it needs.
    #[error("{semantic} has {found} components, expected {expected}")]
    Components {
        /// The attribute.
        semantic: &'static str,
        /// Components it has.
        found: usize,
        /// Components it needs.
        expected: usize,
    },
    /// An attribute has another number of elements than there are positions.
    #[error("{semantic} has {found} elements, POSITION has {positions}")]
    Elements {
        /// The attribute.
        semantic: &'static str,
        /// Elements it has.
        found: usize,
        /// Positions.
        positions: usize,
    },
    /// An index names a vertex past the primitive's positions.
    #[error("index {index} is out of range for {vertices} vertices")]
    IndexOutOfRange {
        /// The index.
        index: u32,
        /// The primitive's vertices.
        vertices: usize,
    },
    /// The mesh builder refused a polygon of this primitive (the polygon is numbered within the mesh).
    #[error(transparent)]
    Build(MeshError),
}

/// What is wrong with the node hierarchy or a camera.
#[derive(Debug, Error)]
pub enum SceneProblem {
    /// A node is its own ancestor.
    #[error("node hierarchy is cyclic (node {node} is its own ancestor)")]
    Cycle {
        /// The node met again on its own path.
        node: usize,
    },
    /// A node named as a level of detail has no mesh.
    #[error("LOD node {node} has no mesh")]
    LodWithoutMesh {
        /// The node.
        node: usize,
    },
    /// A node's `MSFT_lod` extension cannot be used.
    #[error("node {node}: MSFT_lod {problem}")]
    MsftLod {
        /// The node.
        node: usize,
        /// What is wrong with the extension.
        problem: LodProblem,
    },
    /// A camera cannot be used.
    #[error("camera {camera}: {problem}")]
    Camera {
        /// glTF camera index.
        camera: usize,
        /// What is wrong with it.
        problem: CameraProblem,
    },
    /// A mesh the loader built is not where it was put (not expected).
    #[error("mesh slot {slot} is missing")]
    MissingMeshSlot {
        /// Index in the loaded scene's meshes.
        slot: usize,
    },
    /// The winding-reversed copy of a mesh, for a mirrored placement, could not be built.
    #[error("mirrored mesh: {0}")]
    Mirrored(#[source] MeshError),
}

/// What is wrong with a node's `MSFT_lod` extension.
#[derive(Clone, Copy, Debug, Error, PartialEq, Eq)]
pub enum LodProblem {
    /// No `ids` array.
    #[error("has no 'ids' array")]
    NoIds,
    /// An entry of `ids` is not the index of a node.
    #[error("names a missing node (entry {entry} of 'ids')")]
    MissingNode {
        /// The entry's position in `ids`.
        entry: usize,
    },
}

/// What is wrong with a camera.
#[derive(Clone, Copy, Debug, Error, PartialEq)]
pub enum CameraProblem {
    /// A perspective camera's vertical field of view.
    #[error("yfov must be between 0 and pi (it is {yfov})")]
    FieldOfView {
        /// The `yfov` given.
        yfov: f32,
    },
    /// A perspective camera's near and far planes.
    #[error("znear must be positive and zfar beyond it (znear {znear}, zfar {})", far_text(*.zfar))]
    PerspectiveDepth {
        /// The near plane.
        znear: f32,
        /// The far plane, if any.
        zfar: Option<f32>,
    },
    /// An orthographic camera's magnifications.
    #[error("xmag and ymag must be finite and non-zero (they are {xmag} and {ymag})")]
    Magnification {
        /// Horizontal magnification.
        xmag: f32,
        /// Vertical magnification.
        ymag: f32,
    },
    /// An orthographic camera's near and far planes.
    #[error("znear must be at least 0 and zfar beyond it (znear {znear}, zfar {zfar})")]
    OrthographicDepth {
        /// The near plane.
        znear: f32,
        /// The far plane.
        zfar: f32,
    },
    /// The camera's node transform has no inverse.
    #[error("its node transform cannot be inverted")]
    NotInvertible,
}

/// A far plane as a message says it.
fn far_text(zfar: Option<f32>) -> String {
    zfar.map_or_else(|| "none".to_string(), |f| f.to_string())
}

/// Where in a file a budget limit was passed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Place {
    /// The file itself.
    File,
    /// A buffer (glTF index).
    Buffer(usize),
    /// An image (glTF index).
    Image(usize),
    /// The scene's root nodes.
    RootNodes,
    /// A node (glTF index).
    Node(usize),
    /// A node's children (the node's glTF index).
    Children(usize),
    /// An accessor of a mesh primitive.
    Accessor {
        /// glTF mesh index.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// What the accessor holds (`POSITION`, `TEXCOORD`, `COLOR_0`, `indices`).
        semantic: &'static str,
        /// glTF accessor index.
        accessor: usize,
    },
}

impl std::fmt::Display for Place {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Place::File => write!(f, "the file"),
            Place::Buffer(i) => write!(f, "buffer {i}"),
            Place::Image(i) => write!(f, "image {i}"),
            Place::RootNodes => write!(f, "the scene's root nodes"),
            Place::Node(i) => write!(f, "node {i}"),
            Place::Children(i) => write!(f, "node {i}'s children"),
            Place::Accessor { mesh, primitive, semantic, accessor } => {
                write!(f, "mesh {mesh} primitive {primitive}: {semantic} accessor {accessor}")
            }
        }
    }
}
