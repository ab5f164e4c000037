//! Meshes as the renderer takes them: vertices, polygons of any vertex count, and materials.
//!
//! A polygon is a closed loop of vertex indices. Polygons that are not planar are split into a fan of
//! triangles when the mesh is built (a non-planar polygon has no single depth plane or texture mapping);
//! planar polygons are kept whole, and the fill stage splits the ones that are not y-monotone in a given view.

use glam::{Mat4, Vec2, Vec3, Vec4};
use thiserror::Error;

use crate::render::core::texture::Sampler;

/// How a material's alpha is used (glTF `alphaMode`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AlphaMode {
    /// Alpha is ignored.
    #[default]
    Opaque,
    /// A pixel is drawn only where alpha is at least `cutoff`, and then drawn opaque.
    Mask {
        /// The glTF `alphaCutoff` (0.5 when the file does not say).
        cutoff: f32,
    },
}

/// The surface of a polygon: base colour, an optional texture, and how to draw it.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Multiplies the texel and the vertex colour (glTF `baseColorFactor`).
    pub base_color: Vec4,
    /// Index into the draw list's textures, if textured.
    pub texture: Option<usize>,
    /// Wrap modes for the texture.
    pub sampler: Sampler,
    /// When false, polygons facing away from the camera are culled.
    pub double_sided: bool,
    /// Alpha handling.
    pub alpha_mode: AlphaMode,
    /// Depth-test bias in steps towards the viewer (each one pixel of the polygon's depth slope plus
    /// [`DEPTH_BIAS_STEP`] of its depth, like a GPU's polygon offset): a decal lying exactly in the plane of
    /// the surface under it (a road marking, a number on a door) gets 1 (or one more than that surface), so
    /// the z-buffer draws it over the surface instead of fighting it. Painter's methods already draw it
    /// after the surface, in submission order.
    pub depth_bias: u8,
}

/// The constant part of one step of [`Material::depth_bias`]: a relative change of `1/w` (about 0.6 mm at
/// 10 m, 6 cm at 1 km).
pub const DEPTH_BIAS_STEP: f32 = 1.0 / 16384.0;

impl Default for Material {
    fn default() -> Self {
        Self {
            base_color: Vec4::ONE,
            texture: None,
            sampler: Sampler::default(),
            double_sided: false,
            alpha_mode: AlphaMode::Opaque,
            depth_bias: 0,
        }
    }
}

/// One vertex: position, texture coordinate and colour (RGBA, linear `0..=1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Position in model space.
    pub position: Vec3,
    /// Texture coordinate (glTF `TEXCOORD_0`).
    pub uv: Vec2,
    /// Vertex colour (glTF `COLOR_0`, white when absent).
    pub color: Vec4,
}

impl Vertex {
    /// A white vertex at `position` with texture coordinate `uv`.
    #[must_use]
    pub fn new(position: Vec3, uv: Vec2) -> Self {
        Self { position, uv, color: Vec4::ONE }
    }
}

/// A polygon: `count` indices starting at `first` in the mesh's index list, drawn with one material.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Polygon {
    /// Offset of the first index.
    pub first: u32,
    /// Number of vertices (at least 3).
    pub count: u32,
    /// Index into the mesh's materials.
    pub material: u32,
}

/// Why a mesh could not be built.
#[derive(Debug, Error, PartialEq, Eq)]
pub enum MeshError {
    /// A polygon refers to a vertex that does not exist.
    #[error("polygon {polygon} uses vertex {index}, but the mesh has {vertices} vertices")]
    IndexOutOfRange {
        /// Polygon number in submission order.
        polygon: usize,
        /// The bad index.
        index: u32,
        /// Number of vertices.
        vertices: usize,
    },
    /// A polygon refers to a material that does not exist.
    #[error("polygon {polygon} uses material {material}, but the mesh has {materials} materials")]
    MaterialOutOfRange {
        /// Polygon number in submission order.
        polygon: usize,
        /// The bad material index.
        material: u32,
        /// Number of materials.
        materials: usize,
    },
    /// The mesh is too large to index with `u32`.
    #[error("mesh is too large ({what})")]
    TooLarge {
        /// What overflowed.
        what: &'static str,
    },
}

/// A bounding sphere in model space, for object culling.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre.
    pub center: Vec3,
    /// Radius (0 for an empty mesh).
    pub radius: f32,
}

/// An immutable mesh ready to draw.
#[derive(Clone, Debug)]
pub struct Mesh {
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    polygons: Vec<Polygon>,
    materials: Vec<Material>,
    bounds: Sphere,
    /// Polygons given to the builder (before non-planar ones were split).
    source_polygons: usize,
    /// Turns about its model's Y axis to face the eye ([`Mesh::placed_model`]).
    faces_eye: bool,
}

impl Mesh {
    /// The vertices.
    #[inline]
    #[must_use]
    pub fn vertices(&self) -> &[Vertex] {
        &self.vertices
    }
    /// The polygon index list.
    #[must_use]
    pub fn indices(&self) -> &[u32] {
        &self.indices
    }
    /// The polygons, in submission order (the order the ordering table registers them in).
    #[inline]
    #[must_use]
    pub fn polygons(&self) -> &[Polygon] {
        &self.polygons
    }
    /// The materials.
    #[inline]
    #[must_use]
    pub fn materials(&self) -> &[Material] {
        &self.materials
    }
    /// The bounding sphere (finite vertices only).
    #[must_use]
    pub fn bounds(&self) -> Sphere {
        self.bounds
    }
    /// The materials, to adjust after loading (for example [`Material::depth_bias`] for decals).
    pub fn materials_mut(&mut self) -> &mut [Material] {
        &mut self.materials
    }

    /// The vertex indices of polygon `p`.
    #[inline]
    #[must_use]
    pub fn polygon_indices(&self, p: &Polygon) -> &[u32] {
        let start = p.first as usize;
        self.indices.get(start..start + p.count as usize).unwrap_or(&[])
    }
    /// Shifts every material's texture index by `by` (when the mesh's textures are appended to a longer list).
    pub fn rebase_textures(&mut self, by: usize) {
        for m in &mut self.materials {
            if let Some(t) = m.texture.as_mut() {
                *t += by;
            }
        }
    }

    /// Number of polygons handed to the builder, before non-planar ones were split into triangles.
    #[must_use]
    pub fn source_polygon_count(&self) -> usize {
        self.source_polygons
    }

    /// Whether the mesh turns about its model's Y axis to face the eye (an upright impostor: a tree's
    /// single quad standing in, at a distance, for the crossed quads of its close model).
    #[must_use]
    pub fn faces_eye(&self) -> bool {
        self.faces_eye
    }

    /// Makes the mesh turn (or not) about its model's Y axis to face the eye: see [`Mesh::placed_model`].
    /// A turning mesh's [bounds](Mesh::bounds) hold it in every turn (a sphere centred on the axis).
    pub fn set_faces_eye(&mut self, faces: bool) {
        self.faces_eye = faces;
        let b = bounding_sphere(&self.vertices);
        self.bounds = if faces {
            let off = Vec2::new(b.center.x, b.center.z).length();
            Sphere { center: Vec3::new(0.0, b.center.y, 0.0), radius: b.radius + off }
        } else {
            b
        };
    }

    /// The model-to-world matrix the mesh is drawn with when an instance places it by `model` and the eye
    /// is at `eye` (world space): `model` itself, or for a mesh that [faces the eye](Mesh::faces_eye),
    /// `model` turned about its Y axis so that the model's +Z points at the eye's projection on its XZ
    /// plane (a quad in the XY plane then shows its full width from every side, as Sega's Model 1 drew its
    /// trees). An eye on the axis, or a model that cannot be inverted, leaves `model` as it is.
    #[must_use]
    pub fn placed_model(&self, model: &Mat4, eye: Vec3) -> Mat4 {
        if !self.faces_eye {
            return *model;
        }
        let local = model.inverse().transform_point3(eye);
        let len = (local.x * local.x + local.z * local.z).sqrt();
        if !(len.is_finite() && len > 1e-6) {
            return *model;
        }
        let (s, c) = (local.x / len, local.z / len);
        // A turn about Y taking +Z to (s, 0, c).
        let turn = Mat4::from_cols(Vec4::new(c, 0.0, -s, 0.0), Vec4::Y, Vec4::new(s, 0.0, c, 0.0), Vec4::W);
        *model * turn
    }
}

/// Collects vertices and polygons, then validates them into a [`Mesh`].
#[derive(Clone, Debug, Default)]
pub struct MeshBuilder {
    vertices: Vec<Vertex>,
    indices: Vec<u32>,
    polygons: Vec<Polygon>,
    materials: Vec<Material>,
    keep_as_given: bool,
}

impl MeshBuilder {
    /// An empty builder.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds a material and returns its index.
    pub fn material(&mut self, m: Material) -> u32 {
        self.materials.push(m);
        (self.materials.len() - 1) as u32
    }

    /// Adds a vertex and returns its index.
    pub fn vertex(&mut self, v: Vertex) -> u32 {
        self.vertices.push(v);
        (self.vertices.len() - 1) as u32
    }

    /// Number of vertices added so far.
    #[must_use]
    pub fn vertex_count(&self) -> usize {
        self.vertices.len()
    }

    /// Adds a polygon over existing vertex indices; fewer than three indices are ignored.
    pub fn polygon(&mut self, indices: &[u32], material: u32) {
        if indices.len() < 3 {
            return;
        }
        let first = self.indices.len() as u32;
        self.indices.extend_from_slice(indices);
        self.polygons.push(Polygon { first, count: indices.len() as u32, material });
    }

    /// Keeps every polygon as given, one for one, even where it is not planar to the builder's tolerance:
    /// for polygons already checked (pieces cut from planar polygons, whose tiny size would make rounding
    /// look like a bend).
    #[must_use]
    pub fn keep_polygons_as_given(mut self) -> Self {
        self.keep_as_given = true;
        self
    }

    /// Validates indices and materials, splits non-planar polygons into triangles and computes bounds.
    pub fn build(mut self) -> Result<Mesh, MeshError> {
        if self.vertices.len() > u32::MAX as usize / 2 || self.indices.len() > u32::MAX as usize / 2 {
            return Err(MeshError::TooLarge { what: "more than 2^31 vertices or indices" });
        }
        if self.materials.is_empty() {
            self.materials.push(Material::default());
        }
        let source_polygons = self.polygons.len();
        let mut indices = Vec::with_capacity(self.indices.len());
        let mut polygons = Vec::with_capacity(self.polygons.len());
        for (n, p) in self.polygons.iter().enumerate() {
            if p.material as usize >= self.materials.len() {
                return Err(MeshError::MaterialOutOfRange {
                    polygon: n,
                    material: p.material,
                    materials: self.materials.len(),
                });
            }
            let idx = &self.indices[p.first as usize..(p.first + p.count) as usize];
            if let Some(&bad) = idx.iter().find(|&&i| i as usize >= self.vertices.len()) {
                return Err(MeshError::IndexOutOfRange { polygon: n, index: bad, vertices: self.vertices.len() });
            }
            if idx.len() > 3
                && !self.keep_as_given
                && !is_planar(idx.iter().map(|&i| self.vertices[i as usize].position))
            {
                for k in 1..idx.len() - 1 {
                    let first = indices.len() as u32;
                    indices.extend_from_slice(&[idx[0], idx[k], idx[k + 1]]);
                    polygons.push(Polygon { first, count: 3, material: p.material });
                }
            } else {
                let first = indices.len() as u32;
                indices.extend_from_slice(idx);
                polygons.push(Polygon { first, count: p.count, material: p.material });
            }
        }
        let bounds = bounding_sphere(&self.vertices);
        Ok(Mesh {
            vertices: self.vertices,
            indices,
            polygons,
            materials: self.materials,
            bounds,
            source_polygons,
            faces_eye: false,
        })
    }
}

/// True when every vertex lies on the polygon's best-fit plane, to a tolerance relative to its size.
fn is_planar(points: impl Iterator<Item = Vec3> + Clone) -> bool {
    let pts: Vec<Vec3> = points.collect();
    let n = pts.len();
    // Newell's method gives a robust normal for any polygon, convex or not.
    let mut normal = Vec3::ZERO;
    let mut centroid = Vec3::ZERO;
    for i in 0..n {
        let (a, b) = (pts[i], pts[(i + 1) % n]);
        normal += Vec3::new((a.y - b.y) * (a.z + b.z), (a.z - b.z) * (a.x + b.x), (a.x - b.x) * (a.y + b.y));
        centroid += a;
    }
    centroid /= n as f32;
    let size = pts.iter().map(|p| (*p - centroid).length()).fold(0.0f32, f32::max);
    let len = normal.length();
    if !(len.is_finite() && size.is_finite()) || len <= f32::EPSILON * size * size {
        // Degenerate (zero area) or non-finite: nothing to split; later stages drop it.
        return true;
    }
    let normal = normal / len;
    pts.iter().all(|p| (*p - centroid).dot(normal).abs() <= 1e-4 * size)
}

fn bounding_sphere(vertices: &[Vertex]) -> Sphere {
    let mut min = Vec3::splat(f32::INFINITY);
    let mut max = Vec3::splat(f32::NEG_INFINITY);
    for v in vertices.iter().filter(|v| v.position.is_finite()) {
        min = min.min(v.position);
        max = max.max(v.position);
    }
    if !(min.is_finite() && max.is_finite()) {
        return Sphere { center: Vec3::ZERO, radius: 0.0 };
    }
    let center = (min + max) * 0.5;
    let radius = vertices
        .iter()
        .filter(|v| v.position.is_finite())
        .map(|v| (v.position - center).length())
        .fold(0.0f32, f32::max);
    Sphere { center, radius }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32) -> Vertex {
        Vertex::new(Vec3::new(x, y, z), Vec2::ZERO)
    }

    /// A quad in the XY plane, `x0..x0 + 2` wide and 3 high, facing +Z; turning to the eye when `faces`.
    fn quad(x0: f32, faces: bool) -> Mesh {
        let mut b = MeshBuilder::new();
        let q = [
            b.vertex(v(x0, 0., 0.)),
            b.vertex(v(x0 + 2., 0., 0.)),
            b.vertex(v(x0 + 2., 3., 0.)),
            b.vertex(v(x0, 3., 0.)),
        ];
        b.polygon(&q, 0);
        let mut m = b.build().unwrap();
        m.set_faces_eye(faces);
        m
    }

    #[test]
    fn a_mesh_that_faces_the_eye_turns_its_front_to_it_about_its_y_axis() {
        let model = Mat4::from_scale_rotation_translation(
            Vec3::splat(2.0),
            glam::Quat::from_rotation_y(0.7),
            Vec3::new(10.0, 1.0, -4.0),
        );
        let m = quad(-1.0, true);
        assert!(m.faces_eye());
        for eye in [Vec3::new(30.0, 5.0, -4.0), Vec3::new(-7.0, -2.0, 12.0), Vec3::new(10.5, 40.0, -60.0)] {
            let placed = m.placed_model(&model, eye);
            // The model's +Z, placed, points at the eye seen from above; its Y axis and origin stay.
            let front = placed.transform_vector3(Vec3::Z);
            let to_eye = eye - placed.transform_point3(Vec3::ZERO);
            let flat = |d: Vec3| Vec3::new(d.x, 0.0, d.z).normalize();
            assert!(flat(front).dot(flat(to_eye)) > 0.9999, "{eye}");
            assert_eq!(placed.transform_vector3(Vec3::Y), model.transform_vector3(Vec3::Y));
            assert_eq!(placed.w_axis, model.w_axis);
            // The length of a model axis is kept (the turn is a rotation in model space).
            assert!((front.length() - 2.0).abs() < 1e-5);
        }
        // An ordinary mesh, or an eye on the axis, keeps the instance's matrix.
        assert_eq!(quad(-1.0, false).placed_model(&model, Vec3::new(30.0, 5.0, -4.0)), model);
        assert_eq!(m.placed_model(&model, Vec3::new(10.0, 9.0, -4.0)), model);
        assert_eq!(m.placed_model(&model, Vec3::NAN), model);
    }

    #[test]
    fn a_mesh_that_faces_the_eye_is_bounded_in_every_turn() {
        // Off the axis (x from 1 to 3): every turn stays inside the bounds.
        let m = quad(1.0, true);
        let b = m.bounds();
        assert_eq!((b.center.x, b.center.z), (0.0, 0.0));
        for k in 0..16 {
            let turn = Mat4::from_rotation_y(k as f32 * 0.4);
            for p in m.vertices() {
                assert!(turn.transform_point3(p.position).distance(b.center) <= b.radius + 1e-5);
            }
        }
        // Turning it back into an ordinary mesh gives the ordinary bounds.
        let mut plain = m.clone();
        plain.set_faces_eye(false);
        assert_eq!(plain.bounds(), quad(1.0, false).bounds());
    }

    #[test]
    fn non_planar_quads_become_triangles_planar_stay_whole() {
        let mut b = MeshBuilder::new();
        let q = [b.vertex(v(0., 0., 0.)), b.vertex(v(1., 0., 0.)), b.vertex(v(1., 1., 0.)), b.vertex(v(0., 1., 0.))];
        b.polygon(&q, 0);
        let r = [b.vertex(v(0., 0., 0.)), b.vertex(v(1., 0., 0.)), b.vertex(v(1., 1., 0.5)), b.vertex(v(0., 1., 0.))];
        b.polygon(&r, 0);
        let m = b.build().unwrap();
        let counts: Vec<u32> = m.polygons().iter().map(|p| p.count).collect();
        assert_eq!(counts, [4, 3, 3]);
        assert_eq!(m.source_polygon_count(), 2);
        assert!((m.bounds().radius - (0.5f32 * 0.5 * 2.0 + 0.25 * 0.25).sqrt()).abs() < 1e-5);
    }

    #[test]
    fn bad_indices_are_typed_errors() {
        let mut b = MeshBuilder::new();
        b.vertex(v(0., 0., 0.));
        b.polygon(&[0, 1, 2], 0);
        assert_eq!(b.build().unwrap_err(), MeshError::IndexOutOfRange { polygon: 0, index: 1, vertices: 1 });
        let mut b = MeshBuilder::new();
        for _ in 0..3 {
            b.vertex(v(0., 0., 0.));
        }
        b.polygon(&[0, 1, 2], 4);
        assert!(matches!(b.build(), Err(MeshError::MaterialOutOfRange { .. })));
    }
}
