//! Polygon set-up: gather a polygon's vertices, clip it, project and snap it to [`Fx28_4`], cull back faces
//! and zero areas, and split non-monotone polygons, producing [`DrawPolygon`]s for the ordering stage.
//!
//! One object's polygons can be set up in pieces on several threads, each piece into its own [`Batch`];
//! appending the batches in order gives exactly what one pass would.

use std::ops::Range;

use super::vertex::{SetupVertex, VertexTransform, project};
use crate::render::core::batch::{Batch, Counts};
use crate::render::core::door::Door;
use crate::render::core::fixed::Fx28_4;
use crate::render::core::mesh::{AlphaMode, Material, Mesh, Polygon};
use crate::render::core::mip::polygon_lod_of;
use crate::render::core::options::DepthKey;
use crate::render::core::polygon::{DrawPolygon, FastPathRule, PolygonPaint, rows_of};
use crate::render::core::small::{SmallFrame, SmallTriangle};
use crate::render::core::texture::Texture;
use crate::render::core::vertex::{ATTRS, ScreenVertex, Winding, cross, signed_area2, slot, triangle_area2};
use crate::render::geometry::clip::{ClipResult, ClipVertex, VIEW_DEPTH, clip_polygon};
use crate::render::geometry::monotone::{is_y_monotone, triangulate};
use crate::render::simd;
use bias::slope_scaled_bias;

/// The screen vertex of a projected point with texture coordinate `uv` and colour `c` (before the divide).
#[inline]
fn screen_vertex(
    (x, y, depth, q): (Fx28_4, Fx28_4, f32, f32),
    uv: [f32; 2],
    c: [f32; 4],
    divide: bool,
) -> ScreenVertex {
    let m = if divide { q } else { 1.0 };
    let mut attrs = [0.0; ATTRS];
    attrs[slot::DEPTH] = depth;
    attrs[slot::Q] = m;
    attrs[slot::S] = uv[0] * m;
    attrs[slot::T] = uv[1] * m;
    for (a, c) in attrs[slot::RGBA..].iter_mut().zip(c) {
        *a = c * m;
    }
    ScreenVertex { x, y, attrs }
}

/// The corners' view depths of triangle `ids` folded by the object's key rule (before [`DepthKey::Avg`]'s
/// division).
fn key_sum(setup: &ObjectSetup<'_>, ids: &[usize; 3]) -> f32 {
    ids.iter().fold(key_start(setup.key), |key, &i| key_add(setup.key, key, setup.vertices[i].view_depth))
}

/// The ordering key's starting value for a rule.
fn key_start(key: DepthKey) -> f32 {
    match key {
        DepthKey::Avg => 0.0,
        DepthKey::Min => f32::INFINITY,
        DepthKey::Max => f32::NEG_INFINITY,
    }
}

/// Folds one corner's view depth into an ordering key.
#[inline]
fn key_add(rule: DepthKey, key: f32, d: f32) -> f32 {
    match rule {
        DepthKey::Avg => key + d,
        DepthKey::Min => key.min(d),
        DepthKey::Max => key.max(d),
    }
}

/// One object's transformed vertices and what set-up needs to know about the frame.
pub(crate) struct ObjectSetup<'a> {
    /// The mesh drawn (with its split pieces, for `view-lists`).
    pub(crate) mesh: &'a Mesh,
    /// The stored drawing order of its polygons, if one applies.
    pub(crate) stored: Option<&'a [u32]>,
    /// The mesh's vertices transformed, tested and projected.
    pub(crate) vertices: &'a [SetupVertex],
    /// How they were transformed (clipping recomputes clip positions with it).
    pub(crate) transform: &'a VertexTransform,
    /// The ordering key rule.
    pub(crate) key: DepthKey,
    /// Whether the frame is drawn in an order made from the polygons' keys; the z-buffer's is not, and its
    /// polygons all get key 0 (a small triangle's set-up then skips reading the corners' view depths).
    pub(crate) ordered: bool,
    /// Whether attributes are divided by `w` for perspective-correct interpolation.
    pub(crate) perspective_attrs: bool,
    /// The key of every polygon when the object is drawn in a stored order.
    pub(crate) object_key: Option<f32>,
    /// How many textures the draw list has.
    pub(crate) textures: usize,
    /// The draw list's textures when mip levels are chosen per polygon (set-up reads their sizes), else none.
    pub(crate) mip_textures: &'a [Texture],
    /// The screen door the object is drawn through (the ghost car; a level-of-detail fade), if any.
    pub(crate) door: Door,
    /// Which polygons the fill draws by a fast path (small triangles among them are set up here).
    pub(crate) fast_path: FastPathRule,
    /// Whether the fill draws coverage samples: then no small triangles are set up (that fill draws every
    /// polygon from its corners), and a polygon's rows are every row its samples may fall in.
    pub(crate) antialiased: bool,
    /// Whether the frame is drawn four rows a pixel (the rotated grid), whose rows sample shifted columns:
    /// a small triangle's box is widened by their reach.
    pub(crate) tall: bool,
    /// The frame's width in pixels.
    pub(crate) width: i32,
}

/// Set-up's scratch buffers for clipping and splitting, one per batch being written, reused frame after
/// frame.
#[derive(Debug, Default)]
pub(crate) struct SetupScratch {
    clip_in: Vec<ClipVertex>,
    clip_out: Vec<ClipVertex>,
    clip_scratch: Vec<ClipVertex>,
    piece: Vec<ScreenVertex>,
    tris: Vec<[usize; 3]>,
}

/// What set-up needs to know of a material, worked out once for a run of polygons sharing it.
#[derive(Clone, Copy, Debug)]
pub(super) struct MaterialSetup {
    /// The material's index in the mesh.
    pub(super) index: u32,
    /// Its texture, if the draw list has it.
    pub(super) texture: Option<u32>,
    alpha_cutoff: Option<f32>,
    /// Whether its polygons of one colour take the direct small-triangle path ([`ObjectSetup::set_up_small`]).
    pub(super) small: bool,
    /// Its texture's size, when mip levels are chosen per polygon (for each polygon's `λ`).
    mip_size: Option<(u32, u32)>,
}

impl MaterialSetup {
    /// Whether its triangles are set up eight at a time ([`ObjectSetup::run_lanes`]): flat ones with the
    /// direct path.
    #[inline(always)]
    fn lanes(&self) -> bool {
        self.small && self.texture.is_none()
    }
}

/// What gathering a polygon's corners gave: its ordering key and whether all corners share one colour.
struct Gathered {
    key: f32,
    constant_color: Option<[f32; 4]>,
    /// Its signed area when already known (and found not culled).
    area: Option<i64>,
}

impl ObjectSetup<'_> {
    /// The frame small triangles are set up for: its width and its rows' reach.
    #[inline(always)]
    pub(crate) fn small_frame(&self) -> SmallFrame {
        if self.tall { SmallFrame::tall(self.width) } else { SmallFrame::plain(self.width) }
    }

    /// Sets up polygons `range` (positions in the stored order, or polygon indices) into `out`.
    pub(crate) fn run(&self, range: Range<usize>, out: &mut Batch, scratch: &mut SetupScratch) {
        let mut cached: Option<MaterialSetup> = None;
        let mut k = range.start;
        // Objects whose first polygon is a flat triangle with the direct small-triangle path go to the lanes;
        // measured on the game's textured objects the lanes did not pay, and one loop for every other object
        // keeps it as tight as it was.
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = simd::avx2()
            && range.len() >= 2 * super::small_setup_avx2::LANES
            && self.polygon_at(k).and_then(|p| self.material_of(p, &mut cached)).is_some_and(|(_, m)| m.lanes())
        {
            k = self.run_lanes(avx2, range.clone(), out, scratch, &mut cached);
        }
        for k in k..range.end {
            self.polygon(k, out, scratch, &mut cached);
        }
    }

    /// The polygon at position `k` (in the stored order, or its index).
    #[inline(always)]
    pub(super) fn polygon_at(&self, k: usize) -> Option<&Polygon> {
        self.mesh.polygons().get(self.stored.map_or(k, |o| o[k] as usize))
    }

    /// The material of `poly` and what set-up needs to know of it, worked out once for each run of
    /// polygons sharing one (`cached` holds the last); `None` for a material the mesh does not have (which
    /// building a mesh refuses).
    #[inline(always)]
    pub(super) fn material_of(
        &self,
        poly: &Polygon,
        cached: &mut Option<MaterialSetup>,
    ) -> Option<(&Material, MaterialSetup)> {
        let material = self.mesh.materials().get(poly.material as usize)?;
        let m = match *cached {
            Some(m) if m.index == poly.material => m,
            _ => *cached.insert(self.material_setup(poly.material, material)),
        };
        Some((material, m))
    }

    /// Sets up the polygon at position `k` into `out`.
    #[inline(always)]
    pub(super) fn polygon(&self, k: usize, out: &mut Batch, scratch: &mut SetupScratch, c: &mut Option<MaterialSetup>) {
        let Some(poly) = self.polygon_at(k) else { return };
        let idx = self.mesh.polygon_indices(poly);
        let Some((material, m)) = self.material_of(poly, c) else { return };
        let (mut finite, mut outside, mut cut, mut projected) = (true, u8::MAX, 0u8, true);
        for &i in idx {
            let v = &self.vertices[i as usize];
            finite &= v.is_finite();
            outside &= v.outside;
            cut |= v.cut;
            projected &= v.is_projected();
        }
        if !finite {
            out.counts.invalid += 1;
            return;
        }
        if outside != 0 {
            out.counts.outside += 1;
            return;
        }
        // A projected polygon is culled before anything is gathered (a depth bias moves no corner on screen,
        // so its area is the one `finish` would find), and `finish` is handed the area.
        let mut area = None;
        if cut == 0 && projected {
            let a = self.projected_area(idx);
            if culled(a, material, &mut out.counts) {
                return;
            }
            if m.small && self.set_up_small(idx, a, material, &m, out) {
                return;
            }
            area = Some(a);
        }
        let first = out.screen.len();
        let gathered = if cut == 0 {
            // Inside the guard band: the corners as projected once per vertex.
            if !projected {
                out.counts.invalid += 1;
                return;
            }
            self.gather_inside(idx, material, out)
        } else {
            self.gather_clipped(idx, material, out, scratch)
        };
        let Some(g) = gathered else {
            out.screen.truncate(first);
            return;
        };
        self.finish(first, Gathered { area, ..g }, (material, &m), out, scratch);
    }

    /// [`signed_area2`] of the projected corners `idx`.
    #[inline(always)]
    fn projected_area(&self, idx: &[u32]) -> i64 {
        let at = |i: u32| {
            let (x, y, _, _) = self.vertices[i as usize].screen_or_zero();
            (x, y)
        };
        if let &[a, b, c] = idx {
            return triangle_area2([at(a), at(b), at(c)]);
        }
        let next = idx.iter().skip(1).chain(idx.first());
        idx.iter().zip(next).map(|(&p, &q)| cross(at(p), at(q))).sum()
    }

    /// The ordering key of a polygon of `n` corners whose corners' view depths fold to `folded` (asked only
    /// when needed): 0 when the frame is not ordered by keys, the object's key when it is drawn in a stored
    /// order (which keeps its polygons together), else the folded depths (their mean for [`DepthKey::Avg`]).
    #[inline(always)]
    fn polygon_key(&self, n: usize, folded: impl FnOnce() -> f32) -> f32 {
        match self.object_key {
            _ if !self.ordered => 0.0,
            Some(k) => k,
            None => {
                let key = folded();
                if self.key == DepthKey::Avg { key / n as f32 } else { key }
            }
        }
    }

    /// What set-up needs to know of material `index`.
    fn material_setup(&self, index: u32, material: &Material) -> MaterialSetup {
        let texture = material.texture.filter(|&t| t < self.textures).map(|t| t as u32);
        let alpha_cutoff = match material.alpha_mode {
            AlphaMode::Opaque => None,
            AlphaMode::Mask { cutoff } => Some(cutoff),
        };
        // A depth bias moves the corners' depths, which the direct path does not do.
        let fast =
            self.fast_path.small_triangles(texture.is_some(), true, alpha_cutoff.is_some(), !self.door.is_none());
        let mip_size = texture.and_then(|t| self.mip_textures.get(t as usize)).map(|t| (t.width(), t.height()));
        MaterialSetup {
            index,
            texture,
            alpha_cutoff,
            small: fast && !self.antialiased && material.depth_bias == 0,
            mip_size,
        }
    }

    /// Pushes the projected corners of a polygon that needs no clipping.
    fn gather_inside(&self, idx: &[u32], material: &Material, out: &mut Batch) -> Option<Gathered> {
        let mut key = key_start(self.key);
        let mut colors = [0.0f32; 4];
        let mut constant = true;
        for (n, &i) in idx.iter().enumerate() {
            let i = i as usize;
            let (v, s) = (&self.mesh.vertices()[i], &self.vertices[i]);
            key = key_add(self.key, key, s.view_depth);
            let c = (v.color * material.base_color).to_array();
            if n == 0 {
                colors = c;
            } else {
                constant &= c == colors;
            }
            out.screen.push(screen_vertex(s.screen()?, v.uv.to_array(), c, self.perspective_attrs));
        }
        Some(Gathered { key, constant_color: constant.then_some(colors), area: None })
    }

    /// Clips a polygon crossing a clip plane and pushes the projected corners of what is left; `None` (and
    /// counted) when nothing is left or a corner does not project.
    fn gather_clipped(
        &self,
        idx: &[u32],
        material: &Material,
        out: &mut Batch,
        scratch: &mut SetupScratch,
    ) -> Option<Gathered> {
        scratch.clip_in.clear();
        for &i in idx {
            let i = i as usize;
            let (v, s) = (&self.mesh.vertices()[i], &self.vertices[i]);
            let c = v.color * material.base_color;
            let attrs = [v.uv.x, v.uv.y, c.x, c.y, c.z, c.w, s.view_depth];
            let (pos, _) = self.transform.clip_and_depth(v.position);
            scratch.clip_in.push(ClipVertex { pos, attrs });
        }
        let t = self.transform;
        match clip_polygon(&scratch.clip_in, &t.volume, &mut scratch.clip_out, &mut scratch.clip_scratch) {
            ClipResult::Outside => {
                out.counts.outside += 1;
                return None;
            }
            ClipResult::Clipped => out.counts.clipped += 1,
            ClipResult::Inside => {}
        }
        let mut key = key_start(self.key);
        for cv in &scratch.clip_out {
            let Some(p) = project(cv.pos, t.size, t.perspective) else {
                out.counts.invalid += 1;
                return None;
            };
            let a = &cv.attrs;
            out.screen.push(screen_vertex(p, [a[0], a[1]], [a[2], a[3], a[4], a[5]], self.perspective_attrs));
            key = key_add(self.key, key, a[VIEW_DEPTH]);
        }
        let color = |v: &ClipVertex| [v.attrs[2], v.attrs[3], v.attrs[4], v.attrs[5]];
        let first_color = scratch.clip_out.first().map(color);
        let constant_color = first_color.filter(|c| scratch.clip_out.iter().all(|v| color(v) == *c));
        Some(Gathered { key, constant_color, area: None })
    }

    /// Culls, keys and (when not y-monotone) splits the polygon whose corners are `out.screen[first..]`.
    fn finish(
        &self,
        first: usize,
        g: Gathered,
        (material, m): (&Material, &MaterialSetup),
        out: &mut Batch,
        scratch: &mut SetupScratch,
    ) {
        let n = out.screen.len() - first;
        let key = self.polygon_key(n, || g.key);
        if material.depth_bias > 0 {
            slope_scaled_bias(&mut out.screen[first..], material.depth_bias);
        }
        let area = g.area.or_else(|| Some(signed_area2(&out.screen[first..])));
        let Some(area) = area.filter(|&a| g.area.is_some() || !culled(a, material, &mut out.counts)) else {
            out.screen.truncate(first);
            return;
        };
        out.counts.drawn += 1;
        let (texture, alpha_cutoff) = (m.texture, m.alpha_cutoff);
        let paint = PolygonPaint {
            texture,
            sampler: material.sampler,
            alpha_cutoff,
            constant_color: g.constant_color,
            door: self.door,
            // Once for the whole polygon, before any split: its pieces share it.
            lod: m.mip_size.map_or(0, |size| polygon_lod_of(&out.screen[first..], size)),
        };
        let tag = out.tag;
        // Each polygon (or piece) drawn, with its key when the frame is ordered by keys.
        let ordered = self.ordered;
        let push = |out: &mut Batch, first: u32, count: u32, rows: (i32, i32), small: bool, winding: Winding| {
            // Only polygons with corners are walked by their winding (small triangles, as the other set-up
            // paths make them, leave the bit clear).
            let p = DrawPolygon::new(first, count, tag, rows, small, &paint);
            out.polys.push(if small { p } else { p.wound(winding) });
            if ordered {
                out.keys.push(key);
            }
        };
        let (textured, constant) = (texture.is_some(), g.constant_color.is_some());
        let fast = self.fast_path.small_triangles(textured, constant, alpha_cutoff.is_some(), !self.door.is_none())
            && (!textured || self.fast_path.small_textured_at(paint.lod, alpha_cutoff.is_some()));
        // A small triangle with a fast path is set up here, in place of its screen vertices; a flat colour
        // needs only the depth plane (the fill draws a textureless small triangle as flat, see `bands`).
        let small = |corners: &[ScreenVertex], area: i64| match (fast && !self.antialiased, texture) {
            (false, _) => None,
            (true, None) => SmallTriangle::new::<1>(corners, area, self.small_frame()),
            (true, Some(_)) => SmallTriangle::new::<4>(corners, area, self.small_frame()),
        };
        // Culling took the polygons of no area away.
        debug_assert_ne!(area, 0);
        let winding = Winding::of_area(area).unwrap_or(Winding::CounterClockwise);
        if let Some(t) = small(&out.screen[first..], area) {
            out.screen.truncate(first);
            let rows = t.0.rows();
            let f = out.push_small(t, texture.is_some());
            push(out, f, n as u32, rows, true, winding);
        } else if is_y_monotone(&out.screen[first..]) {
            let rows = rows_of(&out.screen[first..], self.antialiased);
            push(out, first as u32, n as u32, rows, false, winding);
        } else {
            out.counts.split += 1;
            self.split(first, area, (out, scratch), |out, corners, area, winding| {
                if let Some(st) = small(corners, area) {
                    let rows = st.0.rows();
                    let f = out.push_small(st, texture.is_some());
                    push(out, f, 3, rows, true, winding);
                } else {
                    let f = out.screen.len() as u32;
                    out.screen.extend_from_slice(corners);
                    push(out, f, 3, rows_of(corners, self.antialiased), false, winding);
                }
            });
        }
    }

    /// Cuts the polygon `out.screen[first..]` of signed area `area` (not y-monotone) into triangles, takes
    /// its corners out of `out.screen`, and hands each triangle of some area to `place` with its area and
    /// winding (a piece of no area covers nothing, and has no winding to walk it by).
    fn split(
        &self,
        first: usize,
        area: i64,
        (out, scratch): (&mut Batch, &mut SetupScratch),
        mut place: impl FnMut(&mut Batch, &[ScreenVertex; 3], i64, Winding),
    ) {
        scratch.tris.clear();
        scratch.piece.clear();
        scratch.piece.extend_from_slice(&out.screen[first..]);
        triangulate(&scratch.piece, area.signum(), &mut scratch.tris);
        out.screen.truncate(first);
        for t in &scratch.tris {
            let corners = t.map(|i| scratch.piece[i]);
            let area = signed_area2(&corners);
            if let Some(winding) = Winding::of_area(area) {
                place(out, &corners, area, winding);
            }
        }
    }
}

/// Whether a polygon of signed area `area` ([`signed_area2`]) is culled, counted as degenerate (no area) or
/// as a back face (clockwise on screen, unless its material is double sided). The caller counts a polygon
/// it draws once it is set up.
#[inline(always)]
pub(super) fn culled(area: i64, material: &Material, counts: &mut Counts) -> bool {
    if area == 0 {
        counts.degenerate += 1;
        true
    } else if area > 0 && !material.double_sided {
        counts.backface += 1;
        true
    } else {
        false
    }
}

mod bias;
mod direct;
#[cfg(target_arch = "x86_64")]
pub mod lanes;
#[cfg(test)]
mod tests;
