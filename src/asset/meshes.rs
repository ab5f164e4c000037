//! Building the renderer's meshes from glTF mesh primitives: accessors read once each and charged to the
//! budget, vertex and polygon counts checked before anything is built, quads merged, decals marked; and
//! the winding-reversed copy a mirrored placement draws.

use std::collections::BTreeMap;
use std::rc::Rc;

use glam::{Vec2, Vec3, Vec4};
use gltf::mesh::Mode;

use super::accessor::{Elements, read_floats, read_indices};
use super::budget::{Limit, OverBudget};
use super::error::{AssetError, Place, PrimitiveProblem};
use super::quads::merge_pairs;
use super::state::Loader;
use super::trim::Trimmer;
use crate::render::{AlphaMode, Material, Mesh, MeshBuilder, MeshError, Sampler, Vertex, Wrap};

/// Why a primitive could not be read: the file is wrong, or it needs more than the budget.
enum Failure {
    Bad(PrimitiveProblem),
    /// Over the budget, with the accessor in the primitive that asked for it.
    OverAt {
        /// What the accessor holds (`POSITION`, `indices`, ...).
        semantic: &'static str,
        /// glTF accessor index.
        accessor: usize,
        over: OverBudget,
    },
    /// A texture's image failed (its error already names the file and the image).
    Image(AssetError),
}

impl From<PrimitiveProblem> for Failure {
    fn from(p: PrimitiveProblem) -> Self {
        Failure::Bad(p)
    }
}

/// Numbers an accessor materialises: elements times components.
fn values_of(acc: &gltf::Accessor<'_>) -> u64 {
    (acc.count() as u64).saturating_mul(acc.dimensions().multiplicity() as u64)
}

impl Loader<'_> {
    fn floats(&mut self, acc: &gltf::Accessor<'_>, semantic: &'static str) -> Result<Rc<Elements>, Failure> {
        if let Some(e) = self.accessors.floats.get(&acc.index()) {
            return Ok(Rc::clone(e));
        }
        let over = |over| Failure::OverAt { semantic, accessor: acc.index(), over };
        self.meter.charge(Limit::AccessorValues, values_of(acc)).map_err(over)?;
        let read = read_floats(acc, self.buffers).map_err(|source| PrimitiveProblem::Accessor { semantic, source });
        let e = Rc::new(read?);
        self.accessors.floats.insert(acc.index(), Rc::clone(&e));
        Ok(e)
    }

    fn indices(&mut self, acc: &gltf::Accessor<'_>) -> Result<Rc<Vec<u32>>, Failure> {
        if let Some(e) = self.accessors.indices.get(&acc.index()) {
            return Ok(Rc::clone(e));
        }
        let semantic = "indices";
        let over = |over| Failure::OverAt { semantic, accessor: acc.index(), over };
        self.meter.charge(Limit::AccessorValues, values_of(acc)).map_err(over)?;
        let read = read_indices(acc, self.buffers).map_err(|source| PrimitiveProblem::Accessor { semantic, source });
        let e = Rc::new(read?);
        self.accessors.indices.insert(acc.index(), Rc::clone(&e));
        Ok(e)
    }

    /// Builds the renderer mesh for a glTF mesh. Before a primitive's accessors are read, its vertices and
    /// (at least half its triangles, as merging makes at most one quad of two) polygons must fit in the
    /// budget left after the instances placed so far, since this mesh will be placed at least once. A
    /// polygon the mesh builder refuses is reported against the primitive it came from.
    pub(super) fn mesh(&mut self, mesh: &gltf::Mesh<'_>) -> Result<Mesh, AssetError> {
        let mut b = MeshBuilder::new();
        let mut polygons = 0u64;
        // Each primitive's index and the polygon count of the mesh after it.
        let mut ends: Vec<(usize, u64)> = Vec::new();
        for prim in mesh.primitives() {
            let (file, mesh, primitive) = (self.file.clone(), mesh.index(), prim.index());
            self.primitive(&prim, &mut b, &mut polygons).map_err(|f| match f {
                Failure::Bad(problem) => AssetError::Primitive { file: file.clone(), mesh, primitive, problem },
                Failure::OverAt { semantic, accessor, over } => {
                    AssetError::budget(&file, Place::Accessor { mesh, primitive, semantic, accessor }, over)
                }
                Failure::Image(e) => e,
            })?;
            ends.push((primitive, polygons));
        }
        let mut built = b.build().map_err(|problem| {
            let (file, mesh) = (self.file.clone(), mesh.index());
            let polygon = match &problem {
                MeshError::IndexOutOfRange { polygon, .. } | MeshError::MaterialOutOfRange { polygon, .. } => {
                    Some(*polygon as u64)
                }
                MeshError::TooLarge { .. } => None,
            };
            match polygon.and_then(|n| primitive_holding(&ends, n)) {
                Some(primitive) => {
                    AssetError::Primitive { file, mesh, primitive, problem: PrimitiveProblem::Build(problem) }
                }
                None => AssetError::Mesh { file, mesh, problem },
            }
        })?;
        super::decals::mark_decals(&mut built, self.meter.decal_pairs_left());
        built.set_faces_eye(faces_eye(mesh));
        Ok(built)
    }

    /// The primitive's material, its base colour texture decoded (the first time its image is named), and
    /// the texture coordinate set that texture reads.
    fn material(&mut self, prim: &gltf::Primitive<'_>) -> Result<(Material, Option<u32>), Failure> {
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
                (self.buffers, self.base, &self.file),
                &mut self.meter,
                &mut self.out.textures,
            );
            material.texture = Some(texture.map_err(Failure::Image)?);
            let s = tex.sampler();
            material.sampler = Sampler { wrap_s: wrap(s.wrap_s()), wrap_t: wrap(s.wrap_t()) };
            uv_set = Some(info.tex_coord());
        }
        Ok((material, uv_set))
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
        self.meter
            .check(Limit::Vertices, b.vertex_count() as u64 + n as u64)
            .and_then(|()| self.meter.check(Limit::Polygons, *polygons + tris.div_ceil(2)))
            .map_err(|over| Failure::OverAt { semantic: "POSITION", accessor: pos_acc.index(), over })?;
        let positions = self.floats(&pos_acc, "POSITION")?;
        if positions.width != 3 {
            return Err(PrimitiveProblem::PositionWidth { components: positions.width }.into());
        }
        let (material, uv_set) = self.material(prim)?;
        let uvs = match uv_set.and_then(|set| prim.get(&gltf::Semantic::TexCoords(set))) {
            Some(acc) => {
                let e = self.floats(&acc, "TEXCOORD")?;
                check_attr(&e, n, 2, "TEXCOORD")?;
                Some(e)
            }
            None => None,
        };
        let colors = match prim.get(&gltf::Semantic::Colors(0)) {
            Some(acc) => {
                let e = self.floats(&acc, "COLOR_0")?;
                if e.width != 3 && e.width != 4 {
                    return Err(PrimitiveProblem::ColorWidth { components: e.width }.into());
                }
                check_attr(&e, n, e.width, "COLOR_0")?;
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
        if let Some(&index) = indices.iter().find(|&&i| i as usize >= n) {
            return Err(PrimitiveProblem::IndexOutOfRange { index, vertices: n }.into());
        }
        let base = b.vertex_count() as u32;
        let verts = vertices(n, &positions, uvs.as_deref(), colors.as_deref());
        let polys = merge_pairs(&verts, &triangles(prim.mode(), indices));
        let (verts, polys) = self.trim_cut_outs(&material, base, verts, polys);
        let m = b.material(material);
        for v in &verts {
            b.vertex(*v);
        }
        let mut idx = Vec::with_capacity(4);
        for poly in polys {
            idx.clear();
            idx.extend(poly.iter().map(|&i| base + i));
            b.polygon(&idx, m);
            *polygons += 1;
        }
        Ok(())
    }

    /// A primitive's polygons with cut-outs trimmed ([`trim_all`]) when `material` is alpha-masked and
    /// textured, the new corners within the vertex budget after the `base` vertices built before.
    fn trim_cut_outs(
        &mut self,
        material: &Material,
        base: u32,
        verts: Vec<Vertex>,
        polys: Vec<Vec<u32>>,
    ) -> (Vec<Vertex>, Vec<Vec<u32>>) {
        let (AlphaMode::Mask { cutoff }, Some(t)) = (material.alpha_mode, material.texture) else {
            return (verts, polys);
        };
        let Some(tex) = self.out.textures.get(t) else { return (verts, polys) };
        let fits = |count: usize| self.meter.check(Limit::Vertices, (base as usize + count) as u64).is_ok();
        let how = (tex, t, material.sampler, material.base_color.w, cutoff);
        trim_all(&mut self.trims, how, verts, polys, fits)
    }
}

/// A polygon's edges, each as its two corners' indices.
fn edges(p: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    (0..p.len()).map(move |k| (p[k], p[(k + 1) % p.len()]))
}

/// A cut-out primitive's polygons trimmed ([`Trimmer::trim`]) where they share no edge with another of
/// them (a neighbour cut elsewhere on the edge would leave a crack), new corners appended to `verts`
/// while `fits` says the vertex count is within the budget, and the vertices no polygon uses any more
/// dropped. Nothing changes when no polygon is trimmed.
fn trim_all(
    trims: &mut Trimmer,
    (tex, index, sampler, alpha, cutoff): (&crate::render::Texture, usize, Sampler, f32, f32),
    mut verts: Vec<Vertex>,
    mut polys: Vec<Vec<u32>>,
    fits: impl Fn(usize) -> bool,
) -> (Vec<Vertex>, Vec<Vec<u32>>) {
    // Each edge by its ends' positions (bits), both directions as one.
    let key = |verts: &[Vertex], a: u32, b: u32| {
        let bits = |i: u32| verts.get(i as usize).map(|v| v.position.to_array().map(f32::to_bits));
        let (p, q) = (bits(a), bits(b));
        if p <= q { (p, q) } else { (q, p) }
    };
    let mut uses: BTreeMap<_, u32> = BTreeMap::new();
    for p in &polys {
        for (a, b) in edges(p) {
            *uses.entry(key(&verts, a, b)).or_default() += 1;
        }
    }
    let mut trimmed = false;
    let mut corners = Vec::with_capacity(4);
    for poly in &mut polys {
        if edges(poly).any(|(a, b)| uses.get(&key(&verts, a, b)).is_some_and(|&n| n > 1)) {
            continue;
        }
        corners.clear();
        corners.extend(poly.iter().filter_map(|&i| verts.get(i as usize).copied()));
        if corners.len() != poly.len() {
            continue;
        }
        let Some(cut) = trims.trim((tex, index), sampler, (alpha, cutoff), &corners) else { continue };
        let new = cut.iter().filter(|c| c.1.is_none()).count();
        if !fits(verts.len() + new) {
            continue;
        }
        let old = std::mem::take(poly);
        for (v, k) in cut {
            poly.push(k.and_then(|k| old.get(k).copied()).unwrap_or_else(|| {
                verts.push(v);
                (verts.len() - 1) as u32
            }));
        }
        trimmed = true;
    }
    if !trimmed {
        return (verts, polys);
    }
    // Keep the vertices still used, in order.
    let mut map = vec![u32::MAX; verts.len()];
    polys.iter().flatten().for_each(|&i| map[i as usize] = 0);
    let mut kept = Vec::with_capacity(verts.len());
    for (i, v) in verts.iter().enumerate() {
        if map[i] == 0 {
            map[i] = kept.len() as u32;
            kept.push(*v);
        }
    }
    polys.iter_mut().flatten().for_each(|i| *i = map[*i as usize]);
    (kept, polys)
}

/// Whether a glTF mesh asks to turn about its Y axis to face the eye: `"extras": {"billboard": "y"}` (glTF
/// has no billboards of its own; any other value, or none, is an ordinary mesh).
fn faces_eye(mesh: &gltf::Mesh<'_>) -> bool {
    mesh.extras().as_ref().is_some_and(|raw| {
        serde_json::from_str::<serde_json::Value>(raw.get())
            .ok()
            .is_some_and(|v| v.get("billboard").and_then(serde_json::Value::as_str) == Some("y"))
    })
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
    let mut copy = b.build()?;
    copy.set_faces_eye(mesh.faces_eye());
    Ok(copy)
}

/// The first `n` vertices from their positions, texture coordinates (zero without) and colours (white
/// without; opaque when RGB).
fn vertices(n: usize, positions: &Elements, uvs: Option<&Elements>, colors: Option<&Elements>) -> Vec<Vertex> {
    (0..n)
        .map(|i| {
            let position = Vec3::new(positions.get(i, 0), positions.get(i, 1), positions.get(i, 2));
            let uv = uvs.map_or(Vec2::ZERO, |e| Vec2::new(e.get(i, 0), e.get(i, 1)));
            let color = colors.map_or(Vec4::ONE, |e| {
                Vec4::new(e.get(i, 0), e.get(i, 1), e.get(i, 2), if e.width == 4 { e.get(i, 3) } else { 1.0 })
            });
            Vertex { position, uv, color }
        })
        .collect()
}

/// The primitive whose polygons include polygon `n` of the mesh, given each primitive's index and the
/// mesh's polygon count after it (primitives in order).
fn primitive_holding(ends: &[(usize, u64)], n: u64) -> Option<usize> {
    ends.iter().find(|&&(_, end)| n < end).map(|&(primitive, _)| primitive)
}

/// Checks that an attribute has `width` components per element and one element per position (`n`).
fn check_attr(e: &Elements, n: usize, width: usize, semantic: &'static str) -> Result<(), PrimitiveProblem> {
    if e.width != width {
        return Err(PrimitiveProblem::Components { semantic, found: e.width, expected: width });
    }
    if e.len() != n {
        return Err(PrimitiveProblem::Elements { semantic, found: e.len(), positions: n });
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
    fn a_polygon_is_traced_to_the_primitive_that_made_it() {
        // Primitive 0 made polygons 0-4, primitive 1 none (points, skipped), primitive 2 polygons 5-6.
        let ends = [(0, 5), (1, 5), (2, 7)];
        let found: Vec<Option<usize>> = [0, 4, 5, 6, 7].iter().map(|&n| primitive_holding(&ends, n)).collect();
        assert_eq!(found, [Some(0), Some(0), Some(2), Some(2), None]);
    }

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
