//! Building the renderer's meshes from glTF mesh primitives: accessors read once each and charged to the
//! budget, vertex and polygon counts checked before anything is built, quads merged, decals marked; and
//! the winding-reversed copy a mirrored placement draws.

use std::rc::Rc;

use glam::{Vec2, Vec3, Vec4};
use gltf::mesh::Mode;

use super::accessor::{Elements, read_floats, read_indices};
use super::budget::{Limit, OverBudget};
use super::error::AssetError;
use super::quads::merge_pairs;
use super::state::Loader;
use crate::render::{AlphaMode, Material, Mesh, MeshBuilder, MeshError, Sampler, Vertex, Wrap};

/// Why a primitive could not be read: the file is wrong, or it needs more than the budget.
enum Failure {
    Bad(String),
    /// Over the budget, with what in the primitive asked for it.
    OverAt(String, OverBudget),
    /// A texture's image failed (its error already names the file and the image).
    Image(AssetError),
}

/// Numbers an accessor materialises: elements times components.
fn values_of(acc: &gltf::Accessor<'_>) -> u64 {
    (acc.count() as u64).saturating_mul(acc.dimensions().multiplicity() as u64)
}

impl Loader<'_> {
    fn floats(&mut self, acc: &gltf::Accessor<'_>, what: &str) -> Result<Rc<Elements>, Failure> {
        if let Some(e) = self.accessors.floats.get(&acc.index()) {
            return Ok(Rc::clone(e));
        }
        let over = |over| Failure::OverAt(format!("{what} accessor {}", acc.index()), over);
        self.meter.charge(Limit::AccessorValues, values_of(acc)).map_err(over)?;
        let e = Rc::new(read_floats(acc, self.buffers).map_err(|e| Failure::Bad(format!("{what}: {e}")))?);
        self.accessors.floats.insert(acc.index(), Rc::clone(&e));
        Ok(e)
    }

    fn indices(&mut self, acc: &gltf::Accessor<'_>) -> Result<Rc<Vec<u32>>, Failure> {
        if let Some(e) = self.accessors.indices.get(&acc.index()) {
            return Ok(Rc::clone(e));
        }
        let over = |over| Failure::OverAt(format!("indices accessor {}", acc.index()), over);
        self.meter.charge(Limit::AccessorValues, values_of(acc)).map_err(over)?;
        let e = Rc::new(read_indices(acc, self.buffers).map_err(|e| Failure::Bad(format!("indices: {e}")))?);
        self.accessors.indices.insert(acc.index(), Rc::clone(&e));
        Ok(e)
    }

    /// Builds the renderer mesh for a glTF mesh. Before a primitive's accessors are read, its vertices and
    /// (at least half its triangles, as merging makes at most one quad of two) polygons must fit in the
    /// budget left after the instances placed so far, since this mesh will be placed at least once.
    pub(super) fn mesh(&mut self, mesh: &gltf::Mesh<'_>) -> Result<Mesh, AssetError> {
        let mut b = MeshBuilder::new();
        let mut polygons = 0u64;
        for prim in mesh.primitives() {
            let file = self.file.clone();
            let at = || format!("mesh {} primitive {}", mesh.index(), prim.index());
            self.primitive(&prim, &mut b, &mut polygons).map_err(|f| match f {
                Failure::Bad(reason) => {
                    AssetError::Primitive { file: file.clone(), mesh: mesh.index(), primitive: prim.index(), reason }
                }
                Failure::OverAt(what, over) => AssetError::budget(&file, format!("{}: {what}", at()), over),
                Failure::Image(e) => e,
            })?;
        }
        let mut built = b.build().map_err(|e| AssetError::Primitive {
            file: self.file.clone(),
            mesh: mesh.index(),
            primitive: 0,
            reason: e.to_string(),
        })?;
        super::decals::mark_decals(&mut built, self.meter.decal_pairs_left());
        Ok(built)
    }

    fn primitive(
        &mut self,
        prim: &gltf::Primitive<'_>,
        b: &mut MeshBuilder,
        polygons: &mut u64,
    ) -> Result<(), Failure> {
        if !matches!(prim.mode(), Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) {
            self.out.skipped_primitives += 1;
            return Ok(());
        }
        let Some(pos_acc) = prim.get(&gltf::Semantic::Positions) else {
            self.out.skipped_primitives += 1;
            return Ok(());
        };
        let n = pos_acc.count();
        let corners = prim.indices().map_or(n, |acc| acc.count());
        let tris = match prim.mode() {
            Mode::Triangles => corners / 3,
            _ => corners.saturating_sub(2),
        } as u64;
        let what = format!("POSITION accessor {}", pos_acc.index());
        self.meter
            .check(Limit::Vertices, b.vertex_count() as u64 + n as u64)
            .and_then(|()| self.meter.check(Limit::Polygons, *polygons + tris.div_ceil(2)))
            .map_err(|over| Failure::OverAt(what, over))?;
        let positions = self.floats(&pos_acc, "POSITION")?;
        if positions.width != 3 {
            return Err(Failure::Bad("POSITION must be VEC3".into()));
        }
        let gmat = prim.material();
        let pbr = gmat.pbr_metallic_roughness();
        let mut material = Material {
            base_color: Vec4::from(pbr.base_color_factor()),
            double_sided: gmat.double_sided(),
            alpha_mode: match gmat.alpha_mode() {
                gltf::material::AlphaMode::Mask => AlphaMode::Mask { cutoff: gmat.alpha_cutoff().unwrap_or(0.5) },
                _ => AlphaMode::Opaque,
            },
            ..Material::default()
        };
        let mut uv_set = None;
        if let Some(info) = pbr.base_color_texture() {
            let tex = info.texture();
            let image = tex.source().index();
            let texture = self.images.texture(
                self.doc,
                image,
                (self.buffers, self.base_dir, &self.file),
                &mut self.meter,
                &mut self.out.textures,
            );
            material.texture = Some(texture.map_err(Failure::Image)?);
            let s = tex.sampler();
            material.sampler = Sampler { wrap_s: wrap(s.wrap_s()), wrap_t: wrap(s.wrap_t()) };
            uv_set = Some(info.tex_coord());
        }
        let uvs = match uv_set.and_then(|set| prim.get(&gltf::Semantic::TexCoords(set))) {
            Some(acc) => {
                let e = self.floats(&acc, "TEXCOORD")?;
                check_attr(&e, n, 2, "TEXCOORD").map_err(Failure::Bad)?;
                Some(e)
            }
            None => None,
        };
        let colors = match prim.get(&gltf::Semantic::Colors(0)) {
            Some(acc) => {
                let e = self.floats(&acc, "COLOR_0")?;
                if e.width != 3 && e.width != 4 {
                    return Err(Failure::Bad("COLOR_0 must be VEC3 or VEC4".into()));
                }
                check_attr(&e, n, e.width, "COLOR_0").map_err(Failure::Bad)?;
                Some(e)
            }
            None => None,
        };
        let sequential;
        let indices: &[u32] = match prim.indices() {
            Some(acc) => {
                sequential = self.indices(&acc)?;
                &sequential
            }
            None => {
                sequential = Rc::new((0..n as u32).collect());
                &sequential
            }
        };
        if let Some(&bad) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(Failure::Bad(format!("index {bad} is out of range for {n} vertices")));
        }
        let base = b.vertex_count() as u32;
        let mut verts = Vec::with_capacity(n);
        for i in 0..n {
            let position = Vec3::new(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2));
            let uv = uvs.as_ref().map_or(Vec2::ZERO, |e| Vec2::new(e.get(i, 0), e.get(i, 1)));
            let color = colors.as_ref().map_or(Vec4::ONE, |e| {
                Vec4::new(e.get(i, 0), e.get(i, 1), e.get(i, 2), if e.width == 4 { e.get(i, 3) } else { 1.0 })
            });
            verts.push(Vertex { position, uv, color });
        }
        let m = b.material(material);
        for v in &verts {
            b.vertex(*v);
        }
        let mut idx = Vec::with_capacity(4);
        for poly in merge_pairs(&verts, &triangles(prim.mode(), indices)) {
            idx.clear();
            idx.extend(poly.iter().map(|&i| base + i));
            b.polygon(&idx, m);
            *polygons += 1;
        }
        Ok(())
    }
}

/// The same mesh with every polygon's winding reversed (first vertex kept, the rest in reverse order), for
/// a placement whose transform mirrors (negative determinant): glTF says the front face flips there.
pub fn reversed_winding(mesh: &Mesh) -> Result<Mesh, MeshError> {
    let mut b = MeshBuilder::new().keep_polygons_as_given();
    for m in mesh.materials() {
        b.material(m.clone());
    }
    for v in mesh.vertices() {
        b.vertex(*v);
    }
    let mut rev = Vec::with_capacity(8);
    for p in mesh.polygons() {
        let idx = mesh.polygon_indices(p);
        let Some((first, rest)) = idx.split_first() else { continue };
        rev.clear();
        rev.push(*first);
        rev.extend(rest.iter().rev());
        b.polygon(&rev, p.material);
    }
    b.build()
}

fn check_attr(e: &Elements, n: usize, width: usize, what: &str) -> Result<(), String> {
    if e.width != width {
        return Err(format!("{what} has {} components, expected {width}", e.width));
    }
    if e.len() != n {
        return Err(format!("{what} has {} elements, POSITION has {n}", e.len()));
    }
    Ok(())
}

fn wrap(w: gltf::texture::WrappingMode) -> Wrap {
    match w {
        gltf::texture::WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        gltf::texture::WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        gltf::texture::WrappingMode::Repeat => Wrap::Repeat,
    }
}

/// Triangles of a TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN index list, with glTF's winding rules.
fn triangles(mode: Mode, idx: &[u32]) -> Vec<[u32; 3]> {
    match mode {
        Mode::TriangleStrip => (0..idx.len().saturating_sub(2))
            .map(|i| if i % 2 == 0 { [idx[i], idx[i + 1], idx[i + 2]] } else { [idx[i + 1], idx[i], idx[i + 2]] })
            .collect(),
        Mode::TriangleFan => (1..idx.len().saturating_sub(1)).map(|i| [idx[i], idx[i + 1], idx[0]]).collect(),
        _ => idx.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_and_fans_follow_gltf_winding() {
        assert_eq!(triangles(Mode::TriangleStrip, &[0, 1, 2, 3]), [[0, 1, 2], [2, 1, 3]]);
        assert_eq!(triangles(Mode::TriangleFan, &[0, 1, 2, 3]), [[1, 2, 0], [2, 3, 0]]);
        assert_eq!(triangles(Mode::Triangles, &[0, 1, 2, 3]), [[0, 1, 2]]);
        assert!(triangles(Mode::TriangleStrip, &[0]).is_empty());
    }

    #[test]
    fn reversing_keeps_vertices_materials_and_first_corners() {
        let mut b = MeshBuilder::new();
        let red = b.material(Material { base_color: Vec4::new(1.0, 0.0, 0.0, 1.0), ..Material::default() });
        let idx: Vec<u32> = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
            .iter()
            .map(|&(x, y)| b.vertex(Vertex::new(Vec3::new(x, y, 0.0), Vec2::ZERO)))
            .collect();
        b.polygon(&idx, red);
        b.polygon(&idx[..3], red);
        let mesh = b.build().unwrap();
        let rev = reversed_winding(&mesh).unwrap();
        assert_eq!(rev.vertices(), mesh.vertices());
        assert_eq!(rev.materials(), mesh.materials());
        let polys: Vec<&[u32]> = rev.polygons().iter().map(|p| rev.polygon_indices(p)).collect();
        assert_eq!(polys, [&[0, 3, 2, 1][..], &[0, 2, 1][..]]);
    }
}
