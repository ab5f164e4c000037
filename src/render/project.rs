//! Polygon set-up: gather a polygon's vertices, clip it, project and snap it to [`Fx28_4`], cull back faces
//! and zero areas, and split non-monotone polygons, producing [`DrawPolygon`]s for the ordering stage.
//!
//! One object's polygons can be set up in pieces on several threads, each piece into its own [`Batch`];
//! appending the batches in order gives exactly what one pass would.

use std::ops::Range;

use glam::Vec4;

use super::DepthKey;
#[cfg(test)]
use super::clip::VertexCodes;
use super::clip::{ClipResult, ClipVertex, ClipVolume, VIEW_DEPTH, clip_polygon};
use super::fixed::Fx28_4;
use super::mesh::{AlphaMode, Material, Mesh};
use super::monotone::triangulate;
use super::pipeline::{DrawPolygon, PolygonPaint, slope_scaled_bias};
use super::scanline::{ATTRS, ScreenVertex, is_y_monotone, signed_area2, slot};
use super::small_triangle::{Corner, SmallTriangle, TexPlanes};
use super::span::FastPathRule;
use super::stats::Stats;
use super::transform::VertexTransform;

/// Polygons dropped or changed during set-up, by reason.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct Counts {
    invalid: u64,
    outside: u64,
    clipped: u64,
    degenerate: u64,
    backface: u64,
    drawn: u64,
    split: u64,
}

impl Counts {
    /// The polygon counts of a frame's statistics.
    fn from_stats(s: &Stats) -> Self {
        Self {
            invalid: s.polygons_invalid,
            outside: s.polygons_outside,
            clipped: s.polygons_clipped,
            degenerate: s.polygons_degenerate,
            backface: s.polygons_backface,
            drawn: s.polygons_drawn,
            split: s.polygons_split,
        }
    }

    /// Adds these counts to a frame's statistics.
    pub(super) fn add_to(&self, stats: &mut Stats) {
        stats.polygons_invalid += self.invalid;
        stats.polygons_outside += self.outside;
        stats.polygons_clipped += self.clipped;
        stats.polygons_degenerate += self.degenerate;
        stats.polygons_backface += self.backface;
        stats.polygons_drawn += self.drawn;
        stats.polygons_split += self.split;
    }
}

/// Set-up output (screen vertices, small triangles and the polygons indexing them) and the scratch buffers
/// that make it.
#[derive(Debug, Default)]
pub(super) struct Batch {
    pub(super) screen: Vec<ScreenVertex>,
    /// Flat small triangles set up for the fast path, in place of their screen vertices.
    pub(super) small: Vec<SmallTriangle>,
    /// Textured ones, with their texture planes.
    pub(super) small_textured: Vec<(SmallTriangle, TexPlanes)>,
    pub(super) polys: Vec<DrawPolygon>,
    /// The polygons' ordering keys, one each, when the frame is ordered by them (empty for the z-buffer:
    /// see [`ObjectSetup::ordered`]).
    pub(super) keys: Vec<f32>,
    pub(super) counts: Counts,
    /// For each band, the indices of its polygons touching the band, when it binned them itself (the
    /// z-buffer's set-up pieces: see [`super::bands::BinnedRun`]); unused in the main batch.
    pub(super) bins: Vec<Vec<u32>>,
    clip_in: Vec<ClipVertex>,
    clip_out: Vec<ClipVertex>,
    clip_scratch: Vec<ClipVertex>,
    piece: Vec<ScreenVertex>,
    tris: Vec<[usize; 3]>,
    /// The number its polygons carry in [`DrawPolygon::batch`] (see [`Screens`]): 0 for the main batch.
    pub(super) tag: u32,
}

impl Batch {
    /// Stores a small triangle's set-up (with its texture planes when `textured`); returns its index.
    fn push_small(&mut self, (t, planes): (SmallTriangle, TexPlanes), textured: bool) -> u32 {
        if textured {
            self.small_textured.push((t, planes));
            self.small_textured.len() as u32 - 1
        } else {
            self.small.push(t);
            self.small.len() as u32 - 1
        }
    }

    /// Empties the output, keeping the allocations.
    pub(super) fn clear(&mut self) {
        self.screen.clear();
        self.small.clear();
        self.small_textured.clear();
        self.polys.clear();
        self.keys.clear();
        self.counts = Counts::default();
    }

    /// Appends the polygons of `others` to this batch, in order (each was tagged with its batch's number
    /// when it was set up); their screen vertices stay where they are, found through [`Screens`].
    ///
    /// Measured on the small-polygon scene with 2 threads: copying the screen vertices too (2.4 MB) took
    /// 0.22 ms a frame, more than the parallel set-up itself saved, and re-tagging the polygons while
    /// copying them in parallel still 0.11-0.15 ms; a plain copy is a memcpy.
    pub(super) fn adopt_polygons(&mut self, others: &[Batch]) {
        for b in others {
            self.polys.extend_from_slice(&b.polys);
            self.keys.extend_from_slice(&b.keys);
        }
        self.adopt_counts(others);
    }

    /// Adds the set-up counts of `others` to this batch's, leaving their polygons where they are.
    pub(super) fn adopt_counts(&mut self, others: &[Batch]) {
        let mut stats = Stats::default();
        self.counts.add_to(&mut stats);
        for b in others {
            b.counts.add_to(&mut stats);
        }
        self.counts = Counts::from_stats(&stats);
    }
}

/// Where the screen vertices (or small triangles) of a frame's polygons are: batch 0 is the main batch,
/// batch `k` the set-up batch `k - 1`.
#[derive(Clone, Copy)]
pub(super) struct Screens<'a> {
    /// The main batch.
    pub(super) main: &'a Batch,
    /// The set-up batches of big objects, whose vertices were left in place.
    pub(super) batches: &'a [Batch],
}

impl<'a> Screens<'a> {
    /// The batch holding polygon `p`'s corners.
    #[inline]
    fn batch(&self, p: &DrawPolygon) -> Option<&'a Batch> {
        match p.batch {
            0 => Some(self.main),
            k => self.batches.get(k as usize - 1),
        }
    }

    /// The screen vertices of polygon `p` (`None` for a small triangle, or a polygon whose indices are out
    /// of range).
    #[inline]
    pub(super) fn of(&self, p: &DrawPolygon) -> Option<&'a [ScreenVertex]> {
        if p.small() {
            return None;
        }
        self.batch(p)?.screen.get(p.first as usize..(p.first + p.count) as usize)
    }

    /// The set-up of small triangle `p` and its texture planes ([`TexPlanes::NONE`] when it has no
    /// texture); `None` if `p` is not one.
    #[inline]
    pub(super) fn small(&self, p: &DrawPolygon) -> Option<(&'a SmallTriangle, &'a TexPlanes)> {
        if !p.small() {
            return None;
        }
        let b = self.batch(p)?;
        if p.texture().is_some() {
            b.small_textured.get(p.first as usize).map(|(t, planes)| (t, planes))
        } else {
            b.small.get(p.first as usize).map(|t| (t, &TexPlanes::NONE))
        }
    }
}

/// A [`SetupVertex`] as bits: view depth, codes, finite, and screen `(x, y, depth, 1/w)` if projected.
#[cfg(test)]
pub(super) type SetupBits = (u32, VertexCodes, bool, Option<(i32, i32, u32, u32)>);

/// One vertex of an object after the transform: its clip codes and, when it needs no clipping, its snapped
/// screen position, so a polygon wholly inside the guard band is set up by gathering its corners (computed
/// once per vertex, however many polygons share it) without going through the clipper.
///
/// The record is 24 bytes: the clip position is not kept (a polygon that needs clipping recomputes its
/// corners' positions, [`VertexTransform::clip_and_depth`]), so the transform writes, and set-up reads, half
/// as much as with it (measured on the small-polygon scene, 1 thread: transform 0.26 -> 0.21 ms). It is plain
/// old data (`repr(C)`, flags as bytes) so that the AVX2 transform writes eight of them with vector stores
/// rather than field by field (0.207 -> 0.162 ms on that scene).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct SetupVertex {
    /// Snapped screen x and y (raw [`Fx28_4`]), depth and `1/w` when `projected`, zeros otherwise.
    x: i32,
    y: i32,
    depth: f32,
    q: f32,
    /// View depth (distance along the view direction), for ordering keys.
    pub(super) view_depth: f32,
    /// Where it lies against the clip planes ([`VertexCodes`]).
    outside: u8,
    cut: u8,
    /// 1 when the clip position and the view depth are finite, else 0.
    finite: u8,
    /// 1 when the vertex is finite, inside every clip plane and projects onto the grid, else 0.
    projected: u8,
}

// The AVX2 transform writes a record as six words in this order (`transform_avx2.rs`).
const _: () = {
    use std::mem::offset_of;
    assert!(size_of::<SetupVertex>() == 24);
    assert!(offset_of!(SetupVertex, x) == 0 && offset_of!(SetupVertex, y) == 4);
    assert!(offset_of!(SetupVertex, depth) == 8 && offset_of!(SetupVertex, q) == 12);
    assert!(offset_of!(SetupVertex, view_depth) == 16 && offset_of!(SetupVertex, outside) == 20);
    assert!(offset_of!(SetupVertex, cut) == 21 && offset_of!(SetupVertex, finite) == 22);
    assert!(offset_of!(SetupVertex, projected) == 23);
};

impl SetupVertex {
    /// Tests and projects a vertex at clip position `pos` with view depth `view_depth`.
    #[inline(always)]
    pub(super) fn new(pos: Vec4, view_depth: f32, volume: &ClipVolume, size: (f32, f32), perspective: bool) -> Self {
        let finite = pos.is_finite() && view_depth.is_finite();
        let codes = volume.codes(pos);
        let screen = if finite && codes.cut == 0 { project(pos, size, perspective) } else { None };
        let (x, y, depth, q) = screen.unwrap_or((Fx28_4(0), Fx28_4(0), 0.0, 0.0));
        Self {
            x: x.0,
            y: y.0,
            depth,
            q,
            view_depth,
            outside: codes.outside,
            cut: codes.cut,
            finite: u8::from(finite),
            projected: u8::from(screen.is_some()),
        }
    }

    /// The snapped screen position, depth and `1/w` (zeros when the vertex did not project).
    #[inline(always)]
    pub(super) fn screen_or_zero(&self) -> (Fx28_4, Fx28_4, f32, f32) {
        (Fx28_4(self.x), Fx28_4(self.y), self.depth, self.q)
    }

    /// The snapped screen position, depth and `1/w`, if the vertex projected.
    #[inline]
    pub(super) fn screen(&self) -> Option<(Fx28_4, Fx28_4, f32, f32)> {
        self.is_projected().then_some(self.screen_or_zero())
    }

    /// Where it lies against the clip planes.
    #[cfg(test)]
    pub(super) fn codes(&self) -> VertexCodes {
        VertexCodes { outside: self.outside, cut: self.cut }
    }

    /// Whether the clip position and the view depth are finite.
    #[inline(always)]
    pub(super) fn is_finite(&self) -> bool {
        self.finite != 0
    }

    /// Whether the vertex has a screen position.
    #[inline(always)]
    pub(super) fn is_projected(&self) -> bool {
        self.projected != 0
    }

    /// Every field as bits, to compare records exactly; every NaN is one value (the sign and payload of a
    /// NaN depend on operand order, which the compiler may swap, and no frame depends on them: a vertex with
    /// one is never drawn).
    #[cfg(test)]
    pub(super) fn bits(&self) -> SetupBits {
        let b = |v: f32| if v.is_nan() { f32::NAN.to_bits() } else { v.to_bits() };
        let screen = self.screen().map(|(x, y, d, q)| (x.0, y.0, b(d), b(q)));
        (b(self.view_depth), self.codes(), self.is_finite(), screen)
    }
}

/// Projects a clip-space position to the snapped screen position, its depth and `1/w`; `None` when it
/// does not land on the fixed-point grid or is not in front of the camera.
#[inline]
fn project(p: Vec4, size: (f32, f32), perspective: bool) -> Option<(Fx28_4, Fx28_4, f32, f32)> {
    let q = 1.0 / p.w;
    let sx = (p.x * q + 1.0) * 0.5 * size.0;
    let sy = (1.0 - p.y * q) * 0.5 * size.1;
    let (x, y) = (Fx28_4::from_f32(sx)?, Fx28_4::from_f32(sy)?);
    if !(p.w > 0.0 && q.is_finite()) {
        return None;
    }
    let depth = if perspective { q } else { 0.5 * (1.0 - p.z * q) };
    Some((x, y, depth, q))
}

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

/// The rows whose centres a polygon covers: those in `[top, bottom)`, the scanline walk's rule.
fn rows(v: &[ScreenVertex]) -> (i32, i32) {
    let (mut top, mut bottom) = (Fx28_4(i32::MAX), Fx28_4(i32::MIN));
    for p in v {
        top = top.min(p.y);
        bottom = bottom.max(p.y);
    }
    if top > bottom { (0, 0) } else { (top.first_centre_at_or_after(), bottom.first_centre_at_or_after()) }
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
pub(super) struct ObjectSetup<'a> {
    /// The mesh drawn (with its split pieces, for `view-lists`).
    pub(super) mesh: &'a Mesh,
    /// The stored drawing order of its polygons, if one applies.
    pub(super) stored: Option<&'a [u32]>,
    /// The mesh's vertices transformed, tested and projected.
    pub(super) vertices: &'a [SetupVertex],
    /// How they were transformed (clipping recomputes clip positions with it).
    pub(super) transform: &'a VertexTransform,
    /// The ordering key rule.
    pub(super) key: DepthKey,
    /// Whether the frame is drawn in an order made from the polygons' keys; the z-buffer's is not, and its
    /// polygons all get key 0 (a small triangle's set-up then skips reading the corners' view depths).
    pub(super) ordered: bool,
    /// Whether attributes are divided by `w` for perspective-correct interpolation.
    pub(super) perspective_attrs: bool,
    /// The key of every polygon when the object is drawn in a stored order.
    pub(super) object_key: Option<f32>,
    /// How many textures the draw list has.
    pub(super) textures: usize,
    /// Draw with the screen door (the ghost car).
    pub(super) see_through: bool,
    /// Which polygons the fill draws by a fast path (small triangles among them are set up here).
    pub(super) fast_path: FastPathRule,
    /// The frame's width in pixels.
    pub(super) width: i32,
}

/// What set-up needs to know of a material, worked out once for a run of polygons sharing it.
#[derive(Clone, Copy, Debug)]
struct MaterialSetup {
    /// The material's index in the mesh.
    index: u32,
    /// Its texture, if the draw list has it.
    texture: Option<u32>,
    alpha_cutoff: Option<f32>,
    /// Whether its polygons of one colour take the direct small-triangle path ([`ObjectSetup::set_up_small`]).
    small: bool,
}

/// What gathering a polygon's corners gave: its ordering key and whether all corners share one colour.
struct Gathered {
    key: f32,
    constant_color: Option<[f32; 4]>,
}

impl ObjectSetup<'_> {
    /// Sets up polygons `range` (positions in the stored order, or polygon indices) into `out`.
    pub(super) fn run(&self, range: Range<usize>, out: &mut Batch) {
        let fallback = Material::default();
        let mut cached: Option<MaterialSetup> = None;
        for k in range {
            let Some(poly) = self.mesh.polygons().get(self.stored.map_or(k, |o| o[k] as usize)) else { continue };
            let idx = self.mesh.polygon_indices(poly);
            let material = self.mesh.materials().get(poly.material as usize).unwrap_or(&fallback);
            // Worked out once for each run of polygons sharing a material.
            let m = match cached {
                Some(m) if m.index == poly.material => m,
                _ => *cached.insert(self.material_setup(poly.material, material)),
            };
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
                continue;
            }
            if outside != 0 {
                out.counts.outside += 1;
                continue;
            }
            if cut == 0 && projected && m.small && self.set_up_small(idx, material, &m, out) {
                continue;
            }
            let first = out.screen.len();
            let gathered = if cut == 0 {
                // Inside the guard band: the corners as projected once per vertex.
                if !projected {
                    out.counts.invalid += 1;
                    continue;
                }
                self.gather_inside(idx, material, out)
            } else {
                self.gather_clipped(idx, material, out)
            };
            let Some(g) = gathered else {
                out.screen.truncate(first);
                continue;
            };
            self.finish(first, g, material, out);
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
        let fast = self.fast_path.applies(texture.is_some(), true, alpha_cutoff.is_some(), self.see_through);
        MaterialSetup { index, texture, alpha_cutoff, small: fast && material.depth_bias == 0 }
    }

    /// Sets up a projected triangle that is a small triangle with a fast path straight from its vertices
    /// (or culls it), giving exactly what [`Self::gather_inside`] and [`Self::finish`] give; `false`, with
    /// nothing written or counted, for any other polygon.
    ///
    /// The general path writes three 40-byte screen vertices, reads them back for the area, the key and
    /// the small triangle's set-up, and then drops them; on the small-polygon scene that was a third of the
    /// set-up stage.
    #[inline]
    fn set_up_small(&self, idx: &[u32], material: &Material, m: &MaterialSetup, out: &mut Batch) -> bool {
        // Arrays built element by element: `[T; N]::map` was not inlined here.
        let &[i0, i1, i2] = idx else { return false };
        let ids = [i0 as usize, i1 as usize, i2 as usize];
        let v = self.vertices;
        let s = [v[ids[0]].screen_or_zero(), v[ids[1]].screen_or_zero(), v[ids[2]].screen_or_zero()];
        if !SmallTriangle::fits([(s[0].0, s[0].1), (s[1].0, s[1].1), (s[2].0, s[2].1)]) {
            return false;
        }
        let mv = self.mesh.vertices();
        let verts = [&mv[ids[0]], &mv[ids[1]], &mv[ids[2]]];
        let product = |k: usize| verts[k].color * material.base_color;
        let p0 = product(0);
        let color0 = p0.to_array();
        // Only a polygon of one colour has a fast path (`MaterialSetup::small`). Equal vertex colours give
        // equal products (as `==` compares them) unless a product is NaN (an infinite channel times 0), which
        // `gather_inside` finds unequal to itself; otherwise the products are compared, as it does. (`&`, not
        // `&&`: three compares are cheaper than the branches between them.)
        let c = verts[0].color;
        let same = (verts[1].color == c) & (verts[2].color == c) & !p0.is_nan();
        if !same && (product(1).to_array() != color0 || product(2).to_array() != color0) {
            return false;
        }
        let (texture, alpha_cutoff) = (m.texture, m.alpha_cutoff);
        let area = (0..3)
            .map(|k| {
                let (p, q) = (s[k], s[(k + 1) % 3]);
                i64::from(p.0.0) * i64::from(q.1.0) - i64::from(q.0.0) * i64::from(p.1.0)
            })
            .sum::<i64>();
        if area == 0 {
            out.counts.degenerate += 1;
            return true;
        }
        if area > 0 && !material.double_sided {
            out.counts.backface += 1;
            return true;
        }
        let corner = |k: usize| {
            let (x, y, depth, q) = s[k];
            let m = if self.perspective_attrs { q } else { 1.0 };
            Corner { x, y, attrs: [depth, m, verts[k].uv.x * m, verts[k].uv.y * m] }
        };
        let corners = [corner(0), corner(1), corner(2)];
        let t = match texture {
            None => SmallTriangle::from_corners::<1>(&corners, area, self.width),
            Some(_) => SmallTriangle::from_corners::<4>(&corners, area, self.width),
        };
        let Some((t, planes)) = t else {
            debug_assert!(false, "a triangle that fits was not set up");
            return false;
        };
        let key = match self.object_key {
            _ if !self.ordered => 0.0,
            Some(k) => k,
            None => {
                let mut key = key_start(self.key);
                for &i in &ids {
                    key = key_add(self.key, key, self.vertices[i].view_depth);
                }
                if self.key == DepthKey::Avg { key / 3.0 } else { key }
            }
        };
        out.counts.drawn += 1;
        let paint = PolygonPaint {
            texture,
            sampler: material.sampler,
            alpha_cutoff,
            constant_color: Some(color0),
            screen_door: self.see_through,
        };
        let first = out.push_small((t, planes), texture.is_some());
        out.polys.push(DrawPolygon::new(first, 3, out.tag, t.rows(), true, &paint));
        if self.ordered {
            out.keys.push(key);
        }
        true
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
        Some(Gathered { key, constant_color: constant.then_some(colors) })
    }

    /// Clips a polygon crossing a clip plane and pushes the projected corners of what is left; `None` (and
    /// counted) when nothing is left or a corner does not project.
    fn gather_clipped(&self, idx: &[u32], material: &Material, out: &mut Batch) -> Option<Gathered> {
        out.clip_in.clear();
        for &i in idx {
            let i = i as usize;
            let (v, s) = (&self.mesh.vertices()[i], &self.vertices[i]);
            let c = v.color * material.base_color;
            let attrs = [v.uv.x, v.uv.y, c.x, c.y, c.z, c.w, s.view_depth];
            let (pos, _) = self.transform.clip_and_depth(v.position);
            out.clip_in.push(ClipVertex { pos, attrs });
        }
        let t = self.transform;
        match clip_polygon(&out.clip_in, &t.volume, &mut out.clip_out, &mut out.clip_scratch) {
            ClipResult::Outside => {
                out.counts.outside += 1;
                return None;
            }
            ClipResult::Clipped => out.counts.clipped += 1,
            ClipResult::Inside => {}
        }
        let mut key = key_start(self.key);
        for cv in &out.clip_out {
            let Some(p) = project(cv.pos, t.size, t.perspective) else {
                out.counts.invalid += 1;
                return None;
            };
            let a = &cv.attrs;
            out.screen.push(screen_vertex(p, [a[0], a[1]], [a[2], a[3], a[4], a[5]], self.perspective_attrs));
            key = key_add(self.key, key, a[VIEW_DEPTH]);
        }
        let color = |v: &ClipVertex| [v.attrs[2], v.attrs[3], v.attrs[4], v.attrs[5]];
        let first_color = out.clip_out.first().map(color);
        let constant_color = first_color.filter(|c| out.clip_out.iter().all(|v| color(v) == *c));
        Some(Gathered { key, constant_color })
    }

    /// Culls, keys and (when not y-monotone) splits the polygon whose corners are `out.screen[first..]`.
    fn finish(&self, first: usize, g: Gathered, material: &Material, out: &mut Batch) {
        let n = out.screen.len() - first;
        let mut key = g.key;
        if self.key == DepthKey::Avg {
            key /= n as f32;
        }
        if material.depth_bias > 0 {
            slope_scaled_bias(&mut out.screen[first..], material.depth_bias);
        }
        // A stored order keeps the object's polygons together, placed by the object's depth.
        if let Some(k) = self.object_key {
            key = k;
        }
        if !self.ordered {
            key = 0.0;
        }
        let area = signed_area2(&out.screen[first..]);
        if area == 0 {
            out.screen.truncate(first);
            out.counts.degenerate += 1;
            return;
        }
        if area > 0 && !material.double_sided {
            out.screen.truncate(first);
            out.counts.backface += 1;
            return;
        }
        out.counts.drawn += 1;
        let texture = material.texture.filter(|&t| t < self.textures).map(|t| t as u32);
        let alpha_cutoff = match material.alpha_mode {
            AlphaMode::Opaque => None,
            AlphaMode::Mask { cutoff } => Some(cutoff),
        };
        let paint = PolygonPaint {
            texture,
            sampler: material.sampler,
            alpha_cutoff,
            constant_color: g.constant_color,
            screen_door: self.see_through,
        };
        let tag = out.tag;
        // Each polygon (or piece) drawn, with its key when the frame is ordered by keys.
        let ordered = self.ordered;
        let push = |out: &mut Batch, first: u32, count: u32, rows: (i32, i32), small: bool| {
            out.polys.push(DrawPolygon::new(first, count, tag, rows, small, &paint));
            if ordered {
                out.keys.push(key);
            }
        };
        let fast = self.fast_path.applies(
            texture.is_some(),
            g.constant_color.is_some(),
            alpha_cutoff.is_some(),
            self.see_through,
        );
        // A small triangle with a fast path is set up here, in place of its screen vertices; a flat colour
        // needs only the depth plane (the fill draws a textureless small triangle as flat, see `bands`).
        let small = |corners: &[ScreenVertex], area: i64| match (fast, texture) {
            (false, _) => None,
            (true, None) => SmallTriangle::new::<1>(corners, area, self.width),
            (true, Some(_)) => SmallTriangle::new::<4>(corners, area, self.width),
        };
        if let Some(t) = small(&out.screen[first..], area) {
            out.screen.truncate(first);
            let rows = t.0.rows();
            let f = out.push_small(t, texture.is_some());
            push(out, f, n as u32, rows, true);
        } else if is_y_monotone(&out.screen[first..]) {
            let rows = rows(&out.screen[first..]);
            push(out, first as u32, n as u32, rows, false);
        } else {
            out.counts.split += 1;
            out.tris.clear();
            out.piece.clear();
            out.piece.extend_from_slice(&out.screen[first..]);
            triangulate(&out.piece, area.signum(), &mut out.tris);
            out.screen.truncate(first);
            for k in 0..out.tris.len() {
                let corners = out.tris[k].map(|i| out.piece[i]);
                if let Some(st) = small(&corners, signed_area2(&corners)) {
                    let rows = st.0.rows();
                    let f = out.push_small(st, texture.is_some());
                    push(out, f, 3, rows, true);
                    continue;
                }
                let f = out.screen.len() as u32;
                out.screen.extend_from_slice(&corners);
                push(out, f, 3, rows(&corners), false);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::{Vec2, Vec3, Vec4};

    use super::*;
    use crate::render::test_rng::Lcg;
    use crate::render::{Camera, Filter, MeshBuilder, TextureMode, Vertex};

    /// Sets up every polygon of `mesh`, seen by an orthographic camera that maps `x, y` to pixels of a
    /// 320x240 frame, with flat shading on the fast path.
    fn set_up_in_pixels(mesh: &crate::render::Mesh) -> Batch {
        let camera = crate::render::Camera {
            view: glam::Mat4::from_translation(Vec3::new(-160.0, -120.0, -10.0)),
            projection: crate::render::Projection::Orthographic { xmag: 160.0, ymag: 120.0, znear: 1.0, zfar: 30.0 },
        };
        let transform = VertexTransform {
            clip_from_model: camera.clip_from_view(320, 240) * camera.view,
            depth_row: camera.view.row(2),
            volume: ClipVolume::new(320, 240, true),
            size: (320.0, 240.0),
            perspective: false,
        };
        let vertices: Vec<_> = mesh.vertices().iter().map(|v| transform.vertex(v.position)).collect();
        let setup = ObjectSetup {
            mesh,
            stored: None,
            vertices: &vertices,
            transform: &transform,
            key: DepthKey::Avg,
            ordered: true,
            perspective_attrs: false,
            object_key: None,
            textures: 0,
            see_through: false,
            fast_path: FastPathRule { filter: Filter::Nearest, mode: TextureMode::Perspective },
            width: 320,
        };
        let mut out = Batch::default();
        setup.run(0..mesh.polygons().len(), &mut out);
        out
    }

    #[test]
    fn the_small_pieces_of_a_split_polygon_are_small_triangles_and_big_ones_keep_their_corners() {
        let mut b = MeshBuilder::new();
        let m = b.material(Material { double_sided: true, ..Material::default() });
        // Two chevrons (a V with a notch in its top: not y-monotone), one 6 pixels across and one 60: each
        // is split into two triangles.
        for (x, s) in [(20.0, 1.0), (100.0, 10.0)] {
            let corners = [(0.0, 0.0), (3.0, 4.0), (6.0, 0.0), (3.0, 6.0)];
            let idx: Vec<u32> = corners
                .iter()
                .map(|&(cx, cy)| {
                    let position = Vec3::new(x + cx * s, 20.0 + cy * s, 0.0);
                    b.vertex(Vertex { position, uv: Vec2::ZERO, color: Vec4::ONE })
                })
                .collect();
            b.polygon(&idx, m);
        }
        let out = set_up_in_pixels(&b.build().unwrap());
        assert_eq!(out.counts.split, 2);
        let small: Vec<bool> = out.polys.iter().map(|p| p.small()).collect();
        assert_eq!(small, [true, true, false, false]);
        assert_eq!(out.small.len(), 2);
        // Only the big pieces' corners are kept.
        assert_eq!(out.screen.len(), 6);
    }

    /// Screen vertices as bits, every NaN one value (a NaN colour's sign and payload depend on operand order).
    fn screen_bits(v: &[ScreenVertex]) -> Vec<(i32, i32, [u32; ATTRS])> {
        let b = |a: f32| if a.is_nan() { f32::NAN.to_bits() } else { a.to_bits() };
        v.iter().map(|v| (v.x.0, v.y.0, v.attrs.map(b))).collect()
    }

    #[test]
    fn polygons_set_up_from_projected_vertices_equal_the_clipper_path_bit_for_bit() {
        let mut rng = Lcg(3);
        let mut b = MeshBuilder::new();
        let tinted = b.material(Material { base_color: Vec4::new(0.9, 0.5, 0.25, 1.0), ..Material::default() });
        let biased = b.material(Material { double_sided: true, depth_bias: 2, ..Material::default() });
        let textured = b.material(Material { texture: Some(0), ..Material::default() });
        let masked = b.material(Material {
            texture: Some(0),
            double_sided: true,
            alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
            base_color: Vec4::new(1.0, 1.0, 1.0, 0.75),
            ..Material::default()
        });
        // Corners whose colours differ only in green, which this material's colour zeroes: one colour.
        let no_green = b.material(Material { base_color: Vec4::new(1.0, 0.0, 1.0, 1.0), ..Material::default() });
        let materials = [biased, tinted, textured, masked, tinted, textured, masked];
        for i in 0..3000 {
            let corners = if i % 3 == 0 { 4 } else { 3 };
            let centre = Vec3::new(rng.unit() * 40.0 - 20.0, rng.unit() * 30.0 - 15.0, -1.0 - rng.unit() * 60.0);
            let idx: Vec<u32> = (0..corners)
                .map(|k| {
                    let a = k as f32 / corners as f32 * std::f32::consts::TAU;
                    let r = 0.2 + rng.unit() * 3.0;
                    let position = centre + Vec3::new(libm::cosf(a) * r, libm::sinf(a) * r, rng.unit() - 0.5);
                    // One colour per polygon for some, per corner for others.
                    let c = match i % 2 {
                        // An infinite channel times the material's 0: a NaN colour, so not one colour.
                        _ if i % 22 == 0 => Vec4::new(0.5, f32::INFINITY, 0.5, 1.0),
                        _ if i % 11 == 0 => Vec4::new(0.5, rng.unit(), 0.5, 1.0),
                        0 => Vec4::splat(0.5),
                        _ => Vec4::new(rng.unit(), rng.unit(), 0.3, 1.0),
                    };
                    b.vertex(Vertex { position, uv: Vec2::new(rng.unit(), rng.unit()), color: c })
                })
                .collect();
            // Pairs of polygons share a material, so a run of polygons reuses its material facts.
            b.polygon(&idx, if i % 11 == 0 { no_green } else { materials[i / 2 % materials.len()] });
        }
        let mesh = b.build().unwrap();
        let (w, h) = (320.0, 240.0);
        let camera = Camera::look_at(Vec3::ZERO, Vec3::NEG_Z, 1.0, 0.5, Some(100.0));
        let transform = VertexTransform {
            clip_from_model: camera.clip_from_view(320, 240) * camera.view,
            depth_row: camera.view.row(2),
            volume: ClipVolume::new(320, 240, true),
            size: (w, h),
            perspective: true,
        };
        let vertices: Vec<_> = mesh.vertices().iter().map(|v| transform.vertex(v.position)).collect();
        // With no textures in the draw list a textured material draws untextured.
        let cases = [
            (DepthKey::Avg, 1, None, true),
            (DepthKey::Min, 0, None, true),
            (DepthKey::Max, 1, None, true),
            (DepthKey::Avg, 1, Some(7.5), true),
            (DepthKey::Max, 1, None, false),
        ];
        for (key, textures, object_key, ordered) in cases {
            let setup = ObjectSetup {
                mesh: &mesh,
                stored: None,
                vertices: &vertices,
                transform: &transform,
                key,
                ordered,
                perspective_attrs: true,
                object_key,
                textures,
                see_through: false,
                fast_path: FastPathRule { filter: Filter::Nearest, mode: TextureMode::Perspective },
                width: 320,
            };
            let (mut fast, mut slow) = (Batch::default(), Batch::default());
            let (mut compared, mut small, mut textured) = (0, 0, 0);
            for (k, poly) in mesh.polygons().iter().enumerate() {
                let idx = mesh.polygon_indices(poly);
                if idx.iter().any(|&i| !vertices[i as usize].is_projected()) {
                    continue; // crosses a plane: both go through the clipper
                }
                fast.clear();
                slow.clear();
                setup.run(k..k + 1, &mut fast);
                let material = &mesh.materials()[poly.material as usize];
                let Some(g) = setup.gather_clipped(idx, material, &mut slow) else {
                    // Wholly off one side of the frame: rejected by both.
                    assert!(fast.polys.is_empty() && fast.counts.outside == 1, "polygon {k}");
                    continue;
                };
                setup.finish(0, g, material, &mut slow);
                assert_eq!(screen_bits(&fast.screen), screen_bits(&slow.screen), "polygon {k}");
                assert_eq!(fast.small, slow.small, "polygon {k}");
                assert_eq!(fast.small_textured, slow.small_textured, "polygon {k}");
                assert_eq!(fast.polys, slow.polys, "polygon {k}");
                assert_eq!(fast.counts, slow.counts, "polygon {k}");
                assert_eq!(fast.keys, slow.keys, "polygon {k}");
                assert_eq!(fast.keys.len(), if ordered { fast.polys.len() } else { 0 }, "polygon {k}");
                compared += usize::from(!fast.polys.is_empty());
                small += fast.small.len() + fast.small_textured.len();
                textured += fast.small_textured.len();
            }
            assert!(compared > 1000, "only {compared} polygons drawn and compared");
            // The whole mesh in one run against the clipper path polygon after polygon into one batch.
            let (mut all_fast, mut all_slow) = (Batch::default(), Batch::default());
            setup.run(0..mesh.polygons().len(), &mut all_fast);
            for poly in mesh.polygons() {
                let (idx, material) = (mesh.polygon_indices(poly), &mesh.materials()[poly.material as usize]);
                let first = all_slow.screen.len();
                match setup.gather_clipped(idx, material, &mut all_slow) {
                    Some(g) => setup.finish(first, g, material, &mut all_slow),
                    None => all_slow.screen.truncate(first),
                }
            }
            assert_eq!(screen_bits(&all_fast.screen), screen_bits(&all_slow.screen));
            assert_eq!(all_fast.small, all_slow.small);
            assert_eq!(all_fast.small_textured, all_slow.small_textured);
            assert_eq!(all_fast.polys, all_slow.polys);
            assert_eq!(all_fast.keys, all_slow.keys);
            assert_eq!(all_fast.counts, all_slow.counts);
            assert!(all_fast.polys.len() > 1000);
            assert!(small > 300, "only {small} small triangles set up");
            assert!(textures == 0 || textured > 100, "only {textured} textured small triangles set up");
        }
    }
}
