//! Checks on the raw glTF JSON that the `gltf` crate's validation lets through but its accessors unwrap.
//!
//! Why: `gltf::Document::validate` checks the schema and every index, but some accessors assume more than
//! it checks and panic on a document it accepted: `Camera::projection` unwraps the object named by `type`
//! (`"type": "orthographic"` with only a `perspective` object), `Image::source` unwraps `uri` when there is
//! no `bufferView` (an image `{}`) and `mimeType` when there is one. These are checked here, on the
//! `gltf::json` types, before the loader calls any accessor. One check must come before the crate's own
//! validation, which indexes the accessor a primitive's `POSITION` names without checking it exists
//! ([`check_before_validation`]; found by the fuzz target). The other accessors the loader calls
//! (samplers, texture sources, accessor views and sparse storage, materials, primitive modes, node
//! children, cameras and meshes) unwrap only indices and enum values that validation does check; the
//! fuzz target (`tests/integration/gltf_fuzz.rs`) holds the loader to that.

use gltf::json::Root;
use gltf::json::camera::Type;
use gltf::json::validation::Checked;
use thiserror::Error;

/// A field the `gltf` crate accepts but whose accessor would panic.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum Unsupported {
    /// A camera's `type` names a projection object it does not have.
    #[error("camera {camera}: type is {kind} but it has no '{kind}' object")]
    CameraObject {
        /// glTF camera index.
        camera: usize,
        /// The projection its type names.
        kind: &'static str,
    },
    /// A camera's `type` is neither perspective nor orthographic.
    #[error("camera {camera}: type must be 'perspective' or 'orthographic'")]
    CameraType {
        /// glTF camera index.
        camera: usize,
    },
    /// An image has neither a `uri` nor a `bufferView`.
    #[error("image {image}: has neither a uri nor a bufferView")]
    ImageSource {
        /// glTF image index.
        image: usize,
    },
    /// A primitive's `POSITION` names an accessor that does not exist.
    #[error("mesh {mesh} primitive {primitive}: POSITION names accessor {accessor}, which does not exist")]
    PositionAccessor {
        /// glTF mesh index.
        mesh: usize,
        /// Primitive index within the mesh.
        primitive: usize,
        /// The accessor index it names.
        accessor: usize,
    },
    /// An image in a buffer view has no `mimeType` (required with `bufferView`).
    #[error("image {image}: has a bufferView but no mimeType")]
    ImageMime {
        /// glTF image index.
        image: usize,
    },
}

/// Checks what `gltf::Document::validate` itself would index unchecked (it panics on a `POSITION` naming a
/// missing accessor); run on the deserialized root before validating it.
pub fn check_before_validation(root: &Root) -> Result<(), Unsupported> {
    use gltf::json::mesh::Semantic;
    for (mesh, m) in root.meshes.iter().enumerate() {
        for (primitive, p) in m.primitives.iter().enumerate() {
            if let Some(index) = p.attributes.get(&Checked::Valid(Semantic::Positions))
                && index.value() >= root.accessors.len()
            {
                return Err(Unsupported::PositionAccessor { mesh, primitive, accessor: index.value() });
            }
        }
    }
    Ok(())
}

/// Checks the fields whose accessors would panic on a validated document; the first problem found is
/// returned.
pub fn check(root: &Root) -> Result<(), Unsupported> {
    for (camera, c) in root.cameras.iter().enumerate() {
        match c.type_ {
            Checked::Valid(Type::Perspective) if c.perspective.is_none() => {
                return Err(Unsupported::CameraObject { camera, kind: "perspective" });
            }
            Checked::Valid(Type::Orthographic) if c.orthographic.is_none() => {
                return Err(Unsupported::CameraObject { camera, kind: "orthographic" });
            }
            Checked::Valid(_) => {}
            Checked::Invalid => return Err(Unsupported::CameraType { camera }),
        }
    }
    for (image, i) in root.images.iter().enumerate() {
        match (&i.buffer_view, &i.uri, &i.mime_type) {
            (None, None, _) => return Err(Unsupported::ImageSource { image }),
            (Some(_), _, None) => return Err(Unsupported::ImageMime { image }),
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn root(json: &str) -> Root {
        gltf::json::deserialize::from_str(json).unwrap()
    }

    #[test]
    fn finds_what_the_crate_would_unwrap() {
        let ok = root(
            r#"{"asset":{"version":"2.0"},"cameras":[{"type":"perspective","perspective":{"yfov":1,"znear":0.1}}],
                "images":[{"uri":"a.png"},{"bufferView":0,"mimeType":"image/png"}]}"#,
        );
        assert_eq!(check(&ok), Ok(()));
        let ortho = root(
            r#"{"asset":{"version":"2.0"},"cameras":[{"type":"orthographic","perspective":{"yfov":1,"znear":0.1}}]}"#,
        );
        assert_eq!(check(&ortho), Err(Unsupported::CameraObject { camera: 0, kind: "orthographic" }));
        let persp = root(
            r#"{"asset":{"version":"2.0"},"cameras":[{"type":"perspective","orthographic":{"xmag":1,"ymag":1,"znear":0,"zfar":1}}]}"#,
        );
        assert_eq!(check(&persp), Err(Unsupported::CameraObject { camera: 0, kind: "perspective" }));
        let weird =
            root(r#"{"asset":{"version":"2.0"},"cameras":[{"type":"fisheye","perspective":{"yfov":1,"znear":0.1}}]}"#);
        assert_eq!(check(&weird), Err(Unsupported::CameraType { camera: 0 }));
        let empty = root(r#"{"asset":{"version":"2.0"},"images":[{"uri":"a.png"},{}]}"#);
        assert_eq!(check(&empty), Err(Unsupported::ImageSource { image: 1 }));
        let nomime = root(r#"{"asset":{"version":"2.0"},"images":[{"bufferView":0}]}"#);
        assert_eq!(check(&nomime), Err(Unsupported::ImageMime { image: 0 }));
        let missing = root(
            r#"{"asset":{"version":"2.0"},"accessors":[],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}]}"#,
        );
        assert_eq!(
            check_before_validation(&missing),
            Err(Unsupported::PositionAccessor { mesh: 0, primitive: 0, accessor: 0 })
        );
    }
}
